"""``cadartifact inspect`` and ``cadartifact view``: what a file holds (its control nets), and a 3-D heatmap of
each face's ripple."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from .root import _console, app, cli_errors, fail
from .usage import escape
from ..errors import CadArtifactError, OptionError
from ..exchange import formats


# ---------------------------------------------------------------- inspect (exchange: what a file holds)
@app.command("inspect", short_help="List the control nets in CAD and mesh files.")
@cli_errors
def inspect_cmd(
    files: List[Path] = typer.Argument(..., help=f"{formats.labels()} files.", show_default=False),
    json_out: bool = typer.Option(False, "--json", help="Print one JSON document (schema below) instead of tables."),
    convert: bool = typer.Option(False, "--convert",
                                 help="Convert revolution/extrusion/offset faces to B-splines instead of skipping them."),
):
    """List the control nets in CAD and mesh files: one row per analysable face (or OBJ chart).

    Columns: face index, kind, degrees, net size, rational / weights vary, periodic, knots uniform,
    kept area (the share of the knot range the face's UV bounds keep: 1.000 untrimmed) and name; then a
    summary line (faces total, analysable, skipped by kind). A file with no analysable face prints a warning
    and exits 0. If any file cannot be read, the other files' tables are printed, then every error (one line
    each, on stderr), and the exit code is 2; with --json nothing but the errors (no partial document).

    JSON schema (--json):

    \b
        {"schema": "cadartifact.inspect/1",
         "files": [{"path": str, "format": "step"|"iges"|"brep"|"obj",
                    "faces_total": int, "analysable": int, "skipped": {kind: int}, "warnings": [str],
                    "faces": [{"face": int, "name": str|null, "kind": str, "degrees": [int, int]|null,
                               "size": [nu, nv], "rational": bool, "weights_vary": bool,
                               "periodic": [bool, bool], "knots_uniform": [bool, bool],
                               "trimmed_fraction": float|null (the kept area)}],
                    "mesh": null | {"vertices": int, "quads": int, "triangles": int, "ngons": int,
                                    "regular_faces": int, "extraordinary": [vertex ids, 0-based],
                                    "crease_edges": int,
                                    "charts": [{"chart": int, "size": [nu, nv], "faces": [mesh face ids]}]}}]}
    """
    import json
    import warnings

    from ..exchange.load import LoadWarning, read
    from ..exchange.summary import result_summary

    summaries, errors = [], []
    for path in files:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", LoadWarning)  # they are in result.warnings, shown below
                result = read(path, convert=convert)
        except CadArtifactError as exc:
            errors.append(exc)
            continue
        summaries.append(result_summary(result, formats.format_of(path).name))
    if errors and json_out:  # fail closed: no partial JSON document for a pipeline to take as whole
        for exc in errors[:-1]:
            fail(str(exc), exc.exit_code)
        raise fail(str(errors[-1]), errors[-1].exit_code)

    if json_out:
        typer.echo(json.dumps({"schema": "cadartifact.inspect/1", "files": summaries}, indent=2))
        return
    _inspect_tables(summaries)
    if errors:  # the readable files' tables are shown; the run still fails (exit 2)
        for exc in errors[:-1]:
            fail(str(exc), exc.exit_code)
        raise fail(str(errors[-1]), errors[-1].exit_code)


def _inspect_tables(summaries: list) -> None:
    """``inspect``'s text: per file its table of faces, a summary line, its mesh and its warnings."""
    from ..runs.records import kind_count, plural
    from ..runs.terminal import print_table
    from rich.table import Table

    con = _console()
    if not con.is_terminal:
        con.width = max(con.width, 132)
    yes = {True: "yes", False: "no"}
    for doc in summaries:
        table = Table(header_style="bold")
        for col in ("face", "kind", "degrees", "net", "rational", "weights vary", "periodic u,v",
                    "uniform knots u,v", "kept area", "name"):
            table.add_column(col)
        for f in doc["faces"]:
            frac = f["trimmed_fraction"]
            table.add_row(
                str(f["face"]), f["kind"], "x".join(map(str, f["degrees"])) if f["degrees"] else "cage",
                "x".join(map(str, f["size"])), yes[f["rational"]], yes[f["weights_vary"]],
                ",".join(yes[x] for x in f["periodic"]), ",".join(yes[x] for x in f["knots_uniform"]),
                "-" if frac is None else f"{frac:.3f}", escape(f["name"] or ""))
        if doc["faces"]:
            print_table(con, table, escape(doc["path"]), keep=[doc["path"]])
        skipped = ", ".join(kind_count(k, n) for k, n in doc["skipped"].items()) or "none"
        con.print(f"{escape(doc['path'])}: {plural(doc['faces_total'], 'face')}, {doc['analysable']} analysable, "
                  f"skipped: {skipped}", soft_wrap=True)
        mesh = doc["mesh"]
        if mesh is not None:
            counts = ((mesh["vertices"], "vertex", "vertices"), (mesh["quads"], "quad", "quads"),
                      (mesh["triangles"], "triangle", "triangles"), (mesh["ngons"], "n-gon", "n-gons"),
                      (len(mesh["extraordinary"]), "extraordinary vertex", "extraordinary vertices"),
                      (mesh["crease_edges"], "crease edge", "crease edges"))
            level0 = sum(1 for c in mesh["charts"] if c.get("level", 0) == 0)
            level1 = len(mesh["charts"]) - level0
            con.print("  mesh: " + ", ".join(f"{n} {one if n == 1 else many}" for n, one, many in counts)
                      + f", {plural(mesh['regular_faces'], 'regular face')} in {plural(level0, 'chart')}"
                      + (f", {plural(level1, 'chart')} after one subdivision step (the other faces)" if level1 else ""),
                      soft_wrap=True)
        for w in doc["warnings"]:
            _console(stderr=True).print(f"[yellow]warning:[/] {escape(w)}", soft_wrap=True)


# ---------------------------------------------------------------- view (3-D heatmaps)
@app.command("view", short_help="3-D heatmap of each face's ripple (PNG, GLB).")
@cli_errors(aliases={"window_size": "size", "faces": "face"})
def view_cmd(
    file: Path = typer.Argument(..., help=f"{formats.labels()} file.", show_default=False),
    direction: str = typer.Option("total", "--direction", "-d",
                                  help="Field to colour: total, x1, x2, diagonal, lateral, signal_error or deviation."),
    tol: Optional[float] = typer.Option(None, "--tol", "-t", help="Colour scale 0..tol in model units, red beyond "
                                        "(default: the gate policy's tolerance for the file, when there is one)."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="PNG to write (default: <file stem>_<direction>.png)."),
    glb: Optional[Path] = typer.Option(None, "--glb", help="Also write the coloured faces as a .glb mesh."),
    face: Optional[List[int]] = typer.Option(None, "--face", help="Only this face index (repeatable)."),
    scheme: Optional[str] = typer.Option(None, "--scheme", "-s", help="Scheme (default: each face's own degrees)."),
    size: str = typer.Option("1200x900", "--size", help="Picture size WIDTHxHEIGHT in pixels."),
    layout: str = typer.Option("auto", "--layout", help="auto, model (faces in place) or tiles (one view per face)."),
    reflection: bool = typer.Option(False, "--reflection", help="Also write the reflection lines (zebra stripes) "
                                    "from the same camera: <png stem>_reflection.png."),
):
    """Render each face coloured by its ripple (off screen) with the control net on top; optionally export glb and
    the reflection lines."""
    from ..dependencies import require
    from ..viz.view import view

    try:
        width, height = (int(x) for x in size.lower().split("x"))
    except ValueError:
        raise OptionError("--size", "WIDTHxHEIGHT in pixels, e.g. 1200x900", size) from None
    require("pyvista", "3-D heatmaps").OFF_SCREEN = True  # this process never opens a window
    tol, tol_source = _view_tolerance(file, tol)
    err = _console(stderr=True)
    if err.is_terminal:
        status = err.status(f"reading {escape(file)}")
        say = lambda message: status.update(escape(message))  # noqa: E731
    else:  # logs and pipes: one plain line per stage
        import contextlib

        status = contextlib.nullcontext()
        say = lambda message: err.print(f"cadartifact: {message}", markup=False, highlight=False,  # noqa: E731
                                        soft_wrap=True)
    with status:
        res = view(file, direction=direction, tol=tol, out=out, glb=glb, faces=face, scheme=scheme,
                   window_size=(width, height), layout=layout, progress=say,
                   reflection=reflection)  # cli_errors names the options
    con = _console()
    from ..runs.records import plural, unit_name

    con.print(f"wrote {escape(res.png)} ({plural(len(res.faces), 'face')}, {res.direction} peak {res.peak:.4g} "
              f"{unit_name(getattr(res, 'unit', None) or _unit_of(file))})", soft_wrap=True)
    con.print(f"tolerance mark: {tol:g} ({tol_source})" if tol is not None else
              "no tolerance mark: pass --tol, or set 'tolerance' in cadartifact.toml or [tool.cadartifact] in "
              "pyproject.toml", soft_wrap=True, markup=False, highlight=False)
    if res.reflection is not None:
        con.print(f"wrote {escape(res.reflection)} (reflection lines)", soft_wrap=True)
    if res.glb is not None:
        con.print(f"wrote {escape(res.glb)}", soft_wrap=True)


def _view_tolerance(file: Path, tol: float | None) -> tuple[float | None, str]:
    """The tolerance ``view`` marks and where it comes from: ``--tol``, else the gate policy's for ``file`` (the
    policy file the gate would find from the working directory upward), else none."""
    if tol is not None:
        return tol, "--tol"
    from ..gate.policy import find_policy
    from ..gate.policy_error import PolicyError

    policy = find_policy()
    try:
        return policy.settings_for(file).tolerance, f"policy {policy.source}"
    except PolicyError:
        return None, ""


def _unit_of(path) -> str:
    """``"mm"`` for the B-rep formats (OCCT reads them in mm), ``"model"`` for OBJ cages (the format's unit)."""
    return formats.format_of(path).unit
