"""Advice a cage user can act on: per region the subdivision level that brings it within the tolerance,
and the extraordinary vertices that need more control.

A cage's density is changed by subdividing it (everywhere, or locally: edge loops around a region),
not by re-gridding a chart, so "chart 9x3 -> 4x3" is restated as a level:

- a chart (a regular region) whose control-net ripple is ``r`` (its share of the tolerance ``s = r / t``)
  is within the tolerance at level ``k = ceil(log4 s)`` (0 when ``s <= 1``): each Catmull-Clark step
  halves the spacing of a bicubic B-spline's control net, whose distance to its surface is of second
  order in the spacing (Prautzsch, Boehm and Paluszny 2002, *Bézier and B-spline techniques*, §6.4:
  the control polygon converges quadratically under knot insertion), so the ripple falls by 4 per level;
- an extraordinary vertex of defect ``d`` (:mod:`cadartifact.analysis.extraordinary`) is within at the
  first level ``k`` with ``d mu^k <= t``; when none up to
  :data:`~cadartifact.analysis.extraordinary.MAX_LEVEL` is, the vertex needs more control (an edge
  loop around it, or a vertex of valence 4 there).

The cage's level is the largest over its regions; its regions and vertices are listed with their own.
"""

from __future__ import annotations

from math import ceil, log

__all__ = ["ripple_level", "cage_advice"]


def ripple_level(share: float | None, max_level: int | None = None) -> int | None:
    """``ceil(log4 share)``, 0 when ``share <= 1``: the level that brings a chart's ripple within the tolerance.

    Parameters
    ----------
    share : float or None
        The ripple's share of the tolerance (None: not known).
    max_level : int, optional
        Levels beyond this give None (default :data:`cadartifact.analysis.extraordinary.MAX_LEVEL`).
    """
    from ..analysis.extraordinary import MAX_LEVEL

    if share is None:
        return None
    top = MAX_LEVEL if max_level is None else max_level
    if share <= 1:
        return 0
    k = ceil(log(share) / log(4) - 1e-12)
    return k if k <= top else None


def cage_advice(face_records: list, vertices: list) -> dict:
    """The cage's advice from its charts' records and its extraordinary vertices.

    Parameters
    ----------
    face_records : list of dict
        The charts' face records (``face``, ``net``, ``share.deviation``).
    vertices : list of dict
        The extraordinary vertices' records (``vertex``, ``face``, ``valence``, ``level``: the level within
        the tolerance, :meth:`~cadartifact.analysis.extraordinary.VertexDefect.level_within`); those with
        ``crease`` true are left out.

    Returns
    -------
    dict
        :class:`~cadartifact.runs.documents.cage.CageAdvice`: ``level`` (the largest region's, None when a
        vertex needs more control), ``regions`` (``{"face", "net", "share", "level"}`` per chart),
        ``vertices`` (``{"vertex", "face", "valence", "level"}`` per extraordinary vertex),
        ``need_control`` (vertex ids) and ``text`` (one line per action, in words).
    """
    from ..analysis.extraordinary import MAX_LEVEL

    regions = []
    for rec in face_records:
        share = (rec.get("share") or {}).get("deviation")
        regions.append({"face": rec["face"], "net": list(rec["net"]), "share": share, "level": ripple_level(share)})
    # vertices where a crease ends are reported, not advised on (their kink is a feature)
    verts = [{k: v[k] for k in ("vertex", "face", "valence", "level")} for v in vertices if not v.get("crease")]
    need = [v["vertex"] for v in verts if v["level"] is None]
    levels = [r["level"] for r in regions] + [v["level"] for v in verts]
    unknown = [r["face"] for r in regions if r["level"] is None and r["share"] is not None]
    level = None if need or unknown else max((k for k in levels if k is not None), default=0)
    text = []
    if level == 0:
        text.append("the cage as it is: every region and extraordinary vertex within the tolerance")
    elif level is not None:
        text.append(f"subdivide to level {level} (or refine only the regions below)")
    for r in regions:
        if r["level"]:
            nu, nv = r["net"]
            text.append(f"chart {r['face']} ({nu}x{nv} points): level {r['level']} "
                        f"({(nu - 1) * 2 ** r['level'] + 1}x{(nv - 1) * 2 ** r['level'] + 1} points)")
        elif r["level"] is None and r["share"] is not None:
            text.append(f"chart {r['face']}: not within by level {MAX_LEVEL}: needs more control")
    for v in verts:
        where = f"centre of face {v['face']}" if v["face"] is not None else f"vertex {v['vertex']}"
        if v["level"]:
            text.append(f"{where} (valence {v['valence']}): level {v['level']} around it")
        elif v["level"] is None:
            text.append(f"{where} (valence {v['valence']}): not within by level {MAX_LEVEL}: needs more "
                        "control (an edge loop around it)")
    return {"level": level, "regions": regions, "vertices": verts, "need_control": need, "text": text}
