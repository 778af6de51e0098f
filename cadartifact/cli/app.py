"""The ``cadartifact`` command line: a thin typer layer over the library.

Exit codes: 0 success (or every face within tolerance), 1 some face needs work
(advise / gate), 2 usage or input error. Errors are one line on stderr, never a
traceback.
"""

from __future__ import annotations

import functools
import os
import sys
from enum import Enum
from pathlib import Path
from typing import List, Optional

import warnings

import typer
from typer.core import TyperGroup

from .usage import UsageError, quiet_warnings, usage_message  # noqa: F401  (re-exported)
from ..errors import CadArtifactError, InputError, OptionError, check_option


class _OneLineUsageErrors(TyperGroup):
    """The command group: usage errors (bad type, unknown option, missing value) are one line and exit 2."""

    def make_context(self, *args, **kwargs):
        try:
            return super().make_context(*args, **kwargs)
        except UsageError as exc:
            raise _usage_exit(exc) from None

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except UsageError as exc:
            raise _usage_exit(exc) from None


def _usage_exit(exc: UsageError):
    if type(exc).__name__ == "NoArgsIsHelpError":
        if getattr(exc, "ctx", None) is not None and exc.ctx.parent is None:
            # a bare ``cadartifact``: the help is what was asked for (stdout, exit 0)
            typer.echo(exc.ctx.get_help())
            return typer.Exit(0)
        return exc  # typer prints a subcommand's help for these
    return fail(usage_message(exc), exc.exit_code)


app = typer.Typer(
    cls=_OneLineUsageErrors,
    name="cadartifact",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # plain click help: it reflows hard-wrapped docstrings, never truncates option names at 80 columns and
    # shows text such as [tool.cadartifact] or the JSON schema's [...] as written (rich markup would eat them)
    rich_markup_mode=None,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _version(value: bool):
    if value:
        from .. import __version__

        typer.echo(f"cadartifact {__version__}")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", "-V", callback=_version, is_eager=True,
                                 help="Print the version and exit."),
):
    """Measure control-net artifacts (ripples) in NURBS and subdivision surfaces and advise control-point density.

    Run 'cadartifact COMMAND -h' for a command's options; 'cadartifact demo' runs the advisor on the bundled
    samples.
    """


def _console(stderr: bool = False):
    from rich.console import Console

    con = Console(stderr=stderr, highlight=False)
    if not con.is_terminal and not stderr and not os.environ.get("COLUMNS"):
        con = Console(stderr=stderr, highlight=False, width=120)  # logs and pipes: do not squeeze tables to 80
    return con


def fail(message: str, code: int = 2) -> "typer.Exit":
    """Print a one-line error to stderr and return the Exit to raise."""
    from rich.markup import escape

    # escaped: messages quote user text and names like [tool.cadartifact] that rich would eat as markup
    from ..errors import one_line

    _console(stderr=True).print(f"[bold red]cadartifact: error:[/] {escape(one_line(message))}", soft_wrap=True)
    return typer.Exit(code)


def cli_errors(func=None, *, aliases: Optional[dict] = None):
    """Turn :class:`CadArtifactError` into a one-line message and its exit code.

    An :class:`OptionError` about a library parameter is reported under the command's option:
    ``scheme`` becomes ``--scheme`` when the command has that option; ``aliases`` maps library
    names that differ from the command's parameter names (``{"tolerance": "tol"}``).
    """
    if func is None:
        return functools.partial(cli_errors, aliases=aliases)
    import inspect

    options = {}
    for name, par in inspect.signature(func).parameters.items():
        decls = [d for d in (getattr(par.default, "param_decls", None) or ()) if d.startswith("--")]
        if decls:
            options[name] = max(decls, key=len).split("/")[0]
    renames = {**options, **{lib: options[name] for lib, name in (aliases or {}).items()}}

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        try:
            return func(*args, **kwargs)
        except CadArtifactError as exc:
            if isinstance(exc, OptionError) and exc.parameter in renames:  # name the option, not the library's name
                exc = OptionError(renames[exc.parameter], exc.expected, exc.received)
            raise fail(str(exc), exc.exit_code) from None
        except (typer.Exit, typer.Abort, UsageError, KeyboardInterrupt):
            raise
        except Exception as exc:  # noqa: BLE001 - no traceback and no exit 1 ("exceeds tolerance") for a failure
            raise fail(f"unexpected failure ({type(exc).__name__}: {exc}); please report it with the input", 2) \
                from None

    return wrapper


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
    """List the scheme catalogue: arrows, mask size, interpolation, reproduction degree."""
    from ..theory.catalogue import scheme, schemes

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


@app.command("maps", short_help="Response maps over the frequency square (paper Figs 8, 10-17).")
@cli_errors(aliases={"schemes": "scheme", "out suffix": "out"})
def maps_cmd(
    scheme: Optional[List[str]] = typer.Option(None, "--scheme", "-s",
                                               help="Scheme name; repeat to compare (default: bicubic; "
                                                    "not with --grid, whose schemes are the paper's)."),
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
    _console().print(f"wrote {path}")


# ---------------------------------------------------------------- advise & demo (the main job)
def _write_json(doc: dict) -> None:
    import json

    typer.echo(json.dumps(doc, indent=2, allow_nan=False))


@app.command("advise", short_help="Advise the control-point density per face for a tolerance.")
@cli_errors(aliases={"tolerance": "tol", "faces": "face"})
def advise_cmd(
    files: List[Path] = typer.Argument(..., help="STEP/IGES/BREP/OBJ files.", show_default=False),
    tol: float = typer.Option(..., "--tol", "-t", help="Tolerance in model units (mm for STEP)."),
    metric: str = typer.Option("peak", "--metric", help="Compare the peak or the RMS ripple: peak or rms."),
    scheme: Optional[str] = typer.Option(None, "--scheme", "-s",
                                         help="Scheme (default: each face's own B-spline degrees; Catmull-Clark for OBJ)."),
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
                                    help="With --write-resampled: write only the advised faces, untrimmed."),
    json_out: bool = typer.Option(False, "--json", help="Print one JSON document (schema: cadartifact.runs.records)."),
    report: Optional[Path] = typer.Option(None, "--report",
                                          help="Also write a self-contained HTML report (tables, heatmaps, maps)."),
    compare: Optional[bool] = typer.Option(None, "--compare/--no-compare",
                                           help="Also advise the other named schemes (default: nets up to 2000 points)."),
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
    from ..analysis.budget import METRICS
    from ..runs.advising import advise_files
    from ..runs.terminal import render

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
    err = _console(stderr=True)
    with _progress(err, "advised", len(files)) as progress:
        doc = advise_files(files, tol, scheme=scheme, metric=metric, include_signal_error=include_signal_error,
                           faces=set(face) if face else None, compare="auto" if compare is None else compare,
                           verify=verify, progress=progress,
                           keep=keep, convert=convert, intent=intent)
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
            _console().print(f"wrote {report}", soft_wrap=True)
    all_ok = all(f["meets_tolerance"] for fl in doc["files"] for f in fl["faces"])
    raise typer.Exit(0 if all_ok else 1)


def _print_written(written: dict, units: str) -> None:
    """One line per written file and per replaced face (its distance to the old surface)."""
    con = _console()
    for f in written["files"]:
        if f["mode"] == "model":
            kept = f" ({len(f['kept'])} advised face(s) kept as they were: advice = today's net)" if f["kept"] else ""
            con.print(f"wrote {f['path']}: the model of {f['source']} with {len(f['faces'])} face(s) "
                      f"replaced{kept}", soft_wrap=True)
        else:
            why = " (an OBJ cage has no B-rep to keep)" if f["source"].lower().endswith(".obj") else ""
            con.print(f"wrote {len(f['faces'])} resampled face(s) only to {f['path']}{why}", soft_wrap=True)
        for r in f["faces"]:
            if r["max_distance"] is None:
                continue
            label = str(r["face"]) + (f" ({r['name']})" if r["name"] else "")
            edges = "" if r["edge_tolerance"] is None else f"; edge tolerance {r['edge_tolerance']:.3g} {units}"
            con.print(f"  face {label}: max {r['max_distance']:.4g} {units}, mean {r['mean_distance']:.4g} {units} "
                      f"from the old surface (same u, v){edges}; "
                      + ("valid" if r["valid"] else "[red]BRepCheck: invalid[/]"), soft_wrap=True)
        if f.get("valid") is False:
            con.print("  [red]BRepCheck rejects the written model[/] (see the JSON 'written')", soft_wrap=True)


def _progress(err, verb: str, total: int):
    """A progress bar on a terminal, else (logs, pipes) one line per file on stderr."""
    from ..runs.terminal import LineProgress, RichProgress

    return RichProgress(err) if err.is_terminal else LineProgress(err, verb, total)


def advise_inputs(files) -> list:
    """The files to advise: a folder stands for its STEP/IGES/BREP/OBJ files (recursively, as ``gate``)."""
    from ..gate.policy import CAD_SUFFIXES, expand_paths

    out = []
    for f in files:
        if Path(f).is_dir():
            found = expand_paths([f]) if any(Path(f).rglob("*")) else []
            found = [p for p in found if p.suffix.lower() in CAD_SUFFIXES]
            if not found:
                raise InputError(f, "folder holds no STEP/IGES/BREP/OBJ file")
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
    """Run the advisor on the bundled samples (samples/*.step, samples/*.obj) and explain what it found."""
    from ..runs.advising import advise_files
    from ..runs.terminal import render

    folder = _samples_dir()
    files = sorted(p for p in folder.iterdir() if p.suffix.lower() in (".step", ".stp", ".obj"))
    err = _console(stderr=True)
    with _progress(err, "advised", len(files)) as progress:
        doc = advise_files(files, tol, progress=progress)
    if json_out:
        _write_json(doc)
        return
    con = _console()
    con.print(f"[bold]cadartifact demo[/]: {len(files)} sample file(s) from {folder}, tolerance {tol:g} mm\n")
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


# ---------------------------------------------------------------- gate (CI quality gate)
@app.command("gate", short_help="CI quality gate: pass / warn / fail per face, reports.")
@cli_errors
def gate_cmd(
    paths: List[str] = typer.Argument(..., help="STEP/IGES/BREP/OBJ files, folders (recursive) or globs.",
                                      show_default=False),
    tol: Optional[float] = typer.Option(None, "--tol", "-t", help="Tolerance in model units (overrides the policy)."),
    policy: Optional[Path] = typer.Option(None, "--policy",
                                          help="Policy TOML (default: cadartifact.toml or [tool.cadartifact] in "
                                               "pyproject.toml, looked up from here upward)."),
    fmt: str = typer.Option("text", "--format", "-f", help="Report format: text, json, junit or sarif."),
    output: Optional[Path] = typer.Option(None, "--output", "-o", help="Write the report to this file (atomically)."),
    report: Optional[Path] = typer.Option(None, "--report", help="Also write a self-contained HTML report."),
    jobs: Optional[int] = typer.Option(None, "--jobs", "-j", help="Worker processes (default: CPU count)."),
    metric: Optional[str] = typer.Option(None, "--metric", help="peak or rms (overrides the policy)."),
    warn_fraction: Optional[float] = typer.Option(None, "--warn-fraction",
                                                  help="Warn at this fraction of the tolerance (0 < f <= 1; "
                                                       "default 0.8)."),
    scheme: Optional[str] = typer.Option(None, "--scheme", "-s", help="Scheme (overrides the policy)."),
    intent: Optional[str] = typer.Option(None, "--intent",
                                         help="Design intent: surface or net (overrides the policy)."),
    verify: bool = typer.Option(False, "--verify/--no-verify",
                                help="Verify the advised net of failing faces on the real surface (slower)."),
    advise: Optional[str] = typer.Option(None, "--advise",
                                         help="Density advice for: failing (faces that warn or fail; default), all "
                                              "or none. The verdict needs today's budget only (policy: advise)."),
    convert: Optional[bool] = typer.Option(None, "--convert/--no-convert",
                                           help="Convert revolution/extrusion/offset faces to B-splines and gate "
                                                "them (overrides the policy's convert; default: skip them)."),
    wide: Optional[bool] = typer.Option(None, "--wide/--narrow",
                                        help="Every column in the text report (default: at 110 columns or more)."),
    read_timeout: Optional[float] = typer.Option(None, "--read-timeout",
                                                 help="Seconds OCCT's reader may take on one file (default 120 or "
                                                      "$CADARTIFACT_READ_TIMEOUT); a file past it is an error."),
    cache: Optional[Path] = typer.Option(None, "--cache",
                                         help="Keep results in this folder, keyed by file content, policy and "
                                              "version: unchanged files are not analysed again (policy: cache)."),
    scheduler: Optional[str] = typer.Option(None, "--scheduler",
                                            help="Run on a Dask cluster: a scheduler address (tcp://host:8786) or "
                                                 "'local' (a LocalCluster of --jobs workers). Needs "
                                                 "cadartifact[dask]."),
    ship: bool = typer.Option(False, "--ship", help="With --scheduler: send the files' bytes to the workers (no "
                                                    "shared storage)."),
    scheduler_timeout: float = typer.Option(10.0, "--scheduler-timeout",
                                            help="Seconds to wait for the scheduler."),
):
    """Quality gate for CI: pass / warn / fail per face against a tolerance policy.

    Exit 0 when every face passes (warnings allowed), 1 when a face fails, 2 on usage errors or unreadable files.

    An unreadable file is reported as an error and the other files are still analysed (fail closed).

    Policy: cadartifact.toml or [tool.cadartifact] in pyproject.toml (see cadartifact.gate.policy).
    """
    import importlib.util
    import os

    from ..gate.run import build_document, run_gate
    from ..gate.policy import base_settings, check_cli, expand_paths, find_policy, load_policy
    from ..gate.reports import FORMATS, render_text, summary_line, to_json, to_junit, to_sarif, to_text, write_atomic
    from ..runs.terminal import LineProgress
    from ..runs.records import plural

    check_option("--format", fmt, FORMATS)
    if jobs is not None and jobs < 1:
        raise OptionError("--jobs", "a number of processes >= 1", jobs)
    if read_timeout is not None and not (0 < read_timeout < float("inf")):
        raise OptionError("--read-timeout", "a positive number of seconds", read_timeout)
    cli = check_cli({"tolerance": tol, "metric": metric, "warn_fraction": warn_fraction, "scheme": scheme,
                     "intent": intent, "convert": convert, "advise": advise})
    pol = load_policy(policy) if policy is not None else find_policy()
    files = expand_paths(paths)
    settings = [pol.settings_for(f, cli) for f in files]  # every usage error before any analysis
    for option, target in (("--output", output), ("--report", report)):
        if target is not None and not (target.parent if str(target.parent) else Path(".")).is_dir():
            raise OptionError(option, "a file in an existing folder", str(target))
    if report is not None and importlib.util.find_spec("cadartifact.viz.html") is None:
        raise OptionError("--report", "the HTML report (cadartifact.viz.html), which is not available in this "
                                      "installation", str(report))

    workers = jobs or os.cpu_count() or 1
    cluster = result_cache = None
    if scheduler is not None:
        from ..gate.cluster import ClusterOptions, require_distributed

        cluster = ClusterOptions(scheduler.strip(), workers=workers, ship=ship, timeout=scheduler_timeout)
        require_distributed()  # a missing extra is a usage error before any work
    elif ship:
        raise OptionError("--ship", "--scheduler too (files are shipped to Dask workers)", "--ship alone")
    cache = cache if cache is not None else pol.cache
    if cache is not None:
        from ..gate.cache import GateCache

        result_cache = GateCache(cache)

    from ..gate.progress import GateProgress

    with GateProgress(_console(stderr=True), len(files)) as progress:
        entries = run_gate(files, settings, jobs=workers, verify=verify, progress=progress, cache=result_cache,
                           cluster=cluster, read_timeout=read_timeout)
    doc = build_document(entries, base_settings(pol, cli), pol)

    if fmt == "text" and output is None:
        con = _console()
        if not con.is_terminal and not os.environ.get("COLUMNS"):  # CI logs: the whole table, unfolded
            con.width = max(con.width, 132)
        render_text(doc, con, wide=wide)
    else:
        text = {"text": to_text, "json": to_json, "junit": to_junit, "sarif": to_sarif}[fmt](doc)
        if output is None:
            typer.echo(text, nl=False)
        else:
            write_atomic(output, text)
            _console().print(summary_line(doc) + f"; {fmt} report written to {output}", soft_wrap=True)
    if report is not None:
        from ..viz.html import write_report

        write_report(doc, report)
    raise typer.Exit(doc["exit_code"])


# ---------------------------------------------------------------- inspect (exchange: what a file holds)
@app.command("inspect", short_help="List the control nets in CAD and mesh files.")
@cli_errors
def inspect_cmd(
    files: List[Path] = typer.Argument(..., help="STEP/IGES/BREP/OBJ files.", show_default=False),
    json_out: bool = typer.Option(False, "--json", help="Print one JSON document (schema below) instead of tables."),
    convert: bool = typer.Option(False, "--convert",
                                 help="Convert revolution/extrusion/offset faces to B-splines instead of skipping them."),
):
    """List the control nets in CAD and mesh files: one row per analysable face (or OBJ chart).

    Columns: face index, kind, degrees, net size, rational / weights vary, periodic, knots uniform,
    kept area (the share of the knot range the face's UV bounds keep: 1.000 untrimmed) and name; then a
    summary line (faces total, analysable, skipped by kind). A file with no analysable face prints a warning
    and exits 0. If any file cannot be read, every error is printed (one line each), nothing else
    is printed (no partial tables or JSON) and the exit code is 2.

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

    from ..exchange.load import SUPPORTED_EXTENSIONS, LoadWarning, read
    from ..exchange.summary import result_summary
    from ..runs.records import kind_count, plural

    summaries, errors = [], []
    for path in files:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", LoadWarning)  # they are in result.warnings, shown below
                result = read(path, convert=convert)
        except CadArtifactError as exc:
            errors.append(exc)
            continue
        summaries.append(result_summary(result, SUPPORTED_EXTENSIONS[Path(path).suffix.lower()]))
    if errors:  # fail closed: no partial output
        for exc in errors[:-1]:
            fail(str(exc), exc.exit_code)
        raise fail(str(errors[-1]), errors[-1].exit_code)

    if json_out:
        typer.echo(json.dumps({"schema": "cadartifact.inspect/1", "files": summaries}, indent=2))
        return
    from rich.table import Table

    con = _console()
    if not con.is_terminal:
        con.width = max(con.width, 132)
    yes = {True: "yes", False: "no"}
    for doc in summaries:
        table = Table(title=doc["path"], header_style="bold", title_justify="left")
        for col in ("face", "kind", "degrees", "net", "rational", "weights vary", "periodic u,v",
                    "uniform knots u,v", "kept area", "name"):
            table.add_column(col)
        for f in doc["faces"]:
            frac = f["trimmed_fraction"]
            table.add_row(
                str(f["face"]), f["kind"], "x".join(map(str, f["degrees"])) if f["degrees"] else "cage",
                "x".join(map(str, f["size"])), yes[f["rational"]], yes[f["weights_vary"]],
                ",".join(yes[x] for x in f["periodic"]), ",".join(yes[x] for x in f["knots_uniform"]),
                "-" if frac is None else f"{frac:.3f}", f["name"] or "")
        if doc["faces"]:
            con.print(table)
        skipped = ", ".join(kind_count(k, n) for k, n in doc["skipped"].items()) or "none"
        con.print(f"{doc['path']}: {plural(doc['faces_total'], 'face')}, {doc['analysable']} analysable, "
                  f"skipped: {skipped}", soft_wrap=True)
        mesh = doc["mesh"]
        if mesh is not None:
            counts = ((mesh["vertices"], "vertex", "vertices"), (mesh["quads"], "quad", "quads"),
                      (mesh["triangles"], "triangle", "triangles"), (mesh["ngons"], "n-gon", "n-gons"),
                      (len(mesh["extraordinary"]), "extraordinary vertex", "extraordinary vertices"),
                      (mesh["crease_edges"], "crease edge", "crease edges"))
            con.print("  mesh: " + ", ".join(f"{n} {one if n == 1 else many}" for n, one, many in counts)
                      + f", {plural(mesh['regular_faces'], 'regular face')} in {plural(len(mesh['charts']), 'chart')}",
                      soft_wrap=True)
        for w in doc["warnings"]:
            _console(stderr=True).print(f"[yellow]warning:[/] {w}", soft_wrap=True)


# ---------------------------------------------------------------- view (3-D heatmaps)
@app.command("view", short_help="3-D heatmap of each face's ripple (PNG, GLB).")
@cli_errors(aliases={"window_size": "size", "faces": "face"})
def view_cmd(
    file: Path = typer.Argument(..., help="STEP/IGES/BREP/OBJ file.", show_default=False),
    direction: str = typer.Option("total", "--direction", "-d",
                                  help="Field to colour: total, x1, x2, diagonal, lateral, signal_error or deviation."),
    tol: Optional[float] = typer.Option(None, "--tol", "-t", help="Colour scale 0..tol in model units, red beyond."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="PNG to write (default: <file stem>_<direction>.png)."),
    glb: Optional[Path] = typer.Option(None, "--glb", help="Also write the coloured faces as a .glb mesh."),
    face: Optional[List[int]] = typer.Option(None, "--face", help="Only this face index (repeatable)."),
    scheme: Optional[str] = typer.Option(None, "--scheme", "-s", help="Scheme (default: each face's own degrees)."),
    size: str = typer.Option("1200x900", "--size", help="Picture size WIDTHxHEIGHT in pixels."),
    layout: str = typer.Option("auto", "--layout", help="auto, model (faces in place) or tiles (one view per face)."),
):
    """Render each face coloured by its ripple (off screen) with the control net on top; optionally export glb."""
    from ..dependencies import require
    from ..viz.view import view

    try:
        width, height = (int(x) for x in size.lower().split("x"))
    except ValueError:
        raise OptionError("--size", "WIDTHxHEIGHT in pixels, e.g. 1200x900", size) from None
    require("pyvista", "3-D heatmaps").OFF_SCREEN = True  # this process never opens a window
    err = _console(stderr=True)
    if err.is_terminal:
        status = err.status(f"reading {file}")
        say = lambda message: status.update(message)  # noqa: E731
    else:  # logs and pipes: one plain line per stage
        import contextlib

        status = contextlib.nullcontext()
        say = lambda message: err.print(f"cadartifact: {message}", markup=False, highlight=False,  # noqa: E731
                                        soft_wrap=True)
    with status:
        res = view(file, direction=direction, tol=tol, out=out, glb=glb, faces=face, scheme=scheme,
                   window_size=(width, height), layout=layout, progress=say)  # cli_errors names the options
    con = _console()
    from ..runs.records import plural, unit_name

    con.print(f"wrote {res.png} ({plural(len(res.faces), 'face')}, {res.direction} peak {res.peak:.4g} "
              f"{unit_name(getattr(res, 'unit', None) or _unit_of(file))})", soft_wrap=True)
    if res.glb is not None:
        con.print(f"wrote {res.glb}", soft_wrap=True)


def _unit_of(path) -> str:
    """``"mm"`` for the B-rep formats (OCCT reads them in mm), ``"model"`` for OBJ cages."""
    return "model" if Path(path).suffix.lower() == ".obj" else "mm"


def run():
    """Run the command line on ``sys.argv`` (:func:`cadartifact.cli.main` starts the reader child first)."""
    quiet_warnings()
    from ..exchange.messages import LoadWarning

    # the reader's warnings are part of every report (tables, JSON); do not echo them with source lines
    warnings.filterwarnings("ignore", category=LoadWarning)
    for stream in (sys.stdout, sys.stderr):  # file names that are not UTF-8 print as \udcff instead of failing
        try:
            stream.reconfigure(errors="backslashreplace")
        except (AttributeError, ValueError):
            pass
    try:
        app()
    except KeyboardInterrupt:
        sys.exit(130)

