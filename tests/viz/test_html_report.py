"""The self-contained HTML report: structure (tables, embedded pictures, no external resources),
the numbers in it against the document, advise --report and gate --report, a Chromium screenshot."""

import base64
import json
import shutil
import subprocess
from html.parser import HTMLParser

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("OCP")
pytest.importorskip("pyvista")

import cadartifact as ca  # noqa: E402
from cadartifact.cli.app import app  # noqa: E402
from cadartifact.errors import OptionError  # noqa: E402
from cadartifact.net import ControlNet, NetOrigin  # noqa: E402
from cadartifact.runs.advising import advise_files  # noqa: E402
from cadartifact.viz import html as H  # noqa: E402

TOL = 0.006  # between the mild ridge (0.0034 mm) and the sharp one (0.0127 mm)


def ridge_points(nu=14, nv=10, amp=2.0, width=9.0, dy=0.0):
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    x, y = 100.0 * i / (nu - 1), 80.0 * j / (nv - 1) + dy
    d = x - 50.0
    z = amp * np.where(np.abs(d) < width, 0.5 * (1 + np.cos(np.pi * d / width)), 0.0) ** 2
    return np.stack([x, y, z], axis=-1)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    from cadartifact.exchange.load import write_step

    root = tmp_path_factory.mktemp("html")
    mild = ControlNet.from_points(ridge_points(amp=0.3, width=14.0, dy=100.0), origin=NetOrigin(kind="bspline"))
    sharp = ControlNet.from_points(ridge_points(), origin=NetOrigin(kind="bspline"))
    write_step([mild, sharp], root / "pair.step")
    write_step([mild], root / "mild.step")
    return root


@pytest.fixture(scope="module")
def doc(files):
    return advise_files([files / "pair.step", files / "mild.step"], TOL, compare=False, verify=False)


class Page(HTMLParser):
    """Collects tags, image sources, table rows (cell texts) and every attribute value."""

    def __init__(self):
        super().__init__()
        self.tags, self.imgs, self.tables, self.attrs = [], [], [], []
        self._row = self._cell = None

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        a = dict(attrs)
        self.attrs += [v or "" for v in a.values()]
        if tag == "img":
            self.imgs.append(a)
        elif tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self._row = []
        elif tag == "td" and self._row is not None:
            self._cell = []

    def handle_endtag(self, tag):
        if tag == "td" and self._cell is not None:
            self._row.append(" ".join("".join(self._cell).split()))
            self._cell = None
        elif tag == "tr" and self._row is not None:
            if self._row:
                self.tables[-1].append(self._row)
            self._row = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def parse(path):
    page = Page()
    text = path.read_text(encoding="utf-8")
    page.feed(text)
    return page, text


def test_structure_is_self_contained(doc, tmp_path):
    out = H.write_report(doc, tmp_path / "report.html")
    page, text = parse(out)
    assert text.startswith("<!DOCTYPE html>")
    assert len(page.tables) == 2  # one per file with faces
    heat = [i for i in page.imgs if i.get("class") == "heatmap"]
    maps = [i for i in page.imgs if i.get("class") == "maps"]
    pairs = [i for i in page.imgs if i.get("class") in ("face-heatmap", "reflection")]
    drawn = sum(min(H.HEATMAP_FACES, len(e["faces"])) for e in doc["files"] if e["faces"])
    # the file's tiled heatmap, then per drawn face its heatmap and reflection lines side by side
    assert len(heat) == 2 and len(maps) == 1 and len(page.imgs) == 3 + len(pairs)
    assert [i["class"] for i in pairs] == ["face-heatmap", "reflection"] * drawn
    assert all(i["alt"].endswith("reflection lines") for i in pairs if i["class"] == "reflection")
    for img in page.imgs:
        assert img["src"].startswith("data:image/png;base64,")
        assert base64.b64decode(img["src"].split(",", 1)[1])[:8] == b"\x89PNG\r\n\x1a\n"
    assert "http://" not in text and "https://" not in text and "//" not in "".join(
        a for a in page.attrs if not a.startswith("data:"))
    assert "script" not in page.tags and "link" not in page.tags and "iframe" not in page.tags
    assert not list(tmp_path.glob(".*tmp"))


def test_tables_list_worst_first_with_the_document_numbers(doc, tmp_path):
    page, _ = parse(H.write_report(doc, tmp_path / "r.html", heatmaps=False, maps=False))
    assert page.imgs == []
    for table, entry in zip(page.tables, doc["files"]):
        faces = {f["face"]: f for f in entry["faces"]}
        shown = [int(row[0].split()[0]) for row in table]
        assert sorted(shown) == sorted(faces)
        shares = [faces[i]["share"]["total"] for i in shown]
        assert shares == sorted(shares, reverse=True)
        for row in table:
            f = faces[int(row[0].split()[0])]
            assert row[1] == "×".join(map(str, f["net"])) and row[2] == f["scheme"] and row[3] == f["method"]
            # X1 cell: share in % and the peak
            x1 = row[4]
            pct = f["share"]["x1"] * 100
            assert (f"{pct:.0f}" if pct >= 100 else f"{pct:.1f}") in x1
            assert row[10].startswith("×".join(map(str, f["advice"]["net"])))
            assert row[10 + 1] == ("within" if f["meets_tolerance"] else
                                   "undecided" if f.get("decision") == "undecided" else "exceeds")
    # the sharp ridge exceeds, the mild one does not: both verdicts are on the page
    verdicts = {row[11] for t in page.tables for row in t}
    assert verdicts == {"within", "exceeds"}


def test_numbers_agree_with_an_independent_budget(doc, files):
    """The document's ripple (advise road) equals budget() on the loaded faces (a separate call path)."""
    nets = {n.origin.face: n for n in ca.load(files / "pair.step")}
    for f in doc["files"][0]["faces"]:
        b = ca.budget(nets[f["face"]], tolerance=TOL)
        assert f["budget"]["total"]["peak"] == pytest.approx(b.stats["total"].peak, abs=1e-9)
        assert f["share"]["x1"] == pytest.approx(b.share("x1"), abs=1e-7)


def test_gate_document_with_verdicts_and_an_error_file(files, tmp_path):
    broken = tmp_path / "broken.step"
    broken.write_text("ISO-10303-21;\nnot a step file\n")
    report = tmp_path / "gate.html"
    result = CliRunner().invoke(app, ["gate", str(files / "pair.step"), str(broken), "--tol", str(TOL),
                                      "--jobs", "1", "--format", "json", "--report", str(report)])
    assert result.exit_code == 2, result.output
    gate_doc = json.loads(result.stdout)
    page, text = parse(report)
    assert len(page.tables) == 1 and len([i for i in page.imgs if i.get("class") == "heatmap"]) == 1
    face_verdicts = sorted(f["verdict"] for f in gate_doc["files"][0]["faces"])
    assert sorted(row[11] for row in page.tables[0]) == face_verdicts
    assert "not a readable STEP file" in text and 'class="error"' in text
    assert "quality gate" in text and "b-error" in text


def test_advise_report_option(files, tmp_path):
    out = tmp_path / "advise.html"
    result = CliRunner().invoke(app, ["advise", str(files / "mild.step"), "--tol", "1", "--no-compare",
                                      "--no-verify", "--report", str(out)])
    assert result.exit_code == 0, result.output
    assert f"wrote {out}" in result.stdout.replace("\n", "")
    page, _ = parse(out)
    assert len(page.tables) == 1 and len(page.imgs) == 2 + 2  # heatmap, maps, the face's ripple and reflection lines


def test_advise_report_bad_folder_is_a_usage_error(files, tmp_path):
    result = CliRunner().invoke(app, ["advise", str(files / "mild.step"), "--tol", "1",
                                      "--report", str(tmp_path / "no" / "r.html")])
    assert result.exit_code == 2 and "--report: expected a file in an existing folder" in result.stderr


def test_bad_documents_and_paths(doc, tmp_path):
    with pytest.raises(OptionError, match="doc"):
        H.write_report({"schema": "x"}, tmp_path / "r.html")
    with pytest.raises(OptionError, match="report"):
        H.write_report(doc, tmp_path / "missing" / "r.html")
    assert list(tmp_path.iterdir()) == []


def test_missing_source_file_gives_a_note_not_a_failure(doc, files, tmp_path):
    moved = json.loads(json.dumps(doc))
    moved["files"][1]["path"] = str(tmp_path / "gone.step")
    page, text = parse(H.write_report(moved, tmp_path / "r.html", maps=False))
    assert len([i for i in page.imgs if i.get("class") == "heatmap"]) == 1
    assert "No heatmap:" in text and "file not found" in text


def test_chromium_renders_the_page(doc, tmp_path):
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        pytest.skip("chromium is not on PATH (CI installs it: apt-get install chromium)")
    report = H.write_report(doc, tmp_path / "r.html")
    shot = tmp_path / "shot.png"
    subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                    "--disable-background-networking", "--disable-component-update", "--disable-sync",
                    f"--user-data-dir={tmp_path / 'profile'}", f"--screenshot={shot}", "--window-size=1200,900",
                    report.as_uri()], capture_output=True, timeout=120, check=False)
    import matplotlib.image as mpimg

    img = mpimg.imread(str(shot))
    assert img.shape[:2] == (900, 1200)
    assert img[..., :3].std() > 0.05
