"""The pipeline quality gate: pass / warn / fail verdicts per face and file, and the exit code.

``cadartifact gate PATH...`` measures every analysable face of every file (the advise document of
:mod:`cadartifact.runs.records`) under the settings its policy gives it (:mod:`cadartifact.gate.policy`)
and adds a verdict, so that a CI job or a pre-commit hook can block a model whose control nets
ripple beyond the tolerance. Report writers are in :mod:`cadartifact.gate.reports`.

The verdict needs today's budget only; the density advice (the costly search) is computed for the
faces the policy's ``advise`` selects (``--advise failing``, the default: those that warn or fail;
``all``; ``none``). A face without it keeps the schema: ``advice: null`` and ``advice_skipped``, the reason.

Per face, by the decision rule of ISO 14253-1 with the intent's uncertainty ``U``
(:mod:`cadartifact.advice.decision`): ``fail`` when the value (ripple, or whole deviation with
``include_signal_error``, under the metric) does not conform (``value - U > t``), ``warn`` when it conforms
(``value + U <= t``) but ``value >= warn_fraction * tolerance``, else ``pass``; an undecided face gets the
policy's ``undecided`` verdict (``warn`` by default, ``fail`` makes the exit code 1); faces with non-uniform knots are capped at ``warn`` only when the
policy says ``measured = "warn"`` (the default gates them: :mod:`cadartifact.gate.policy`). Per file: the worst face;
``pass`` with a note when the file has no analysable face; ``error`` when it cannot be read or
analysed. Fail closed: an ``error`` file never passes, every readable file is still analysed and
reported, and the exit code is then 2; else 1 when any face fails, else 0.
"""

from __future__ import annotations

import os

from ..errors import CadArtifactError, one_line
from ..execution.settings import ExecutionSettings
from ..runs.verdicts import VERDICTS, face_verdict, worst_verdict
from .policy import FileSettings, Policy

__all__ = ["GATE_SCHEMA", "INVALID_SKIPS", "VERDICTS", "build_document", "face_verdict", "file_verdict", "gate_file",
           "merge_parts", "run_gate"]

GATE_SCHEMA = "cadartifact.gate/4"  # versions: runs/documents/gate.py


def _child_imports() -> tuple:
    """What the reader child imports while idle after a read of the gate: the analysis of its share of the faces."""
    from ..runs.face_sharing import CHILD_IMPORTS

    return CHILD_IMPORTS[:1] + (__name__,) + CHILD_IMPORTS[1:]


def file_verdict(entry: dict) -> str:
    """The worst verdict of the faces and the shared edges; ``error`` for an entry with an error; ``pass`` without
    faces."""
    if entry.get("error"):
        return "error"
    return worst_verdict([f["verdict"] for f in entry["faces"]] + [e["verdict"] for e in entry.get("edges") or []])


# ---------------------------------------------------------------- analysis (one file, any process)
def _error_entry(path: str, settings: FileSettings | None, message: str) -> dict:
    return {"path": path, "verdict": "error", "error": message, "units": None, "faces_total": None, "skipped": {},
            "warnings": [], "notes": [], "ignored_faces": [], "faces": [],
            "policy": settings.to_dict() if settings else None}


#: Skipped-face kinds that mean broken data (non-finite or all-coincident poles, faces the STEP transfer
#: dropped), not a face type.
INVALID_SKIPS = ("degenerate", "conversion failed", "dropped")


def gate_file(path: str, settings: FileSettings, verify: bool = False, read_timeout: float | None = None,
              part: tuple[int, int] | None = None, *, sharing=None, reuse: bool = True) -> dict:
    """Read, advise and judge one file; never raises (errors become an ``error`` entry).

    Parameters
    ----------
    path : str
    settings : FileSettings
    verify : bool
        Verify the advice of failing faces on the real surface (slower).
    read_timeout : float, optional
        Seconds OCCT's reader may take on the file (see :func:`cadartifact.exchange.read`).
    part : (int, int), optional
        ``(r, k)``: only the analysable faces at positions ``r, r + k, ...`` (a face batch of a big file
        on a cluster); the entry then carries ``_part`` and is completed by :func:`merge_parts`.
    sharing : cadartifact.execution.sharing.Sharing, optional
        Leave to share the file's faces with the idle reader child (the run's only process).
    reuse : bool
        Repeated faces reuse their first face's analysis (the run's ``reuse_faces``).

    Returns
    -------
    dict
        The advise document's file entry plus ``units``, ``verdict``, ``policy`` (the settings),
        ``notes``, ``ignored_faces``, ``analysed_share`` (OBJ: the share of the cage's area in analysed
        charts, else None), ``share_failure`` (only when that share is below ``min_analysed_share``:
        the file fails) and per face ``verdict``, ``verdict_reason``, ``value``, ``advice_skipped`` (None, or why the advice was not computed), ``entity_line`` (the
        line of the STEP entity ``entity``, else None) and ``peak_at`` (warn/fail faces:
        :func:`cadartifact.runs.records.peak_location`, else None); or an error entry
        ``{"path", "verdict": "error", "error": message, "faces": [], ...}``.

    Notes
    -----
    Fail closed: a file that cannot be read, a face whose analysis raises or gives a non-finite
    value, and a face the reader skipped because its control points are invalid (NaN/infinite or all
    coincident: :data:`INVALID_SKIPS`) make the whole file an ``error``. Faces skipped because they
    are analytic (planes, cylinders...) are simply not gated.
    """
    from ..runs.face_sharing import quiet_analysis

    try:
        # numpy overflow warnings (e.g. 1e300 coordinates) would only add noise: the non-finite
        # result is turned into an error below
        with quiet_analysis():
            return _gate_file(path, settings, verify, read_timeout, part, sharing, reuse)
    except CadArtifactError as exc:
        return _file_error(path, settings, str(exc))
    except Exception as exc:  # fail closed: an unexpected failure must not let the file pass
        return _error_entry(path, settings, one_line(f"{path}: analysis failed ({type(exc).__name__}: {exc})"))


def _file_error(path: str, settings: FileSettings, message: str) -> dict:
    """The error entry of a file for an error message, prefixed with the file's path when it is not."""
    if not message.startswith(str(path)):
        message = f"{path}: {message}"
    return _error_entry(path, settings, one_line(message))


def _gate_file(path: str, settings: FileSettings, verify: bool, read_timeout: float | None = None,
               part: tuple[int, int] | None = None, sharing=None, reuse: bool = True) -> dict:
    from ..exchange.load import read
    from ..exchange.step_text import entity_line
    from ..runs.face_sharing import analyse_faces
    from ..runs.records import subdivided_record

    if os.path.isdir(path):  # a folder the walk could not list (gate_policy._walk)
        from ..errors import InputError

        try:
            os.listdir(path)
        except OSError as exc:
            raise InputError(path, f"cannot read this folder ({exc.strerror or exc}): its files are not gated") from None
        raise InputError(path, "a folder, not a file")
    # after its read the reader child imports the analysis while idle, before the first share reaches it
    res = read(path, convert=settings.convert, timeout=read_timeout, idle=sharing.imports if sharing else ())
    invalid = sum(res.skipped.get(k, 0) for k in INVALID_SKIPS)
    if invalid:
        detail = "; ".join(w.removeprefix(f"{path}: ") for w in res.warnings if "no analysable face" not in w)
        raise CadArtifactError(f"{invalid} face(s) could not be read or have invalid control points"
                               + (f" ({detail})" if detail else ""))
    todo = [net for net in res.nets if net.origin.face not in settings.ignore_faces]
    positions = list(range(len(todo)))
    if part is not None:
        positions = positions[part[0]::part[1]]
    faces, error = [], None
    # records with peak_at for faces that warn or fail, in face order; the first error fails the file. A batch
    # finds repeated faces over the whole file (its repeats' first faces may lie in another batch), so that its
    # records are those of the whole file's run
    for pos, outcome in zip(positions, analyse_faces(todo, settings, verify, only=None if part is None else positions,
                                                     sharing=sharing, reuse=reuse)):
        if isinstance(outcome, BaseException):
            if part is None:
                raise outcome
            error = [pos, str(outcome)]  # the merge raises the first of all parts'
            break
        outcome["entity_line"] = entity_line(path, outcome.get("entity"))
        faces.append(outcome)
    present = {n.origin.face for n in res.nets}
    ignored = sorted(settings.ignore_faces)
    notes = []
    missing = [i for i in ignored if i not in present]
    if missing:
        notes.append(f"ignore_faces {missing} name no analysable face of this file")
    from ..runs.cage_records import vertices_and_coverage

    vertices, share = vertices_and_coverage(res, settings.tolerance)  # a cage's extraordinary vertices
    entry = {"path": path, "units": res.nets[0].unit if res.nets else None, "faces_total": res.faces_total,
             "analysed_share": None if share is None else round(share, 9)}
    subdivided = subdivided_record(res)
    if subdivided is not None:
        entry["subdivided"] = subdivided
    entry |= {"skipped": dict(res.skipped), "warnings": list(res.warnings), "notes": notes,
             "ignored_faces": [i for i in ignored if i in present], "policy": settings.to_dict(), "faces": faces}
    if vertices is not None and (part is None or part[0] == 0):
        # batch 0 of a cluster run carries them: the merge keeps its keys
        entry["extraordinary"] = vertices
    if part is not None:
        entry["_part"] = {"index": part[0], "of": part[1], "positions": positions[:len(faces)], "error": error,
                          "share": share}
        return entry
    return _complete(entry, share, settings)


def merge_parts(parts: list, settings: FileSettings) -> dict:
    """One file's entry from its face batches (:func:`gate_file` with ``part``), as :func:`gate_file` gives it
    whole: faces in file order, the first error of all batches (or the read error, the same in each)."""
    for e in parts:
        if "_part" not in e:  # the file could not be read: every batch says so alike
            return e
    errors = [e["_part"]["error"] for e in parts if e["_part"]["error"] is not None]
    path = parts[0]["path"]
    if errors:
        return _file_error(path, settings, min(errors)[1])
    ranked = sorted((pos, k, f) for k, e in enumerate(parts) for pos, f in zip(e["_part"]["positions"], e["faces"]))
    entry = {key: value for key, value in parts[0].items() if key != "_part"}
    entry["notes"] = list(entry["notes"])
    entry["faces"] = [f for _, _, f in ranked]
    return _complete(entry, parts[0]["_part"]["share"], settings)


def _complete(entry: dict, share, settings: FileSettings) -> dict:
    """The file-level verdict and notes of an entry whose faces are all in."""
    from ..runs.records import coverage_text, kind_count

    notes = entry["notes"]
    if getattr(settings, "profile", None) is not None:
        entry["edges"], entry["edges_counted"] = _edges(entry["path"], settings, notes)
    if not entry["faces"] and not entry.get("edges"):
        notes.append("no analysable chart (nothing to gate)" if "extraordinary" in entry else
                     "no analysable face (nothing to gate): pass")
    entry["verdict"] = file_verdict(entry)
    if share is not None:
        skipped = ", ".join(kind_count(k, n) for k, n in sorted(entry["skipped"].items()))
        text = coverage_text(share, entry.get("subdivided")) + (f"; not analysed: {skipped}" if skipped else "")
        if share < settings.min_analysed_share:
            entry["share_failure"] = (f"{text}, below min_analysed_share {settings.min_analysed_share:g}")
            entry["verdict"] = worst_verdict([entry["verdict"], "fail"])
        elif share < 1:
            notes.append(text)
    if "extraordinary" in entry:
        from ..runs.cage_records import cage_advice_record, vertex_failure

        entry["cage_advice"] = cage_advice_record(entry["faces"], entry["extraordinary"])
        failure = vertex_failure(entry["extraordinary"], settings.tolerance)
        if failure:
            entry["extraordinary_failure"] = failure
            entry["verdict"] = worst_verdict([entry["verdict"], "fail"])
    return entry


def _edges(path: str, settings: FileSettings, notes: list) -> tuple:
    """The judged edges two faces of a B-rep file share and the file's edges by kind
    (:mod:`cadartifact.analysis.edges`, measured where OCCT reads: the reader child); ``(None, None)`` for other
    formats, or with a note when OCCT fails on them (the faces' verdicts stand)."""
    from ..analysis.edges import EDGES_FUNCTION, file_edges, judge_edges
    from ..exchange import formats

    record = formats.format_of(path)
    if not record.brep:
        return None, None
    from ..execution import child
    from ..exchange.reader_start import PRELOAD

    try:
        if child.enabled() and not child.serving():
            found = child.call(EDGES_FUNCTION, (path, record.name), path=path, what="OCCT",
                               actor="OCCT's continuity between faces", preload=PRELOAD)
        else:
            found = file_edges(path, record.name)
    except Exception as exc:  # noqa: BLE001 - said in the notes, never silent
        notes.append(one_line(f"continuity between faces not measured ({type(exc).__name__}: {exc})"))
        return None, None
    edges = judge_edges(found["edges"], settings.profile, settings.ignore_faces)
    for e in edges:  # the file's own unit in each criterion
        for c in e["criteria"]:
            c["unit"] = c["unit"].replace("model units", "mm")
    return edges, found["counted"]


def _gate_task(task: tuple, reuse: bool = True) -> dict:
    """:func:`gate_file` of a ``(path, settings, verify)`` task (what a pool worker runs)."""
    return gate_file(*task, reuse=reuse)


# ---------------------------------------------------------------- the run
def _run_isolated(tasks: list, jobs: int, done, worker=None, execution: ExecutionSettings | None = None) -> list:
    """Run ``worker`` (default :func:`gate_file`) over ``(path, settings, verify)`` tasks in a process pool
    (:class:`~cadartifact.execution.executors.ProcessPool`), each worker's reader child run under ``execution``.

    A task whose worker process dies (a crash in native code) becomes an error entry; the others are
    rerun one per process so that only the culprit is blamed.
    """
    from functools import partial

    from ..execution.executors import ProcessPool
    from ..exchange.reader_start import BREP_SUFFIXES, PRELOAD

    execution = execution or ExecutionSettings()
    worker = worker or partial(_gate_task, reuse=execution.reuse_faces)
    # each worker reads with a reader child of its own: start it with the worker, so that its OCP
    # import overlaps the worker's own start-up (OBJ-only runs need none)
    brep = execution.isolation and any(str(t[0]).lower().endswith(tuple(BREP_SUFFIXES)) for t in tasks)

    def crashed(task):
        path, settings = task[0], task[1]
        return _error_entry(path, settings, f"{path}: the analysis process crashed (corrupt geometry?)")

    # biggest files first (a cheap proxy for their cost) balances the workers' loads
    pool = ProcessPool(jobs, initializer=_start_worker, initargs=(execution, PRELOAD if brep else ()),
                       crashed=crashed, cost=lambda t: _size(t[0]))
    return pool.map(worker, tasks, done)


def _start_worker(execution: ExecutionSettings, preload: tuple) -> None:
    """A pool worker's start: its reader child runs under the run's settings, and starts now with ``preload``."""
    from ..execution import child

    child.configure(execution)
    if preload:
        child.prestart(preload)


def _size(path: str) -> int:
    try:
        return os.path.getsize(path)
    except OSError:
        return 0


def run_gate(paths, settings: list[FileSettings], *, jobs: int | None = None, verify: bool = False, progress=None,
             cache=None, cluster=None, read_timeout: float | None = None,
             execution: ExecutionSettings | None = None) -> list:
    """Gate files (in parallel with ``jobs > 1``); results in input order, identical for any ``jobs``.

    Parameters
    ----------
    paths : list of path-like
    settings : list of FileSettings
        One per path.
    jobs : int, optional
        Worker processes; 1 runs in this process (default: ``execution.workers``).
    progress : callable, optional
        ``progress(entry)`` after each file; with a ``cache``, ``progress(entry, cached=bool)``.
    cache : cadartifact.gate.cache.GateCache, optional
        Take unchanged files' entries from it, store the new ones.
    cluster : cadartifact.execution.settings.ClusterOptions, optional
        Run the analysis on a Dask cluster instead of this machine's processes (default: ``execution.cluster``).
    read_timeout : float, optional
        Seconds OCCT's reader may take on one file (a file past it is an ``error`` entry; default:
        ``execution.read_timeout``).
    execution : cadartifact.execution.settings.ExecutionSettings, optional
        How the run executes (the CLI builds it from its options and the environment); ``jobs``, ``cluster``
        and ``read_timeout``, when given, replace its own.

    Returns
    -------
    list of dict
        File entries (:func:`gate_file`).
    """
    from ..execution.child import configured

    done = progress or (lambda entry, **kw: None)
    tasks = [(os.fspath(p), s, verify) for p, s in zip(paths, settings)]
    execution = execution or ExecutionSettings()
    changes = {k: v for k, v in (("workers", jobs), ("cluster", cluster), ("read_timeout", read_timeout))
               if v is not None}
    execution = execution.replace(**changes) if changes else execution
    # this process's reader child (and each worker's) runs under the run's settings, for this run only
    with configured(execution):
        if cache is not None:  # the seam to cadartifact.gate.cache: it runs only the misses
            return cache.run(tasks, lambda todo, finished: _execute(todo, execution, finished), done,
                             reuse=execution.reuse_faces)
        return _execute(tasks, execution, done)


def _execute(tasks: list, execution: ExecutionSettings, done) -> list:
    if execution.cluster is not None:  # the seam to cadartifact.gate.cluster (imports distributed)
        import sys

        from .cluster import run_on_cluster

        return run_on_cluster(tasks, execution.cluster, done, execution, sys.modules[__name__])
    from ..execution.executors import SerialExecutor, workers_can_start

    jobs = max(1, min(execution.workers, len(tasks)))
    if jobs == 1 or not workers_can_start():
        from ..execution.sharing import Sharing

        # the only worker: the reader child's core may take part of a file's faces
        sharing = Sharing(_child_imports()) if execution.share_faces else None
        return SerialExecutor().map(lambda t: gate_file(*t, sharing=sharing, reuse=execution.reuse_faces), tasks,
                                    done)
    return _run_isolated(tasks, jobs, done, execution=execution)


def build_document(entries: list, base: dict, policy: Policy) -> dict:
    """The gate document: the advise document's keys, verdicts, summary and exit code.

    Parameters
    ----------
    entries : list of dict
        File entries from :func:`run_gate`.
    base : dict
        The settings without per-file overrides (``tolerance``, ``metric``, ``include_signal_error``,
        ``warn_fraction``, ``measured``, ``scheme``).
    policy : Policy

    Returns
    -------
    dict
        ``{"schema": "cadartifact.advise/4", "gate": "cadartifact.gate/4", "tolerance", "units",
        "metric", "include_signal_error", "warn_fraction", "measured", "undecided",
        "profile": the PDQ profile's thresholds (:func:`cadartifact.gate.profiles.profile_dict`) | None,
        "policy": source | None,
        "files": [...], "summary": {..., "undecided": faces the decision rule left undecided,
        "criteria": {criterion: {"warn", "fail", "not_evaluated"}: faces} (only with a profile),
        "verdicts": {"files": {...}, "faces": {...}}},
        "verdict", "exit_code"}``
    """
    from ..runs.records import SCHEMA

    face_counts = {v: 0 for v in VERDICTS[:3]}
    file_counts = {v: 0 for v in VERDICTS}
    summary = {"files": len(entries), "faces": 0, "within": 0, "exceeding": 0, "undecided": 0, "unreachable": 0}
    for e in entries:
        file_counts[e["verdict"]] += 1
        for f in e["faces"]:
            face_counts[f["verdict"]] += 1
            summary["faces"] += 1
            summary["within" if f["meets_tolerance"] else
                    "undecided" if f.get("decision") == "undecided" else "exceeding"] += 1
            # a face without advice (skipped by --advise) is not counted as out of reach
            summary["unreachable"] += 0 if (f["advice"] or {}).get("meets_tolerance", True) else 1
    if base.get("profile") not in (None, "none"):  # the PDQ criteria's counts (only with a profile)
        crit: dict = {}
        for e in entries:
            for f in e["faces"]:
                for c in f.get("criteria") or []:
                    n = crit.setdefault(c["criterion"], {"warn": 0, "fail": 0, "not_evaluated": 0})
                    if not c["evaluated"]:
                        n["not_evaluated"] += 1
                    elif c["verdict"] in ("warn", "fail"):
                        n[c["verdict"]] += 1
        summary["criteria"] = crit
        from ..analysis.edges import edge_summary

        summary["edges"] = edge_summary([d for e in entries for d in e.get("edges") or []])
    summary["errors"] = file_counts["error"]
    summary["verdicts"] = {"files": file_counts, "faces": face_counts}
    verdict = worst_verdict(e["verdict"] for e in entries)
    exit_code = 2 if verdict == "error" else 1 if verdict == "fail" else 0
    units = next((e["units"] for e in entries if e.get("units")), "mm")
    # with the tolerance only in overrides, the top level shows the first file's (the schema needs one)
    tolerance = base["tolerance"]
    if tolerance is None:
        tolerance = next((e["policy"]["tolerance"] for e in entries if e.get("policy")), None)
    from .profiles import profile_dict

    profile = base.get("profile")
    return {"schema": SCHEMA, "gate": GATE_SCHEMA, "tolerance": tolerance, "units": units,
            "metric": base["metric"], "include_signal_error": base["include_signal_error"],
            "intent": base.get("intent", "surface"), "warn_fraction": base["warn_fraction"], "measured": base["measured"],
            "undecided": base.get("undecided", "warn"), "scheme": base["scheme"],
            "profile": profile_dict(None if profile == "none" else profile),
            "policy": policy.source[len("policy "):] if policy.source else None,
            "files": entries, "summary": summary, "verdict": verdict, "exit_code": exit_code}
