"""``cadartifact advise`` and ``cadartifact demo``: the main job, the control-point density per face for a
tolerance (on the user's files, or on the bundled samples)."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from .root import _console, app, cli_errors, fail
from .usage import escape
from ..errors import CadArtifactError, InputError, check_option
from ..exchange import formats


# ---------------------------------------------------------------- advise & demo (the main job)
def _write_json(doc: dict) -> None:
    import json

    typer.echo(json.dumps(doc, indent=2, allow_nan=False))


@app.command("advise", short_help="Advise the control-point density per face for a tolerance.")
@cli_errors(aliases={"tolerance": "tol", "faces": "face"})
def advise_cmd(
    files: List[Path] = typer.Argument(..., help=f"{formats.labels()} files.", show_default=False),
    tol: float = typer.Option(..., "--tol", "-t", help="Tolerance in model units (mm for STEP)."),
    metric: str = typer.Option("peak", "--metric", help="Compare the peak or the RMS ripple: peak or rms."),
    scheme: Optional[str] = typer.Option(None, "--scheme", "-s",
                                         help="Scheme (default: each face's own B-spline degrees; Catmull-Clark "
                                              "for OBJ); file:MASK.json for a designed mask."),
    include_signal_error: bool = typer.Option(False, "--include-signal-error",
                                              help="Let the tolerance cover the whole deviation from intent."),
    intent: str = typer.Option("surface", "--intent",
                               help="Design intent: surface (the surface less its ripple) or net (the shape the "
                                    "control points sample)."),
    face: Optional[List[int]] = typer.Option(None, "--face", help="Only this face index (repeatable)."),
    write_resampled: Optional[Path] = typer.Option(
        None, "--write-resampled",
        help="Write the model to this .step/.stp file with each face whose advice changes its net replaced by "
             "the advised surface (trims, names, other faces and units kept). Several input files: one "
             "OUT_<input stem>.step each."),
    faces_only: bool = typer.Option(False, "--faces-only",
                                    help="With --write-resampled: write only the advised faces, untrimmed "
                                         "(a face whose advice finds no net that conforms is not written)."),
    json_out: bool = typer.Option(False, "--json", help="Print one JSON document (schema: cadartifact.runs.records)."),
    report: Optional[Path] = typer.Option(None, "--report",
                                          help="Also write a self-contained HTML report (tables, heatmaps, maps)."),
    compare: Optional[bool] = typer.Option(None, "--compare/--no-compare",
                                           help="Also advise the other named schemes (default: for OBJ cages and an explicit --scheme, "
                                                "nets up to 2000 points; off for B-rep faces)."),
    verify: bool = typer.Option(True, "--verify/--no-verify", help="Verify each advice on the real surface (OCCT)."),
    convert: bool = typer.Option(False, "--convert",
                                 help="Convert revolution/extrusion/offset faces to B-splines instead of skipping them."),
    wide: Optional[bool] = typer.Option(None, "--wide/--narrow",
                                        help="Every direction column (default: when the terminal has 110 columns)."),
):
    """Advise the control-point density that keeps each face's ripple within the tolerance.

    Exit 0 when every face meets the tolerance today, 1 when some face needs another density,
    2 on usage or input errors.
    """
    from ..analysis.settings import METRICS
    from ..runs.advising import advise_files
    from ..runs.terminal import render
    from .environment import execution_settings

    check_option("--metric", metric, METRICS)
    check_option("--intent", intent, ("surface", "net"))
    if not (tol > 0) or tol != tol or tol == float("inf"):
        raise fail(f"--tol: expected a positive number of model units, received {tol!r}")
    if scheme is not None:
        from ..theory.catalogue import scheme as get_scheme

        get_scheme(scheme)  # a bad name fails before any file is read
    if report is not None and not (report.parent if str(report.parent) else Path(".")).is_dir():
        raise fail(f"--report: expected a file in an existing folder, received {str(report)!r}")
    if write_resampled is not None:  # a bad output is a usage error before any work
        from ..exchange.model_writer import check_step_output

        check_step_output(write_resampled, "--write-resampled")
    elif faces_only:
        raise fail("--faces-only: expected together with --write-resampled, received it alone")
    keep = [] if write_resampled else None
    files = advise_inputs(files)
    if write_resampled is not None:  # never over an input, whatever the spelling: before any work
        from ..runs.advising import check_not_an_input

        check_not_an_input(files, write_resampled)
    err = _console(stderr=True)
    with _progress(err, "advised", len(files)) as progress:
        doc = advise_files(files, tol, scheme=scheme, metric=metric, include_signal_error=include_signal_error,
                           faces=set(face) if face else None, compare="auto" if compare is None else compare,
                           verify=verify, progress=progress,
                           keep=keep, convert=convert, intent=intent, execution=execution_settings())
    if write_resampled is not None and keep:
        from .. import __version__
        from ..runs.advising import write_advised

        provenance = {"tool": "cadartifact advise", "version": __version__, "tolerance": float(tol),
                      "units": str(doc.get("units") or "mm"), "metric": metric,
                      "intent": str(doc.get("intent", "net")),
                      "include_signal_error": str(bool(include_signal_error)).lower()}
        doc["written"] = write_advised(keep, write_resampled, faces_only=faces_only, provenance=provenance)
    if json_out:
        _write_json(doc)
    else:
        render(doc, _console(), wide=wide)
        if doc.get("written"):
            _print_written(doc["written"], doc.get("units") or "mm")
    if report is not None:
        from ..viz.html import write_report

        write_report(doc, report)
        if not json_out:
            _console().print(f"wrote {escape(report)}", soft_wrap=True)
    raise typer.Exit(doc["exit_code"])  # the document's own: one source of truth (runs.advising.exit_code)


def _print_written(written: dict, units: str) -> None:
    """One line per written file, per replaced face (its distance to the old face, edge tolerance before and
    after, BRepCheck) and per refused face (why it was kept)."""
    con = _console()
    for f in written["files"]:
        if f["path"] is None:
            why = [f"{len(f['refused'])} new net(s) refused"] if f["refused"] else []
            why += [f"{len(f['kept'])} face(s) kept as they were (advice = today's net, or no net conforms)"] \
                if f["kept"] else []
            con.print(f"wrote nothing for {escape(f['source'])}: " + ("; ".join(why) or "no face advised"),
                      soft_wrap=True)
        elif f["mode"] == "model":
            kept = (f" ({len(f['kept'])} advised face(s) kept as they were: advice = today's net, or no net "
                    "conforms)") if f["kept"] else ""
            con.print(f"wrote {escape(f['path'])}: the model of {escape(f['source'])} with "
                      f"{len(f['faces'])} face(s) replaced{kept}", soft_wrap=True)
        else:
            record = formats.format_of(f["source"])
            why = "" if record.brep else f" (an {record.label} cage has no B-rep to keep)"
            kept = f" ({len(f['kept'])} advised face(s) not written: no net conforms)" if f["kept"] else ""
            con.print(f"wrote {len(f['faces'])} resampled face(s) only to {escape(f['path'])}{why}{kept}",
                      soft_wrap=True)
        for r in f["faces"]:
            if r["max_distance"] is None:
                continue
            label = str(r["face"]) + (f" ({escape(r['name'])})" if r["name"] else "")
            allowed = "" if r.get("allowed_distance") is None else f" (allowed {r['allowed_distance']:.4g})"
            edges = "" if r["edge_tolerance"] is None else (
                f"; edge tolerance {r.get('edge_tolerance_before') or 0:.3g} -> {r['edge_tolerance']:.3g} {units}")
            valid = "valid" if r["valid"] else "[red]BRepCheck: invalid[/]" + (
                " (as in the input)" if r.get("valid_before") is False else "")
            con.print(f"  face {label}: {r['max_distance']:.4g} {units} from the old face{allowed}, mean "
                      f"{r['mean_distance']:.4g} {units} (by projection, both ways){edges}; {valid}", soft_wrap=True)
        for c in f.get("surface_types", []):
            con.print(f"  face {c['face']}: a {c['before']} surface in the input, written as a {c['after']} surface "
                      "by OCCT's STEP writer", soft_wrap=True)
        for r in f.get("refused", []):
            con.print(f"  face {r['face']} kept as it was, its advised net cannot be written: {escape(r['reason'])}",
                      soft_wrap=True)
        if f.get("valid") is False:
            con.print("  [red]BRepCheck rejects the written model[/] (see the JSON 'written')", soft_wrap=True)


def _progress(err, verb: str, total: int):
    """A progress bar on a terminal, else (logs, pipes) one line per file on stderr."""
    from ..runs.terminal import LineProgress, RichProgress

    return RichProgress(err) if err.is_terminal else LineProgress(err, verb, total)


def advise_inputs(files) -> list:
    """The files to advise: a folder stands for its STEP/IGES/BREP/OBJ files (recursively, as ``gate``)."""
    from ..gate.policy import expand_paths

    out = []
    for f in files:
        if Path(f).is_dir():
            found = expand_paths([f]) if any(Path(f).rglob("*")) else []
            found = [p for p in found if p.suffix.lower() in formats.cad_suffixes()]
            if not found:
                raise InputError(f, f"folder holds no {formats.labels()} file")
            out.extend(found)
        else:
            out.append(Path(f))
    return out


def _samples_dir() -> Path:
    """The samples shipped inside the package (``cadartifact/samples``, package data), else the checkout's."""
    from importlib.resources import files

    try:
        bundled = Path(str(files("cadartifact") / "samples"))
    except (ModuleNotFoundError, TypeError):  # pragma: no cover - a zipped or odd install
        bundled = None
    for cand in (bundled, Path(__file__).resolve().parent.parent / "samples"):
        if cand is not None and cand.is_dir() and any(cand.glob("*.st*p")):
            return cand
    raise CadArtifactError("cadartifact/samples: the bundled samples were not found (a broken installation? "
                           "reinstall cadartifact)")


@app.command("demo", short_help="Run the advisor on the bundled samples.")
@cli_errors(aliases={"tolerance": "tol"})
def demo_cmd(
    tol: float = typer.Option(0.05, "--tol", "-t", help="Tolerance in mm."),
    json_out: bool = typer.Option(False, "--json", help="Print the JSON document instead of tables."),
):
    """Run the advisor on the bundled samples (samples/*.step, samples/*.obj) and explain what it found.

    Exit 0 whatever the samples' faces read (a demonstration; its JSON's ``exit_code`` is what ``advise`` on the
    same files would exit with), 2 on usage errors.
    """
    from ..runs.advising import advise_files
    from ..runs.terminal import render
    from .environment import execution_settings

    folder = _samples_dir()
    files = sorted(p for p in folder.iterdir() if p.suffix.lower() in formats.suffixes())
    err = _console(stderr=True)
    with _progress(err, "advised", len(files)) as progress:
        doc = advise_files(files, tol, progress=progress, execution=execution_settings())
    if json_out:
        _write_json(doc)
        return
    con = _console()
    con.print(f"[bold]cadartifact demo[/]: {len(files)} sample file(s) from {escape(folder)}, "
              f"tolerance {tol:g} mm\n", soft_wrap=True)
    render(doc, con)
    con.print("\n" + demo_hint(doc, tol), soft_wrap=True)


def demo_hint(doc: dict, tol: float) -> str:
    """The demo's closing explanation: says how the advice was verified, for the formats present."""
    words = {"occt": "on the real OCCT surface", "subdivision": "by numerical subdivision of the cage",
             "uniform-bspline": "on the uniform B-spline surface of the net"}
    methods = {(r["advice"].get("verification") or {}).get("method") for f in doc["files"] for r in f["faces"]}
    roads = [text for key, text in words.items() if key in methods]
    how = f" (verified {' and '.join(roads)})" if roads else ""
    return ("Each cell is that direction's ripple in model units and as a share of the tolerance; 'advised' is the "
            "net with the fewest control points whose best fit of the design intent stays within it"
            f"{how}. Try: cadartifact advise FILE --tol {tol:g} --json")
