"""``cadartifact schemes`` and ``cadartifact maps``: the scheme catalogue and its response maps (the spectral
engine)."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import List, Optional

import typer

from .root import _console, app, cli_errors
from .usage import escape
from ..errors import OptionError, check_option


class Stage(str, Enum):
    one_step = "one-step"
    limit = "limit"
    continuous = "continuous"


# ---------------------------------------------------------------- schemes & maps (spectral engine)
@app.command("schemes", short_help="The scheme catalogue.")
@cli_errors
def schemes_cmd(
    json_out: bool = typer.Option(False, "--json", help="Print the catalogue as JSON."),
):
    """List the scheme catalogue: arrows, mask size, interpolation, generation degree."""
    from ..theory.catalogue import scheme, schemes

    rows = []
    for name in schemes():
        s = scheme(name)
        rows.append({
            "name": s.name,
            "arrows": list(s.arrows) if s.arrows is not None else None,
            "mask": list(s.mask.shape),
            "interpolating": s.interpolating,
            "generation_degree": s.generation_degree,
            "limit_stencil": list(s.limit_stencil.shape),
        })
    if json_out:
        import json

        typer.echo(json.dumps(rows, indent=2))
        return
    from rich.table import Table

    from ..runs.terminal import print_table

    table = Table(title="cadartifact schemes", header_style="bold")
    for col in ("name", "arrows X1,X2,X1+X2,X1-X2", "mask", "limit stencil", "interpolating", "generates degree"):
        table.add_column(col)
    for r in rows:
        arrows = ",".join(map(str, r["arrows"])) if r["arrows"] else "kernel"
        table.add_row(r["name"], arrows, "x".join(map(str, r["mask"])), "x".join(map(str, r["limit_stencil"])),
                      "yes" if r["interpolating"] else "no", str(r["generation_degree"]))
    print_table(_console(), table)
    _console().print("Also: bspline(p,q) for any degrees >= 1, box(n1,n2,n3,n4), or Scheme.from_mask(array).")


@app.command("maps", short_help="Response maps over the frequency square (paper Figs 8, 10-17).")
@cli_errors(aliases={"schemes": "scheme", "out suffix": "out"})
def maps_cmd(
    scheme: Optional[List[str]] = typer.Option(None, "--scheme", "-s",
                                               help="Scheme name or file:MASK.json; repeat to compare (default: "
                                                    "bicubic; not with --grid, whose schemes are the paper's)."),
    stage: str = typer.Option("limit", "--stage", help="Which response to map: one-step, limit or continuous."),
    out: Path = typer.Option(Path("maps.png"), "--out", "-o", help="PNG file to write."),
    grid: bool = typer.Option(False, "--grid", help="Draw the paper's Figure 8 array (g axis x d diagonal smoothing pairs)."),
    resolution: int = typer.Option(401, "--resolution", help="Grid points per axis (16 to 4096)."),
    domain: str = typer.Option("quadrant", "--domain", help="quadrant: [0, 1/2]^2 as the paper; square: [-1/2, 1/2]^2."),
):
    """Maps of the responses over the frequency square, like the paper's Figures 8 and 10-17."""
    from ..viz.maps import plot_grid, plot_maps

    # Choices are validated here (not by a click Choice or an Enum) so that a bad value is one line and exit 2.
    stages = [s.value for s in Stage]
    if stage.replace("_", "-") not in stages:
        check_option("--stage", stage, stages)
    stage = stage.replace("-", "_")
    if grid:
        if scheme:  # the Figure 8 array is a fixed family of schemes: a -s would be silently ignored
            raise OptionError("--scheme", "no --scheme with --grid (the grid draws the paper's g x d family)",
                              " ".join(scheme))
        path = plot_grid(out, stage=stage, resolution=resolution, domain=domain)
    else:
        path = plot_maps(scheme or ["bicubic"], out, stage=stage, resolution=resolution, domain=domain)
    _console().print(f"wrote {escape(path)}", soft_wrap=True)
