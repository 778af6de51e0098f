"""The README's commands run as written (issue 12): every ``sh`` block line without a placeholder.

Each ``cadartifact ...`` line runs in a fresh folder holding a copy of ``samples/`` (the README's
paths are relative to the checkout), through this interpreter. Install lines (``python3 -m venv ...
&& .venv/bin/pip install ...``) are what ``.ci/run`` does; their final ``.venv/bin/cadartifact``
command is run here. The test-suite line is this suite. Numbers are not asserted (the advice is
changing): exit codes, and the shape of the output.
"""

import re
import shlex
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

from cadartifact.testing.paths import ROOT

PLACEHOLDERS = re.compile(r"your-org|<[a-z ]+>|\bFILE\b|\bPATH\b|my_mask")

pytest.importorskip("OCP")


def readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text()
    out = []
    for block in re.findall(r"```sh\n(.*?)```", text, re.S):
        for line in block.splitlines():
            line = re.split(r"\s+#\s", line, maxsplit=1)[0].strip()
            if not line or PLACEHOLDERS.search(line):
                continue
            if line.startswith("python3 -m venv"):
                last = line.split("&&")[-1].strip()
                if "pytest" in last:
                    continue  # the test suite: this run
                assert last.startswith(".venv/bin/cadartifact"), line
                line = last.replace(".venv/bin/cadartifact", "cadartifact", 1)
            if line not in out:  # the quickstart's demo is also in the CLI list
                out.append(line)
    return out


COMMANDS = readme_commands()


def test_the_readme_has_runnable_commands():
    assert len(COMMANDS) >= 10 and "cadartifact demo" in COMMANDS


@pytest.mark.slow
@pytest.mark.parametrize("command", COMMANDS)
def test_readme_command_runs_as_written(command, tmp_path):
    shutil.copytree(ROOT / "samples", tmp_path / "samples")
    args = shlex.split(command)
    assert args[0] == "cadartifact", command
    res = subprocess.run([sys.executable, "-m", "cadartifact.cli", *args[1:]], cwd=tmp_path, capture_output=True,
                         text=True, timeout=300)
    advisory = args[1] in ("advise", "gate", "demo")
    assert res.returncode in ((0, 1) if advisory else (0,)), (command, res.stderr[-2000:])
    assert "Traceback" not in res.stderr and "error:" not in res.stderr, res.stderr[-2000:]
    assert res.stdout.strip() or "--output" in args, command
    if "--json" in args:
        import json

        assert json.loads(res.stdout)["schema"].startswith("cadartifact.")
    for opt in ("--out", "--output", "--write-resampled"):
        if opt in args:
            written = tmp_path / args[args.index(opt) + 1]
            assert written.is_file() and written.stat().st_size > 0, (command, opt)
    if "junit" in args:
        assert ET.parse(tmp_path / args[args.index("--output") + 1]).getroot().tag == "testsuites"
