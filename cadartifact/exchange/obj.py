"""A small, strict Wavefront OBJ reader that keeps polygons as they are (no triangulation).

Read: ``v x y z [w]`` vertices and ``f a b c ...`` faces (``a``, ``a/t``, ``a//n``,
``a/t/n``; negative indices count back from the last vertex). OpenSubdiv tags
``t name ni/nf/ns ints... floats... strings...`` are kept (``crease`` edges with
their sharpness, the rest as generic tags). Every other statement (``vt``, ``vn``,
``o``, ``g``, ``s``, ``usemtl``, ``l``, comments, unknown keywords) is skipped.
A trailing ``\\`` continues a statement on the next line.

Every statement keeps the line it starts on (1-based, lines ended by LF, CR or CRLF as editors and SARIF count
them; comments and blank lines counted, a continued statement at its first line): :attr:`ObjData.vertex_lines`
and :attr:`ObjData.face_lines` locate a vertex or face in the file (the gate's findings point there).

Errors are :class:`~cadartifact.errors.FileFormatError` with the file and line:
non-finite or missing coordinates, a face index out of range, a face with fewer
than 3 vertices or a repeated vertex.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..errors import FileFormatError
from .messages import quote
from .quadmesh import Tag

#: ASCII numbers only: Python's int()/float() also take other scripts' digits and "1_0".
_INT = re.compile(r"[-+]?[0-9]+\Z")
_FLOAT = re.compile(r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?\Z|[-+]?(?:nan|inf|infinity)\Z",
                    re.IGNORECASE)
#: A face vertex: ``v``, ``v/t``, ``v//n`` or ``v/t/n``.
_FACE_ITEM = re.compile(r"([-+]?[0-9]+)(?:/(?:[-+]?[0-9]+)?(?:/[-+]?[0-9]+)?)?\Z")


def _int(token: str) -> int:
    if not _INT.match(token):
        raise ValueError(token)
    return int(token)


def _float(token: str) -> float:
    if not _FLOAT.match(token):
        raise ValueError(token)
    return float(token)

__all__ = ["ObjData", "Tag", "parse_obj", "statement_lines"]

#: Line ends: LF, CR and CRLF only (str.splitlines also splits at form feeds, U+2028 and others, which editors
#: and SARIF viewers do not count as lines).
_LINE_END = re.compile(r"\r\n|\r|\n")


@dataclass
class ObjData:
    """What :func:`parse_obj` found: vertices ``(n, 3)``, faces (0-based ids) and tags.

    ``vertex_lines[i]`` and ``face_lines[j]`` are the 1-based lines of vertex ``i``'s ``v`` statement and face
    ``j``'s ``f`` statement (:func:`statement_lines`).
    """

    vertices: np.ndarray
    faces: list[tuple[int, ...]]
    tags: list[Tag] = field(default_factory=list)
    face_lines: list[int] = field(default_factory=list)
    vertex_lines: list[int] = field(default_factory=list)
    #: Whether the text ends with a line break (a file cut short usually does not).
    ends_with_line_break: bool = True


def statement_lines(text: str):
    """Yield ``(line, tokens)`` per statement of an OBJ text: ``line`` the 1-based line it starts on, ``tokens``
    its words with continuation lines (a trailing ``\\``) joined and comments (``#`` to the line's end)
    removed; blank and comment-only lines yield nothing but are counted."""
    pending: list[str] = []
    start = 0
    for number, raw in enumerate(_LINE_END.split(text), start=1):
        line = raw.split("#", 1)[0].rstrip()
        if not pending:
            start = number
        if line.endswith("\\"):
            pending.append(line[:-1])
            continue
        pending.append(line)
        tokens = " ".join(pending).split()
        pending = []
        if tokens:
            yield start, tokens
    if pending:
        tokens = " ".join(pending).split()
        if tokens:
            yield start, tokens


def _tag(path, number: int, tokens: list[str]) -> Tag:
    """Parse ``t name ni/nf/ns args...`` (lenient: a malformed tag keeps its name only)."""
    name = tokens[1] if len(tokens) > 1 else ""
    try:
        ni, nf, ns = (_int(x) for x in tokens[2].split("/"))
        args = tokens[3:]
        ints = tuple(_int(x) for x in args[:ni])
        floats = tuple(_float(x) for x in args[ni:ni + nf])
        strings = tuple(args[ni + nf:ni + nf + ns])
    except (IndexError, ValueError):
        return Tag(name)
    return Tag(name, ints, floats, strings)


def parse_obj(path) -> ObjData:
    """Parse an OBJ file into vertices, polygon faces and OpenSubdiv tags.

    Parameters
    ----------
    path : path-like
        An existing, non-empty file (checked by the caller).

    Returns
    -------
    ObjData
        ``vertices (n, 3) float``; ``faces`` as tuples of 0-based vertex ids in file
        order; ``tags``; ``vertex_lines`` and ``face_lines`` the 1-based line of each vertex's and face's
        statement.
    """
    path = Path(path)
    try:
        text = path.read_bytes().decode("utf-8", errors="strict")
    except UnicodeDecodeError:
        raise FileFormatError(path, "not an OBJ file (binary or not UTF-8 text)") from None
    if "\x00" in text:
        raise FileFormatError(path, "not an OBJ file (binary data)")
    coords: list[tuple[float, float, float]] = []
    faces: list[tuple[int, ...]] = []
    face_lines: list[int] = []
    vertex_lines: list[int] = []
    tags: list[Tag] = []
    for number, tokens in statement_lines(text):
        key = tokens[0]
        if key == "v":
            try:
                xyz = tuple(_float(x) for x in tokens[1:4])
            except ValueError:
                raise FileFormatError(path, f"line {number}: vertex coordinates are not numbers") from None
            if len(xyz) != 3:
                raise FileFormatError(path, f"line {number}: vertex needs 3 coordinates, found {len(xyz)}")
            if not all(math.isfinite(c) for c in xyz):
                raise FileFormatError(path, f"line {number}: vertex {len(coords) + 1} has a NaN or infinite coordinate")
            coords.append(xyz)
            vertex_lines.append(number)
        elif key == "f":
            ids = []
            for item in tokens[1:]:
                m = _FACE_ITEM.match(item)
                if m is None or item.endswith("/"):
                    raise FileFormatError(path, f"line {number}: face vertex {quote(item)} is not v, v/t, v//n "
                                          "or v/t/n with integer indices") from None
                head = m.group(1)
                k = int(head)
                if k < 0:
                    k = len(coords) + k + 1
                if k < 1 or k > len(coords):
                    raise FileFormatError(path, f"line {number}: face refers to vertex {head if len(head) <= 40 else head[:40] + '...'}, "
                                          f"but only {len(coords)} vertices are defined so far")
                ids.append(k - 1)
            if len(ids) < 3:
                raise FileFormatError(path, f"line {number}: face has {len(ids)} vertices, needs at least 3")
            if len(set(ids)) != len(ids):
                raise FileFormatError(path, f"line {number}: face repeats a vertex ({quote(' '.join(tokens[1:]))})")
            faces.append(tuple(ids))
            face_lines.append(number)
        elif key == "t":
            tags.append(_tag(path, number, tokens))
        # everything else (vt, vn, vp, o, g, s, l, usemtl, mtllib, ...) carries no net data
    vertices = np.array(coords, dtype=float).reshape(-1, 3)
    return ObjData(vertices=vertices, faces=faces, tags=tags, face_lines=face_lines, vertex_lines=vertex_lines,
                   ends_with_line_break=not text or text.endswith(("\n", "\r")))


def read_obj(path):
    """Read an OBJ cage: its mesh record, grid charts and one cage net per chart.

    Returns
    -------
    LoadResult
        ``nets[i]`` is chart ``i`` (``degrees None``, kind ``"quad-chart"``, ``origin.face == i``): first the
        charts of the cage as read (level 0), then those of the faces left over (triangles, n-gons, quads at an
        irregular vertex) after one Catmull-Clark step (level 1, ``refined``), where every face is a quad and the
        irregular region shrinks to the children touching an extraordinary vertex;
        ``faces_total`` counts polygons; ``skipped`` counts the polygons of which no part is analysed, by kind
        (see :mod:`cadartifact.exchange.quadmesh`).

    Raises
    ------
    InputError
        Missing or empty file, or a mesh without quad faces.
    FileFormatError
        Malformed statements or a non-manifold edge (see :func:`parse_obj`).
    """
    from ..errors import InputError, InvalidNetError
    from ..net import ControlNet, NetOrigin
    from .files import LoadResult
    from .messages import warn
    from .quadmesh import Chart, build_quadmesh, find_charts
    from .subdivision import refine_cage
    from .files import check_file

    path = check_file(path)
    data = parse_obj(path)
    if not data.faces:
        raise InputError(path, "no faces in the OBJ file")
    mesh, topology = build_quadmesh(path, data.vertices, data.faces, data.tags)
    # where each vertex and face stands in the file, for findings about them (an extraordinary vertex's line)
    mesh = replace(mesh, vertex_lines=tuple(data.vertex_lines), face_lines=tuple(data.face_lines))
    if mesh.n_quads == 0:
        raise InputError(path, f"no quad faces ({mesh.n_triangles} triangles, {mesh.n_ngons} n-gons): "
                         "a quad cage is needed")
    messages: list[str] = []
    if not data.ends_with_line_break:  # a cage cut short loses faces without a parse error: say so
        messages.append(f"{path}: the file does not end with a line break: it may be cut short (its last line is "
                        "read as it stands)")
    nets, charts = [], []
    degenerate = 0

    def add_charts(found, grid_mesh, level):
        nonlocal degenerate
        for candidate, chart in enumerate(found):
            origin = NetOrigin(file=str(path), face=len(charts), kind="quad-chart")
            try:
                net = ControlNet(points=grid_mesh.vertices[chart.vertex_ids], degrees=None, origin=origin,
                                 unit="model")
            except InvalidNetError as exc:
                # charts are numbered by the nets kept: name a skipped one by its grid and its first mesh face
                problem = str(exc).removeprefix(origin.label() + ": ")
                nu, nv = chart.vertex_ids.shape
                first = int(chart.face_ids.flat[0])
                line = data.face_lines[first if level == 0 else int(refined.parent[first])]
                at = f"level {level} " if level else ""
                messages.append(f"skipped chart: {path}: {at}grid {candidate} ({nu}x{nv} points, mesh faces from "
                                f"{first}, line {line}): {problem}")
                degenerate += 1
                continue
            charts.append(Chart(index=len(charts), vertex_ids=chart.vertex_ids, face_ids=chart.face_ids,
                                level=level))
            nets.append(net)

    add_charts(find_charts(mesh, topology), mesh, 0)
    # triangles, n-gons and irregular quads: after the scheme's first step every face is a quad, and the
    # regular ones among their children are charted on that level
    charted = np.zeros(mesh.n_faces, bool)
    for chart in charts:
        charted[chart.face_ids.ravel()] = True
    refined = None
    if not charted.all():
        refined = refine_cage(path, mesh)
        add_charts(find_charts(refined.mesh, refined.topology, analysed=~charted[refined.parent]),
                   refined.mesh, 1)
        for chart in charts:
            if chart.level == 1:
                charted[refined.parent[chart.face_ids.ravel()]] = True
    idle = ~charted
    irregular_quads = int(np.count_nonzero(idle & (mesh.face_sizes == 4) & ~mesh.regular_faces))
    skipped = {k: n for k, n in (("triangle", int(np.count_nonzero(idle & (mesh.face_sizes == 3)))),
                                 ("n-gon", int(np.count_nonzero(idle & (mesh.face_sizes > 4)))),
                                 ("irregular quad", irregular_quads), ("degenerate", degenerate)) if n}
    if not nets:
        messages.append(f"{path}: no analysable face (no regular quad face; "
                        f"{len(mesh.extraordinary)} extraordinary vertices)")
    for message in messages:
        warn(message)
    return LoadResult(path=path, nets=nets, faces_total=mesh.n_faces, skipped=skipped, warnings=messages,
                      mesh=mesh, charts=charts, refined=refined)
