"""A self-contained HTML report of an advise or gate document.

One page, no external resources: inline CSS, pictures embedded as base64 PNG ``data:`` URIs, so the
file can be attached to a CI run or mailed as it is. It shows

* a header with the tolerance, metric, units and the summary (and the gate verdict and policy when
  the document comes from ``cadartifact gate``);
* per file: a table of its faces, worst first (face, net, scheme, method, the share of the
  tolerance each direction takes as a small bar with the peak in model units, the whole ripple,
  the advised net, the verdict), the reader's notes and warnings;
* per file one heatmap picture of its worst faces (:mod:`cadartifact.viz.view`);
* the response maps of the schemes used (:func:`cadartifact.viz.maps.maps_figure`).

>>> from cadartifact.runs.records import advise_files
>>> from cadartifact.viz.html import write_report
>>> write_report(advise_files(["part.step"], 0.05), "report.html")     # doctest: +SKIP
"""

from __future__ import annotations

import base64
import datetime
import html
import math
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import CadArtifactError, OptionError
from .facemaps import unit_text

if TYPE_CHECKING:  # the records the page reads (runs/documents: docs/schema.md); gate records extend advise's
    from typing import TypeAlias

    from ..runs.documents.advise import AdviseDocument, AdviseFile
    from ..runs.documents.face import AdviseFace
    from ..runs.documents.gate import GateDocument, GateFace, GateFile

    Document: TypeAlias = AdviseDocument | GateDocument
    FileEntry: TypeAlias = AdviseFile | GateFile
    Face: TypeAlias = AdviseFace | GateFace

__all__ = ["write_report", "render_html", "HEATMAP_FACES", "HEATMAP_FILES", "MAP_SCHEMES"]

#: Faces drawn in each file's heatmap (the worst ones).
HEATMAP_FACES = 4
#: Files that get a heatmap (in document order); later files get a note.
HEATMAP_FILES = 24
#: Schemes whose response maps are drawn (most used first).
MAP_SCHEMES = 4
HEATMAP_SIZE = (1000, 620)
#: Each drawn face's heatmap and reflection lines, side by side.
PAIR_SIZE = (560, 420)

_DIRECTIONS = (("x1", "X1 (u)"), ("x2", "X2 (v)"), ("diagonal", "diagonal"), ("lateral", "lateral"))

_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,Helvetica,Arial,sans-serif;margin:0;color:#1d2430;
background:#f4f6f9;font-size:14px}
header{background:#1f2a3c;color:#fff;padding:18px 28px}
header h1{margin:0 0 6px;font-size:22px;font-weight:600}
header .meta{opacity:.85;font-size:13px}
main{padding:16px 28px 40px;max-width:1400px}
.cards{display:flex;gap:12px;flex-wrap:wrap;margin:6px 0 18px}
.card{background:#fff;border-radius:8px;padding:10px 16px;box-shadow:0 1px 2px rgba(0,0,0,.08);min-width:110px}
.card .n{font-size:22px;font-weight:600}.card .l{font-size:12px;color:#5b6575}
section.file{background:#fff;border-radius:10px;box-shadow:0 1px 3px rgba(0,0,0,.08);padding:14px 18px;
margin:0 0 22px}
section.file h2{font-size:16px;margin:0 0 4px;word-break:break-all}
.sub{color:#5b6575;font-size:12px;margin-bottom:8px}
table{border-collapse:collapse;width:100%;font-size:13px}
th{text-align:left;background:#eef1f5;padding:6px 5px;font-weight:600;white-space:nowrap}
td{padding:4px 5px;border-top:1px solid #e6e9ee;vertical-align:middle;white-space:nowrap}
td.num{font-variant-numeric:tabular-nums}
.bar{display:inline-block;width:44px;height:8px;background:#e6e9ee;border-radius:4px;vertical-align:middle;
margin-right:6px;overflow:hidden}
.bar i{display:block;height:100%;border-radius:4px}
.ok{background:#2e9d58}.near{background:#d9a21b}.over{background:#d3312b}
.pk{color:#5b6575;font-size:11px;margin-left:50px;line-height:1.1}
.scroll{overflow-x:auto}
.badge{display:inline-block;padding:1px 8px;border-radius:10px;font-size:12px;font-weight:600;color:#fff}
.b-pass,.b-within{background:#2e9d58}.b-warn{background:#d9a21b}.b-fail,.b-exceeds,.b-error{background:#d3312b}
.small{font-size:11px;color:#5b6575;white-space:normal}
.error{background:#fdecea;color:#8a1c17;border-radius:6px;padding:8px 12px;margin:6px 0}
.note{color:#6b5200;font-size:12px;margin:2px 0}
figure{margin:14px 0 4px}.pair{display:flex;gap:10px;flex-wrap:wrap}.pair img{max-width:100%}
.pair figure{flex:1 1 420px;margin:6px 0}
figure img{max-width:100%;height:auto;border:1px solid #e6e9ee;border-radius:6px}
figcaption{font-size:12px;color:#5b6575;margin-top:4px}
footer{color:#8a93a3;font-size:12px;padding:0 28px 24px}
nav.toc{background:#fff;border-radius:8px;padding:8px 16px;margin:0 0 16px;box-shadow:0 1px 2px rgba(0,0,0,.08)}
nav.toc ol{margin:4px 0;padding-left:22px}nav.toc a{color:#1f2a3c}
"""


def _e(x) -> str:
    return html.escape("" if x is None else str(x), quote=True)


def _num(x, digits: int = 3) -> str:
    if x is None or not isinstance(x, (int, float)) or not math.isfinite(x):
        return "–"
    return "0" if abs(x) < 1e-10 else f"{x:.{digits}g}"


def _bar(share, peak, unit: str, warn_fraction: float) -> str:
    """Share of the tolerance as a bar (full at 100 %), the percentage and the peak."""
    if share is None or not math.isfinite(share):
        return f'<span class="pk">{_num(peak)} {_e(unit)}</span>'
    cls = "over" if share > 1 else "near" if share >= warn_fraction else "ok"
    width = max(0.0, min(share, 1.0)) * 100
    return (f'<span class="bar"><i class="{cls}" style="width:{width:.1f}%"></i></span>'
            f'{_percent(share)}<div class="pk">{_num(peak)} {_e(unit)}</div>')


def _percent(share: float) -> str:
    pct = share * 100
    return f"{pct:.0f}&#8239;%" if abs(pct) >= 100 else f"{pct:.1f}&#8239;%"


def _value_key(doc: Document) -> str:
    return "deviation" if doc.get("include_signal_error") else "total"


def _face_value(face: Face, doc: Document) -> float:
    share = (face.get("share") or {}).get(_value_key(doc))
    if share is not None and math.isfinite(share):
        return share
    return -1.0


def _verdict(face: Face) -> tuple[str, str, str]:
    """``(css class, text, explanation)``: the gate verdict when present, else from the advise fields."""
    if face.get("verdict"):
        v = str(face["verdict"])
        return v, v, face.get("verdict_reason", "")
    if face.get("meets_tolerance") is None:
        return "", "", ""
    adv = face.get("advice") or {}
    if face["meets_tolerance"]:
        coarser = adv.get("points") is not None and adv["points"] < face["net"][0] * face["net"][1]
        return "within", "within", "within the tolerance" + ("; the advised net is coarser" if coarser else "")
    if face.get("decision") == "undecided":
        return "warn", "undecided", "the value +/- the intent's uncertainty U straddles the tolerance"
    return "exceeds", "exceeds", ("resample at the advised net" if adv.get("meets_tolerance")
                                  else "no density up to the search limit meets the tolerance")


def _advised(face: Face) -> str:
    adv = face.get("advice")
    if not adv:
        return "–"
    comp = adv.get("comparison") or {}
    others = ", ".join(f"{k} {'×'.join(map(str, v['net']))}" for k, v in comp.items() if v.get("net"))
    tip = f' title="other schemes: {_e(others)}"' if others else ""
    text = f'<span{tip}>{"×".join(str(n) for n in adv["net"])}</span>'
    if adv.get("verifiable") is False:
        text += '<div class="small">unverifiable: the net determines its shape only to ±U</div>'
    elif not adv.get("meets_tolerance", True):
        text += '<div class="small">out of reach</div>'
    else:
        ver = adv.get("verification")
        if ver is not None and not ver.get("meets", True):
            text += '<div class="small">unverified</div>'
    return text


def _face_rows(faces: list[Face], doc: Document, unit: str, warn_fraction: float) -> str:
    key = _value_key(doc)
    metric = doc.get("metric", "peak")
    rows = []
    for f in sorted(faces, key=lambda f: -_face_value(f, doc)):
        share = f.get("share") or {}
        budget = f.get("budget") or {}
        label = _e(f.get("face")) + (f' <span class="small">{_e(f["name"])}</span>' if f.get("name") else "")
        cls, text, why = _verdict(f)
        badge = f'<span class="badge b-{_e(cls)}" title="{_e(why)}">{_e(text)}</span>' if text else ""
        cells = [label, "×".join(map(str, f.get("net", []))), _e(f.get("scheme")),
                 f'<span title="{_e(f.get("reason", ""))}">{_e(f.get("method"))}</span>']
        cells += [_bar(share.get(k), (budget.get(k) or {}).get(metric), unit, warn_fraction) for k, _ in _DIRECTIONS]
        from ..runs.records import estimated_u

        unc = f.get("uncertainty") or {}
        u = ("–" if estimated_u(f) is None else
             f'<span title="the intent\'s expanded uncertainty U (u {_num(unc.get("u"))}, v {_num(unc.get("v"))} '
             f'{_e(unit)}); decision: {_e(f.get("decision"))}">{_num(unc["peak"])}</span>')
        cells += [_bar(share.get(key), (budget.get(key) or {}).get(metric), unit, warn_fraction), u, _advised(f), badge]
        rows.append("<tr>" + "".join(f'<td class="num">{c}</td>' for c in cells) + "</tr>")
    return "\n".join(rows)


def _img(png: bytes, alt: str, cls: str) -> str:
    data = base64.b64encode(png).decode("ascii")
    return f'<img class="{cls}" alt="{_e(alt)}" src="data:image/png;base64,{data}">'


def _heatmap(entry: FileEntry, doc: Document, tol: float, unit: str) -> str:
    """One picture of the file's worst faces, or a note saying why there is none."""
    from ..exchange.load import read
    from .view import face_maps, png_bytes, render_image

    faces = sorted(entry["faces"], key=lambda f: -_face_value(f, doc))[:HEATMAP_FACES]
    wanted = {f["face"]: f.get("scheme") for f in faces}
    direction = _value_key(doc)
    try:
        nets = [n for n in read(entry["path"]).nets if n.origin.face in wanted]
        if not nets:
            return '<p class="note">No heatmap: the faces are no longer in the file.</p>'
        order = {face: k for k, face in enumerate(wanted)}
        nets.sort(key=lambda n: order[n.origin.face])
        maps = []
        for net in nets:  # each face under the scheme it was analysed with
            maps += face_maps([net], direction, wanted[net.origin.face])
        what = "worst face" if len(maps) == 1 else f"{len(maps)} worst faces"
        title = f"{Path(entry['path']).name}: {what}, {'deviation' if direction == 'deviation' else 'ripple'}"
        image = render_image(maps, direction=direction, tol=tol, title=title, window_size=HEATMAP_SIZE,
                             layout="tiles" if len(maps) > 1 else "model")
    except CadArtifactError as exc:
        return f'<p class="note">No heatmap: {_e(exc)}</p>'
    except Exception as exc:  # a picture (e.g. no OpenGL on this machine) must not cost the report
        return f'<p class="note">No heatmap: rendering failed ({_e(type(exc).__name__)}: {_e(exc)})</p>'
    caption = (f"|{direction.replace('_', ' ')}| on the limit surface, 0 to the tolerance {tol:g} {_e(unit)}; reds: "
               "beyond it, darkest at the peak (magenta dot). Thin lines: the control net.")
    return (f"<figure>{_img(png_bytes(image), title, 'heatmap')}<figcaption>{caption}</figcaption></figure>"
            + _reflection_pairs(maps, direction, tol))


def _reflection_pairs(maps, direction: str, tol: float) -> str:
    """Per drawn face, its heatmap and its reflection lines side by side, from one camera
    (:mod:`cadartifact.viz.reflection`): a crease or a break to a neighbour breaks the stripes, ripple waves them."""
    from .view import png_bytes, render_image

    out = []
    try:
        for m in maps:
            face = m.net.origin.face
            heat = render_image([m], direction=direction, tol=tol, title=f"face {face}: ripple",
                                window_size=PAIR_SIZE, layout="model")
            zebra = render_image([m], direction=direction, title=f"face {face}: reflection lines",
                                 window_size=PAIR_SIZE, layout="model", reflection=True)
            out.append(f'<div class="pair"><figure>{_img(png_bytes(heat), f"face {face} ripple", "face-heatmap")}'
                       f"</figure><figure>{_img(png_bytes(zebra), f'face {face} reflection lines', 'reflection')}"
                       "</figure></div>")
    except Exception as exc:  # a picture must not cost the report
        return f'<p class="note">No reflection lines: rendering failed ({_e(type(exc).__name__)}: {_e(exc)})</p>'
    caption = ("Each face's ripple (left) and reflection lines (right) from the same camera: stripes of a light "
               "tunnel reflected by the face; a crease or a break to a neighbour breaks them, a curvature jump "
               "kinks them, ripple makes them wave.")
    return "".join(out) + f'<p class="small">{caption}</p>'


def _response_maps(doc: Document) -> str:
    from .maps import maps_figure

    names, more = map_schemes(doc)
    if not names:
        return ""
    import io

    try:
        fig = maps_figure(names, "limit", 201)
    except Exception as exc:  # as for heatmaps: the tables matter more than the picture
        return f'<p class="note">No response maps: {_e(exc)}</p>'
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    caption = ("Per scheme: signal kept |a|, artifact energy in % of the signal and lateral artifact, over the "
               "frequency square in cycles per control point (limit surface at refined vertices). Ripple appears "
               "where the design's detail approaches the net's Nyquist limit (1/2).")
    if more:
        caption += f" Not drawn (used by fewer faces): {', '.join(more)}; cadartifact maps -s NAME draws any."
    return (f'<section class="file" id="maps"><h2>Response maps of the schemes used</h2>'
            f"<figure>{_img(buf.getvalue(), 'response maps: ' + ', '.join(names), 'maps')}"
            f"<figcaption>{caption}</figcaption></figure></section>")


def map_schemes(doc: Document) -> tuple[list, list]:
    """The schemes the faces use, most used first, one name per distinct scheme (``bicubic`` and
    ``bspline(3,3)`` are one mask): ``(drawn, not drawn)``, at most :data:`MAP_SCHEMES` drawn."""
    import numpy as np

    from ..theory.catalogue import scheme as get_scheme

    counts: dict = {}
    for entry in doc["files"]:
        for f in entry.get("faces", []):
            if f.get("scheme"):
                counts[f["scheme"]] = counts.get(f["scheme"], 0) + 1
    groups: list = []  # [name, mask, count]
    for name in sorted(counts, key=lambda s: (-counts[s], s)):
        try:
            mask = np.asarray(get_scheme(name).mask, float)
        except CadArtifactError:
            mask = None
        for g in groups:
            if mask is not None and g[1] is not None and g[1].shape == mask.shape and np.allclose(g[1], mask):
                g[2] += counts[name]
                break
        else:
            groups.append([name, mask, counts[name]])
    groups.sort(key=lambda g: -g[2])
    names = [g[0] for g in groups]
    return names[:MAP_SCHEMES], names[MAP_SCHEMES:]


def _contents(doc: Document) -> str:
    """A table of contents: one link per file with its verdict and face count."""
    items = []
    for k, entry in enumerate(doc["files"]):
        v = entry.get("verdict")
        badge = f' <span class="badge b-{_e(v)}">{_e(v)}</span>' if v else ""
        n = len(entry.get("faces") or [])
        items.append(f'<li><a href="#file-{k}">{_e(entry.get("path"))}</a>{badge} '
                     f'<span class="small">{n} face{"" if n == 1 else "s"}</span></li>')
    items.append('<li><a href="#maps">Response maps of the schemes used</a></li>')
    return f'<nav class="toc"><b>Contents</b><ol>{"".join(items)}</ol></nav>'


def _relation(doc: Document) -> str:
    """How the advise counts (within / exceeding) relate to the gate verdicts (pass / warn / fail)."""
    faces = [f for e in doc["files"] for f in e.get("faces") or []]
    exceeding = [f for f in faces if f.get("meets_tolerance") is False]
    fail = sum(1 for f in exceeding if f.get("verdict") == "fail")
    capped = sum(1 for f in exceeding if f.get("verdict") == "warn")
    near = sum(1 for f in faces if f.get("meets_tolerance") and f.get("verdict") == "warn")
    text = (f"{len(exceeding)} exceeding: faces whose value is above the tolerance; {fail} of them fail")
    if capped:
        text += (f" and {capped} are capped at warn (measured faces, outside the uniform theory, under policy "
                 "measured = 'warn')")
    text += (f"; the other {near} warn face{'' if near == 1 else 's'} {'is' if near == 1 else 'are'} within the "
             "tolerance but above the warn fraction of it.")
    return f'<p class="small">{_e(text)}</p>'


def _advice_details(faces: list[Face], doc: Document, unit: str) -> str:
    """Per face, folded: why each direction has its count, how the advice was verified, and what the other
    schemes would need."""
    rows = []
    for f in sorted(faces, key=lambda f: -_face_value(f, doc)):
        adv = f.get("advice") or {}
        ver, comp = adv.get("verification"), adv.get("comparison") or {}
        reasons = adv.get("reasons") or {}
        if ver is None and not comp and not reasons:
            continue
        bits = []
        for d in ("u", "v"):
            r = reasons.get(d)
            if r:
                bits.append(f"{d}: {r['today']} &rarr; {r['advised']} ({_e(r['reason'])})")
        for note in adv.get("notes") or []:
            bits.append(_e(note))
        if ver is not None:
            ok = "meets" if ver.get("meets") else "does not meet"
            bits.append(f"verification ({_e(ver.get('method'))}, K = {2 ** int(ver.get('levels') or 0)}): "
                        f"{_num(ver.get('value'))} {_e(unit)} {ok} the tolerance")
        if comp:
            bits.append("other schemes: " + ", ".join(
                f"{_e(k)} {'×'.join(map(str, v.get('net') or []))} ({v.get('points')} points"
                f"{'' if v.get('meets_tolerance', True) else ', out of reach'})" for k, v in comp.items()))
        label = f"face {_e(f.get('face'))}" + (f" {_e(f['name'])}" if f.get("name") else "")
        rows.append(f"<li>{label}: {'; '.join(bits)}</li>")
    if not rows:
        return ""
    return f'<details class="small"><summary>Advice details</summary><ul>{"".join(rows)}</ul></details>'


def _criteria_table(entry: FileEntry, unit: str) -> str:
    """The PDQ criteria of a gate run with a profile: a row per face and criterion (value, verdict, thresholds,
    worst place, detail or why it was not evaluated); empty without criteria."""
    from ..gate.reports import criterion_text

    rows = []
    for f in entry.get("faces") or []:
        for c in f.get("criteria") or []:
            at = c.get("at") or {}
            where = "" if not at else ("uv (" + ", ".join(_num(t, 6) for t in at.get("uv") or []) + ")"
                                       + (" xyz (" + ", ".join(_num(x, 6) for x in at["xyz"]) + ")"
                                          if at.get("xyz") else ""))
            cls = c["verdict"] if c["evaluated"] else "warn"
            text = c["verdict"] if c["evaluated"] else "not evaluated"
            rows.append(f"<tr><td>{_e(f.get('face'))}</td><td>{_e(c['criterion'])} ({_e(c['code'])})</td>"
                        f"<td>{_e(criterion_text(c, unit, where=False))}</td>"
                        f'<td><span class="badge b-{_e(cls)}">{_e(text)}</span></td><td>{_e(where)}</td>'
                        f"<td>{_e(c['detail'] or c['reason'] or '')}</td></tr>")
    if not rows:
        return ""
    return ('<details class="pdq"><summary>PDQ criteria (value, thresholds, worst place)</summary>'
            '<div class="scroll"><table><thead><tr><th>face</th><th>criterion</th><th>value and thresholds</th>'
            "<th>verdict</th><th>where</th><th>detail</th></tr></thead><tbody>" + "".join(rows)
            + "</tbody></table></div></details>")


def render_html(doc: Document, *, heatmaps: bool = True, maps: bool = True) -> str:
    """The report page as a string (see :func:`write_report`)."""
    if not isinstance(doc, dict) or not isinstance(doc.get("files"), list):
        raise OptionError("doc", "an advise or gate document (cadartifact.runs.records schema)", type(doc).__name__)
    from .. import __version__

    tol = doc.get("tolerance")
    units = {e.get("units") for e in doc["files"] if e.get("faces")}
    # one unit per file: the header names it only when every file shares it
    unit = unit_text(units.pop() if len(units) == 1 else doc.get("units") or "mm")
    mixed = len({e.get("units") for e in doc["files"] if e.get("faces")}) > 1
    metric = doc.get("metric", "peak")
    warn_fraction = doc.get("warn_fraction") or 1.0
    what = "deviation (ripple and signal error)" if doc.get("include_signal_error") else "ripple"
    summary = doc.get("summary", {})
    gate = doc.get("gate") is not None

    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             '<meta name="viewport" content="width=device-width, initial-scale=1">',
             f"<title>cadartifact {'gate' if gate else 'advise'} report</title><style>{_CSS}</style></head><body>"]
    meta = [f"tolerance {_num(tol, 4)} {'(in each file’s units)' if mixed else _e(unit)} on the {_e(metric)} "
            f"{what}"]
    if gate:
        meta.append(f"warn from {_num(warn_fraction)} of the tolerance")
        meta.append(f"policy {_e(doc.get('policy') or 'defaults')}")
    meta.append(datetime.datetime.now().strftime("%Y-%m-%d %H:%M"))
    verdict = (f' <span class="badge b-{_e(doc["verdict"])}">{_e(doc["verdict"])}</span>' if doc.get("verdict")
               else "")
    parts.append(f"<header><h1>cadartifact {'quality gate' if gate else 'density advice'}{verdict}</h1>"
                 f'<div class="meta">{" · ".join(meta)}</div></header><main>')
    # every face in one class of each row: within + undecided + exceeding = pass + warn + fail = faces; "out of
    # reach" is named as a subset, files failing as a whole (analysed share) and unreadable ones are files
    cards = [("files", summary.get("files")), ("faces", summary.get("faces")), ("within", summary.get("within")),
             ("undecided", summary.get("undecided") or None), ("exceeding", summary.get("exceeding")),
             ("of them out of reach", summary.get("unreachable"))]
    if gate:
        fv = summary.get("verdicts", {}).get("faces", {})
        whole = sum(1 for e in doc["files"] if e.get("share_failure"))
        cards += [("pass", fv.get("pass")), ("warn", fv.get("warn")), ("fail", fv.get("fail")),
                  ("files failing whole", whole or None), ("file errors", summary.get("errors"))]
    parts.append('<div class="cards">' + "".join(
        f'<div class="card"><div class="n">{_e(v)}</div><div class="l">{_e(k)}</div></div>'
        for k, v in cards if v is not None) + "</div>")
    if gate:
        parts.append(_relation(doc))
    parts.append(_contents(doc))

    heads = ["face", "net", "scheme", "method"] + [h for _, h in _DIRECTIONS] + [
        "deviation" if doc.get("include_signal_error") else "ripple", "±U", "advised", "verdict"]
    pictures = 0
    for k, entry in enumerate(doc["files"]):
        unit = unit_text(entry.get("units")) if entry.get("units") else unit_text(doc.get("units") or "mm")
        ftol = (entry.get("policy") or {}).get("tolerance") or tol
        fverdict = f' <span class="badge b-{_e(entry["verdict"])}">{_e(entry["verdict"])}</span>' \
            if entry.get("verdict") else ""
        parts.append(f'<section class="file" id="file-{k}"><h2>{_e(entry.get("path"))}{fverdict}</h2>')
        sub = []
        if entry.get("faces_total") is not None:
            sub.append(f"{len(entry.get('faces', []))} analysed of {entry['faces_total']} faces")
        from ..runs.records import kind_count

        skipped = ", ".join(kind_count(kind, n) for kind, n in sorted((entry.get("skipped") or {}).items()))
        if skipped:
            sub.append(f"not analysed: {_e(skipped)}")
        if entry.get("analysed_share") is not None:
            sub.append(f"analysed charts cover {100 * entry['analysed_share']:.1f} % of the area")
        if entry.get("share_failure"):
            parts.append(f'<div class="error">{_e(entry["share_failure"])}</div>')
        if entry.get("extraordinary_failure"):
            parts.append(f'<div class="error">{_e(entry["extraordinary_failure"])}</div>')
        sub.append(f"values in {_e(unit)}")
        if ftol is not None and ftol != tol:
            sub.append(f"tolerance {_num(ftol, 4)} {_e(unit)} (policy override)")
        if entry.get("ignored_faces"):
            sub.append("ignored faces: " + ", ".join(map(str, entry["ignored_faces"])))
        if sub:
            parts.append(f'<div class="sub">{" · ".join(sub)}</div>')
        if entry.get("error"):
            parts.append(f'<div class="error">{_e(entry["error"])}</div>')
        for note in list(entry.get("warnings") or []) + list(entry.get("notes") or []):
            parts.append(f'<p class="note">{_e(note)}</p>')
        if entry.get("faces"):
            parts.append('<div class="scroll"><table><thead><tr>'
                         + "".join(f"<th>{_e(h)}</th>" for h in heads) + "</tr></thead><tbody>")
            parts.append(_face_rows(entry["faces"], doc, unit, warn_fraction))
            parts.append("</tbody></table></div>")
            parts.append('<div class="small">Bars: share of the tolerance per direction (full at 100 %, red '
                         f"beyond); below: the {_e(metric)} in {_e(unit)}.</div>")
            parts.append(_advice_details(entry["faces"], doc, unit))
            parts.append(_criteria_table(entry, unit))
            if heatmaps and ftol:
                if pictures < HEATMAP_FILES:
                    parts.append(_heatmap(entry, doc, float(ftol), unit))
                    pictures += 1
                else:
                    parts.append(f'<p class="note">No heatmap: only the first {HEATMAP_FILES} files are drawn '
                                 f"(cadartifact view FILE draws any file).</p>")
        parts.append("</section>")
    if maps:
        parts.append(_response_maps(doc))
    parts.append(f"</main><footer>cadartifact {_e(__version__)} · schema {_e(doc.get('schema'))}"
                 f"{' · ' + _e(doc['gate']) if gate else ''}</footer></body></html>")
    return "\n".join(p for p in parts if p)


def write_report(doc: Document, path, *, heatmaps: bool = True, maps: bool = True) -> Path:
    """Write the document as one self-contained HTML page.

    Parameters
    ----------
    doc : dict
        An advise document (:class:`~cadartifact.runs.documents.advise.AdviseDocument`) or a gate document
        (:class:`~cadartifact.runs.documents.gate.GateDocument`, which adds verdicts).
    path : path-like
        The ``.html`` file, written atomically (temporary file + rename), in an existing folder.
    heatmaps : bool
        Embed one picture of the worst :data:`HEATMAP_FACES` faces per file (files are read again).
    maps : bool
        Embed the response maps of the schemes used.

    Returns
    -------
    Path
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise OptionError("report", "a file in an existing folder", str(path))
    from .facemaps import write_atomic

    return write_atomic(path, render_html(doc, heatmaps=heatmaps, maps=maps).encode("utf-8"))
