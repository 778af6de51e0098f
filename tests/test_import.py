"""``import cadartifact`` must stay light: no heavy package (not even numpy, see below)."""

import subprocess
import sys

HEAVY = ("OCP", "cadquery", "pyvista", "vtk", "matplotlib", "trimesh", "meshio", "typer", "rich")


def test_import_loads_numpy_only():
    code = (
        "import sys, cadartifact; "
        f"print(' '.join(m for m in {HEAVY!r} if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"import cadartifact loaded: {out.stdout.strip()}"


def test_public_names_resolve_lazily():
    import cadartifact

    for name in ("ControlNet", "errors", "scheme", "schemes"):
        assert getattr(cadartifact, name) is not None


def test_the_reader_child_starts_before_numpy():
    """The CLI's first step (cli_prestart, reader_start) needs the standard library only, so that OCCT's
    reader child is spawned before this process spends its first 0.1 s importing numpy."""
    code = "import sys, cadartifact.cli.prestart, cadartifact.exchange.reader_start; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
