"""Starting the child process (:mod:`.child`) with the standard library only, and the frames it is sent.

A caller may start the child as its very first step, before numpy is imported, so that the child's own imports
(``preload``: e.g. OCCT's bindings, named by the caller) overlap the caller's; with an *early* request the child
also starts working at once. :func:`take` gives the started child to :mod:`.child`, which uses the early answer
only for the very same request (function, arguments, working directory) and otherwise stops that child and starts
another: a wrong guess costs time, never a different result.
"""

from __future__ import annotations

import atexit
import os
import pickle
import struct
import subprocess
import sys

__all__ = ["HEADER", "spawn", "stop", "write_frame", "request", "request_key", "start", "take"]

HEADER = struct.Struct("!Q")
#: The child's module, run as ``python -m``.
CHILD_MODULE = __name__.rpartition(".")[0] + ".child"
#: The folder holding this package: first on the child's path, so that it imports this very code.
PACKAGE_PARENT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

_prestarted: tuple | None = None  # (Popen, early request key or None), until take()


def spawn(preload: tuple = ()) -> subprocess.Popen:
    """A new child: it imports ``preload`` (module names), says ``ready`` and serves framed requests on its pipes."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([PACKAGE_PARENT] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep)
                                                            if p])
    # -P: not the working directory first on sys.path, where another checkout's cadartifact would win
    return subprocess.Popen([sys.executable, "-P", "-m", CHILD_MODULE, *preload],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                            env=env, close_fds=True)


def write_frame(fd: int, payload: bytes) -> None:
    """One length-prefixed frame."""
    view = memoryview(HEADER.pack(len(payload)) + payload)
    while view:
        view = view[os.write(fd, view):]


def request(function: str, args: tuple, idle: tuple = ()) -> bytes:
    """The frame payload of a request: ``module:function``, its arguments, the working directory they are
    relative to, and what the child imports once it has answered (``idle``)."""
    return pickle.dumps((function, args, os.getcwd(), tuple(idle)), protocol=pickle.HIGHEST_PROTOCOL)


def request_key(function: str, args: tuple) -> bytes:
    """What identifies a request: the function, its arguments and the working directory they are relative to."""
    return pickle.dumps((function, args, os.getcwd()), protocol=pickle.HIGHEST_PROTOCOL)


def start(early: tuple | None = None, idle: tuple = (), preload: tuple = ()) -> None:
    """Start the child now; with ``early = (function, args)`` also send it that request (``idle``: what it
    imports once it has answered; ``preload``: what it imports before it says ``ready``). Does nothing when a
    child was already started."""
    global _prestarted
    if _prestarted is not None:
        return
    proc = spawn(preload)
    key = None
    if early is not None:
        function, args = early
        try:
            write_frame(proc.stdin.fileno(), request(function, args, idle))  # held by the pipe until preloaded
            key = request_key(function, args)
        except OSError:
            key = None
    _prestarted = (proc, key)
    atexit.register(_stop_unused)


def take() -> tuple | None:
    """The started child and its early request's key, ``(Popen, key or None)``, once (None: none, or dead)."""
    global _prestarted
    got, _prestarted = _prestarted, None
    if got is not None and got[0].poll() is not None:
        stop(got[0])
        return None
    return got


def stop(proc: subprocess.Popen) -> None:
    """Kill a child and reap it (its pipes closed)."""
    try:
        proc.kill()
    except OSError:
        pass
    proc.wait()
    for f in (proc.stdin, proc.stdout):
        try:
            f.close()
        except OSError:
            pass


def _stop_unused() -> None:
    """At exit: a child started for a request that never came (a usage error, a cached result) is stopped."""
    got = take()
    if got is not None:
        stop(got[0])
