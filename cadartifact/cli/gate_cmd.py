"""``cadartifact gate``: the CI quality gate, pass / warn / fail per face against a tolerance policy, with
text, JSON, JUnit, SARIF and GitLab Code Quality reports, and a baseline."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from .root import _console, app, cli_errors
from .usage import escape
from ..errors import OptionError, check_option
from ..exchange import formats
from ..gate.keys import keys as setting_keys


def _option(name: str):
    """``gate``'s option of a gate setting: its names and help as its :class:`cadartifact.gate.keys.Key` declares
    them (no default here: an option not given leaves the policy's value)."""
    key = setting_keys()[name]
    return typer.Option(None, *key.option, help=key.help)


# ---------------------------------------------------------------- gate (CI quality gate)
@app.command("gate", short_help="CI quality gate: pass / warn / fail per face, reports.")
@cli_errors
def gate_cmd(
    paths: List[str] = typer.Argument(..., help=f"{formats.labels()} files, folders (recursive) or globs.",
                                      show_default=False),
    tol: Optional[float] = _option("tolerance"),
    policy: Optional[Path] = typer.Option(None, "--policy",
                                          help="Policy TOML (default: cadartifact.toml or [tool.cadartifact] in "
                                               "pyproject.toml, looked up from here upward)."),
    profile: Optional[str] = _option("profile"),
    fmt: str = typer.Option("text", "--format", "-f",
                            help="Report format: text, json, junit, sarif or gitlab (GitLab Code Quality)."),
    output: Optional[Path] = typer.Option(None, "--output", "-o", help="Write the report to this file (atomically)."),
    report: Optional[Path] = typer.Option(None, "--report", help="Also write a self-contained HTML report."),
    baseline: Optional[Path] = typer.Option(None, "--baseline",
                                            help="Compare with this baseline (or a gate JSON report): only new "
                                                 "findings and faces whose reading got worse beyond its "
                                                 "uncertainty fail; fixed ones are listed."),
    update_baseline: bool = typer.Option(False, "--update-baseline",
                                         help="Write this run's findings to the --baseline file (exit 0 unless "
                                              "a file cannot be read)."),
    jobs: Optional[int] = typer.Option(None, "--jobs", "-j", help="Worker processes (default: CPU count)."),
    metric: Optional[str] = _option("metric"),
    warn_fraction: Optional[float] = _option("warn_fraction"),
    scheme: Optional[str] = _option("scheme"),
    intent: Optional[str] = _option("intent"),
    verify: bool = typer.Option(False, "--verify/--no-verify",
                                help="Verify the advised net of failing faces on the real surface (slower)."),
    advise: Optional[str] = _option("advise"),
    undecided: Optional[str] = _option("undecided"),
    convert: Optional[bool] = _option("convert"),
    wide: Optional[bool] = typer.Option(None, "--wide/--narrow",
                                        help="Every column in the text report (default: at 110 columns or more)."),
    read_timeout: Optional[float] = typer.Option(None, "--read-timeout",
                                                 help="Seconds OCCT's reader may take on one file (default 120 or "
                                                      "$CADARTIFACT_READ_TIMEOUT: docs/environment.md); a file "
                                                      "past it is an error."),
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
    A face is judged with the intent's uncertainty U (ISO 14253-1): it fails only when value - U > t; an
    undecided face (value - U <= t < value + U) warns, or fails or passes with --undecided / policy undecided.

    An unreadable file is reported as an error and the other files are still analysed (fail closed).

    Policy: cadartifact.toml or [tool.cadartifact] in pyproject.toml (see cadartifact.gate.policy).
    """
    given = dict(locals())  # the options as typed, by parameter name
    import importlib.util
    import os

    from ..gate.run import build_document, run_gate
    from ..gate.policy import base_settings, check_cli, expand_paths, find_policy, load_policy
    from ..gate.reports import FORMATS, render_text, summary_line, to_json, to_junit, to_text, write_atomic
    from ..gate.sarif import to_sarif

    check_option("--format", fmt, FORMATS)
    if jobs is not None and jobs < 1:
        raise OptionError("--jobs", "a number of processes >= 1", jobs)
    if read_timeout is not None and not (0 < read_timeout < float("inf")):
        raise OptionError("--read-timeout", "a positive number of seconds", read_timeout)
    # the settings' options (their Keys), checked as the policy's keys are; the profile is resolved below
    cli = check_cli({name: given[key.param or name] for name, key in setting_keys().items()
                     if key.option and key.check is not None})
    if profile is not None:
        from ..gate.policy import PolicyError
        from ..gate.profiles import resolve_profile

        try:
            cli["profile"] = resolve_profile(profile, Path.cwd(), "--profile")
        except PolicyError as exc:
            if exc.key != "profile":  # the profile file's own error names its file and key
                raise
            raise PolicyError("--profile", None, exc.problem) from None
    pol = load_policy(policy) if policy is not None else find_policy()
    files = expand_paths(paths)
    settings = [pol.settings_for(f, cli) for f in files]  # every usage error before any analysis
    for option, target in (("--output", output), ("--report", report)):
        if target is not None and not (target.parent if str(target.parent) else Path(".")).is_dir():
            raise OptionError(option, "a file in an existing folder", str(target))
    previous = []
    if baseline is not None:
        from ..gate.baseline import load_baseline
        from ..gate.codequality import baseline_findings

        if baseline.exists() or not update_baseline:  # a first --update-baseline creates it
            previous = load_baseline(baseline, baseline_findings)
        if update_baseline and not (baseline.parent if str(baseline.parent) else Path(".")).is_dir():
            raise OptionError("--baseline", "a file in an existing folder", str(baseline))
    elif update_baseline:
        raise OptionError("--update-baseline", "--baseline FILE too (the file to write)", "--update-baseline alone")
    if report is not None and importlib.util.find_spec("cadartifact.viz.html") is None:
        raise OptionError("--report", "the HTML report (cadartifact.viz.html), which is not available in this "
                                      "installation", str(report))

    from .environment import cluster_options, execution_settings

    workers = jobs or os.cpu_count() or 1
    cluster = result_cache = None
    if scheduler is not None:
        from ..execution.dask import require_distributed

        cluster = cluster_options(scheduler.strip(), workers=workers, ship=ship, timeout=scheduler_timeout)
        require_distributed()  # a missing extra is a usage error before any work
    elif ship:
        raise OptionError("--ship", "--scheduler too (files are shipped to Dask workers)", "--ship alone")
    # the run's execution: the environment's settings (read here only), then the options
    execution = execution_settings(read_timeout=read_timeout, workers=int(workers), cluster=cluster)
    cache = cache if cache is not None else pol.cache
    if cache is not None:
        from ..gate.cache import GateCache

        result_cache = GateCache(cache)

    from ..gate.progress import GateProgress

    with GateProgress(_console(stderr=True), len(files)) as progress:
        entries = run_gate(files, settings, verify=verify, progress=progress, cache=result_cache,
                           execution=execution)
    doc = build_document(entries, base_settings(pol, cli), pol)
    if baseline is not None:
        from ..gate.baseline import to_baseline
        from ..gate.codequality import apply_baseline, baseline_findings

        apply_baseline(doc, previous, str(baseline))
        if update_baseline:  # this run's findings are accepted: only an unreadable file fails
            found = baseline_findings(doc)
            write_atomic(baseline, to_baseline(found))
            doc["exit_code"] = doc["baseline"]["exit_code"] = 2 if doc["summary"]["errors"] else 0
            _console(stderr=True).print(f"baseline written to {escape(baseline)}: {len(found)} finding(s)",
                                        soft_wrap=True)

    if fmt == "text" and output is None:
        con = _console()
        if not con.is_terminal and not os.environ.get("COLUMNS"):  # CI logs: the whole table, unfolded
            con.width = max(con.width, 132)
        render_text(doc, con, wide=wide)
    else:
        from ..gate.codequality import to_gitlab

        text = {"text": to_text, "json": to_json, "junit": to_junit, "sarif": to_sarif, "gitlab": to_gitlab}[fmt](doc)
        if output is None:
            typer.echo(text, nl=False)
        else:
            write_atomic(output, text)
            _console().print(summary_line(doc) + f"; {fmt} report written to {escape(output)}", soft_wrap=True)
    if report is not None:
        from ..viz.html import write_report

        write_report(doc, report)
    raise typer.Exit(doc["exit_code"])
