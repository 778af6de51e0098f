"""The one face pipeline (cadartifact.runs.face): its options, its record, its two phases.

The doors themselves (gate, advise, the CadQuery hook) are compared in tests/test_three_doors.py; here the
pipeline is called directly on nets made in the test.
"""

import json

import numpy as np
import pytest

from cadartifact.analysis.settings import RunSettings
from cadartifact.errors import OptionError
from cadartifact.net import ControlNet, NetOrigin
from cadartifact.runs import face
from cadartifact.runs.face import ADVISE, GATE, FaceOptions, analyse_face

pytest.importorskip("OCP")


def _net(nu=12, nv=10, amp=1.0, scale=1.0):
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    x, y = 100.0 * i / (nu - 1), 60.0 * j / (nv - 1)
    z = amp * np.sin(2 * np.pi * x / 37.0) * np.cos(2 * np.pi * y / 23.0) + 0.02 * x
    return ControlNet.from_points(scale * np.stack([x, y, z], -1), degrees=(3, 3),
                                  origin=NetOrigin(name="f", face=0, kind="bspline"))


@pytest.mark.parametrize("changes, parameter", [
    ({"advice": "some"}, "advice"), ({"reading": "other"}, "reading"), ({"verify": "sometimes"}, "verify"),
    ({"compare": "maybe"}, "compare"), ({"advice": "failing"}, "verdict"), ({"criteria": True}, "verdict"),
])
def test_bad_options_name_their_parameter(changes, parameter):
    with pytest.raises(OptionError) as info:
        FaceOptions(**changes)
    assert info.value.parameter == parameter and "\n" not in str(info.value)


def test_the_default_options_give_a_budget_record_only():
    rec = analyse_face(_net(), RunSettings(tolerance=0.05))
    assert rec["advice"] is None and rec["decision"] in ("conforms", "undecided", "does not conform")
    assert not {"verdict", "criteria", "peak_at", "entity_line"} & rec.keys()
    bare = analyse_face(_net(), RunSettings())  # no tolerance: no shares, decision, uncertainty
    assert bare["share"] is None and bare["decision"] is None and bare["uncertainty"] is None
    assert bare["budget"] == rec["budget"]


def test_the_gate_options_add_the_verdict_and_the_peak_in_the_records_key_order():
    from cadartifact.gate.policy import FileSettings

    settings = FileSettings(tolerance=0.01)
    rec = analyse_face(_net(), settings, GATE.replace(advice=settings.advise))
    keys = list(rec)
    assert keys[-8:] == ["verdict", "verdict_reason", "value", "advice_skipped", "ripple_verdict", "criteria",
                         "entity_line", "peak_at"]
    assert rec["verdict"] == "fail" and rec["advice"] is not None and rec["peak_at"]["value"] > 0.01
    passing = analyse_face(_net(amp=0.0), FileSettings(tolerance=1.0), GATE.replace(advice="failing"))
    assert passing["advice"] is None and passing["advice_skipped"] == "face passes (--advise failing)"
    assert passing["peak_at"] is None


def test_a_verification_left_for_later_gives_the_same_record():
    """The face-sharing split (phase one here, the verification and the peak in phase two) changes nothing."""
    settings = RunSettings(tolerance=0.01)
    at_once = analyse_face(_net(), settings, ADVISE)
    work = face.start_face(_net(), settings, ADVISE, later=True)
    assert work.advice.pending is not None and work.record["advice"]["verification"] is None
    later = face.finish_face(work, settings, ADVISE).record
    assert later["advice"]["verification"] is not None
    assert json.dumps(later) == json.dumps(at_once)


def test_a_non_finite_result_fails_where_asked(monkeypatch):
    """``finite``: a budget that overflowed (inf/NaN become None in the record) is an error, not a passing face."""
    from cadartifact.runs import records

    real = records.budget_record

    def overflowed(*args, **kwargs):
        rec = real(*args, **kwargs)
        rec["budget"]["total"]["peak"] = None
        return rec

    monkeypatch.setattr(records, "budget_record", overflowed)
    with pytest.raises(face.NonFiniteResult, match="non-finite value"):
        analyse_face(_net(), RunSettings(tolerance=0.05), FaceOptions(finite=True))
    assert analyse_face(_net(), RunSettings(tolerance=0.05))["budget"]["total"]["peak"] is None
