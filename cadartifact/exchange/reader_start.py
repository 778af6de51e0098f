"""OCCT's reader child: what it preloads, the requests of a read, and its early start, with the standard library only.

The child itself is the execution wing's (:mod:`cadartifact.execution.child`, started by
:mod:`cadartifact.execution.start`); this module names what the exchange wing asks of it. The CLI starts it as its
very first step, before numpy, typer or the analysis are imported, so that the child's import of OCP overlaps
them; when the command line names the one file it will read first, the child is also handed that read at once
(an *early* request). The child uses the early answer only for the very same request (function, arguments,
working directory) and otherwise is stopped and another started: a wrong guess costs time, never a different
result.
"""

from __future__ import annotations

from pathlib import Path

from ..execution import start as _start
from . import formats

__all__ = ["READ_FUNCTION", "PRELOAD", "BREP_FORMATS", "BREP_SUFFIXES", "read_request", "start"]

#: The reader the child runs on a B-rep file.
READ_FUNCTION = formats.OCCT_READER
#: What the reader child imports before its first request: OCCT's bindings, once.
PRELOAD = ("cadartifact.exchange.step",)

#: File suffixes the child reads, and their format (:func:`cadartifact.exchange.formats.brep_formats`; the other
#: formats, OBJ, are read in the analysing process).
BREP_FORMATS = formats.LiveMapping(formats.brep_formats)
#: The same suffixes (``tuple(BREP_SUFFIXES)`` for ``str.endswith``).
BREP_SUFFIXES = formats.LiveTuple(lambda: tuple(formats.brep_formats()))


def read_request(path, fmt: str, convert: bool) -> tuple[str, tuple]:
    """``(function, args)`` of the child's read of a B-rep file (:func:`cadartifact.exchange.read` sends it).

    A STEP or IGES file's text is checked by the caller while the child reads (``prescanned``)."""
    path = Path(path)
    record = formats.FORMATS[fmt]
    args = (path, fmt, bool(convert), True) if record.text_checked else (path, fmt, bool(convert))
    return record.reader, args


def start(early: tuple | None = None, idle: tuple = ()) -> None:
    """Start the reader child now (:func:`cadartifact.execution.start.start` with :data:`PRELOAD`); with
    ``early = (function, args)`` also send it that request (``idle``: what it imports once it has answered,
    named by the caller). The caller decides whether there is to be a child (isolation on)."""
    _start.start(early, idle, PRELOAD)
