"""Advise over files: the advise document (:mod:`.records` gives its schema), and the resampled surfaces
written beside it (``--write-resampled``)."""

from __future__ import annotations

from pathlib import Path

from ..analysis.settings import RunSettings, check_tolerance
from ..errors import FileFormatError, OptionError
from ..exchange import formats
from .records import SCHEMA, json_number, subdivided_record

__all__ = ["advise_files", "exit_code", "resampled_nets", "advised_outputs", "check_not_an_input", "allowed_distances", "edge_rules",
           "write_advised"]


def advise_files(paths, tolerance: float, *, scheme=None, metric: str = "peak", include_signal_error: bool = False,
                 faces=None, compare="auto", verify: bool = True, progress=None, keep=None,
                 convert: bool = False, intent: str = "surface", execution=None) -> dict:
    """Load every file, advise every analysable face, and build the document.

    Parameters
    ----------
    paths : list of path-like
    tolerance : float
    scheme, metric, include_signal_error
        As :func:`cadartifact.advise`.
    faces : set of int, optional
        Only these face indices (per file); an index that no file has raises :class:`OptionError`.
    progress : callable, optional
        ``progress(kind, total_or_None, label)``: "files" once with the count of faces, "face" per face,
        "file" after each file (``total`` its face count, ``label`` its path).
    keep : list, optional
        If given, ``(path, net, advice)`` tuples are appended (for writing resampled faces).
    convert : bool
        Convert revolution/extrusion/offset faces to B-splines (as :func:`cadartifact.read`).
    execution : cadartifact.execution.settings.ExecutionSettings, optional
        How the run executes (the reader child's timeout and isolation, sharing faces with it, reusing
        repeated faces); default :class:`~cadartifact.execution.settings.ExecutionSettings()`.

    Returns
    -------
    dict
        The document described in this module's docstring.

    Raises
    ------
    CadArtifactError
        For the first file that cannot be read: nothing is returned (fail closed, no partial document).
    """
    from ..exchange.load import read

    # the run's settings, checked before any file is read (each face's advice would raise the same errors later)
    settings = RunSettings(tolerance=tolerance, metric=metric, scheme=scheme, intent=intent,
                           include_signal_error=include_signal_error)
    check_tolerance(settings.tolerance)  # the advice needs one (None passes RunSettings: a budget needs none)
    paths = [Path(p) for p in paths]
    if not paths:
        raise OptionError("FILE", "at least one file", "none")
    from ..execution.child import configured
    from ..execution.settings import ExecutionSettings
    from ..execution.sharing import Sharing
    from .face_sharing import CHILD_IMPORTS

    execution = execution or ExecutionSettings()
    # one sharing for the reads and the faces: after its read the reader child imports the analysis while
    # idle, then takes its share of each file's faces (not when the Advice objects are kept: they stay here)
    sharing = Sharing(CHILD_IMPORTS) if keep is None and execution.share_faces else None
    with configured(execution):
        # read all first: a bad file fails before any output
        loaded = [read(p, convert=convert, idle=sharing.imports if sharing else ()) for p in paths]
        for p, res in zip(paths, loaded):
            if res.skipped.get("degenerate"):
                # NaN/infinite, absurdly large or coincident control points: fail closed, never "within"
                import re

                why = next((w for w in res.warnings if re.search(r"#\d+: ", w)), "")
                m = re.search(r"#(\d+): (.*)", why)
                raise FileFormatError(p, f"face {m.group(1)}: {m.group(2)}" if m else
                                      "a face has invalid control points")
            if res.skipped.get("dropped"):  # faces the STEP transfer lost: the file is not what it says
                why = next((w for w in res.warnings if "was dropped" in w), "")
                raise FileFormatError(p, why.removeprefix(f"{p}: ") or "a face could not be read")
        if faces is not None:  # a face index no file has is a usage error, not an empty (passing) report
            have = sorted({n.origin.face for r in loaded for n in r.nets})
            missing = sorted(set(faces) - set(have))
            if missing:
                where = paths[0].name if len(paths) == 1 else f"any of the {len(paths)} files"
                shown = ", ".join(map(str, have[:20])) + (", ..." if len(have) > 20 else "") if have else "none"
                raise OptionError("faces", f"an analysable face index of {where} ({shown})", missing[0])
        total_faces = sum(len([n for n in r.nets if faces is None or n.origin.face in faces]) for r in loaded)
        if progress:
            progress("files", total_faces, "")
        doc_files = []
        summary = {"files": len(paths), "faces": 0, "within": 0, "exceeding": 0, "undecided": 0, "unreachable": 0}
        from ..exchange.step_text import entity_line
        from .face_sharing import advise_faces, one_blas_thread

        advice = dict(compare=compare, verify=verify)
        for path, res in zip(paths, loaded):
            entries = []
            todo = [net for net in res.nets if faces is None or net.origin.face in faces]

            def face_done(i, todo=todo, path=path):
                if progress:
                    progress("face", None, f"{path.name}#{todo[i].origin.face}")

            # one outcome per face, in order (part of them from the idle reader child unless the advice
            # objects are kept, which stay in the process that made them); the first error stops the run.
            # One BLAS thread, as in the gate and the reader child: the numbers do not depend on who computed them
            with one_blas_thread():
                outcomes = advise_faces(todo, settings, advice, path, done=face_done, keep=keep is not None,
                                        sharing=sharing, reuse=execution.reuse_faces)
            for net, outcome in zip(todo, outcomes):
                if isinstance(outcome, BaseException):
                    raise outcome
                rec, adv = outcome
                rec["entity_line"] = entity_line(path, rec.get("entity"))
                entries.append(rec)
                if keep is not None:
                    keep.append((path, net, adv))
                summary["faces"] += 1
                summary[_summary_key(rec)] += 1
                summary["unreachable"] += 0 if rec["advice"]["meets_tolerance"] else 1
            if progress:
                progress("file", len(entries), str(path))
            record = {"path": str(path), "units": res.nets[0].unit if res.nets else None,
                      "faces_total": res.faces_total}
            from .cage_records import vertices_and_coverage

            vertices, share = vertices_and_coverage(res, settings.tolerance)  # a cage's extraordinary vertices
            record["analysed_share"] = json_number(share)
            subdivided = subdivided_record(res)
            if subdivided is not None:
                record["subdivided"] = subdivided
            doc_files.append({**record, "skipped": dict(res.skipped), "warnings": list(res.warnings),
                              "faces": entries})
            if vertices is not None:
                from .cage_records import cage_advice_record

                doc_files[-1].update(extraordinary=vertices, cage_advice=cage_advice_record(entries, vertices))
        units = next((r.nets[0].unit for r in loaded if r.nets), "mm")
        return {"schema": SCHEMA, "tolerance": settings.tolerance, "units": units, "metric": settings.metric,
                "intent": settings.reading, "include_signal_error": settings.include_signal_error,
                "files": doc_files, "summary": summary, "exit_code": exit_code(doc_files)}


def exit_code(files: list) -> int:
    """``cadartifact advise``'s exit code for a document's ``files``: 0 when every face meets the tolerance today
    (no face at all included), else 1.

    The document carries it (``exit_code``) and the command exits with the document's value, so that a pipeline
    reading the JSON and one reading the exit code see the same outcome. Usage and input errors exit 2 and write
    no document.
    """
    return 0 if all(f["meets_tolerance"] for entry in files for f in entry["faces"]) else 1


def _summary_key(rec: dict) -> str:
    """Where a face counts in the summary: ``within`` (conforms), ``undecided`` or ``exceeding``."""
    if rec["meets_tolerance"]:
        return "within"
    return "undecided" if rec.get("decision") == "undecided" else "exceeding"


def resampled_nets(kept) -> list:
    """The advised nets of ``(path, net, advice)`` tuples as B-spline nets ready for :func:`write_step`.

    A cage (OBJ chart) becomes a B-spline net of the scheme's degrees (bicubic for Catmull-Clark)
    with uniform clamped knots; faces under non-B-spline schemes keep their own degrees.
    """
    from ..net import ControlNet, clamped_uniform_knots
    from ..theory.catalogue import scheme as get_scheme

    out = []
    for _, net, adv in kept:
        new = adv.resampled()
        if not new.is_bspline:
            degs = get_scheme(adv.scheme).degrees or (3, 3)
            degs = tuple(min(d, n - 1) for d, n in zip(degs, new.shape))
            knots = tuple(clamped_uniform_knots(n, d) for n, d in zip(new.shape, degs))
            new = ControlNet(points=new.points, degrees=degs, knots=knots, unit=new.unit, origin=new.origin)
        out.append(new)
    return out


def advised_outputs(kept, out) -> list:
    """``(source path, output path, [(path, net, advice), ...])`` per input file of ``kept``.

    One input file writes ``out`` itself; several write ``OUT_<input stem>.step`` each, next to ``out``.
    """
    groups: dict = {}
    for item in kept:
        groups.setdefault(Path(item[0]), []).append(item)
    out = Path(out)
    if len(groups) == 1:
        return [(src, out, items) for src, items in groups.items()]
    return [(src, out.with_name(f"{out.stem}_{src.stem}{out.suffix}"), items) for src, items in groups.items()]


def check_not_an_input(paths, out) -> None:
    """:class:`InputError` naming ``out`` when writing it (or, for several input files, ``OUT_<input stem>``:
    :func:`advised_outputs`) would overwrite one of the input ``paths``: the same file under another spelling,
    through a symbolic link or a hard link included. Checked before any file is read."""
    import os

    from ..errors import InputError

    paths = [Path(p) for p in paths]
    out = Path(out)
    targets = [out] + ([out.with_name(f"{out.stem}_{p.stem}{out.suffix}") for p in paths] if len(paths) > 1 else [])
    for target in targets:
        for path in paths:
            same = os.path.realpath(target) == os.path.realpath(path)
            if not same and target.exists() and path.exists():
                try:
                    same = os.path.samefile(target, path)
                except OSError:
                    same = False
            if same:
                raise InputError(target, f"is the input file {path}: --write-resampled would overwrite it "
                                 "(write to another file)")


def allowed_distances(items) -> dict:
    """Per face of ``(path, net, advice)`` tuples, how far its written face may lie from the old one (model
    units): the tolerance plus the old face's ripple, the peak the advice read for today's net (the new surface
    is within ``t`` of the intent, the intent within today's ripple of the old surface)."""
    out = {}
    for _, net, adv in items:
        today = (getattr(adv, "today", None) or {}).get("peak")
        if today is not None and getattr(adv, "tolerance", None) is not None:
            out[net.origin.face] = float(adv.tolerance) + float(today)
    return out


def _tolerance(items):
    """The run's tolerance (every advice of a run has the same)."""
    return next((float(adv.tolerance) for _, _, adv in items if getattr(adv, "tolerance", None) is not None), None)


def _measured(record):
    """The figures a refused replacement measured (None: refused before it was built)."""
    if record is None:
        return None
    out = {key: json_number(record.get(key)) if not isinstance(record.get(key), bool) else record.get(key)
           for key in ("distance_to_old", "distance_from_old", "max_distance", "allowed_distance",
                       "edge_tolerance_before", "edge_tolerance", "valid_before", "valid")}
    if record.get("edges"):
        out["edges"] = record["edges"]
    return out


def edge_rules(profile=None, units: str = "mm"):
    """The check :func:`~cadartifact.exchange.model_writer.write_model` runs on a written model's edges: the
    gate's continuity rules (G0 gap, G1 angle, G2 jump of ``profile``, the default profile when None) along the
    edges of the replaced faces, against the input's own verdict per edge
    (:mod:`cadartifact.analysis.edge_changes`). The input's verdicts are measured once per face and kept.

    Returns
    -------
    callable
        ``check(source shape, written shape, {face index: measured figures}) -> {face index: (reason, [edge
        records])}``: the replaced faces charged with an edge whose verdict got worse.
    """
    from ..analysis.edge_changes import blame, edge_verdicts, reason, worse_edges
    from ..analysis.quality import default_profile

    profile = profile or default_profile()
    before: dict = {}
    seen: set = set()

    def check(source, written, measured: dict) -> dict:
        faces = set(measured)
        if faces - seen:
            before.update(edge_verdicts(source, faces - seen, profile))
            seen.update(faces)
        worse = worse_edges(before, edge_verdicts(written, faces, profile))
        charged = blame(worse, faces, {i: r.get("max_distance") or 0.0 for i, r in measured.items()})
        return {face: (reason(face, edges, units), [_edge_json(e) for e in edges]) for face, edges in charged.items()}

    return check


def _edge_json(edge: dict) -> dict:
    """A worse edge as the ``refused[].measured.edges`` record (numbers JSON-safe)."""
    return {"faces": edge["faces"], "criterion": edge["criterion"], "rule": edge["rule"],
            "value": json_number(edge["value"]), "before": json_number(edge["before"]),
            "verdict": edge["verdict"], "verdict_before": edge["verdict_before"], "limit": json_number(edge["limit"])}


def write_advised(kept, out, *, faces_only: bool = False, provenance: dict | None = None, profile=None) -> dict:
    """Write the advice of ``(path, net, advice)`` tuples: whole models, or the advised faces only.

    Parameters
    ----------
    kept : list of (path, ControlNet, Advice)
        As collected by :func:`advise_files` with ``keep``.
    out : path-like
        A ``.step``/``.stp`` file (see :func:`advised_outputs` for several input files).
    faces_only : bool
        Write every advised face as an untrimmed B-spline face (no model). OBJ inputs are
        always written this way (a cage has no B-rep to keep).
    provenance : dict, optional
        Header provenance (tool, version, tolerance, intent).
    profile : Profile, optional
        The gate's thresholds whose continuity rules between faces a written model must keep (:func:`edge_rules`);
        None: the default profile.

    Returns
    -------
    dict
        The document's ``written`` entry: ``{"mode": "model" | "faces-only" | "mixed", "files": [{"path",
        "source", "mode", "faces": [{"face", "name", "max_distance", "mean_distance",
        "edge_tolerance", "valid", "model_valid", ...}], "kept": [face indices left as they were],
        "refused": [{"face", "reason", "measured"}], "valid": BRepCheck on the written model or None,
        "surface_types": [{"face", "before", "after"}] (model mode: every face OCCT's STEP writer turned into
        another kind of surface than it was given, as the file reads back)}], "path",
        "faces"}`` (``path`` and ``faces`` repeat the first file's, for one input file). In model mode only
        faces whose advice is a new net that conforms are replaced; faces whose advice keeps today's net, or
        finds none that conforms (an honest no), stay untouched and are listed in ``kept``. In faces-only mode every
        face whose advice conforms is written (today's net where the advice keeps it); a face whose advice is an
        honest no is not written and is listed in ``kept`` (the face's advice says why); when no face conforms,
        nothing is written and ``path`` is null. Either way ``faces``, ``kept`` and ``refused`` add up to the
        advised faces. Each replaced face is measured as written
        (:func:`cadartifact.exchange.model_writer.write_model`): within ``t`` + the old face's ripple (the
        value the advice read for today's net) + its edge tolerance of the old face by projection both
        ways, edge tolerances within the input's + ``t``, BRepCheck no worse than the input's. A face whose new net the writer
        refuses (it does not cover the face's trimmed region, or it measures beyond those bounds) stays
        as it was and is listed in ``refused`` with the reason and, when measured, what the best
        replacement measured; the other faces are written. If every replacement of a file is refused,
        that file is not written and its ``path`` is null.
    """
    from ..exchange.model_writer import check_step_output, write_model
    from ..exchange.step import write_step

    check_step_output(out)
    check_not_an_input(sorted({str(p) for p, _, _ in kept}), out)
    files = []
    for src, target, items in advised_outputs(kept, out):
        nets = resampled_nets(items)
        by_face = {net.origin.face: new for (_, net, _), new in zip(items, nets)}
        brep = formats.format_of(src).brep  # a model to keep, else (a cage) its faces only
        mode = "faces-only" if faces_only or not brep else "model"
        asked: dict = {}
        refused: dict = {}
        measurements: dict = {}
        types: dict = {}
        # only a verified advice is written as advised (SPEC §5): a face whose advice is an honest no (undecided,
        # or no net verifiable) is kept as it stands in a model, and is not written to a faces-only file
        conforming = {net.origin.face: new for (_, net, adv), new in zip(items, nets)
                      if getattr(adv, "meets_tolerance", True)}
        if mode == "faces-only" and not brep:
            asked = conforming
            written = [n for n in nets if n.origin.face in conforming]
            if written:
                write_step(written, target, provenance={"source": src.name, **(provenance or {})})
            faces = [{"face": n.origin.face, "name": n.origin.name, "max_distance": None, "mean_distance": None,
                      "edge_tolerance": None, "valid": None} for n in written]
        elif mode == "faces-only":
            asked = conforming
            faces = write_model(src, asked, target, provenance=provenance, faces_only=True,
                                refused=refused) if asked else []
        else:
            asked = {i: new for (_, net, adv), new in zip(items, nets)
                     if (i := net.origin.face) in conforming and not getattr(adv, "kept_today", new.shape == net.shape)}
            units = next((net.unit for _, net, _ in items if getattr(net, "unit", None)), None) or "mm"
            faces = write_model(src, asked, target, provenance=provenance, refused=refused,
                                allowed=allowed_distances(items), tolerance=_tolerance(items),
                                measurements=measurements, edge_check=edge_rules(profile, units), types=types)
        kept_faces = sorted(set(by_face) - set(asked))  # not written as advised: today's net, or an honest no
        checks = [r.get("model_valid") for r in faces if r.get("model_valid") is not None]
        # every replacement refused: nothing was written (the model would be today's); faces only: no face conforms
        path = None if (asked and len(refused) == len(asked) or mode == "faces-only" and not faces) else str(target)
        files.append({"path": path, "source": str(src), "mode": mode, "faces": faces, "kept": kept_faces,
                      "refused": [{"face": i, "reason": why, "measured": _measured(measurements.get(i))}
                                  for i, why in refused.items()],
                      "valid": all(checks) if checks else None})
        if mode == "model" and path is not None:  # faces OCCT's writer turned into another kind of surface
            files[-1]["surface_types"] = [{"face": i, "before": a, "after": b} for i, (a, b) in sorted(types.items())]
    modes = {f["mode"] for f in files}
    return {"mode": modes.pop() if len(modes) == 1 else "mixed", "files": files,
            "path": files[0]["path"] if files else str(out), "faces": files[0]["faces"] if len(files) == 1 else
            [dict(r, file=f["path"]) for f in files for r in f["faces"]]}
