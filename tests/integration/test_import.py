"""``import cadartifact`` must stay light: no heavy package (not even numpy, see below)."""

import subprocess
import sys

from cadartifact.testing.paths import SAMPLES

HEAVY = ("OCP", "cadquery", "pyvista", "vtk", "matplotlib", "trimesh", "meshio", "typer", "rich")


def test_import_loads_numpy_only():
    code = (
        "import sys, cadartifact; "
        f"print(' '.join(m for m in {HEAVY!r} if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"import cadartifact loaded: {out.stdout.strip()}"


def test_public_names_resolve_lazily():
    """The public names are loaded on first use (not by ``import cadartifact``), as the very objects of the
    modules that define them."""
    code = ("import sys, cadartifact as ca; loaded = 'cadartifact.theory.catalogue' in sys.modules; "
            "from cadartifact import errors, net; from cadartifact.theory import catalogue; "
            "print(loaded, ca.ControlNet is net.ControlNet, ca.errors is errors, ca.scheme is catalogue.scheme, "
            "ca.schemes is catalogue.schemes)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "True", "True", "True", "True"], out.stdout


def test_the_reader_child_starts_before_numpy():
    """The CLI's first step (cli_prestart, reader_start) needs the standard library only, so that OCCT's
    reader child is spawned before this process spends its first 0.1 s importing numpy."""
    code = "import sys, cadartifact.cli.prestart, cadartifact.exchange.reader_start; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_a_gate_run_does_not_import_scipy(tmp_path):
    """scipy is for the scheme designer (theory.design, theory.regularity): importing ``scipy.fft`` alone cost a
    gate process 0.1-0.4 s, more than the analysis of a small file (issue 24). The gate and advise paths use
    numpy's FFT, in this process and in the reader child alike (here: the file read in-process)."""
    from pathlib import Path

    sample = SAMPLES / "wavy_panel_diagonal.step"
    code = ("import sys\n"
            f"sys.argv = ['cadartifact', 'advise', {str(sample)!r}, '--tol', '0.05', '--json']\n"
            "from cadartifact.cli.app import run\n"
            "try:\n    run()\nexcept SystemExit:\n    pass\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] == 'scipy'), file=sys.stderr)\n")
    env = dict(__import__("os").environ, CADARTIFACT_READ_ISOLATION="0")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert out.stderr.strip().splitlines()[-1] == "[]", out.stderr[-2000:]
