"""Advise over files: the per-face results, the JSON document and the terminal tables.

The document (``cadartifact advise --json``) has this schema (version 1)::

    {
      "schema": "cadartifact.advise/1",
      "tolerance": float, "units": "mm", "metric": "peak" | "rms",
      "intent": "surface" | "net", "include_signal_error": bool,
      "files": [{
        "path": str, "units": "mm" | "model" | null,
        "faces_total": int, "skipped": {kind: count}, "warnings": [str],
        "analysed_share": float | null (OBJ: share of the cage's area in analysed charts),
        "faces": [{
          "face": int, "name": str | null, "kind": "bspline" | "bezier" | "converted" | "quad-chart",
          "net": [nu, nv], "degrees": [p, q] | null, "units": "mm" | "model", "scheme": str,
          "entity": int | null (STEP: the face's #id in the file), "entity_line": int | null (its line),
          "canonical": str | null (what the face exactly is: "sphere r=12.5", "revolved: circular in u"),
          "exact": [u, v] each null | "line" | "circle" | "surface" (directions without artifact),
          "peak_at": null | {"value", "index": [x, y], "uv": [u, v] | null, "xyz": [x, y, z]}
                     (faces beyond the tolerance: where the ripple peaks),
          "method": "predicted" | "measured", "reason": str, "intent": "surface" | "net",
          "uniform": bool (uniform knots and constant weights, or a cage), "notes": [str],
          "budget": {"x1" | "x2" | "diagonal" | "lateral" | "total" | "signal_error" | "deviation":
                     {"peak": float, "rms": float}},
          "share": {same keys: value / tolerance under the metric},
          "meets_tolerance": bool,
          "advice": {"net": [n'u, n'v], "points": int, "intent": str, "objective": "deviation" | "ripple",
                     "budget": {"deviation" (the advised net against the intent), "boundary" (its borders
                                against today's), its own "x1" ... "total": {"peak", "rms"}},
                     "share": {...}, "today": {"peak", "rms", "boundary"} (today's net, scored the same way),
                     "meets_tolerance": bool, "binding": "u" | "v" | null, "kept_today": bool,
                     "reasons": {"u" | "v": {"today", "advised", "change", "coarser_value", "binding", "reason"}},
                     "verification": {"method": "occt" | "today", "levels", "region": "face", "value", "rms",
                                      "meets", "coarser": {"shape", "value", "meets"},
                                      "samples" (net reading: distance to today's points)} | null,
                     "comparison": {scheme: {"net", "points", "meets_tolerance", "objective"}},
                     "notes": [str]}
        }]
      }],
      "summary": {"files": int, "faces": int, "within": int, "exceeding": int, "unreachable": int},
      "written": {...}  (only with --write-resampled: see :func:`write_advised`)
    }

``total`` is the whole ripple (x1 + x2 + diagonal); ``deviation`` is everything the surface differs
from the intent (ripple and signal error); ``lateral`` is the part of the ripple running across
features (SPEC §3 weighting).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from .artifact_budget import METRICS, check_tolerance
from .errors import FileFormatError, OptionError, check_option

__all__ = ["advise_files", "budget_record", "face_record", "render", "write_advised", "SCHEMA"]

SCHEMA = "cadartifact.advise/1"
DIRECTIONS = ("x1", "x2", "diagonal", "lateral", "total", "signal_error", "deviation")


def _f(x):
    return None if x is None or not math.isfinite(x) else round(float(x), 9)


def budget_record(net, budget, include_signal_error: bool = False) -> dict:
    """One face's entry of the document from its :class:`~cadartifact.budget.Budget` (``advice`` None)."""
    t = budget.tolerance
    key = "deviation" if include_signal_error else "total"
    return {
        "face": net.origin.face,
        "name": net.origin.name,
        "kind": net.origin.kind,
        "net": list(net.shape),
        "degrees": list(net.degrees) if net.degrees else None,
        "rational": net.rational,
        "units": net.unit,
        "entity": getattr(net.origin, "entity", None),
        "canonical": getattr(net, "canonical", None),
        "exact": list(getattr(net, "exact", (None, None))),
        "scheme": budget.scheme,
        "method": budget.method,
        "uniform": bool(net.knots is None or net.uniform),
        "intent": budget.intent,
        "reason": budget.reason,
        "notes": budget.notes,
        "budget": {k: {"peak": _f(s.peak), "rms": _f(s.rms)} for k, s in budget.stats.items()},
        "share": None if t is None else {k: _f(s.get(budget.metric) / t) for k, s in budget.stats.items()},
        "meets_tolerance": None if t is None else bool(budget.stats[key].get(budget.metric) <= t),
        "advice": None,
    }


def peak_location(net, scheme=None, field: str = "total", current=None) -> dict:
    """Where a face's ripple peaks: fine-grid index, surface parameters and position.

    Parameters
    ----------
    net : ControlNet
    scheme : str or Scheme, optional
        As :func:`cadartifact.budget` (the scheme the face was analysed with).
    field : str
        ``"total"`` (ripple) or ``"deviation"``.
    current : Budget, optional
        The face's budget under this scheme and the ``surface`` reading, computed with
        ``keep_fields=True`` (the gate has it already); else it is computed here.

    Returns
    -------
    dict
        ``{"value", "index": [x, y] (analysis coordinates, spans), "uv": [u, v] | None (B-spline faces),
        "xyz": [x, y, z]}``;
        ``value`` is the budget's peak of ``field`` over the region its stats cover, ``xyz`` the point of
        the face at ``uv`` (OCCT) or, for cages, of the limit surface there (model units).
    """
    import numpy as np

    from .artifact_budget import budget

    b = current if current is not None and current.fields is not None else budget(net, scheme, keep_fields=True)
    values = np.where(b.region, np.abs(b.scalar_fields[field]), -np.inf)
    i, j = np.unravel_index(int(np.argmax(values)), values.shape)
    x, y = float(b.fields.x[i]), float(b.fields.y[j])
    uv = None
    xyz = np.asarray(b.fields.surface)[i, j]  # cages: the limit surface there
    if net.knots is not None:
        from .exchange import evaluate_grid
        from .frames import axis_frames

        fu, fv = axis_frames(net)
        uv = [float(fu.param(x)), float(fv.param(y))]
        # the face's own point at that uv (the fine grid of a predicted face is the uniform model's)
        xyz = evaluate_grid(net, np.array([uv[0]]), np.array([uv[1]]))[0, 0]
    return {"value": _f(values[i, j]), "index": [round(x, 9), round(y, 9)],
            "uv": None if uv is None else [round(t, 9) for t in uv], "xyz": [_f(c) for c in xyz]}


def face_record(net, advice) -> dict:
    """One face's entry of the document from its :class:`~cadartifact.advice.Advice`."""
    rec = budget_record(net, advice.current, advice.include_signal_error)
    rec["advice"] = advice.to_dict()
    return rec


def analysed_share(result) -> float | None:
    """Share of an OBJ cage's surface area that its analysed charts cover; None for B-rep files.

    Parameters
    ----------
    result : LoadResult
        With ``mesh`` (polygons) and ``charts`` (the analysed grid cells, ``face_ids``).

    Returns
    -------
    float or None
        ``sum(area of charted faces) / sum(area of all faces)``, polygon areas by fan triangulation
        of the control polygons (1.0 for a mesh of zero area with every face charted).
    """
    import numpy as np

    mesh = getattr(result, "mesh", None)
    if mesh is None:
        return None
    v = np.asarray(mesh.vertices, float)
    areas = np.zeros(len(mesh.faces))
    for k, ids in enumerate(mesh.faces):
        p = v[list(ids)]
        areas[k] = 0.5 * np.linalg.norm(np.cross(p[1:-1] - p[0], p[2:] - p[0]), axis=-1).sum()
    charted = np.zeros(len(mesh.faces), bool)
    for chart in result.charts:
        charted[np.asarray(chart.face_ids).ravel()] = True
    total = float(areas.sum())
    if not total > 0:
        return float(charted.mean()) if len(charted) else None
    return float(areas[charted].sum() / total)


def advise_files(paths, tolerance: float, *, scheme=None, metric: str = "peak", include_signal_error: bool = False,
                 faces=None, compare="auto", verify: bool = True, progress=None, keep=None,
                 convert: bool = False, intent: str = "surface") -> dict:
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

    Returns
    -------
    dict
        The document described in this module's docstring.

    Raises
    ------
    CadArtifactError
        For the first file that cannot be read: nothing is returned (fail closed, no partial document).
    """
    from .exchange import read

    check_option("metric", metric, METRICS)
    tolerance = check_tolerance(tolerance)  # before any file is read (each face's advice would raise it too)
    paths = [Path(p) for p in paths]
    if not paths:
        raise OptionError("FILE", "at least one file", "none")
    from .face_sharing import sharing

    # one sharing block for the reads and the faces: after its read the reader child imports the analysis while
    # idle, then takes its share of each file's faces (not when the Advice objects are kept: they stay here)
    with sharing(keep is None):
        loaded = [read(p, convert=convert) for p in paths]  # read all first: a bad file fails before any output
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
        summary = {"files": len(paths), "faces": 0, "within": 0, "exceeding": 0, "unreachable": 0}
        from .exchange.step_text import entity_line
        from .face_sharing import advise_faces, one_blas_thread

        options = dict(tolerance=tolerance, scheme=scheme, metric=metric, include_signal_error=include_signal_error,
                       compare=compare, verify=verify, intent=intent)
        key = "deviation" if include_signal_error else "total"
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
                outcomes = advise_faces(todo, options, path, key, done=face_done, keep=keep is not None)
            for net, outcome in zip(todo, outcomes):
                if isinstance(outcome, BaseException):
                    raise outcome
                rec, adv = outcome
                rec["entity_line"] = entity_line(path, rec.get("entity"))
                entries.append(rec)
                if keep is not None:
                    keep.append((path, net, adv))
                summary["faces"] += 1
                summary["within" if rec["meets_tolerance"] else "exceeding"] += 1
                summary["unreachable"] += 0 if rec["advice"]["meets_tolerance"] else 1
            if progress:
                progress("file", len(entries), str(path))
            doc_files.append({"path": str(path), "units": res.nets[0].unit if res.nets else None,
                              "faces_total": res.faces_total, "analysed_share": _f(analysed_share(res)),
                              "skipped": dict(res.skipped),
                              "warnings": list(res.warnings), "faces": entries})
        units = next((r.nets[0].unit for r in loaded if r.nets), "mm")
        return {"schema": SCHEMA, "tolerance": float(tolerance), "units": units, "metric": metric,
                "intent": "net" if include_signal_error else intent,
                "include_signal_error": bool(include_signal_error), "files": doc_files, "summary": summary}


def resampled_nets(kept) -> list:
    """The advised nets of ``(path, net, advice)`` tuples as B-spline nets ready for :func:`write_step`.

    A cage (OBJ chart) becomes a B-spline net of the scheme's degrees (bicubic for Catmull-Clark)
    with uniform clamped knots; faces under non-B-spline schemes keep their own degrees.
    """
    from .net import ControlNet, clamped_uniform_knots
    from .catalogue import scheme as get_scheme

    out = []
    for _, net, adv in kept:
        new = adv.resampled()
        if new.degrees is None:
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


def write_advised(kept, out, *, faces_only: bool = False, provenance: dict | None = None) -> dict:
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

    Returns
    -------
    dict
        The document's ``written`` entry: ``{"mode": "model" | "faces-only" | "mixed", "files": [{"path",
        "source", "mode", "faces": [{"face", "name", "max_distance", "mean_distance",
        "edge_tolerance", "valid", "model_valid"}], "kept": [face indices left as they were],
        "valid": BRepCheck on the written model or None}], "path", "faces"}``
        (``path`` and ``faces`` repeat the first file's, for one input file). In model mode only
        faces whose advice is a new net are replaced; faces whose advice keeps today's net stay
        untouched and are listed in ``kept``.
    """
    from .exchange.model_writer import check_step_output, write_model
    from .exchange.step import write_step

    check_step_output(out)
    files = []
    for src, target, items in advised_outputs(kept, out):
        nets = resampled_nets(items)
        by_face = {net.origin.face: new for (_, net, _), new in zip(items, nets)}
        mode = "faces-only" if faces_only or src.suffix.lower() == ".obj" else "model"
        if mode == "faces-only" and src.suffix.lower() == ".obj":
            write_step(nets, target, provenance={"source": src.name, **(provenance or {})})
            faces = [{"face": n.origin.face, "name": n.origin.name, "max_distance": None, "mean_distance": None,
                      "edge_tolerance": None, "valid": None} for n in nets]
            kept_faces = []
        elif mode == "faces-only":
            faces = write_model(src, by_face, target, provenance=provenance, faces_only=True)
            kept_faces = []
        else:
            changed = {net.origin.face: new for (_, net, adv), new in zip(items, nets)
                       if not getattr(adv, "kept_today", new.shape == net.shape)}
            faces = write_model(src, changed, target, provenance=provenance)
            kept_faces = sorted(set(by_face) - set(changed))
        checks = [r.get("model_valid") for r in faces if r.get("model_valid") is not None]
        files.append({"path": str(target), "source": str(src), "mode": mode, "faces": faces, "kept": kept_faces,
                      "valid": all(checks) if checks else None})
    modes = {f["mode"] for f in files}
    return {"mode": modes.pop() if len(modes) == 1 else "mixed", "files": files,
            "path": files[0]["path"] if files else str(out), "faces": files[0]["faces"] if len(files) == 1 else
            [dict(r, file=f["path"]) for f in files for r in f["faces"]]}


def kind_count(kind: str, n: int) -> str:
    """``"3 irregular quads"``, ``"1 triangle"``, ``"2 planes"``: a count of skipped faces of one kind."""
    if n == 1 or kind.endswith("s") or kind in ("degenerate", "conversion failed"):
        return f"{n} {kind}"
    return f"{n} {kind}es" if kind.endswith(("sh", "ch", "x")) else f"{n} {kind}s"


def plural(n: int, word: str) -> str:
    """``"1 face"``, ``"2 faces"``."""
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def _mm_pct(value, share) -> str:
    """A value in model units with its share of the tolerance: ``0.0213 43%``."""
    if value is None or share is None:
        return "-"
    pct = f"{share * 100:.0f}%" if share < 10 else f"{share:.0f}x"
    colour = "green" if share <= 0.5 else "yellow" if share <= 1.0 else "red"
    return f"{value:.3g} [{colour}]{pct}[/]"


def _bar(share: float | None, width: int = 4) -> str:
    """A compact bar of a share of the tolerance: green up to half, yellow up to 1, red beyond."""
    if share is None:
        return ""
    filled = min(width, int(round(min(share, 1.0) * width)))
    colour = "green" if share <= 0.5 else "yellow" if share <= 1.0 else "red"
    pct = f"{share * 100:.0f}%" if share < 10 else f"{share:.0f}x"
    return f"[{colour}]{'█' * filled}{'·' * (width - filled)} {pct:>4}[/]"


def unit_name(units: str | None) -> str:
    """How a unit is written in every report: ``"mm"``, or ``"model units"`` (OBJ, unknown)."""
    return "model units" if units in (None, "model") else units


_units = unit_name


#: Below this console width ``render`` uses its narrow layout (``wide=None``).
WIDE_COLUMNS = 110


def _worst_direction(share: dict) -> str:
    """``"X2 204%"``: the direction (X1, X2, diagonal) whose ripple takes most of the tolerance."""
    name, value = max(((k, share.get(k) or 0.0) for k in ("x1", "x2", "diagonal")), key=lambda kv: kv[1])
    label = {"x1": "X1", "x2": "X2", "diagonal": "diag"}[name]
    pct = f"{value * 100:.0f}%" if value < 10 else f"{value:.0f}x"
    return f"{label} {pct}"


def canonical_lines(faces) -> list[str]:
    """One line per canonical label among face records: ``"canonical: sphere r=12.5: faces 3, 15"``.

    Canonical faces (exactly a plane, cylinder, ..., or exactly straight/circular along a direction)
    carry no ripple along their exact directions; the label says which.
    """
    groups: dict = {}
    for r in faces:
        if r.get("canonical"):
            groups.setdefault(r["canonical"], []).append(str(r["face"]))
    return [f"canonical: {label}: {'face' if len(ids) == 1 else 'faces'} {', '.join(ids)}"
            for label, ids in groups.items()]


def _face_label(r: dict, limit: int = 24) -> str:
    label = str(r["face"]) + (f" {r['name']}" if r["name"] else "")
    return label if len(label) <= limit else label[:limit - 1] + "~"


def render(doc: dict, console, wide: bool | None = None) -> None:
    """Print one rich table per file and a summary line.

    Each direction column shows that ripple's share of the tolerance (peak or RMS, as the
    document's metric), with a small bar; ``ripple`` is all of it together.

    Parameters
    ----------
    doc : dict
        The advise document.
    console : rich.console.Console
    wide : bool, optional
        Every direction column (X1, X2, diagonal, lateral). Default: when the console is at least
        :data:`WIDE_COLUMNS` wide; narrower consoles (80 columns) get face, net, ripple, the worst
        direction, advised net and verdict, each cell whole (the rest is in ``--wide`` and the JSON).
    """
    from rich import box
    from rich.table import Table

    if wide is None:
        wide = console.width >= WIDE_COLUMNS
    t = doc["tolerance"]
    key = "deviation" if doc["include_signal_error"] else "total"
    value_name = "deviation" if key == "deviation" else "ripple"
    for f in doc["files"]:
        schemes = sorted({r["scheme"] for r in f["faces"]})
        methods = sorted({f"{r['method']}, intent {r.get('intent', 'surface')}" for r in f["faces"]})
        caption = (f"tolerance {t:g} {_units(f.get('units') or doc['units'])} ({doc['metric']}); cells: "
                   f"{_units(f.get('units') or doc['units'])} and % of the tolerance; road: meas(ured) or "
                   f"pred(icted) / intent; "
                   f"scheme {', '.join(schemes) or '-'}; {'; '.join(methods) or 'no face analysed'}")
        table = Table(title=f"[bold]{f['path']}[/]", caption=caption, box=box.SIMPLE_HEAD, header_style="bold",
                      title_justify="left", caption_justify="left", pad_edge=False)
        cols = (("face", "net", "road", "X1 (u)", "X2 (v)", "diagonal", "lateral", value_name, "advised", "verdict")
                if wide else ("face", "net", value_name, "worst", "advised", "verdict"))
        for col in cols:
            # the face label may fold (it is the only free text); numbers never wrap or shrink
            table.add_column(col, no_wrap=col != "face", overflow="fold" if col == "face" else "ellipsis")
        rows = sorted(f["faces"], key=lambda r: -(r["share"][key] or 0.0))
        for r in rows:
            sh = r["share"]
            adv = r["advice"]
            if r["meets_tolerance"]:
                verdict = "[green]within[/]"
                if wide and adv["points"] < r["net"][0] * r["net"][1]:
                    verdict += " [dim](coarser ok)[/]"
            elif adv["meets_tolerance"]:
                verdict = "[red]exceeds[/]"
            else:
                verdict = "[red]exceeds[/] [dim](out of reach)[/]" if wide else "[red]unreachable[/]"
            advised = "x".join(map(str, adv["net"]))
            ver = adv.get("verification")
            if ver is not None and not ver.get("meets", True):
                advised += " [yellow]?[/]"
            mm = r["budget"]
            if wide:
                road = f"{'pred' if r['method'] == 'predicted' else 'meas'}/{r.get('intent', 'surface')}"
                table.add_row(_face_label(r), "x".join(map(str, r["net"])), road,
                              *(_mm_pct(mm[k][doc["metric"]], sh[k]) for k in ("x1", "x2", "diagonal", "lateral", key)),
                              advised, verdict)
            else:
                table.add_row(_face_label(r), "x".join(map(str, r["net"])), _mm_pct(mm[key][doc["metric"]], sh[key]),
                              _worst_direction(sh), advised, verdict)
        console.print(table)
        for line in canonical_lines(f["faces"]):  # no ripple along their exact directions
            console.print(f"  {line}", soft_wrap=True, markup=False, highlight=False)
        for r in rows:  # why each direction of a changed net has its count
            reasons = (r.get("advice") or {}).get("reasons") or {}
            if reasons and not (r.get("advice") or {}).get("kept_today", True):
                why = "; ".join(f"{d} {reasons[d]['today']}->{reasons[d]['advised']}: {reasons[d]['reason']}"
                                for d in ("u", "v") if d in reasons)
                console.print(f"  face {r['face']}: {why}", soft_wrap=False, overflow="fold")
        skipped = ", ".join(kind_count(k, v) for k, v in sorted(f["skipped"].items()))
        share = f.get("analysed_share")
        if skipped:
            cover = "" if share is None else f" (the analysed charts cover {100 * share:.1f} % of the area)"
            console.print(f"  not analysed: {skipped}{cover}")
        for w in f["warnings"]:
            console.print(f"  [yellow]warning:[/] {w}")
    s = doc["summary"]
    console.print(f"[bold]{plural(s['faces'], 'face')} in {plural(s['files'], 'file')}: {s['within']} within tolerance, "
                  f"{s['exceeding']} exceeding[/]" + (f", {s['unreachable']} out of reach" if s["unreachable"] else ""))
    if any((ff["advice"].get("verification") or {}).get("meets") is False for fl in doc["files"] for ff in fl["faces"]):
        console.print("[yellow]?[/] the advised net did not verify on the real surface's interior "
                      "(clamped ends of strongly curved faces): see the JSON 'verification'.")


@dataclass
class RichProgress:
    """A progress-callback for :func:`advise_files` drawing a rich progress bar on stderr."""

    console: object
    enabled: bool = True

    def __post_init__(self):
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

        self._p = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                           console=self.console, transient=True, disable=not self.enabled)
        self._task = None

    def __enter__(self):
        self._p.__enter__()
        return self

    def __exit__(self, *exc):
        return self._p.__exit__(*exc)

    def __call__(self, kind, total, label):
        if kind == "files":
            self._task = self._p.add_task("advising faces", total=total)
        elif kind == "face" and self._task is not None:
            self._p.update(self._task, advance=1, description=f"advising {label}")


_ING = {"advised": "advising", "gated": "gating", "rendered": "rendering"}


class LineProgress:
    """Progress for logs and pipes (no terminal): one plain line per file on stderr, with the time taken.

    Works as the ``progress`` callback of :func:`advise_files` (kind "file") and, through
    :meth:`file_done`, of the gate and of ``view``. Inside a file of many faces (kind "face") a
    heartbeat line follows every ``heartbeat`` seconds, so that a long file shows it is moving.
    """

    def __init__(self, console, verb: str = "advised", total: int | None = None, heartbeat: float = 10.0):
        import time

        self.console, self.verb, self.total, self.done = console, verb, total, 0
        self.heartbeat = heartbeat
        self._clock = time.perf_counter
        self._start = self._last = self._clock()
        self._faces = 0

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def _count(self, n: int) -> str:
        return f"{n}/{self.total}" if self.total else str(n)

    def __call__(self, kind, total, label):
        if kind == "file":
            self.file_done(label, f"{plural(total, 'face')}")
        elif kind == "face":
            self._faces += 1
            now = self._clock()
            if now - self._last >= self.heartbeat:
                self._last = now
                where = label.rsplit("#", 1)[0]
                self.console.print(f"cadartifact: [{self._count(self.done + 1)}] {_ING.get(self.verb, self.verb)} "
                                   f"{where}: {plural(self._faces, 'face')} done ({now - self._start:.1f} s)",
                                   markup=False, highlight=False, soft_wrap=True)

    def file_done(self, path: str, detail: str = "") -> None:
        self.done += 1
        self._faces = 0
        now = self._clock()
        took, self._start = now - self._start, now
        self._last = now
        self.console.print(f"cadartifact: [{self._count(self.done)}] {self.verb} {path}" + (f": {detail}" if detail else "")
                           + f" ({took:.1f} s)", markup=False, highlight=False, soft_wrap=True)
