"""``import cadartifact`` must stay light: numpy only."""

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
