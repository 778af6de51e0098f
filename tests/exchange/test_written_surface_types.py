"""The written record says which faces OCCT's STEP writer turned into another kind of surface.

A degenerate torus (STEP ``DEGENERATE_TOROIDAL_SURFACE``, major radius below the minor one, as NIST CTC-02 has six)
reads as a torus and OCCT's STEP writer writes it as a ``SURFACE_OF_REVOLUTION``. The family: a model of such a
torus face (two sizes) beside a B-spline face, in mm and inches; the B-spline face is replaced by the same surface
with a knot more. The write lists the torus face in ``types`` as (torus, revolution), the written file's text has
no toroidal surface left, and the replaced face's record says bspline -> bspline. The CLI's text says it in one line
per face.
"""

from __future__ import annotations

import math
import re
import warnings

import pytest

pytest.importorskip("OCP")

from cadartifact.exchange.load import occ_surface, read  # noqa: E402
from cadartifact.exchange.model_writer import write_model  # noqa: E402
from cadartifact.exchange.occ import net_from_surface, quiet_occt  # noqa: E402
from cadartifact.exchange.step import write_settings  # noqa: E402
from cadartifact.testing.extended_faces import smooth_face  # noqa: E402

PROVENANCE = {"tool": "cadartifact test", "version": "0.1.0", "tolerance": 0.05, "intent": "surface"}


def degenerate_torus_model(path, major, minor, unit):
    """A STEP model of a degenerate torus face and a B-spline face: OCCT writes the torus as a surface of
    revolution of its circle, which is put back as the ``DEGENERATE_TOROIDAL_SURFACE`` it is (the same axis)."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.Geom import Geom_ToroidalSurface
    from OCP.gp import gp_Ax3
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
    from OCP.TopoDS import TopoDS_Compound

    torus = BRepBuilderAPI_MakeFace(Geom_ToroidalSurface(gp_Ax3(), major, minor), 0.0, math.pi / 2, 0.2, 1.2,
                                    1e-7).Face()
    net = smooth_face(seed=1)
    bspline = BRepBuilderAPI_MakeFace(occ_surface(net.replace(points=net.points + [0.0, 0.0, 50.0])), 1e-7).Face()
    compound = TopoDS_Compound()
    builder = BRep_Builder()
    builder.MakeCompound(compound)
    builder.Add(compound, torus)
    builder.Add(compound, bspline)
    writer = STEPControl_Writer()
    with quiet_occt(), write_settings(unit, None):
        assert writer.Transfer(compound, STEPControl_AsIs) == IFSelect_RetDone
        assert writer.Write(str(path)) == IFSelect_RetDone
    text = path.read_text()
    (ident,) = re.findall(r"(#\d+) = SURFACE_OF_REVOLUTION\('',#\d+,#\d+\);", text)
    top = max(int(n) for n in re.findall(r"^#(\d+) =", text, flags=re.M))
    scale = 25.4 if unit == "INCH" else 1.0
    axis = (f"#{top + 1} = AXIS2_PLACEMENT_3D('',#{top + 2},#{top + 3},#{top + 4});\n"
            f"#{top + 2} = CARTESIAN_POINT('',(0.,0.,0.));\n#{top + 3} = DIRECTION('',(0.,0.,1.));\n"
            f"#{top + 4} = DIRECTION('',(1.,0.,0.));\n")
    text = re.sub(rf"^{ident} = SURFACE_OF_REVOLUTION\('',#\d+,#\d+\);",
                  f"{ident} = DEGENERATE_TOROIDAL_SURFACE('',#{top + 1},{major / scale!r},{minor / scale!r},.T.);",
                  text, flags=re.M)
    text = text.replace("ENDSEC;\nEND-ISO", axis + "ENDSEC;\nEND-ISO", 1)
    path.write_text(text)
    return path


def refined(net):
    surface = occ_surface(net)
    u0, u1, v0, v1 = surface.Bounds()
    surface.InsertUKnot(u0 + 0.37 * (u1 - u0), 1, 1e-9)
    return net_from_surface(surface, origin=net.origin, uv_bounds=net.uv_bounds)


@pytest.mark.parametrize("major, minor, unit", [(5.0, 8.0, "MM"), (2.0, 12.0, "INCH")])
def test_a_degenerate_torus_written_as_a_surface_of_revolution_is_said(major, minor, unit, tmp_path, monkeypatch):
    from cadartifact.exchange.model_writer import _read_source
    from cadartifact.exchange.occ import iter_faces, surface_kind
    from OCP.BRep import BRep_Tool

    source = degenerate_torus_model(tmp_path / "model.step", major, minor, unit)
    kinds = [surface_kind(BRep_Tool.Surface_s(f))[0] for _, f in iter_faces(_read_source(source)[0])]
    assert sorted(kinds) == ["bspline", "torus"]
    torus, plain = kinds.index("torus"), kinds.index("bspline")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        nets = {n.origin.face: n for n in read(source).nets}
    out = tmp_path / "out.step"
    types = {}
    (record,) = write_model(source, {plain: refined(nets[plain])}, out, provenance=PROVENANCE, types=types)
    assert types == {torus: ("torus", "revolution")}
    assert record["surface_type"] == record["surface_type_written"] == "bspline"
    text = out.read_text()
    assert "TOROIDAL_SURFACE" not in text and "SURFACE_OF_REVOLUTION" in text
    # the CLI's line for it
    from cadartifact.cli import advise_cmds

    lines = []
    console = type("Console", (), {"print": lambda self, line, **_: lines.append(line)})()
    monkeypatch.setattr(advise_cmds, "_console", lambda *a, **k: console)
    advise_cmds._print_written({"files": [{"path": str(out), "source": str(source), "mode": "model", "faces": [],
                                           "kept": [], "refused": [], "valid": True,
                                           "surface_types": [{"face": torus, "before": "torus",
                                                              "after": "revolution"}]}]}, "mm")
    assert any(f"face {torus}: a torus surface in the input, written as a revolution surface" in s for s in lines)


@pytest.mark.realdata
@pytest.mark.slow
def test_ctc_02_degenerate_tori_are_listed(tmp_path):
    import json

    from typer.testing import CliRunner

    from cadartifact.cli.app import app
    from cadartifact.testing.paths import REAL_STEP, REALDATA_MISSING

    source = REAL_STEP / "nist_ctc_02_asme1_ap242-1.stp"
    if not source.exists():
        pytest.skip(REALDATA_MISSING)
    out = tmp_path / "ctc02.step"
    result = CliRunner().invoke(app, ["advise", str(source), "--tol", "0.01", "--write-resampled", str(out), "--json"])
    (f,) = json.loads(result.stdout)["written"]["files"]
    assert f["path"] == str(out) and f["faces"]
    changed = {c["face"]: (c["before"], c["after"]) for c in f["surface_types"]}
    assert changed == {i: ("torus", "revolution") for i in (214, 311, 313, 315, 317, 319)}
    assert all(r["surface_type"] == r["surface_type_written"] == "bspline" for r in f["faces"])
