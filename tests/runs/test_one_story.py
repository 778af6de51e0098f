"""The explanation lines tell the JSON's story: every number they print is a number of the face's record.

For the samples and generated faces (a trimmed face extended past its trim, a jointed face, a revolved face with
an exact arc) at several tolerances, the advise document is built and rendered as the terminal shows it; each
explanation line (``face N: u a->b: ...``) is parsed and every number in it must be, to the digits printed, a
number of that face's JSON record (or the run's tolerance). A binding direction's text and the verification's
``coarser`` agree: where the text says one point fewer breaks the tolerance, the coarser net measured on OCCT's
surface does not meet it, or the text says it is not confirmed. Counts inside a trim say so.
"""

from __future__ import annotations

import io
import re

import pytest

from cadartifact.testing.paths import ROOT

NUMBER = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def _numbers(value):
    if isinstance(value, bool):
        return
    if isinstance(value, (int, float)):
        yield float(value)
    elif isinstance(value, dict):
        for v in value.values():
            yield from _numbers(v)
    elif isinstance(value, (list, tuple)):
        for v in value:
            yield from _numbers(v)


def _found(x: float, pool) -> bool:
    return any(abs(abs(v) - x) <= 6e-4 * x + 1e-12 for v in pool)


def _story(paths, tolerance, tmp_path):
    from rich.console import Console

    from cadartifact.runs.advising import advise_files
    from cadartifact.runs.terminal import render

    doc = advise_files([str(p) for p in paths], tolerance)
    checked = 0
    for f in doc["files"]:  # one file at a time: face numbers repeat across files
        out = io.StringIO()
        render(dict(doc, files=[f]), Console(file=out, width=400, color_system=None, soft_wrap=True))
        checked += _check(out.getvalue(), {str(r["face"]): r for r in f["faces"]}, tolerance)
    return checked


def _check(text: str, faces: dict, tolerance: float) -> int:
    checked = 0
    for line in text.splitlines():
        m = re.match(r"\s+face (\S+): ([uv] \d+->\d+.*)$", line)
        if not m:
            continue
        rec = faces[m.group(1)]
        pool = list(_numbers(rec)) + [float(tolerance)]
        for token in NUMBER.findall(m.group(2)):
            assert _found(abs(float(token)), pool), f"{token} in {line!r} is not in the JSON record"
        advice = rec["advice"]
        for d, reason in advice["reasons"].items():
            if reason["today"] != rec["net"]["uv".index(d)] and f"{d} {reason['today']}->" in line:
                assert "inside the trim" in line
        ver = advice.get("verification") or {}
        if advice["binding"] and (ver.get("coarser") or {}).get("meets"):
            assert "not confirmed" in advice["reasons"][advice["binding"]]["reason"]
        checked += 1
    return checked


def _faces(tmp_path):
    from cadartifact.exchange.step import write_step
    from cadartifact.testing.arc_faces import revolved_face
    from cadartifact.testing.extended_faces import extended_face, jointed_face, smooth_face

    nets = [extended_face(smooth_face(n=(8, 7), amplitude=6.0, seed=1), sides=("u0", "v1"), ext=0.04, bend=0.02,
                          trim="third"),
            jointed_face(pieces=2, seed=2), revolved_face(20.0, 60.0, 3, 10, seed=1, ripple=0.4)]
    path = tmp_path / "generated.step"
    write_step(nets, path)
    return path


@pytest.mark.slow
@pytest.mark.parametrize("tolerance", [0.05, 0.01, 0.005])
def test_explanations_carry_the_records_numbers(tolerance, tmp_path):
    samples = [ROOT / "samples" / n for n in ("hull_freeform.step", "car_hood_coarse.step",
                                               "wavy_panel_diagonal.step")]
    assert _story(samples + [_faces(tmp_path)], tolerance, tmp_path) >= 3


def test_explanations_carry_the_records_numbers_fast(tmp_path):
    assert _story([ROOT / "samples" / "car_hood_coarse.step", _faces(tmp_path)], 0.01, tmp_path) >= 2
