"""``cadartifact design``: design a binary quad subdivision mask with the least artifact where asked
(:func:`cadartifact.theory.design.design`), write it (JSON + NumPy), its maps beside the named schemes, and print
its figures. The JSON file is a scheme: ``--scheme file:NAME.json`` in advise, gate and maps."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from .root import _console, app, cli_errors
from ..errors import OptionError

_CLASSES = ("C0", "C1", "C2")


def _support(text: str) -> tuple[int, int]:
    parts = text.lower().replace(" ", "").split("x")
    try:
        sizes = [int(p) for p in parts]
    except ValueError:
        sizes = []
    if len(sizes) == 1:
        sizes = sizes * 2
    if len(sizes) != 2:
        raise OptionError("--support", "a mask size such as 6x6 (or 6), 3 to 9 per side", text)
    return sizes[0], sizes[1]


def _zero(text: str) -> tuple[float, float]:
    try:
        wx, wy = (float(v) for v in text.split(","))
    except ValueError:
        raise OptionError("--zero", "a frequency pair WX,WY in cycles per control point, e.g. 0.25,0.25",
                          text) from None
    return wx, wy


@app.command("design", short_help="Design a subdivision mask with the least artifact where asked.")
@cli_errors(aliases={"support": "support", "zeros": "zero"})
def design_cmd(
    support: str = typer.Option("6x6", "--support", help="Mask size, e.g. 6x6 (3 to 9 per side)."),
    symmetry: str = typer.Option("square", "--symmetry",
                                 help="square (the square's 8 symmetries) or axes (the two axis reflections)."),
    degree: int = typer.Option(3, "--degree",
                               help="Polynomial degree generated (sum rules): such nets carry no artifact."),
    objective: str = typer.Option("energy", "--objective",
                                  help="Artifact minimised: energy, x1, x2, diagonal or lateral."),
    stage: str = typer.Option("limit", "--stage", help="limit (surface at the refined vertices) or one-step."),
    region: float = typer.Option(0.5, "--region",
                                 help="Average over |wx|, |wy| <= REGION cycles per control point "
                                      "(0.5: the Nyquist square)."),
    zero: Optional[List[str]] = typer.Option(None, "--zero",
                                             help="WX,WY where the artifact must be exactly 0 (repeatable)."),
    continuity: str = typer.Option("C1", "--continuity", help="Smoothness to prove: C0, C1 or C2."),
    attenuation_weight: float = typer.Option(0.0, "--attenuation-weight",
                                             help="Weight of the signal loss over the band (0: artifact only)."),
    attenuation_band: float = typer.Option(0.25, "--attenuation-band",
                                           help="Band of the signal bound and of the signal loss, cycles per "
                                                "point."),
    min_signal: float = typer.Option(0.2, "--min-signal",
                                     help="The signal response stays at least this (0 < s <= 1) on the band: "
                                          "positive, its attenuation bounded."),
    normalisation: str = typer.Option("signal", "--normalisation",
                                      help="signal (the artifact as a share of the signal, the paper's percent "
                                           "of the signal) or absolute."),
    name: str = typer.Option("designed", "--name", help="The scheme's label and the output files' stem."),
    out: Path = typer.Option(Path("."), "--out", "-o", help="Folder for NAME.json, NAME.npy and NAME-maps.png."),
    maps: bool = typer.Option(True, "--maps/--no-maps",
                              help="Draw the maps beside the named schemes (paper Figs 16-17)."),
    json_out: bool = typer.Option(False, "--json", help="Print the design document as JSON."),
):
    """Design a binary quad subdivision mask: given support and symmetry, sum rules, least artifact over a region,
    exact zeros where asked, smoothness proven. Writes NAME.json (use it as --scheme file:NAME.json), NAME.npy and
    the maps."""
    from ..errors import check_option
    from ..theory.design import DESIGN_STAGES, design

    check_option("--continuity", continuity.upper(), _CLASSES)
    stage_name = stage.replace("-", "_")
    if stage_name not in DESIGN_STAGES:
        check_option("--stage", stage, ("limit", "one-step"))
    stem_name = name.strip()
    if not stem_name or any(c in stem_name for c in "/\\") or stem_name.startswith("."):
        raise OptionError("--name", "a plain file stem (no folders)", name)
    result = design(support=_support(support), symmetry=symmetry, degree=degree, objective=objective,
                    stage=stage_name, region=region, zeros=[_zero(z) for z in (zero or [])],
                    continuity=int(continuity.upper()[1]), attenuation_weight=attenuation_weight,
                    attenuation_band=attenuation_band, min_signal=min_signal, normalisation=normalisation,
                    name=stem_name)
    js, npy = result.save(out / stem_name)
    picture = None
    if maps:
        from ..theory.catalogue import SCHEME_NAMES, scheme
        from ..viz.maps import plot_maps

        named = [scheme(n) for n in SCHEME_NAMES]
        picture = plot_maps([*named, result.scheme], out / f"{stem_name}-maps.png", stage=result.spec.stage,
                            resolution=201)
    if json_out:
        import json

        doc = result.as_dict()
        doc["files"] = {"json": str(js), "npy": str(npy), "maps": None if picture is None else str(picture)}
        typer.echo(json.dumps(doc, indent=2, allow_nan=False))
        return
    _print(result, js, npy, picture)


def _print(result, js, npy, picture):
    import numpy as np
    from rich.table import Table

    con = _console()
    spec = result.spec
    con.print(f"designed {result.scheme.name}: {spec.support[0]}x{spec.support[1]} mask, {spec.symmetry} symmetry, "
              f"degree {spec.degree}, {spec.objective} at the {spec.stage.replace('_', '-')} stage over "
              f"|w| <= {spec.region:g} ({result.seconds:.1f} s)")
    con.print(f"mask x 64:\n{np.array2string(np.asarray(result.mask) * 64, precision=4, suppress_small=True)}")
    p = result.proof
    con.print(f"proof: {p.as_dict()['proven']} (difference contraction {p.contraction:.4f} in {p.contraction_steps} "
              f"step(s); Sobolev exponent >= {p.sobolev:.4f}, Holder >= {p.holder:.4f})")
    for (wx, wy), v in zip(spec.zeros, result.zeros):
        con.print(f"artifact at ({wx:g}, {wy:g}): {v:.3g}")
    con.print(f"signal response >= {result.min_signal:.4g} on |w| <= {spec.attenuation_band:g} (bound "
              f"{spec.min_signal:g}); generation degree {result.scheme.generation_degree}")
    share = " / signal" if spec.normalisation == "signal" else ""
    table = Table(title=f"RMS {spec.objective} artifact{share} over |w| <= {spec.region:g}", header_style="bold")
    for col in ("scheme", "artifact RMS", "objective"):
        table.add_column(col)
    rows = [(result.scheme.name, result.artifact, result.objective)] + [
        (k, v[1], v[0]) for k, v in result.references.items()]
    for n, a, j in sorted(rows, key=lambda r: r[2]):
        table.add_row(n, f"{a:.6g}", f"{j:.6g}")
    con.print(table)
    con.print(f"wrote {js}, {npy}" + (f", {picture}" if picture is not None else ""))
    con.print(f"use it: --scheme file:{js}")
