"""The reader child imports the same cadartifact as the process that starts it.

The child runs ``python -P -m cadartifact.execution.child`` with ``PYTHONPATH`` led by the folder holding
the parent's package; were that folder wrong, the child would silently import whichever cadartifact is
installed (another checkout's code reading the files).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import cadartifact
from cadartifact.execution import start

PACKAGE_PARENT = Path(cadartifact.__file__).resolve().parent.parent


def test_spawn_puts_the_package_parent_first_on_the_child_path(monkeypatch):
    seen = {}

    class Recorder:
        def __init__(self, argv, **kwargs):
            seen["argv"], seen["env"] = argv, kwargs["env"]

    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(["/elsewhere/one", "/elsewhere/two"]))
    monkeypatch.setattr(start.subprocess, "Popen", Recorder)
    start.spawn()
    first, *rest = seen["env"]["PYTHONPATH"].split(os.pathsep)
    assert Path(first).resolve() == PACKAGE_PARENT
    assert (Path(first) / "cadartifact" / "__init__.py").is_file()
    assert rest == ["/elsewhere/one", "/elsewhere/two"]  # the caller's path is kept, after it
    assert seen["argv"][1:] == ["-P", "-m", "cadartifact.execution.child"]


def test_child_of_a_copied_package_imports_the_copy(tmp_path):
    """A copy of the package outside any installation, started without PYTHONPATH from another folder: the
    child it spawns reports the copy's package folder, not the installed one."""
    copy = tmp_path / "checkout"
    shutil.copytree(PACKAGE_PARENT / "cadartifact", copy / "cadartifact",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    script = textwrap.dedent(f"""
        import sys
        import time
        sys.path.insert(0, {str(copy)!r})
        import cadartifact
        import pickle
        from cadartifact.execution import child, start
        deadline = time.monotonic() + 240
        proc = start.spawn()
        try:
            assert child._read_frame(proc.stdout.fileno(), deadline) == b"ready"
            start.write_frame(proc.stdin.fileno(), start.request("importlib.resources:files", ("cadartifact",)))
            kind, value = pickle.loads(child._read_frame(proc.stdout.fileno(), deadline))
        finally:
            start.stop(proc)
        print(cadartifact.__file__)
        print(kind, value)
    """)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    run = subprocess.run([sys.executable, "-P", "-c", script], cwd=tmp_path, env=env, capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    parent_file, child = run.stdout.strip().splitlines()
    assert Path(parent_file).resolve() == (copy / "cadartifact" / "__init__.py").resolve()
    kind, value = child.split(" ", 1)
    assert kind == "ok", child
    assert Path(value).resolve() == (copy / "cadartifact").resolve()
