"""Every JSON document of the samples and of ``../shared/realdata`` stays the same, byte for byte.

The layout work (issue 21) moves every module and changes no result: this test holds the SHA-256 of each
``advise --json``, ``gate --format json`` and ``inspect --json`` document, recorded before the move, and
runs the same commands again as a user would (the console script, from the repository's root, with the
paths as written in the record). A change that is *meant* to change documents records them anew::

    python tests/test_documents_unchanged.py --record          # rewrites tests/golden/documents.json
    python tests/test_documents_unchanged.py --dump DIR        # writes the documents themselves, to diff

and says why in its commit and in CHANGELOG.md.
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "tests" / "golden" / "documents.json"
REALDATA = ROOT.parent / "shared" / "realdata"
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


def _cases() -> list[tuple[str, str]]:
    if not RECORD.exists():
        return []
    recorded = json.loads(RECORD.read_text())["documents"]
    return sorted({(c, p) for c, p in (key.split(" ", 1) for key in recorded)})


@pytest.mark.slow
@pytest.mark.parametrize("command,path", _cases(), ids=lambda x: x)
def test_document_is_byte_identical(command, path):
    if path.startswith("../shared/") and not REALDATA.is_dir():
        pytest.skip("../shared/realdata is not beside the checkout")
    expected = json.loads(RECORD.read_text())["documents"][f"{command} {path}"]
    out, code = document(command, path)
    assert code == expected["exit"], f"{command} {path}: exit {code}, recorded {expected['exit']}"
    assert len(out) == expected["bytes"] and hashlib.sha256(out).hexdigest() == expected["sha256"], (
        f"`cadartifact {' '.join(COMMANDS[command]).format(path=path)}` printed another document than the one "
        f"recorded ({len(out)} bytes, recorded {expected['bytes']}); see this module's docstring to compare them")


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
            record[f"{command} {path}"] = {"exit": code, "bytes": len(out), "sha256": hashlib.sha256(out).hexdigest()}
            if opts.dump:
                opts.dump.mkdir(parents=True, exist_ok=True)
                (opts.dump / f"{Path(path).name}.{command}.json").write_bytes(out)
            print(f"{command:8s} {path}: exit {code}, {len(out)} bytes", flush=True)
    if opts.record:
        RECORD.write_text(json.dumps({"about": "SHA-256 of each document; tests/test_documents_unchanged.py",
                                      "documents": record}, indent=1, sort_keys=True) + "\n")
