"""A face whose advised net cannot be written faithfully is kept as it is, with the reason; the others are written.

The family: generated faces extended past their trims (cadartifact.testing.extended_faces) written to STEP
bounded by their trims, and replacement nets cut short of the trim (OCCT's Segment on a copy of the surface)
by 0.5-5 % of the range on one to four sides. Those faces are refused and kept, a refined net on another face is
written, and the file reads back with the same faces (the kept ones with their old poles). Every replacement
refused: nothing is written. The CLI says so in the JSON (validated against the schema) and in one text line
per kept face; the real linkrods model keeps face 20 (and says why for every kept face).
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

pytest.importorskip("OCP")

from typer.testing import CliRunner  # noqa: E402

from cadartifact.cli.app import app  # noqa: E402
from cadartifact.exchange.load import occ_surface, read  # noqa: E402
from cadartifact.exchange.model_writer import write_model  # noqa: E402
from cadartifact.exchange.occ import net_from_surface  # noqa: E402
from cadartifact.exchange.step import write_step  # noqa: E402
from cadartifact.runs.documents import json_schema  # noqa: E402
from cadartifact.testing.extended_faces import extended_face, smooth_face  # noqa: E402
from cadartifact.testing.paths import REAL_STEP, REALDATA_MISSING, ROOT  # noqa: E402

PROVENANCE = {"tool": "cadartifact test", "version": "0.1.0", "tolerance": 0.05, "intent": "surface"}
SHORT = [(("u0",), 0.005), (("u1", "v1"), 0.02), (("v0",), 0.05), (("u0", "u1", "v0", "v1"), 0.01)]


def quiet_read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read(path)


def cut_short(net, sides, share):
    """``net``'s surface cut ``share`` of the trimmed range short of the trim on ``sides``."""
    surface = occ_surface(net)
    u0, u1, v0, v1 = net.uv_bounds
    du, dv = share * (u1 - u0), share * (v1 - v0)
    surface.Segment(u0 + du * ("u0" in sides), u1 - du * ("u1" in sides),
                    v0 + dv * ("v0" in sides), v1 - dv * ("v1" in sides))
    return net_from_surface(surface, origin=net.origin)


def refined(net):
    """The same surface with one knot more in each direction (OCCT's knot insertion on a copy)."""
    surface = occ_surface(net)
    u0, u1, v0, v1 = surface.Bounds()
    surface.InsertUKnot(u0 + 0.37 * (u1 - u0), 1, 1e-9)
    surface.InsertVKnot(v0 + 0.61 * (v1 - v0), 1, 1e-9)
    return net_from_surface(surface, origin=net.origin, uv_bounds=net.uv_bounds)


def model(tmp_path, sides, seed=0):
    """Three faces side by side, each extended past its trim on ``sides`` (the middle one on none)."""
    nets = []
    for k in range(3):
        face = smooth_face(seed=seed + k)
        face = face.replace(points=face.points + np.array([120.0 * k, 0.0, 0.0]))
        nets.append(extended_face(face, sides=sides, ext=0.03) if k != 1 else face)
    return write_step(nets, tmp_path / "model.step")


@pytest.mark.parametrize("sides, share", SHORT, ids=["-".join(s) + f"-{p}" for s, p in SHORT])
def test_a_net_short_of_the_trim_is_kept_with_the_reason_and_the_others_written(sides, share, tmp_path):
    source = model(tmp_path, ("u0", "u1", "v0", "v1"))
    nets = {n.origin.face: n for n in quiet_read(source).nets}
    assert sorted(nets) == [0, 1, 2]
    out = tmp_path / "out.step"
    refused = {}
    records = write_model(source, {0: cut_short(nets[0], sides, share), 1: refined(nets[1]),
                                   2: cut_short(nets[2], sides[::-1], share)}, out,
                          provenance=PROVENANCE, refused=refused)
    assert [r["face"] for r in records] == [1] and records[0]["valid"] and records[0]["max_distance"] < 1e-6
    assert sorted(refused) == [0, 2]
    for why in refused.values():
        assert why.startswith("expected a net over the face's parameter range") and "received u [" in why
    back = {n.origin.face: n for n in quiet_read(out).nets}
    assert quiet_read(out).faces_total == 3 and sorted(back) == [0, 1, 2]
    for index in (0, 2):  # kept as it was
        assert back[index].shape == nets[index].shape
        assert np.allclose(back[index].points, nets[index].points, atol=1e-9)
    assert back[1].shape == refined(nets[1]).shape


def test_every_replacement_refused_writes_nothing(tmp_path):
    source = model(tmp_path, ("u1",))
    nets = {n.origin.face: n for n in quiet_read(source).nets}
    out = tmp_path / "out.step"
    refused = {}
    assert write_model(source, {i: cut_short(nets[i], ("u1",), 0.02) for i in (0, 2)}, out,
                       provenance=PROVENANCE, refused=refused) == []
    assert sorted(refused) == [0, 2] and not out.exists()


def invoke(args):
    return CliRunner().invoke(app, [str(a) for a in args])


def validator():
    jsonschema = pytest.importorskip("jsonschema")
    return jsonschema.Draft202012Validator(json_schema("advise"))


def test_cli_every_face_refused_writes_nothing_and_says_so(tmp_path, monkeypatch):
    from cadartifact.errors import OptionError
    from cadartifact.exchange import model_writer

    def short(index, surface, net, face=None):
        raise OptionError(f"replacements[{index}]", "a net over the face's parameter range", "a shorter one")

    monkeypatch.setattr(model_writer, "_check_range", short)
    out = tmp_path / "advised.step"
    args = ["advise", ROOT / "samples" / "wavy_panel_diagonal.step", "--tol", "0.05", "--no-verify", "--no-compare",
            "--write-resampled", out]
    doc = json.loads(invoke([*args, "--json"]).stdout)
    (f,) = doc["written"]["files"]
    assert f["path"] is None and doc["written"]["path"] is None and f["faces"] == [] and f["refused"]
    assert list(validator().iter_errors(doc)) == []
    assert not out.exists()
    text = invoke(args).stdout
    assert "wrote nothing for" in text and not out.exists()
    assert sum("kept as it was, its advised net cannot be written" in line for line in text.splitlines()) \
        == len(f["refused"])


@pytest.mark.realdata
@pytest.mark.slow
def test_linkrods_keeps_face_20(tmp_path):
    source = REAL_STEP / "linkrods.step"
    if not source.exists():
        pytest.skip(REALDATA_MISSING)
    out = tmp_path / "linkrods_advised.step"
    args = ["advise", source, "--tol", "0.05", "--write-resampled", out]
    result = invoke([*args, "--json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert list(validator().iter_errors(doc)) == []
    (f,) = doc["written"]["files"]
    refused = {r["face"]: r["reason"] for r in f["refused"]}
    # face 20 (its net ends short of its trim, and one direction is exact) is never written; every kept face says why
    assert 20 not in {r["face"] for r in f["faces"]} and all(refused.values())
    assert not set(refused) & {r["face"] for r in f["faces"]}
    if f["path"] is not None:  # at t = 0.05 its non-rational faces open edges beyond the gate's rules: kept too
        assert f["path"] == str(out) and quiet_read(out).faces_total == quiet_read(source).faces_total
    text = " ".join(invoke(args).stdout.split())
    assert all(f"face {k} kept as it was" in text for k in refused)
