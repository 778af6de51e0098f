"""Advise over files: the per-face results, the JSON document and the terminal tables.

The document (``cadartifact advise --json``) has this schema (version 1)::

    {
      "schema": "cadartifact.advise/1",
      "tolerance": float, "units": "mm", "metric": "peak" | "rms",
      "include_signal_error": bool,
      "files": [{
        "path": str, "units": "mm" | "model" | null,
        "faces_total": int, "skipped": {kind: count}, "warnings": [str],
        "faces": [{
          "face": int, "name": str | null, "kind": "bspline" | "bezier" | "converted" | "quad-chart",
          "net": [nu, nv], "degrees": [p, q] | null, "scheme": str,
          "method": "predicted" | "measured", "reason": str,
          "budget": {"x1" | "x2" | "diagonal" | "lateral" | "total" | "signal_error" | "deviation":
                     {"peak": float, "rms": float}},
          "share": {same keys: value / tolerance under the metric},
          "meets_tolerance": bool,
          "advice": {"net": [n'u, n'v], "points": int, "budget": {...}, "share": {...},
                     "meets_tolerance": bool, "binding": "u" | "v" | null,
                     "verification": {"method", "levels", "value", "meets", "coarser": {...},
                                      OCCT only: "uniform_match", "clamped_ends", "value_clamped";
                                      "note" when one step coarser also meets on the interior} | null,
                     "comparison": {scheme: {"net", "points", "meets_tolerance"}}}
        }]
      }],
      "summary": {"files": int, "faces": int, "within": int, "exceeding": int, "unreachable": int}
    }

``total`` is the whole ripple (x1 + x2 + diagonal); ``deviation`` is everything the surface differs
from the intent (ripple and signal error); ``lateral`` is the part of the ripple running across
features (SPEC §3 weighting).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from .budget import METRICS
from .errors import FileFormatError, OptionError, check_option

__all__ = ["advise_files", "budget_record", "face_record", "render", "SCHEMA"]

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
        "scheme": budget.scheme,
        "method": budget.method,
        "reason": budget.reason,
        "budget": {k: {"peak": _f(s.peak), "rms": _f(s.rms)} for k, s in budget.stats.items()},
        "share": None if t is None else {k: _f(s.get(budget.metric) / t) for k, s in budget.stats.items()},
        "meets_tolerance": None if t is None else bool(budget.stats[key].get(budget.metric) <= t),
        "advice": None,
    }


def face_record(net, advice) -> dict:
    """One face's entry of the document from its :class:`~cadartifact.advisor.Advice`."""
    rec = budget_record(net, advice.current, advice.include_signal_error)
    rec["advice"] = advice.to_dict()
    return rec


def advise_files(paths, tolerance: float, *, scheme=None, metric: str = "peak", include_signal_error: bool = False,
                 faces=None, compare="auto", verify: bool = True, progress=None, keep=None) -> dict:
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
        ``progress(kind, total_or_None, label)``: "files" once with the count, "face" per face.
    keep : list, optional
        If given, ``(path, net, advice)`` tuples are appended (for writing resampled faces).

    Returns
    -------
    dict
        The document described in this module's docstring.

    Raises
    ------
    CadArtifactError
        For the first file that cannot be read: nothing is returned (fail closed, no partial document).
    """
    from .advisor import advise
    from .exchange import read

    check_option("metric", metric, METRICS)
    paths = [Path(p) for p in paths]
    if not paths:
        raise OptionError("FILE", "at least one file", "none")
    loaded = [read(p) for p in paths]  # read everything first: a bad file fails before any output
    for p, res in zip(paths, loaded):
        if res.skipped.get("degenerate"):
            # NaN/infinite, absurdly large or coincident control points: fail closed, never "within"
            import re

            why = next((w for w in res.warnings if re.search(r"#\d+: ", w)), "")
            m = re.search(r"#(\d+): (.*)", why)
            raise FileFormatError(p, f"face {m.group(1)}: {m.group(2)}" if m else "a face has invalid control points")
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
    for path, res in zip(paths, loaded):
        entries = []
        for net in res.nets:
            if faces is not None and net.origin.face not in faces:
                continue
            adv = advise(net, tolerance, scheme, metric=metric, include_signal_error=include_signal_error,
                         compare=compare, verify=verify)
            rec = face_record(net, adv)
            key = "deviation" if include_signal_error else "total"
            if any(rec["budget"][k][metric] is None for k in {key, "total"}):  # face_record maps inf/NaN to None
                raise FileFormatError(path, f"face {net.origin.face}: the analysis gave a non-finite value "
                                            "(coordinates or weights too large?)")
            entries.append(rec)
            if keep is not None:
                keep.append((path, net, adv))
            summary["faces"] += 1
            summary["within" if rec["meets_tolerance"] else "exceeding"] += 1
            summary["unreachable"] += 0 if adv.meets_tolerance else 1
            if progress:
                progress("face", None, f"{path.name}#{net.origin.face}")
        doc_files.append({"path": str(path), "units": res.nets[0].unit if res.nets else None,
                          "faces_total": res.faces_total, "skipped": dict(res.skipped),
                          "warnings": list(res.warnings), "faces": entries})
    units = next((r.nets[0].unit for r in loaded if r.nets), "mm")
    return {"schema": SCHEMA, "tolerance": float(tolerance), "units": units, "metric": metric,
            "include_signal_error": bool(include_signal_error), "files": doc_files, "summary": summary}


def resampled_nets(kept) -> list:
    """The advised nets of ``(path, net, advice)`` tuples as B-spline nets ready for :func:`write_step`.

    A cage (OBJ chart) becomes a B-spline net of the scheme's degrees (bicubic for Catmull-Clark)
    with uniform clamped knots; faces under non-B-spline schemes keep their own degrees.
    """
    from .net import ControlNet, clamped_uniform_knots
    from .schemes import scheme as get_scheme

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


def _bar(share: float | None, width: int = 4) -> str:
    """A compact bar of a share of the tolerance: green up to half, yellow up to 1, red beyond."""
    if share is None:
        return ""
    filled = min(width, int(round(min(share, 1.0) * width)))
    colour = "green" if share <= 0.5 else "yellow" if share <= 1.0 else "red"
    pct = f"{share * 100:.0f}%" if share < 10 else f"{share:.0f}x"
    return f"[{colour}]{'█' * filled}{'·' * (width - filled)} {pct:>4}[/]"


def _units(units: str | None) -> str:
    return "model units" if units in (None, "model") else units


def render(doc: dict, console) -> None:
    """Print one rich table per file and a summary line.

    Each direction column shows that ripple's share of the tolerance (peak or RMS, as the
    document's metric), with a small bar; ``ripple`` is all of it together.
    """
    from rich import box
    from rich.table import Table

    t = doc["tolerance"]
    for f in doc["files"]:
        schemes = sorted({r["scheme"] for r in f["faces"]})
        methods = sorted({r["method"] for r in f["faces"]})
        caption = (f"tolerance {t:g} {_units(f.get('units') or doc['units'])} ({doc['metric']}); scheme {', '.join(schemes) or '-'}; "
                   f"{', '.join(methods) or 'no face analysed'}")
        table = Table(title=f"[bold]{f['path']}[/]", caption=caption, box=box.SIMPLE_HEAD, header_style="bold",
                      title_justify="left", caption_justify="left", pad_edge=False)
        for col in ("face", "net", "X1 (u)", "X2 (v)", "diagonal", "lateral", "ripple", "advised", "verdict"):
            table.add_column(col, no_wrap=True)
        rows = sorted(f["faces"], key=lambda r: -(r["share"]["deviation" if doc["include_signal_error"] else "total"]
                                                  or 0.0))
        for r in rows:
            sh = r["share"]
            adv = r["advice"]
            label = str(r["face"]) + (f" {r['name']}" if r["name"] else "")
            if r["meets_tolerance"]:
                verdict = "[green]within[/]"
                if adv["points"] < r["net"][0] * r["net"][1]:
                    verdict += " [dim](coarser ok)[/]"
            elif adv["meets_tolerance"]:
                verdict = "[red]exceeds[/]"
            else:
                verdict = "[red]exceeds[/] [dim](out of reach)[/]"
            advised = "x".join(map(str, adv["net"]))
            ver = adv.get("verification")
            if ver is not None and not ver.get("meets", True):
                advised += " [yellow]?[/]"
            table.add_row(label[:24], "x".join(map(str, r["net"])), _bar(sh["x1"]), _bar(sh["x2"]),
                          _bar(sh["diagonal"]), _bar(sh["lateral"]),
                          _bar(sh["deviation" if doc["include_signal_error"] else "total"]), advised, verdict)
        console.print(table)
        skipped = ", ".join(f"{v} {k}" for k, v in sorted(f["skipped"].items()))
        if skipped:
            console.print(f"  not analysed: {skipped}")
        for w in f["warnings"]:
            console.print(f"  [yellow]warning:[/] {w}")
    s = doc["summary"]
    console.print(f"[bold]{s['faces']} face(s) in {s['files']} file(s): {s['within']} within tolerance, "
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
        elif self._task is not None:
            self._p.update(self._task, advance=1, description=f"advising {label}")
