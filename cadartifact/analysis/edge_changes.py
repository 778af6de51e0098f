"""Whether a model's edges got worse: the gate's continuity verdicts along the edges of some faces, before and
after those faces changed (a written model against its input).

The edges of the changed faces are measured in both models (:func:`cadartifact.analysis.edges.shape_edges`,
restricted to those faces) and judged against one :class:`~cadartifact.analysis.quality.Profile`
(:func:`~cadartifact.analysis.edges.judge_edges`), exactly as ``gate --profile`` judges the written file. An edge
is matched by its two faces and its rank among the edges those two faces share (the written model is a copy of the
input with the same topology). Per criterion (G0 gap, G1 angle, G2 jump) the edge got worse when

* its verdict got worse (pass -> warn or fail, warn -> fail), or
* the input already failed it and its value grew by more than :data:`SLACK` of the criterion's fail threshold.

A criterion the input could not evaluate (a sharp edge's G1, an edge OCCT could not measure) is not compared.
:func:`blame` says which changed face each worse edge is charged to: the only changed face of the edge, else (both
changed) the one that moved farther from its old face.
"""

from __future__ import annotations

__all__ = ["SLACK", "edge_verdicts", "worse_edges", "blame", "reason"]

#: An already failing value may grow by this share of the criterion's fail threshold (sampling noise).
SLACK = 0.1
_RANK = {"pass": 0, "warn": 1, "fail": 2}
_WORDS = {"edge_gap": ("gap", "mm"), "edge_angle": ("angle", "degrees"), "edge_curvature": ("curvature jump", "")}


def edge_verdicts(shape, faces, profile) -> dict:
    """The judged records of the edges of ``faces`` (face indices) in ``shape``.

    Returns
    -------
    dict
        ``(face i, face j, rank) -> record`` (:func:`~cadartifact.analysis.edges.judge_edges`; ``i < j``, ``rank``
        the edge's place among the edges ``i`` and ``j`` share, in OCCT's edge order).
    """
    from .edges import judge_edges, shape_edges

    records = judge_edges(shape_edges(shape, faces=faces)["edges"], profile)
    out: dict = {}
    for record in sorted(records, key=lambda r: r["edge"]):
        i, j = sorted(record["faces"])
        rank = sum(1 for key in out if key[:2] == (i, j))
        out[(i, j, rank)] = record
    return out


def _limit(criterion: dict) -> float | None:
    threshold = criterion["threshold"] or {}
    return threshold.get("fail") if threshold.get("fail") is not None else threshold.get("warn")


def worse_edges(before: dict, after: dict) -> list:
    """The edges of ``after`` whose verdict is worse than in ``before`` (both :func:`edge_verdicts`).

    Returns
    -------
    list of dict
        One per edge and criterion that got worse: ``{"faces": [i, j], "criterion", "rule", "value", "before",
        "verdict", "verdict_before", "limit", "at"}``: ``value`` / ``before`` as written / in the input (model
        units, degrees or a share), ``rule`` the gate's rule id (``CA131``), ``limit`` the threshold crossed (when the input already failed: its value
        + :data:`SLACK` of the fail threshold), ``at`` the place of the written value (``{"t", "xyz"}``).
    """
    from .quality import CRITERIA

    out = []
    for key, new in sorted(after.items()):
        old = before.get(key)
        if old is None:
            continue
        was = {c["criterion"]: c for c in old["criteria"]}
        for c in new["criteria"]:
            o = was.get(c["criterion"])
            if not c["evaluated"] or o is None or not o["evaluated"]:
                continue
            rank, rank_before = _RANK[c["verdict"]], _RANK[o["verdict"]]
            fail = _limit(c)
            grew = rank == rank_before == 2 and fail is not None and c["value"] > o["value"] + SLACK * abs(fail)
            if rank <= rank_before and not grew:
                continue
            crossed = c["threshold"][c["verdict"]] if rank > rank_before else o["value"] + SLACK * abs(fail)
            out.append({"faces": list(key[:2]), "criterion": c["criterion"], "rule": CRITERIA[c["criterion"]].rule[0],
                        "value": c["value"],
                        "before": o["value"], "verdict": c["verdict"], "verdict_before": o["verdict"],
                        "limit": crossed, "at": c["at"]})
    return out


def blame(worse: list, changed, distance: dict) -> dict:
    """Which changed face each worse edge is charged to.

    Parameters
    ----------
    worse : list of dict
        :func:`worse_edges`.
    changed : collection of int
        The faces that changed.
    distance : dict int -> float
        How far each changed face moved from its old one: of an edge between two changed faces, the farther is
        charged.

    Returns
    -------
    dict
        ``face index -> [its worse edges]`` (the worst first: the largest excess over the limit, as a share of it).
    """
    changed = set(changed)
    out: dict = {}
    for edge in worse:
        mine = [f for f in edge["faces"] if f in changed]
        if not mine:
            continue
        face = mine[0] if len(mine) == 1 else max(mine, key=lambda f: (distance.get(f, 0.0), f))
        out.setdefault(face, []).append(edge)
    for edges in out.values():
        edges.sort(key=lambda e: -(e["value"] - e["limit"]) / max(abs(e["limit"]), 1e-300))
    return out


def reason(face: int, edges: list, units: str = "mm") -> str:
    """One line for ``face``'s worse edges: the worst, ``edge continuity: gap X mm > Y (input Z) ...``, and how
    many more."""
    e = edges[0]
    word, unit = _WORDS.get(e["criterion"], (e["criterion"], ""))
    unit = units if unit == "mm" else unit
    unit = f" {unit}" if unit else ""
    other = [f for f in e["faces"] if f != face] or [face]
    if e["verdict_before"] == "fail":  # the input failed it already: it may not grow beyond the slack
        said = f"> {e['limit']:.4g} (input {e['before']:.4g}, already failing, + {SLACK:g} of the fail threshold)"
    else:
        said = f"> {e['limit']:.4g} (input {e['before']:.4g})"
    head = f"edge continuity: {word} {e['value']:.4g}{unit} {said}"
    more = f"; {len(edges) - 1} more edge(s) worse" if len(edges) > 1 else ""
    return f"{head} at its edge with face {other[0]} ({e['rule']}){more}"
