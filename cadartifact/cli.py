"""The ``cadartifact`` command line: a thin typer layer over the library.

Exit codes: 0 success (or every face within tolerance), 1 some face needs work
(advise / gate), 2 usage or input error. Errors are one line on stderr, never a
traceback.
"""

from __future__ import annotations

import functools
import sys
from enum import Enum
from pathlib import Path
from typing import List, Optional

import typer

from .errors import CadArtifactError

app = typer.Typer(
    name="cadartifact",
    help="Measure control-net artifacts (ripples) in NURBS and subdivision surfaces and advise control-point density.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode="rich",
)


def _console(stderr: bool = False):
    from rich.console import Console

    return Console(stderr=stderr, highlight=False)


def fail(message: str, code: int = 2) -> "typer.Exit":
    """Print a one-line error to stderr and return the Exit to raise."""
    _console(stderr=True).print(f"[bold red]cadartifact: error:[/] {message}", soft_wrap=True)
    return typer.Exit(code)


def cli_errors(func):
    """Turn :class:`CadArtifactError` into a one-line message and its exit code."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        try:
            return func(*args, **kwargs)
        except CadArtifactError as exc:
            raise fail(str(exc), exc.exit_code) from None

    return wrapper


class Stage(str, Enum):
    one_step = "one-step"
    limit = "limit"
    continuous = "continuous"


# ---------------------------------------------------------------- schemes & maps (spectral engine)
@app.command("schemes")
@cli_errors
def schemes_cmd(
    json_out: bool = typer.Option(False, "--json", help="Print the catalogue as JSON."),
):
    """List the scheme catalogue: arrows, mask size, interpolation, reproduction degree."""
    from .schemes import scheme, schemes

    rows = []
    for name in schemes():
        s = scheme(name)
        rows.append({
            "name": s.name,
            "arrows": list(s.arrows) if s.arrows is not None else None,
            "mask": list(s.mask.shape),
            "interpolating": s.interpolating,
            "reproduction_degree": s.reproduction_degree,
            "limit_stencil": list(s.limit_stencil.shape),
        })
    if json_out:
        import json

        typer.echo(json.dumps(rows, indent=2))
        return
    from rich.table import Table

    table = Table(title="cadartifact schemes", header_style="bold")
    for col in ("name", "arrows X1,X2,X1+X2,X1-X2", "mask", "limit stencil", "interpolating", "reproduces degree"):
        table.add_column(col)
    for r in rows:
        arrows = ",".join(map(str, r["arrows"])) if r["arrows"] else "kernel"
        table.add_row(r["name"], arrows, "x".join(map(str, r["mask"])), "x".join(map(str, r["limit_stencil"])),
                      "yes" if r["interpolating"] else "no", str(r["reproduction_degree"]))
    _console().print(table)
    _console().print("Also: bspline(p,q) for any degrees >= 1, box(n1,n2,n3,n4), or Scheme.from_mask(array).")


@app.command("maps")
@cli_errors
def maps_cmd(
    scheme: List[str] = typer.Option(["bicubic"], "--scheme", "-s", help="Scheme name; repeat to compare."),
    stage: str = typer.Option("limit", "--stage", help="Which response to map: one-step, limit or continuous."),
    out: Path = typer.Option(Path("maps.png"), "--out", "-o", help="PNG file to write."),
    grid: bool = typer.Option(False, "--grid", help="Draw the paper's Figure 8 array (g axis x d diagonal smoothing pairs)."),
    resolution: int = typer.Option(401, "--resolution", help="Grid points per axis (16 to 4096)."),
    domain: str = typer.Option("quadrant", "--domain", help="quadrant: [0, 1/2]^2 as the paper; square: [-1/2, 1/2]^2."),
):
    """Maps of the responses over the frequency square, like the paper's Figures 8 and 10-17."""
    from .errors import OptionError
    from .viz.maps import plot_grid, plot_maps

    # Validated here (not by a click Choice/range) so that a bad value is one line and exit 2.
    stages = [s.value for s in Stage]
    if stage.replace("_", "-") not in stages:
        raise OptionError("--stage", "one of " + ", ".join(stages), stage)
    stage = stage.replace("-", "_")
    if grid:
        path = plot_grid(out, stage=stage, resolution=resolution, domain=domain)
    else:
        path = plot_maps(scheme, out, stage=stage, resolution=resolution, domain=domain)
    _console().print(f"wrote {path}")


def main():  # console-script entry point
    try:
        app()
    except KeyboardInterrupt:
        sys.exit(130)


if __name__ == "__main__":
    main()
