"""What every reader shares (no OCP): the file check, the formats by extension, and what a read returns."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import FileFormatError, InputError
from . import formats

if TYPE_CHECKING:
    from .quadmesh import QuadMesh

__all__ = ["SUPPORTED_EXTENSIONS", "LoadResult", "check_file", "format_of"]

#: lower-case extension -> format name, read from the registry (:data:`cadartifact.exchange.formats.FORMATS`)
SUPPORTED_EXTENSIONS = formats.LiveMapping(formats.suffixes)


@dataclass(frozen=True, eq=False)
class LoadResult:
    """Everything read from one file.

    Attributes
    ----------
    path : Path
    nets : list of ControlNet
        The analysable faces (STEP/IGES/BREP) or grid charts (OBJ), in file order.
    faces_total : int
        Every face in the file (B-rep faces; OBJ polygons).
    skipped : dict str -> int
        Faces not analysed, by kind: ``"plane"``, ``"cylinder"``, ``"cone"``, ``"sphere"``,
        ``"torus"``, ``"revolution"``, ``"extrusion"``, ``"offset"``, ..., ``"degenerate"``,
        ``"dropped"`` (STEP faces OCCT's transfer lost: broken entities);
        for OBJ ``"triangle"``, ``"n-gon"``, ``"irregular quad"``.
    warnings : list of str
        Also issued through :func:`warnings.warn` (category ``LoadWarning``).
    mesh : QuadMesh or None
        OBJ only: the polygon mesh with its regularity analysis.
    charts : list of Chart
        OBJ only: ``charts[i]`` is the grid behind ``nets[i]`` (``nets[i].origin.face == i``), on the mesh of
        its ``level``.
    refined : Refined or None
        OBJ only: the cage after one Catmull-Clark step (:mod:`cadartifact.exchange.subdivision`), when some
        face of the cage as read is outside its level-0 charts; level-1 charts refer to its mesh.
    """

    path: Path
    nets: list = field(default_factory=list)
    faces_total: int = 0
    skipped: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)
    mesh: QuadMesh | None = None
    charts: list = field(default_factory=list)
    refined: object = None

    @property
    def analysable(self) -> int:
        """Number of nets."""
        return len(self.nets)


def format_of(path: Path) -> str:
    """The format's name of a file by its extension (any case); raises :class:`UnsupportedFormatError` listing the
    supported ones (:func:`cadartifact.exchange.formats.format_of` gives the whole record)."""
    return formats.format_of(path).name


def check_file(path: str | os.PathLike) -> Path:
    """Return ``path`` as a Path if it is a readable, non-empty file, else raise :class:`InputError`."""
    path = Path(path)
    if not path.exists():
        raise InputError(path, "file not found")
    if not path.is_file():
        raise InputError(path, "not a file")
    try:
        size = path.stat().st_size
        with open(path, "rb"):
            pass
    except OSError as exc:
        raise InputError(path, f"cannot be read ({exc.strerror or exc})") from None
    if size == 0:
        raise FileFormatError(path, "empty file")
    return path
