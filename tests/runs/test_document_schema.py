"""Every document the commands write validates against the JSON Schema generated from its records
(:mod:`cadartifact.runs.documents`, ``cadartifact schema KIND``), and the schema is strict enough to refuse a
document that is wrong: a key of the wrong type, a missing key, a key no record lists, a value outside its set.

The documents: the golden ones (tests/golden, the samples and ../shared/realdata as recorded), and the samples
run again with options the golden ones do not use: the scheme comparison, the net reading, --write-resampled,
--verify, PDQ profiles from the command line and from a policy file with overrides, an OBJ cage, an unreadable
file, --advise all; and face records with joins kept and with no density that conforms (generated faces).
"""

from __future__ import annotations

import copy
import functools
import gzip
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from cadartifact.cli.app import app
from cadartifact.runs.documents import ADVISE_SCHEMA, GATE_SCHEMA, INSPECT_SCHEMA, KINDS, json_schema

jsonschema = pytest.importorskip("jsonschema")

from cadartifact.testing.paths import GOLDEN as GOLDEN_FOLDER, ROOT, SAMPLES  # noqa: E402

GOLDEN = GOLDEN_FOLDER / "documents.json.gz"


@pytest.fixture(scope="module")
def validators():
    out = {}
    for kind in KINDS:
        schema = json_schema(kind)
        jsonschema.Draft202012Validator.check_schema(schema)  # a schema a validator accepts
        out[kind] = jsonschema.Draft202012Validator(schema)
    return out


def problems(validator, doc) -> list[str]:
    """Each validation error as ``path: message`` (empty: the document is valid)."""
    return [f"{'/'.join(map(str, e.absolute_path))}: {e.message[:300]}" for e in validator.iter_errors(doc)]


def record_validator(kind: str, record: str):
    """A validator of one record (``$defs`` entry) of a document's schema."""
    schema = json_schema(kind)
    return jsonschema.Draft202012Validator({"$schema": schema["$schema"], "$ref": f"#/$defs/{record}",
                                            "$defs": schema["$defs"]})


# ---------------------------------------------------------------- the recorded documents
@functools.lru_cache(maxsize=1)
def _golden() -> dict:
    return json.loads(gzip.decompress(GOLDEN.read_bytes()))["documents"]


@pytest.mark.parametrize("case", [pytest.param(c, marks=[pytest.mark.slow] if "/realdata/" in c else [])
                                  for c in sorted(_golden())], ids=lambda c: c)
def test_every_golden_document_validates(case, validators):
    """The recorded documents (the real data's too: they are in the record, their files need not be here)."""
    doc = _golden()[case]["document"]
    found = problems(validators[case.split(" ", 1)[0]], doc)
    assert not found, f"{case}: {len(found)} problems, first: {found[:5]}"


# ---------------------------------------------------------------- the samples, run again with other options
def cli(*args, cwd: Path | None = None):
    """Run the command line in this process; ``(exit code, stdout)``."""
    import os

    old = os.getcwd()
    if cwd is not None:
        os.chdir(cwd)
    try:
        result = CliRunner().invoke(app, [str(a) for a in args])
    finally:
        os.chdir(old)
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    return result.exit_code, result.stdout


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    root = tmp_path_factory.mktemp("documents")
    for p in SAMPLES.iterdir():
        (root / p.name).write_bytes(p.read_bytes())
    (root / "broken.step").write_text("ISO-10303-21;\nHEADER;\nthis is not a STEP file\n")
    (root / "strict.toml").write_text("[waviness]\nwarn = 0\nfail = 0\n")
    (root / "policy.toml").write_text('tolerance = 0.05\nprofile = "strict.toml"\n[[override]]\nglob = "clean*"\n'
                                      'profile = "none"\ntolerance = 0.01\n')
    return root


#: (name, command line, expected exit code); {root} is the folder of the samples' copies.
RUNS = [
    ("advise-compare", ["advise", "clean_panel.step", "cage.obj", "--tol", "0.05", "--json", "--compare"], 0),
    ("advise-net-reading", ["advise", "hull_freeform.step", "--tol", "0.05", "--json", "--intent", "net",
                            "--no-verify"], 1),
    ("advise-rms-signal", ["advise", "car_hood_coarse.step", "--tol", "0.02", "--metric", "rms",
                           "--include-signal-error", "--json"], 1),
    ("advise-write", ["advise", "wavy_panel_diagonal.step", "cage.obj", "--tol", "0.05", "--json",
                      "--write-resampled", "out.step"], 1),
    ("advise-write-faces-only", ["advise", "wavy_panel_diagonal.step", "--tol", "0.05", "--json",
                                 "--write-resampled", "faces.step", "--faces-only"], 1),
    ("gate-profile-verify", ["gate", "clean_panel.step", "car_hood_coarse.step", "cage.obj", "broken.step",
                             "--tol", "0.05", "--format", "json", "--profile", "default", "--verify", "--jobs", "1"],
     2),
    ("gate-policy-overrides", ["gate", "clean_panel.step", "wavy_panel_diagonal.step", "--policy", "policy.toml",
                               "--format", "json", "--jobs", "1"], 1),
    ("gate-advise-all", ["gate", "hull_freeform.step", "cage.obj", "--tol", "0.05", "--format", "json",
                         "--advise", "all", "--intent", "net", "--undecided", "fail", "--jobs", "1"], 1),
    ("gate-advise-none", ["gate", "wavy_panel_diagonal.step", "--tol", "0.05", "--format", "json",
                          "--advise", "none", "--jobs", "1"], 1),
    ("gate-unreadable", ["gate", "broken.step", "--tol", "0.05", "--format", "json", "--jobs", "1"], 2),
    ("inspect-all", ["inspect", "clean_panel.step", "car_hood_coarse.step", "hull_freeform.step",
                     "wavy_panel_diagonal.step", "cage.obj", "--json", "--convert"], 0),
]


@pytest.mark.slow
@pytest.mark.parametrize("name,args,code", RUNS, ids=[r[0] for r in RUNS])
def test_every_document_the_samples_give_validates(name, args, code, files, validators):
    got, out = cli(*args, cwd=files)
    assert got == code, f"{name}: exit {got}, expected {code}: {out[:500]}"
    doc = json.loads(out)
    found = problems(validators[args[0]], doc)
    assert not found, f"{name}: {len(found)} problems, first: {found[:5]}"
    if name == "advise-write":  # the options reached the document: written, a cage and a B-rep face
        assert doc["written"]["mode"] == "mixed" and "model_valid" in doc["written"]["faces"][0]
    if name == "gate-profile-verify":
        assert [f["verdict"] for f in doc["files"]] == ["pass", "fail", "pass", "error"]
        assert doc["summary"]["criteria"] and doc["files"][0]["faces"][0]["criteria"]
        assert any((f["advice"] or {}).get("verification") for e in doc["files"] for f in e["faces"])
    if name == "gate-policy-overrides":
        assert doc["files"][0]["policy"]["profile"] is None and doc["files"][1]["policy"]["profile"]["name"] == \
            "strict"


@pytest.mark.slow
def test_face_records_with_joins_and_with_no_density_validate():
    """Advice the samples do not give: the joins of a jointed face kept, and an honest no (no density
    conforms), in the face record of the advise document."""
    from cadartifact.testing.extended_faces import jointed_face

    from cadartifact.advice.advise import advise
    from cadartifact.runs.records import face_record

    validator = record_validator("advise", "AdviseFace")
    f = jointed_face(2, 0, "C0", seed=1)
    for tol, what in ((0.05, "joins"), (5e-5, "no_density")):
        rec = face_record(f, advise(f, tol, compare=False))
        rec.update(face=0, entity_line=None, peak_at=None)  # what the document adds (a file's face has an index)
        assert rec["advice"][what], f"the case no longer gives {what}"
        found = problems(validator, json.loads(json.dumps(rec)))
        assert not found, f"{what}: {found[:5]}"


# ---------------------------------------------------------------- strict: a wrong document fails
def _sample_gate(validators) -> dict:
    doc = _golden()["gate samples/car_hood_coarse.step"]["document"]
    assert not problems(validators["gate"], doc)
    return copy.deepcopy(doc)


def _set(doc, path, value):
    *parents, last = path
    for k in parents:
        doc = doc[k]
    if value is _DELETE:
        del doc[last]
    else:
        doc[last] = value


_DELETE = object()
FACE = ("files", 0, "faces", 0)
WRONG = [
    ("a count as a string", ("summary", "faces"), "3"),
    ("a number as a string", (*FACE, "value"), "0.1"),
    ("a net of three counts", (*FACE, "net"), [12, 9, 4]),
    ("a flag as a number", (*FACE, "meets_tolerance"), 1),
    ("a verdict outside its set", (*FACE, "verdict"), "maybe"),
    ("a null where a record is required", (*FACE, "budget"), None),
    ("a peak as a string", (*FACE, "budget", "total", "peak"), "big"),
    ("a missing required key", (*FACE, "decision"), _DELETE),
    ("a missing budget component", (*FACE, "budget", "lateral"), _DELETE),
    ("a missing top-level key", ("exit_code",), _DELETE),
    ("a key no record lists", (*FACE, "colour"), "red"),
    ("another version", ("gate",), "cadartifact.gate/2"),
]


@pytest.mark.parametrize("what,path,value", WRONG, ids=[w[0] for w in WRONG])
def test_a_wrong_document_fails(what, path, value, validators):
    doc = _sample_gate(validators)
    _set(doc, path, value)
    assert problems(validators["gate"], doc), f"{what} at {path} passed the schema"


def test_a_wrong_advise_or_inspect_document_fails(validators):
    advise = copy.deepcopy(_golden()["advise samples/cage.obj"]["document"])
    inspect = copy.deepcopy(_golden()["inspect samples/cage.obj"]["document"])
    assert not problems(validators["advise"], advise) and not problems(validators["inspect"], inspect)
    advise["files"][0]["faces"][0]["advice"]["reasons"]["u"]["today"] = 7.5
    inspect["files"][0]["mesh"]["charts"][0].pop("size")
    assert problems(validators["advise"], advise) and problems(validators["inspect"], inspect)
    assert problems(validators["advise"], _golden()["gate samples/cage.obj"]["document"])  # a gate is no advise


# ---------------------------------------------------------------- one version, the schema command
def test_the_versions_are_the_writers():
    from cadartifact.gate.run import GATE_SCHEMA as WRITTEN_GATE
    from cadartifact.runs.records import SCHEMA

    assert (ADVISE_SCHEMA, GATE_SCHEMA) == (SCHEMA, WRITTEN_GATE)
    assert json_schema("advise")["title"] == ADVISE_SCHEMA and json_schema("gate")["title"] == GATE_SCHEMA
    assert json_schema("advise")["properties"]["schema"]["const"] == ADVISE_SCHEMA
    assert json_schema("gate")["properties"]["gate"]["const"] == GATE_SCHEMA
    assert json_schema("inspect")["properties"]["schema"]["const"] == INSPECT_SCHEMA
    assert _golden()["inspect samples/cage.obj"]["document"]["schema"] == INSPECT_SCHEMA


def test_the_records_are_described():
    """Every record carries its docstring as the schema's description (what a pipeline author reads)."""
    for kind in KINDS:
        schema = json_schema(kind)
        bare = sorted(name for name, d in schema["$defs"].items() if not d.get("description"))
        assert not bare, f"{kind}: records without a description: {bare}"
        assert schema["$defs"]["PeakRms" if kind != "inspect" else "Mesh"]["additionalProperties"] is False
    gate_face = json_schema("gate")["$defs"]["GateFace"]["properties"]
    assert gate_face["face"]["description"] and gate_face["verdict"]["description"]  # inherited keys, and its own


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_the_published_schema_files_are_current(kind):
    """docs/schemas/KIND.schema.json (linked from docs/schema.md, for pipelines without cadartifact) is what the
    records give today."""
    path = ROOT / "docs" / "schemas" / f"{kind}.schema.json"
    assert json.loads(path.read_text()) == json_schema(kind), (
        f"{path.relative_to(ROOT)} is out of date: cadartifact schema {kind} > {path.relative_to(ROOT)}")


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_schema_command_prints_the_schema(kind):
    code, out = cli("schema", kind)
    assert code == 0 and json.loads(out) == json_schema(kind)


def test_schema_command_refuses_an_unknown_kind():
    result = CliRunner().invoke(app, ["schema", "advice"])
    assert result.exit_code == 2 and result.stdout == ""
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "advise, gate, inspect" in lines[0] and "'advice'" in lines[0]
