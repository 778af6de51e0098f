"""A long-lived child process that runs requests, so that a crash or a hang costs one request, not the run.

OCCT's STEP transfer can segfault on a corrupt file (a flipped byte, a deleted line) or loop for
minutes. :func:`call` runs ``module:function(*args)`` in a child process that imports what its callers
name once (``preload``, e.g. OCCT's bindings) and serves requests over a pipe (length-prefixed pickles).

- A child that dies (a signal, an abort) is reported as ``FileFormatError("PATH: the STEP reader
  crashed on this file (SIGSEGV)")`` and a new child is started for the next request.
- A child that gives no answer within the timeout is killed: ``"... gave no answer in N s"``.
  The timeout is the ``timeout`` argument, else the configured settings' ``read_timeout``
  (:func:`configured`; the CLI sets it from ``--read-timeout`` or the environment).
- With ``isolation=False`` in the configured settings, callers run their work in this process (:func:`enabled`).

The child's own stdout and stderr go to ``/dev/null`` (OCCT prints parse errors there directly).
Its results are the same objects the function returns in this process (pickled).
"""

from __future__ import annotations

import atexit
import contextlib
import importlib
import os
import pickle
import select
import signal
import sys
import threading
import time

from . import start as _start
from ..errors import CadArtifactError, FileFormatError, InputError
from .settings import ExecutionSettings, InvalidValue, check_timeout

__all__ = ["START_TIMEOUT", "ChildFailed", "answered", "call", "configure", "configured", "enabled",
           "error_fields", "prestart", "read_timeout", "rebuilt_error", "serving", "settings", "shutdown", "warm"]

#: Seconds the child may take to start (its ``preload`` imports) before its first request.
START_TIMEOUT = 120.0
#: Named in the hint of a read that timed out (the CLI reads it: :mod:`cadartifact.cli.environment`).
TIMEOUT_HINT = "CADARTIFACT_READ_TIMEOUT or --read-timeout"

_HEADER = _start.HEADER
_serving = False  # True in the child process itself (it serves requests: it runs OCCT in its own process)
_settings = ExecutionSettings()  # this process's child: on or off, its timeout (configure, configured)


class ChildFailed(FileFormatError):
    """The child process crashed or gave no answer in time while working on a request (OCCT's fault, or the
    input's): the request's file or face is an error, the run goes on with a new child."""


def serving() -> bool:
    """Whether this process is the child (requests it gets run here: there is no child of the child)."""
    return _serving


def settings() -> ExecutionSettings:
    """The settings the child is run under in this process (:func:`configure`)."""
    return _settings


def configure(new: ExecutionSettings) -> ExecutionSettings:
    """Run the child under ``new`` from now on (whether there is one, its timeout); returns the previous settings.

    Raises
    ------
    OptionError
        ``new`` is not an :class:`~cadartifact.execution.settings.ExecutionSettings`.
    """
    global _settings
    if not isinstance(new, ExecutionSettings):
        from ..errors import OptionError

        raise OptionError("settings", "ExecutionSettings", type(new).__name__)
    saved, _settings = _settings, new
    return saved


@contextlib.contextmanager
def configured(new: ExecutionSettings | None):
    """Within the block, the child runs under ``new`` (None: as configured already)."""
    if new is None:
        yield _settings
        return
    saved = configure(new)
    try:
        yield new
    finally:
        configure(saved)


def enabled() -> bool:
    """Whether work goes to the child process (the configured settings' ``isolation``)."""
    return _settings.isolation


def read_timeout(timeout: float | None = None) -> float:
    """The timeout in seconds: ``timeout`` if given, else the configured settings' ``read_timeout``.

    Raises
    ------
    OptionError
        A timeout that is not a positive finite number; the configured one's when it could not be read
        (:class:`~cadartifact.execution.settings.InvalidValue`: a bad ``CADARTIFACT_READ_TIMEOUT``).
    """
    value = _settings.read_timeout if timeout is None else check_timeout(timeout)
    if isinstance(value, InvalidValue):
        raise value.error()
    return value


# ---------------------------------------------------------------- framing
_write_frame = _start.write_frame


def _read_exact(fd: int, n: int, deadline: float | None) -> bytes | None:
    """``n`` bytes from ``fd``; None at end of file; TimeoutError past ``deadline`` (monotonic)."""
    chunks, got = [], 0
    while got < n:
        if deadline is not None:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError
            ready, _, _ = select.select([fd], [], [], remaining)
            if not ready:
                raise TimeoutError
        chunk = os.read(fd, min(n - got, 1 << 20))
        if not chunk:
            return None
        chunks.append(chunk)
        got += len(chunk)
    return b"".join(chunks)


def _read_frame(fd: int, deadline: float | None) -> bytes | None:
    head = _read_exact(fd, _HEADER.size, deadline)
    if head is None:
        return None
    return _read_exact(fd, _HEADER.unpack(head)[0], deadline)


# ---------------------------------------------------------------- parent side
class _Child:
    """One child process serving requests.

    ``early``: the key (:func:`.start.request_key`) of a request the child was sent when the caller started it
    (:func:`.start.start`), whose answer is still to be read.
    """

    def __init__(self, proc=None, early: bytes | None = None, preload: tuple = ()):
        self.proc = proc if proc is not None else _start.spawn(preload)
        self.early = early
        self.ready = False

    @classmethod
    def new(cls, preload: tuple = ()) -> "_Child":
        """The child started early (:func:`.start.start`), else a new one importing ``preload``."""
        got = _start.take()
        return cls(*got) if got is not None else cls(preload=preload)

    def kill(self) -> None:
        _start.stop(self.proc)


_lock = threading.Lock()
_child: _Child | None = None
_busy: int | None = None  # the thread running `during` of a call (it holds _lock)


class _DuringFailed(Exception):
    """What ``during`` raised, carried past the handlers of the child's failures."""


def shutdown() -> None:
    """Stop the child process (it is started again on the next :func:`call`)."""
    global _child
    with _lock:
        if _child is not None:
            _child.kill()
            _child = None


def warm() -> bool:
    """Whether a reader child is running (started, not dead), so a call costs no start-up."""
    if _busy == threading.get_ident():  # inside `during`: the child is busy with this thread's request
        return False
    with _lock:
        return enabled() and _child is not None and _child.proc.poll() is None


def answered() -> bool:
    """Inside ``during``: whether the child's answer to this thread's request is waiting to be read (or the
    child has died), so that the caller's own work can stop early and read it. False elsewhere.

    Reads nothing (``select`` with no wait on the child's pipe); the lock is not taken, since the
    :func:`call` running ``during`` holds it on this very thread.
    """
    child = _child
    if _busy != threading.get_ident() or child is None or not child.ready:
        return False
    if child.proc.poll() is not None:
        return True
    return bool(select.select([child.proc.stdout.fileno()], [], [], 0)[0])


def prestart(preload: tuple = ()) -> None:
    """Start the child now, without waiting for it: its ``preload`` imports (OCP: about a second) then overlap
    this process's own imports and setup instead of following them. The first :func:`call` waits for
    it as usual; a child never called is stopped at exit. Does nothing with isolation off."""
    global _child
    if not enabled() or _busy == threading.get_ident():
        return
    with _lock:
        if _child is None or _child.proc.poll() is not None:
            if _child is not None:
                _child.kill()
            else:
                atexit.register(shutdown)
            _child = _Child.new(preload)


def _died_message(child: _Child) -> str:
    child.proc.wait()
    code = child.proc.returncode
    if code is not None and code < 0:
        try:
            return signal.Signals(-code).name
        except ValueError:
            return f"signal {-code}"
    return f"exit status {code}"


def call(function: str, args: tuple, *, path, what: str = "STEP", timeout: float | None = None, during=None,
         actor: str | None = None, idle: tuple = (), preload: tuple = ()):
    """Run ``module:function(*args)`` in the child process and return its result.

    Parameters
    ----------
    function : str
        ``"package.module:function"``, importable in the child.
    args : tuple
        Picklable arguments.
    path : path-like
        The file being read (named in the errors).
    what : str
        The reader's name in the errors (``"STEP"``, ``"IGES"``, ``"BREP"``).
    timeout : float, optional
        Seconds (see :func:`read_timeout`); ``float("inf")``: no limit (work that is not a read).
    during : callable, optional
        Work of this process's own, run once while the child works on the request (the two
        overlap on two cores). When it raises, the child is stopped and its answer never read.
    actor : str, optional
        Who failed, in the errors (default ``"the WHAT reader"``, with a hint about the timeout); e.g.
        ``"OCCT's evaluation of face 3"``.
    idle : tuple of str, optional
        Modules the child imports when it is idle after its answer (the work this process may send it next).
    preload : tuple of str, optional
        Modules a new child imports before it takes its first request (a child already running keeps its own).

    Raises
    ------
    CadArtifactError
        What the function raised (same class and message), or what ``during`` raised.
    ChildFailed
        The child crashed or gave no answer in time (a :class:`FileFormatError`).
    FileFormatError
        The child failed unexpectedly.
    """
    global _child, _busy
    if _busy == threading.get_ident():  # from `during`: the child works on this thread's request (the Lock would hang)
        raise RuntimeError("the reader child is busy with this process's own request (child.call inside during)")
    limit = None if timeout == float("inf") else read_timeout(timeout)  # inf: no limit (analysis, not a read)
    # relative paths are relative to this process's working directory, which may change between calls
    request = _start.request(function, args, idle)
    with _lock:
        for attempt in (0, 1):
            if _child is None or _child.proc.poll() is not None:
                if _child is not None:
                    _child.kill()
                if _child is None:
                    atexit.register(shutdown)  # once per child: a closed pipe ends it anyway, this reaps it
                _child = _Child.new(preload)
            child = _child
            # the CLI's guess of its first read (already sent): its answer serves only that very request
            sent = child.early is not None and child.early == _start.request_key(function, args)
            if child.early is not None and not sent:
                child.kill()
                _child = child = _Child(preload=preload)
            child.early = None
            try:
                # the pipe holds the request until the child, once OCP is imported, reads it
                if not sent:
                    _write_frame(child.proc.stdin.fileno(), request)
                if during is not None:
                    work, during = during, None
                    _busy = threading.get_ident()
                    try:
                        work()
                    except BaseException as exc:  # not to be read as the child's failure by the handlers below
                        raise _DuringFailed(exc) from None
                    finally:
                        _busy = None
                if not child.ready:  # the first answer is "ready", once OCP is imported
                    hello = _read_frame(child.proc.stdout.fileno(), time.monotonic() + START_TIMEOUT)
                    if hello != b"ready":
                        raise BrokenPipeError
                    child.ready = True
                reply = _read_frame(child.proc.stdout.fileno(), None if limit is None else time.monotonic() + limit)
            except _DuringFailed as failed:  # this process's own work failed: the child's answer is not wanted
                child.kill()
                _child = None
                raise failed.args[0] from None
            except TimeoutError:
                child.kill()
                _child = None
                waited = START_TIMEOUT if limit is None or not child.ready else limit
                if actor is not None:
                    raise ChildFailed(path, f"{actor} gave no answer in {waited:g} s and was stopped") from None
                raise ChildFailed(path, f"the {what} reader gave no answer in {waited:g} s and was stopped "
                                  f"(corrupt file? for a very large file raise {TIMEOUT_HINT})") from None
            except (BrokenPipeError, ConnectionResetError):
                reply = None
                if not child.ready and attempt == 0:  # the child did not start: try once more
                    child.kill()
                    _child = None
                    continue
            if reply is None:
                why = _died_message(child)
                child.kill()
                _child = None
                raise ChildFailed(path, f"{actor} crashed ({why})" if actor is not None
                                  else f"the {what} reader crashed on this file ({why})")
            break
    return _unpack(reply, path, what, actor)


def error_fields(exc: CadArtifactError) -> tuple:
    """An error as picklable data: ``(module, class name, path, problem, message, attributes)``; ``attributes``:
    its own (an :class:`~cadartifact.errors.OptionError`'s ``parameter``, ``expected``, ``received``; the text of
    one that does not pickle), which callers read (the CLI names the option from ``parameter``)."""
    attrs = {k: _picklable(v) for k, v in getattr(exc, "__dict__", {}).items() if not k.startswith("_")}
    return (type(exc).__module__, type(exc).__qualname__, getattr(exc, "path", None), getattr(exc, "problem", None),
            str(exc), attrs)


def _picklable(value):
    try:
        pickle.dumps(value)
        return value
    except Exception:  # noqa: BLE001 - any object: its text is what is left of it
        return repr(value)


def rebuilt_error(module: str, name: str, path, problem, message: str, attrs: dict | None = None) -> CadArtifactError:
    """The error :func:`error_fields` described: same class, message and attributes (a
    :class:`CadArtifactError` when the class cannot be found or cannot be rebuilt)."""
    try:
        cls = getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError):
        cls = CadArtifactError
    if isinstance(cls, type) and issubclass(cls, Exception) and not issubclass(cls, CadArtifactError):
        try:  # a plain exception (a face's unexpected failure): the same class, worded alike by the CLI
            return cls(message)
        except Exception:  # noqa: BLE001 - a class that wants other arguments
            return CadArtifactError(message)
    if not (isinstance(cls, type) and issubclass(cls, CadArtifactError)):
        return CadArtifactError(message)
    if issubclass(cls, InputError) and problem is not None:
        return cls(path, problem)
    exc = cls.__new__(cls)
    Exception.__init__(exc, message)
    exc.__dict__.update(attrs or {})
    return exc


def _unpack(reply: bytes, path, what: str, actor: str | None = None):
    kind, *rest = pickle.loads(reply)
    if kind == "ok":
        return rest[0]
    if kind == "error":
        raise rebuilt_error(*rest)
    name, message = rest
    raise FileFormatError(path, f"{actor or f'the {what} reader'} failed ({name}: {' '.join(message.split())[:200]})")


# ---------------------------------------------------------------- child side
def _serve(preload: tuple = ()) -> None:
    """The child's loop: import ``preload``, then one request frame in, one reply frame out, until the pipe
    closes."""
    global _serving
    _serving = True
    # run as ``python -m``, this module is ``__main__``: the requests import it again under its own name, and
    # that copy must know it is the child too (else an evaluation here would start a child of the child)
    importlib.import_module(_start.CHILD_MODULE)._serving = True
    fd_in, fd_out = os.dup(0), os.dup(1)
    devnull = os.open(os.devnull, os.O_RDWR)
    for fd in (0, 1, 2):  # OCCT writes to the console directly; nothing may reach the protocol pipe
        os.dup2(devnull, fd)
    import warnings

    warnings.simplefilter("ignore")  # the warnings travel in the results
    for name in preload:  # e.g. OCP, once
        try:
            importlib.import_module(name)
        except Exception:  # noqa: BLE001 - a module missing here (OCP): each request that needs it reports it
            pass
    _write_frame(fd_out, b"ready")
    idle: tuple = ()
    while True:
        frame = _read_frame(fd_in, None)
        if frame is None:
            return
        try:
            function, args, cwd, idle = pickle.loads(frame)
            os.chdir(cwd)
            module, _, name = function.partition(":")
            value = getattr(importlib.import_module(module), name)(*args)
            reply = ("ok", value)
        except CadArtifactError as exc:
            reply = ("error", *error_fields(exc))
        except BaseException as exc:  # noqa: BLE001 - every failure must reach the parent as an answer
            reply = ("exception", type(exc).__name__, str(exc))
        try:
            payload = pickle.dumps(reply, protocol=pickle.HIGHEST_PROTOCOL)
        except Exception as exc:  # noqa: BLE001
            payload = pickle.dumps(("exception", type(exc).__name__, f"unpicklable result: {exc}"))
        _write_frame(fd_out, payload)
        # idle after an answer: import what the parent said it may send next (idle_imports), off the
        # critical path of its next request
        for name in [m for m in idle if m not in sys.modules]:
            if select.select([fd_in], [], [], 0)[0]:
                break
            try:
                importlib.import_module(name)
            except Exception:  # noqa: BLE001 - an import that fails here fails again, and is reported, on use
                pass


if __name__ == "__main__":
    _serve(tuple(sys.argv[1:]))
