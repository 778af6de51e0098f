"""Every JSON document of the samples and of ``../shared/realdata`` stays the same.

This test holds each ``advise --json``, ``gate --format json`` and ``inspect --json`` document (gzipped, in
``tests/golden/documents.json.gz``) and runs the same commands again as a user would (the console script,
from the repository's root, with the paths as written in the record). The exit code, every key, string,
boolean and integer (densities, counts, verdicts) must be equal; every other number within
``NUMBER_RTOL`` of its size plus ``NUMBER_ATOL`` (model units or shares): a faster transform that sums in
another order moves the 13th digit, and that is not a change of result (issue 24). Recorded first by the
layout work (issue 21) before it moved every module. A change that is *meant* to change documents records
them anew::

    python tests/integration/test_documents_unchanged.py --record          # rewrites tests/golden/documents.json.gz
    python tests/integration/test_documents_unchanged.py --dump DIR        # writes the documents themselves, to diff

and says why in its commit and in CHANGELOG.md.
"""

from __future__ import annotations

import gzip
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

from cadartifact.testing.paths import REALDATA, REALDATA_MISSING, ROOT

RECORD = ROOT / "tests" / "golden" / "documents.json.gz"
#: Numbers (not integers) may move by this share of their size, plus NUMBER_ATOL: rounding, not results.
NUMBER_RTOL = 1e-6
NUMBER_ATOL = 1e-9
SAMPLES = ["samples/clean_panel.step", "samples/car_hood_coarse.step", "samples/hull_freeform.step",
           "samples/wavy_panel_diagonal.step", "samples/cage.obj"]
COMMANDS = {
    "advise": ["advise", "{path}", "--tol", "0.05", "--json"],
    "gate": ["gate", "{path}", "--tol", "0.05", "--format", "json"],
    "inspect": ["inspect", "{path}", "--json"],
}


def _command_line() -> list[str]:
    """The console script beside this interpreter (as a user runs it), else the same entry point through -c."""
    script = Path(sys.executable).with_name("cadartifact")
    if script.exists():
        return [str(script)]
    return [sys.executable, "-c", "import sys; from cadartifact.cli import main; sys.argv[0] = 'cadartifact'; main()"]


def document(command: str, path: str) -> tuple[bytes, int]:
    """The document a command prints for ``path`` (relative to the repository's root) and its exit code."""
    args = [a.format(path=path) for a in COMMANDS[command]]
    env = dict(os.environ, COLUMNS="120")
    done = subprocess.run(_command_line() + args, cwd=ROOT, capture_output=True, env=env, timeout=600)
    return done.stdout, done.returncode


def _recorded() -> dict:
    return json.loads(gzip.decompress(RECORD.read_bytes()))["documents"] if RECORD.exists() else {}


def _cases() -> list[tuple[str, str]]:
    return sorted({(c, p) for c, p in (key.split(" ", 1) for key in _recorded())})


def differences(old, new, where: str = "") -> list[str]:
    """Where two JSON values differ beyond rounding (see the module's docstring), as ``path: old -> new``."""
    if isinstance(old, (bool, int)) or isinstance(new, (bool, int)):  # counts, densities, flags: exact
        return [] if old == new and type(old) is type(new) else [f"{where}: {old!r} -> {new!r}"]
    if isinstance(old, (int, float)) and isinstance(new, (int, float)):
        same = (math.isnan(old) and math.isnan(new)) or abs(old - new) <= NUMBER_RTOL * max(abs(old), abs(new)) \
            + NUMBER_ATOL
        return [] if same else [f"{where}: {old!r} -> {new!r}"]
    if isinstance(old, dict) and isinstance(new, dict):
        if old.keys() != new.keys():
            return [f"{where}: keys {sorted(old.keys() ^ new.keys())} added or removed"]
        return [d for k in old for d in differences(old[k], new[k], f"{where}.{k}")]
    if isinstance(old, list) and isinstance(new, list):
        if len(old) != len(new):
            return [f"{where}: {len(old)} items -> {len(new)}"]
        return [d for i, (a, b) in enumerate(zip(old, new)) for d in differences(a, b, f"{where}[{i}]")]
    return [] if old == new else [f"{where}: {old!r} -> {new!r}"]


def test_differences_sees_results_and_forgives_rounding():
    doc = {"faces": [{"advised": [12, 9], "verdict": "fail", "peak": 0.0123456789, "ok": True}]}
    moved = json.loads(json.dumps(doc))
    moved["faces"][0]["peak"] = 0.0123456789 * (1 + 1e-9)
    assert differences(doc, moved) == []
    for key, value, where in (("advised", [12, 10], "advised[1]: 9 -> 10"), ("verdict", "warn", "verdict: 'fail' -> 'warn'"),
                              ("peak", 0.01235, "peak: 0.0123456789 -> 0.01235"), ("ok", False, "ok: True -> False")):
        changed = json.loads(json.dumps(doc))
        changed["faces"][0][key] = value
        assert differences(doc, changed) == [f".faces[0].{where}"]
    assert differences({"a": 1}, {"a": 1, "b": 2}) == [": keys ['b'] added or removed"]
    assert differences({"n": 3}, {"n": 3.0}) != []  # an integer is a count: its type is part of it


@pytest.mark.slow
@pytest.mark.parametrize("command,path", _cases(), ids=lambda x: x)
def test_document_is_unchanged(command, path):
    if path.startswith("../shared/") and not REALDATA.is_dir():
        pytest.skip(REALDATA_MISSING)
    expected = _recorded()[f"{command} {path}"]
    out, code = document(command, path)
    assert code == expected["exit"], f"{command} {path}: exit {code}, recorded {expected['exit']}"
    found = differences(expected["document"], json.loads(out))
    assert not found, (
        f"`cadartifact {' '.join(COMMANDS[command]).format(path=path)}` printed another document than the one "
        f"recorded ({len(found)} differences, first: {found[:5]}); see this module's docstring")


def _all_inputs() -> list[str]:
    real = sorted(str(p.relative_to(ROOT.parent).as_posix()) for p in (REALDATA / "step").glob("*")) + \
        sorted(str(p.relative_to(ROOT.parent).as_posix()) for p in (REALDATA / "obj").glob("*.obj"))
    return SAMPLES + ["../" + p for p in real]


if __name__ == "__main__":
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--record", action="store_true", help="record the documents' digests anew")
    parser.add_argument("--dump", type=Path, help="write every document into this folder")
    opts = parser.parse_args()
    if not (opts.record or opts.dump):
        parser.error("say --record, --dump DIR or both")
    record = {}
    for path in _all_inputs():
        for command in COMMANDS:
            out, code = document(command, path)
            record[f"{command} {path}"] = {"exit": code, "document": json.loads(out)}
            if opts.dump:
                opts.dump.mkdir(parents=True, exist_ok=True)
                (opts.dump / f"{Path(path).name}.{command}.json").write_bytes(out)
            print(f"{command:8s} {path}: exit {code}, {len(out)} bytes", flush=True)
    if opts.record:
        text = json.dumps({"about": "each document and its exit code; tests/integration/test_documents_unchanged.py",
                           "documents": record}, sort_keys=True, separators=(",", ":"))
        RECORD.write_bytes(gzip.compress(text.encode(), compresslevel=9, mtime=0))
