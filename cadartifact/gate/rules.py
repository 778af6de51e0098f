"""The gate's SARIF rules: its own (CA001-CA007, CA110) and one per PDQ criterion, read from the criteria's
registry (:data:`cadartifact.analysis.quality.CRITERIA`). Standard library only."""

from __future__ import annotations

from ..registry import LiveMapping, LiveTuple

__all__ = ["SARIF_SCHEMA", "RULES", "CRITERION_RULES"]

SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"

#: SARIF rules: id, name, default level, short description; those of the PDQ criteria come from their registry
#: (:data:`cadartifact.analysis.quality.CRITERIA`, ``rule``), between CA005 and CA110.
_OWN_RULES = (
    ("CA001", "ripple-exceeds-tolerance", "error",
     "A face's control-net ripple (artifact) exceeds the tolerance"),
    ("CA002", "ripple-near-tolerance", "warning",
     "A face's ripple is within the tolerance but above the warn fraction of it, is undecided (its value "
     "+/- the intent's uncertainty U straddles the tolerance; policy undecided = 'warn'), or has non-uniform "
     "knots and is capped at warn by policy (measured = 'warn')"),
    ("CA003", "unreadable-file", "error",
     "A file could not be read or analysed; the gate fails closed"),
    ("CA004", "no-analysable-face", "note",
     "A file has no B-spline face or quad chart to analyse"),
    ("CA005", "analysed-share-too-small", "error",
     "An OBJ cage's analysed charts cover less of its area than the policy's min_analysed_share"),
    ("CA007", "extraordinary-vertex-defect", "error",
     "An OBJ cage's extraordinary vertex has a limit-surface shape defect beyond the tolerance"),
)
_NOT_EVALUATED = ("CA110", "pdq-not-evaluated", "note",
                  "A PDQ criterion could not be evaluated on a face (the reason is given)")


def _rules() -> tuple:
    from ..analysis.quality import CRITERIA

    criteria = tuple((spec.rule[0], spec.rule[1], "warning", spec.rule[2]) for spec in CRITERIA.values())
    return _OWN_RULES + criteria + (_NOT_EVALUATED,)


def _criterion_rules() -> dict:
    from ..analysis.quality import CRITERIA

    return {key: spec.rule[0] for key, spec in CRITERIA.items()}


RULES = LiveTuple(_rules)

#: SARIF rule of each PDQ criterion (:data:`cadartifact.analysis.quality.CRITERIA`, in order).
CRITERION_RULES = LiveMapping(_criterion_rules)

