"""A faces-only file holds verified advice only (SPEC §5 "An answer or an honest no", "What is verified is what is
written").

A face whose advice finds no net that conforms (an honest no) is not written as if it were advised: model mode
keeps it as it stands, faces-only mode leaves it out; both list it in ``written.files[].kept``, and a file's
``faces``, ``kept`` and ``refused`` add up to its advised faces. ``car_hood_coarse`` at t = 0.01 is such a face
(the candidates' U, 0.024, leaves no net verifiable); ``hull_freeform`` conforms at 0.01 (38x13).
"""

from __future__ import annotations

import dataclasses
import json
import warnings

import pytest

pytest.importorskip("OCP")

from typer.testing import CliRunner  # noqa: E402

import cadartifact as ca  # noqa: E402
from cadartifact.cli.app import app  # noqa: E402
from cadartifact.exchange.load import read  # noqa: E402
from cadartifact.runs.advising import write_advised  # noqa: E402
from cadartifact.testing.paths import SAMPLES  # noqa: E402

HOOD, HULL = SAMPLES / "car_hood_coarse.step", SAMPLES / "hull_freeform.step"


def quiet_read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read(path)


def advise_cli(*args):
    result = CliRunner().invoke(app, ["advise", *map(str, args), "--tol", "0.01", "--no-compare"])
    assert result.exit_code in (0, 1), result.output
    return result


def _adds_up(f, advised):
    assert sorted([r["face"] for r in f["faces"]] + f["kept"] + [r["face"] for r in f["refused"]]) == sorted(advised)


def test_an_honest_no_is_not_written_to_a_faces_only_file(tmp_path):
    out = tmp_path / "faces.step"
    doc = json.loads(advise_cli(HOOD, "--json", "--write-resampled", out, "--faces-only").stdout)
    (face,) = doc["files"][0]["faces"]
    assert not face["advice"]["meets_tolerance"] and face["advice"]["decision"] != "conforms"
    (f,) = doc["written"]["files"]
    assert f["mode"] == "faces-only" and f["path"] is None and doc["written"]["path"] is None
    assert f["faces"] == [] and f["kept"] == [face["face"]] and f["refused"] == []
    _adds_up(f, [face["face"]])
    assert not out.exists()
    text = advise_cli(HOOD, "--write-resampled", out, "--faces-only").stdout
    assert "wrote nothing for" in text and "1 face(s) kept as they were" in " ".join(text.split())
    assert not out.exists()


def test_model_and_faces_only_keep_the_same_faces(tmp_path):
    """Two inputs, one conforming face and one honest no: faces-only writes the conforming face alone (read back:
    the advised net), model mode replaces it and keeps the other model as it stands; both list the same kept."""
    out = tmp_path / "o.step"
    doc = json.loads(advise_cli(HOOD, HULL, "--json", "--write-resampled", out, "--faces-only").stdout)
    advice = {(r["path"], g["face"]): g["advice"] for r in doc["files"] for g in r["faces"]}
    by_source = {f["source"]: f for f in doc["written"]["files"]}
    hood, hull = by_source[str(HOOD)], by_source[str(HULL)]
    assert hood["path"] is None and hood["kept"] == [0] and not (tmp_path / "o_car_hood_coarse.step").exists()
    assert hull["path"] == str(tmp_path / "o_hull_freeform.step") and hull["kept"] == []
    (written,) = hull["faces"]
    assert advice[(str(HULL), written["face"])]["meets_tolerance"]
    back = quiet_read(hull["path"])
    assert back.faces_total == 1
    assert list(back.nets[0].shape) == advice[(str(HULL), written["face"])]["net"]
    for f in (hood, hull):
        _adds_up(f, [0])

    model = tmp_path / "m.step"
    doc = json.loads(advise_cli(HOOD, HULL, "--json", "--write-resampled", model).stdout)
    by_source = {f["source"]: f for f in doc["written"]["files"]}
    assert by_source[str(HOOD)]["kept"] == [0] and by_source[str(HOOD)]["faces"] == []
    assert [r["face"] for r in by_source[str(HULL)]["faces"]] == [0]
    kept = quiet_read(by_source[str(HOOD)]["path"])  # the model as it stands: today's net
    assert kept.nets[0].shape == quiet_read(HOOD).nets[0].shape


def test_a_cage_face_with_no_conforming_net_is_not_written(tmp_path):
    """A cage is always written faces only: a chart whose advice is an honest no (its advice made one here) is left
    out and listed in ``kept``; the others are written and read back with their advised nets."""
    cage = SAMPLES / "cage.obj"
    nets = ca.load(cage)
    advices = [ca.advise(n, 0.05, compare=False, verify=False) for n in nets]
    assert all(a.meets_tolerance for a in advices)
    no = dataclasses.replace(advices[0], meets_tolerance=False, decision="undecided")
    kept = [(cage, nets[0], no)] + [(cage, n, a) for n, a in zip(nets[1:], advices[1:])]
    out = tmp_path / "cage.step"
    got = write_advised(kept, out)
    (f,) = got["files"]
    assert f["mode"] == "faces-only" and f["kept"] == [nets[0].origin.face]
    _adds_up(f, [n.origin.face for n in nets])
    if len(nets) > 1:
        back = quiet_read(out)
        assert back.faces_total == len(nets) - 1
        assert [tuple(n.shape) for n in back.nets] == [tuple(a.shape) for a in advices[1:]]
    else:
        assert f["path"] is None and not out.exists()
