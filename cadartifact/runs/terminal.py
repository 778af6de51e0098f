"""What a person reads in a terminal: the advise document as rich tables, and the progress of a long run
(a bar on a terminal, one line per file in a log).

A console with ``soft_wrap`` set (the command line's off a terminal: CI logs, pipes, files) wraps nothing:
a path or a name stays one token on one line, to copy or grep, and a table takes its content's width
(:func:`print_table`). On a terminal, tables are fitted to its width; paths are never cut by rich either
(their lines are soft-wrapped: the terminal folds them at its edge)."""

from __future__ import annotations

import re

from dataclasses import dataclass
from typing import TYPE_CHECKING

from .records import coverage_text, estimated_u, kind_count, plural, unit_name

if TYPE_CHECKING:  # the records the tables read (runs/documents: docs/schema.md)
    from collections.abc import Iterable

    from .documents.advise import AdviseDocument
    from .documents.face import FaceRecord, Shares

__all__ = ["WIDE_COLUMNS", "canonical_lines", "direction_reason", "face_cell", "worst_direction", "wraps_nothing",
           "print_table", "render", "RichProgress", "LineProgress", "say"]


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


#: Below this console width ``render`` uses its narrow layout (``wide=None``).
WIDE_COLUMNS = 110


def worst_direction(share: Shares) -> str:
    """``"X2 204%"``: the direction (X1, X2, diagonal) whose ripple takes most of the tolerance."""
    name, value = max(((k, share.get(k) or 0.0) for k in ("x1", "x2", "diagonal")), key=lambda kv: kv[1])
    label = {"x1": "X1", "x2": "X2", "diagonal": "diag"}[name]
    pct = f"{value * 100:.0f}%" if value < 10 else f"{value:.0f}x"
    return f"{label} {pct}"


def canonical_lines(faces: Iterable[FaceRecord]) -> list[str]:
    """One line per canonical label among face records: ``"canonical: sphere r=12.5: faces 3, 15"``.

    Canonical faces (exactly a plane, cylinder, ..., or exactly straight/circular along a direction)
    carry no ripple along their exact directions; the label says which. Faces written piecewise Bezier (or
    exact) in both directions carry none at all: ``"no ripple by construction (u: 4 Bezier pieces of degree 3;
    v: ...): face 2"``.
    """
    groups: dict = {}
    for r in faces:
        construction = re.search(r"no ripple by construction \((.*)\)$", r.get("reason") or "")
        if r.get("canonical"):
            groups.setdefault(f"canonical: {r['canonical']}", []).append(str(r["face"]))
        elif construction:  # piecewise Bezier (or exact) both ways: zero, and why
            groups.setdefault(f"no ripple by construction ({construction[1]})", []).append(str(r["face"]))
    return [f"{label}: {'face' if len(ids) == 1 else 'faces'} {', '.join(ids)}" for label, ids in groups.items()]


def face_cell(r: FaceRecord, limit: int | None = 24) -> str:
    """``"3 hood_left"``: the face's index and name, cut to ``limit`` characters (``~`` at the end); whole
    with ``limit=None``."""
    label = str(r["face"]) + (f" {r['name']}" if r["name"] else "")
    return label if limit is None or len(label) <= limit else label[:limit - 1] + "~"


def wraps_nothing(console) -> bool:
    """Whether ``console`` wraps no line (``soft_wrap``: the command line's console off a terminal): then
    no name is cut or folded and tables take their content's width."""
    return bool(getattr(console, "soft_wrap", False))


def wrap_lines(text: str, width: int, keep=()) -> list[str]:
    """``text`` wrapped at spaces to ``width`` with continuation lines indented by 4; never inside a word, so
    that a path stays whole, nor inside the ``keep`` strings (face labels: ``part.step#3 outer skin``)."""
    import textwrap

    glue = "\ue000"  # a private-use character: a space textwrap does not break at
    for k in sorted(keep, key=len, reverse=True):  # a label before the path it starts with
        text = text.replace(k, k.replace(" ", glue))
    return [line.replace(glue, " ") for line in textwrap.wrap(
        text, width=width, subsequent_indent="    ", break_long_words=False, break_on_hyphens=False)]


def say(console, text: str, keep=(), wrap: bool = True) -> None:
    """Print an explanation line (plain text, no markup), wrapped by :func:`wrap_lines` to the console's width.
    ``wrap`` False: one line, as it is (a report file)."""
    if wrap and len(text) > console.width:
        text = "\n".join(wrap_lines(text, console.width, keep))
    console.print(text, soft_wrap=True, markup=False, highlight=False)


def _wrapped_heading(console, heading: str, keep=()):
    """The heading (rich markup) as styled lines wrapped like :func:`say`'s: the plain text is wrapped, then the
    styled text is cut at the same places, so that colours stay on their words."""
    from rich.text import Text

    text = Text.from_markup(heading, style="table.title")
    if text.cell_len <= console.width:
        return text
    lines, cuts, at = wrap_lines(text.plain, console.width, keep), [], 0
    for line in lines[1:]:  # each continuation's first word, found after the previous line's
        at = text.plain.index(line.lstrip(), at + 1)
        cuts.append(at)
    parts = text.divide(cuts)
    for part in parts[1:]:
        part.pad_left(4)
    for part in parts:
        part.rstrip()
    return Text("\n").join(parts)


def print_table(console, table, heading: str | None = None, keep=()) -> None:
    """Print ``heading`` (rich markup: escape the paths in it) on a line of its own, then ``table``.

    The heading is wrapped at spaces to the console's width, never inside a word or the ``keep`` strings (the
    file's path: it stays whole, on a line of its own if it must); on a console that
    :func:`wraps_nothing`, the table takes its content's width, past the console's if it must, so that
    no cell is cut or folded. Elsewhere (a terminal) the table is fitted to the console's width.
    """
    if heading is not None:
        console.print(_wrapped_heading(console, heading, keep), soft_wrap=True, highlight=False)
    if wraps_nothing(console):
        from rich.measure import Measurement

        need = Measurement.get(console, console.options.update_width(1 << 20), table).maximum
        if need > console.width:
            table.width = need
    console.print(table)


def direction_reason(record: FaceRecord, reasons: dict, d: str) -> str:
    """``"u 5->4: <reason>"`` from the record's own values; counts of the spans a trim uses (the advice reads only
    those) say so beside the face's whole count, which the table's net column shows."""
    x = reasons[d]
    whole = record["net"]["uv".index(d)]
    inside = "" if x["today"] == whole else f" (inside the trim: {x['today']} of the face's {whole})"
    return f"{d} {x['today']}->{x['advised']}{inside}: {x['reason']}"


def render(doc: AdviseDocument, console, wide: bool | None = None) -> None:
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
        On a console that :func:`wraps_nothing` (a log), face labels are whole and a table takes its
        content's width.
    """
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    if wide is None:
        wide = console.width >= WIDE_COLUMNS
    limit = None if wraps_nothing(console) else 24  # a log shows every face name whole
    t = doc["tolerance"]
    key = "deviation" if doc["include_signal_error"] else "total"
    value_name = "deviation" if key == "deviation" else "ripple"
    for f in doc["files"]:
        schemes = sorted({r["scheme"] for r in f["faces"]})
        methods = sorted({f"{r['method']}, intent {r.get('intent', 'surface')}" for r in f["faces"]})
        caption = (f"tolerance {t:g} {unit_name(f.get('units') or doc['units'])} ({doc['metric']}); cells: "
                   f"{unit_name(f.get('units') or doc['units'])} and % of the tolerance; road: meas(ured) or "
                   f"pred(icted) / intent; "
                   f"scheme {', '.join(schemes) or '-'}; {'; '.join(methods) or 'no face analysed'}")
        table = Table(caption=caption, box=box.SIMPLE_HEAD, header_style="bold", caption_justify="left",
                      pad_edge=False)
        cols = (("face", "net", "road", "X1 (u)", "X2 (v)", "diagonal", "lateral", value_name, "+/-U", "advised",
                 "verdict") if wide else ("face", "net", value_name, "+/-U", "worst", "advised", "verdict"))
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
            elif r.get("decision") == "undecided":
                verdict = "[yellow]undecided[/]"
            elif adv["meets_tolerance"]:
                verdict = "[red]exceeds[/]"
            else:
                verdict = "[red]exceeds[/] [dim](out of reach)[/]" if wide else "[red]unreachable[/]"
            advised = "x".join(map(str, adv["net"])) if adv.get("verifiable", True) else "[yellow]unverifiable[/]"
            if r.get("kind") == "quad-chart" and f.get("cage_advice"):  # a cage's density changes by levels
                k = next((g["level"] for g in f["cage_advice"]["regions"] if g["face"] == r["face"]), None)
                advised = "more control" if k is None else f"level {k}"
            unc = "-" if estimated_u(r) is None else f"{estimated_u(r):.2g}"
            ver = adv.get("verification")
            if ver is not None and not ver.get("meets", True):
                advised += " [yellow]?[/]"
            mm = r["budget"]
            if wide:
                road = f"{'pred' if r['method'] == 'predicted' else 'meas'}/{r.get('intent', 'surface')}"
                table.add_row(face_cell(r, limit), "x".join(map(str, r["net"])), road,
                              *(_mm_pct(mm[k][doc["metric"]], sh[k]) for k in ("x1", "x2", "diagonal", "lateral", key)),
                              unc, advised, verdict)
            else:
                table.add_row(face_cell(r, limit), "x".join(map(str, r["net"])),
                              _mm_pct(mm[key][doc["metric"]], sh[key]), unc, worst_direction(sh), advised, verdict)
        print_table(console, table, f"[bold]{escape(f['path'])}[/]", keep=[f['path']])
        for line in canonical_lines(f["faces"]):  # no ripple along their exact directions
            console.print(f"  {line}", soft_wrap=True, markup=False, highlight=False)
        for r in rows:  # the advice's honest no (SPEC §5): the intent's uncertainty leaves no room
            for n in (r.get("advice") or {}).get("notes") or []:
                if n.startswith("the net determines its shape only"):
                    console.print(f"  face {r['face']}: {n}", markup=False, highlight=False)
        for r in rows:  # why each direction of a changed net has its count
            reasons = (r.get("advice") or {}).get("reasons") or {}
            if reasons and not (r.get("advice") or {}).get("kept_today", True):
                why = "; ".join(direction_reason(r, reasons, d) for d in ("u", "v") if d in reasons)
                console.print(f"  face {r['face']}: {why}", markup=False, highlight=False)
        skipped = ", ".join(kind_count(k, v) for k, v in sorted(f["skipped"].items()))
        share = f.get("analysed_share")
        if share is not None:  # a cage: its coverage, whatever it is
            console.print(f"  {coverage_text(share, f.get('subdivided'))}"
                          + (f"; not analysed: {skipped}" if skipped else ""), markup=False, highlight=False)
        elif skipped:
            console.print(f"  not analysed: {skipped}")
        for line in cage_lines(f):  # folded at the terminal's width, between words
            console.print(f"  {line}", markup=False, highlight=False)
        for w in f["warnings"]:
            console.print(f"  [yellow]warning:[/] {escape(w)}")
    s = doc["summary"]
    console.print(f"[bold]{plural(s['faces'], 'face')} in {plural(s['files'], 'file')}: {s['within']} within tolerance, "
                  f"{s['exceeding']} exceeding[/]"
                  # out of reach: a named subset of the exceeding (and undecided) faces, never a class of its own
                  + (f", {s['undecided']} undecided" if s.get("undecided") else "")
                  + (f" ({s['unreachable']} of them out of reach: no density up to the search limit meets the "
                     "tolerance)" if s["unreachable"] else ""))
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
            from rich.markup import escape

            self._p.update(self._task, advance=1, description=f"advising {escape(label)}")


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


def cage_lines(f: dict) -> list:
    """A cage's extraordinary vertices (count, curvature classes, worst defect) and its advice, as lines."""
    verts = f.get("extraordinary")
    if verts is None:
        return []
    if not verts:
        return ["extraordinary vertices: none"]
    kinds = ", ".join(f"{sum(v['curvature'] == k for v in verts)} {k}" for k in ("bounded", "zero", "unbounded")
                      if any(v["curvature"] == k for v in verts))
    worst = max(verts, key=lambda v: v["defect"])
    beyond = sum(v["within"] is False for v in verts)
    lines = [f"extraordinary vertices: {len(verts)} (curvature {kinds}); worst defect {worst['defect']:.3g} "
             f"at vertex {worst['vertex']} (valence {worst['valence']})"
             + (f"; {beyond} beyond the tolerance" if beyond else "")]
    return lines + [f"advice: {t}" for t in f["cage_advice"]["text"]]
