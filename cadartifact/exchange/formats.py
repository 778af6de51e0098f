"""The file formats cadartifact reads: one registry, :data:`FORMATS`, from which everything else is derived.

A format is one :class:`FileFormat` entry: its name (the ``"format"`` of ``inspect``'s document), its suffixes, its
reader, and how the rest of the package treats it (an OCCT B-rep read in the reader child, with a model to keep and
lengths in mm, or a cage read in this process in model units). The readers' suffix table
(:data:`cadartifact.exchange.SUPPORTED_EXTENSIONS`), the reader child's formats
(:data:`cadartifact.exchange.reader_start.BREP_FORMATS`), the files a folder or a glob contributes to ``gate`` and
``advise`` (:data:`cadartifact.gate.policy.CAD_SUFFIXES`), the pre-commit hook's file filter
(:func:`hook_pattern`, ``.pre-commit-hooks.yaml``) and the command line's ``STEP/IGES/BREP/OBJ`` all read it.

Adding a format is one entry here (and its reader). Standard library only: the reader child's start-up
(:mod:`.reader_start`) reads this module before numpy is imported.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Union

from ..errors import OptionError, UnsupportedFormatError
from ..registry import LiveMapping, LiveTuple

__all__ = ["FileFormat", "FORMATS", "register", "format_of", "suffixes", "brep_formats", "cad_suffixes",
           "labels", "hook_pattern", "LiveMapping", "LiveTuple"]

#: The reader child's function for a B-rep file (``module:function``, run by
#: :mod:`cadartifact.execution.child`).
OCCT_READER = "cadartifact.exchange.load:read_occt"


@dataclass(frozen=True)
class FileFormat:
    """One file format.

    Attributes
    ----------
    name : str
        The format's name (``inspect``'s ``"format"``; the readers' ``fmt``).
    suffixes : tuple of str
        Lower-case suffixes with their dot (files match in any case).
    label : str
        How messages and help name the format (``"STEP"``); also the reader child's ``what``.
    reader : str or callable
        ``"module:function"`` (imported on first use) or a function: ``reader(path) -> LoadResult`` for a
        format read in this process; for a B-rep format, the reader child's function (:data:`OCCT_READER`).
    brep : bool
        An OCCT B-rep: read in the reader child (:mod:`cadartifact.execution.child`), lengths in mm, a model
        that ``--write-resampled`` keeps (only the faces of other formats are written).
    gated : bool
        A folder or a glob given to ``gate`` or ``advise`` contributes its files of this format (and the
        pre-commit hook passes them).
    text_checked : bool
        B-rep: the caller checks the file's text while the reader child reads it (``prescanned``).
    """

    name: str
    suffixes: tuple
    label: str
    reader: Union[str, Callable]
    brep: bool = False
    gated: bool = True
    text_checked: bool = False

    def __post_init__(self):
        if not self.suffixes or not all(isinstance(s, str) and s.startswith(".") and s == s.lower()
                                        for s in self.suffixes):
            raise OptionError("suffixes", "lower-case suffixes starting with a dot", self.suffixes)

    @property
    def unit(self) -> str:
        """The length unit of its nets: ``"mm"`` (OCCT reads B-reps in mm) or ``"model"`` (unitless)."""
        return "mm" if self.brep else "model"

    def read(self, path):
        """Read a file of this format in this process (not a B-rep: :func:`cadartifact.exchange.read` sends those
        to the reader child): ``reader(path)``."""
        reader = self.reader
        if isinstance(reader, str):
            module, _, function = reader.partition(":")
            reader = getattr(importlib.import_module(module), function)
        return reader(path)


#: The registry: name -> format, in the order messages list them.
FORMATS: dict = {f.name: f for f in (
    FileFormat("step", (".step", ".stp"), "STEP", OCCT_READER, brep=True, text_checked=True),
    FileFormat("iges", (".iges", ".igs"), "IGES", OCCT_READER, brep=True, text_checked=True),
    FileFormat("brep", (".brep", ".brp"), "BREP", OCCT_READER, brep=True),
    FileFormat("obj", (".obj",), "OBJ", "cadartifact.exchange.obj:read_obj"),
)}


def register(fmt: FileFormat) -> FileFormat:
    """Add a format to :data:`FORMATS` (a suffix already taken by another format is an error)."""
    taken = {s: f.name for f in FORMATS.values() if f.name != fmt.name for s in f.suffixes}
    clash = [s for s in fmt.suffixes if s in taken]
    if clash:
        raise OptionError("suffixes", "suffixes no other format reads", f"{clash[0]} (read as {taken[clash[0]]})")
    FORMATS[fmt.name] = fmt
    return fmt


def suffixes() -> dict:
    """Lower-case suffix -> format name, every format."""
    return {s: f.name for f in FORMATS.values() for s in f.suffixes}


def format_of(path) -> FileFormat:
    """The format of a file by its suffix (any case).

    Raises
    ------
    UnsupportedFormatError
        An unknown suffix; the message lists the supported ones.
    """
    path = Path(path)
    name = suffixes().get(path.suffix.lower())
    if name is None:
        listed = ", ".join(sorted(suffixes()))
        raise UnsupportedFormatError(path, f"unsupported file extension {path.suffix or '(none)'!r}; "
                                     f"supported: {listed}")
    return FORMATS[name]


def brep_formats() -> dict:
    """Suffix -> format name of the formats OCCT's reader child reads."""
    return {s: f.name for f in FORMATS.values() if f.brep for s in f.suffixes}


def cad_suffixes() -> tuple:
    """The suffixes a folder or a glob contributes to ``gate`` and ``advise``."""
    return tuple(s for f in FORMATS.values() if f.gated for s in f.suffixes)


def labels() -> str:
    """``"STEP/IGES/BREP/OBJ"``: the gated formats, as messages and help name them."""
    return "/".join(f.label for f in FORMATS.values() if f.gated)


def hook_pattern() -> str:
    """The pre-commit hook's ``files:`` regex (``.pre-commit-hooks.yaml``): the gated suffixes, any case."""
    return r"(?i)\.(" + "|".join(s[1:] for s in cad_suffixes()) + r")$"
