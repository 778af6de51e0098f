"""Starting OCCT's reader child with the standard library only, and the requests it serves.

The CLI starts the child (:mod:`cadartifact.exchange.isolation`) as its very first step, before
numpy, typer or the analysis are imported, so that the child's import of OCP overlaps them. When
the command line names the one file it will read first, the child is also handed that read at
once (an *early* request): it reads while this process is still importing. :func:`take` gives the
started child to :mod:`~cadartifact.exchange.isolation`, which uses the early answer only for the
very same request (function, arguments, working directory) and otherwise stops that child and
starts another: a wrong guess costs time, never a different result.
"""

from __future__ import annotations

import atexit
import os
import pickle
import struct
import subprocess
import sys
from pathlib import Path

__all__ = ["HEADER", "ENV_ISOLATION", "READ_FUNCTION", "ANALYSIS_MODULES", "BREP_FORMATS", "BREP_SUFFIXES", "isolation_enabled",
           "spawn", "stop", "write_frame", "request", "request_key", "read_request", "start", "take"]

HEADER = struct.Struct("!Q")
ENV_ISOLATION = "CADARTIFACT_READ_ISOLATION"

#: The reader the child runs on a B-rep file.
READ_FUNCTION = "cadartifact.exchange.load:read_occt"

#: What the child imports while idle after a read of ``gate`` or ``advise``: the analysis of its share of
#: the faces (:mod:`cadartifact.runs.face_sharing`).
ANALYSIS_MODULES = ("cadartifact.runs.face_sharing", "cadartifact.gate.run", "cadartifact.advice.advise")

#: File suffixes the child reads, and their format (OBJ is read in the analysing process).
BREP_FORMATS = {".step": "step", ".stp": "step", ".iges": "iges", ".igs": "iges", ".brep": "brep", ".brp": "brep"}
#: The same suffixes, for ``str.endswith``.
BREP_SUFFIXES = tuple(BREP_FORMATS)

_prestarted: tuple | None = None  # (Popen, early request key or None), until take()


def isolation_enabled() -> bool:
    """Whether readers run in the child process (``CADARTIFACT_READ_ISOLATION`` is not ``0``)."""
    return os.environ.get(ENV_ISOLATION, "1").strip().lower() not in ("0", "false", "no", "off")


def spawn() -> subprocess.Popen:
    """A new reader child (it imports OCP, says ``ready`` and serves framed requests on its pipes)."""
    env = dict(os.environ)
    # the child must import this very package, wherever it was imported from: the folder holding the
    # package, found from the package itself so that moving this module between wings cannot change it
    package = sys.modules[__name__.partition(".")[0]]
    root = os.path.dirname(os.path.dirname(os.path.abspath(package.__file__)))
    env["PYTHONPATH"] = os.pathsep.join([root] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    # -P: not the working directory first on sys.path, where another checkout's cadartifact would win
    return subprocess.Popen([sys.executable, "-P", "-m", "cadartifact.exchange.isolation"],
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


def read_request(path, fmt: str, convert: bool) -> tuple[str, tuple]:
    """``(function, args)`` of the child's read of a B-rep file (:func:`cadartifact.exchange.read` sends it).

    A STEP or IGES file's text is checked by the caller while the child reads (``prescanned``)."""
    path = Path(path)
    return (READ_FUNCTION, (path, fmt, bool(convert), True) if fmt in ("step", "iges") else (path, fmt, bool(convert)))


def start(early: tuple | None = None, idle: tuple = ()) -> None:
    """Start the child now; with ``early = (function, args)`` also send it that request (``idle``: what it
    imports once it has answered). Does nothing with isolation off or when a child was already started."""
    global _prestarted
    if _prestarted is not None or not isolation_enabled():
        return
    proc = spawn()
    key = None
    if early is not None:
        function, args = early
        try:
            write_frame(proc.stdin.fileno(), request(function, args, idle))  # held by the pipe until OCP is in
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
    """Kill a reader child and reap it (its pipes closed)."""
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
    """At exit: a child started for a read that never came (a usage error, a cached result) is stopped."""
    got = take()
    if got is not None:
        stop(got[0])
