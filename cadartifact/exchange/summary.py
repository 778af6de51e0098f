"""Plain-data summaries of what was read (the ``inspect`` command's rows and JSON)."""

from __future__ import annotations

from ..net import ControlNet

__all__ = ["parameter_range", "trimmed_fraction", "net_summary", "result_summary"]


def parameter_range(net: ControlNet) -> tuple[float, float, float, float] | None:
    """The full knot range ``(u0, u1, v0, v1)``: ``[t_p, t_{m-p-1}]`` per direction (None for a cage)."""
    if not net.is_bspline:
        return None
    out = []
    for t, p in zip(net.knots, net.degrees):
        out += [float(t[p]), float(t[len(t) - p - 1])]
    return tuple(out)


def trimmed_fraction(net: ControlNet) -> float | None:
    """Area of the face's UV bounds over the area of the full knot range (1.0 = untrimmed).

    None for cages and nets without ``uv_bounds``.
    """
    full = parameter_range(net)
    if full is None or net.uv_bounds is None:
        return None
    u0, u1, v0, v1 = net.uv_bounds
    area = (full[1] - full[0]) * (full[3] - full[2])
    if area <= 0:
        return None
    return float((u1 - u0) * (v1 - v0) / area)


def net_summary(net: ControlNet) -> dict:
    """One face/chart as JSON-ready data (see the ``inspect`` command for the schema)."""
    return {
        "face": net.origin.face,
        "name": net.origin.name,
        "kind": net.origin.kind,
        "degrees": list(net.degrees) if net.is_bspline else None,
        "size": list(net.shape),
        "rational": net.rational,
        "weights_vary": net.weights_vary,
        "periodic": list(net.periodic),
        "knots_uniform": list(net.knots_uniform),
        "trimmed_fraction": trimmed_fraction(net),
    }


def result_summary(result, fmt: str) -> dict:
    """One file's :class:`~cadartifact.exchange.LoadResult` as JSON-ready data."""
    mesh = result.mesh
    return {
        "path": str(result.path),
        "format": fmt,
        "faces_total": result.faces_total,
        "analysable": len(result.nets),
        "skipped": dict(sorted(result.skipped.items())),
        "warnings": list(result.warnings),
        "faces": [net_summary(n) for n in result.nets],
        "mesh": None if mesh is None else {
            "vertices": int(len(mesh.vertices)),
            "quads": mesh.n_quads,
            "triangles": mesh.n_triangles,
            "ngons": mesh.n_ngons,
            "regular_faces": mesh.n_regular_faces,
            "extraordinary": [int(v) for v in mesh.extraordinary],
            "crease_edges": int(len(mesh.crease_edges)),
            "charts": [{"chart": c.index, "size": list(c.shape), "faces": [int(f) for f in c.face_ids.ravel()],
                        "level": int(c.level)} for c in result.charts],
        },
    }
