"""The gate's result cache: hits, misses on a changed byte / policy / version, corrupt entries, reports.

The second road for every cached number: the same files gated without a cache, whose documents
(json, text, junit, sarif, html) must equal the warm run's byte for byte. Which files were
analysed is counted by wrapping :func:`cadartifact.gate.run.gate_file`, not by the cache's own counters.
"""

import json
import threading

import pytest
from typer.testing import CliRunner

import cadartifact
import cadartifact.gate.run as gate
from cadartifact.cli.app import app
from cadartifact.gate.cache import GateCache, cache_key, file_digest

from cadartifact.testing.outcomes import no_traceback
from cadartifact.testing.vault_support import SAMPLES, TOL, documents, settings_for, small_set

pytest.importorskip("OCP")


@pytest.fixture()
def counted(monkeypatch):
    """Paths analysed by the in-process gate (jobs=1), in order."""
    seen = []
    real = gate.gate_file

    def counting(path, settings, verify=False, *args, **kwargs):  # kwargs: the run's sharing and reuse
        seen.append(path)
        return real(path, settings, verify, *args, **kwargs)

    monkeypatch.setattr(gate, "gate_file", counting)
    return seen


def gated(files, cache=None, tol=TOL):
    policy, cli, settings = settings_for(files, tol)
    return gate.run_gate(files, settings, jobs=1, cache=cache), policy, cli


def test_warm_cache_gives_the_same_documents_and_analyses_nothing(tmp_path, counted):
    files = small_set(tmp_path / "in", real=False)
    plain, policy, cli = gated(files)
    expected = documents(plain, policy, cli, tmp_path)
    counted.clear()
    cache = GateCache(tmp_path / "cache")
    cold, *_ = gated(files, cache)
    assert len(counted) == len(files) and cache.hits == 0
    counted.clear()
    progress = []
    policy, cli, settings = settings_for(files)
    warm = gate.run_gate(files, settings, jobs=1, cache=GateCache(tmp_path / "cache"),
                         progress=lambda entry, cached=False: progress.append((entry["path"], cached)))
    # error entries are never cached: the broken file is read again, fail closed on fresh evidence
    assert counted == [str(files[-1])]
    assert sorted(progress) == sorted((str(f), f.name != "broken.step") for f in files)
    for run in (cold, warm):
        got = documents(run, policy, cli, tmp_path)
        for fmt in expected:
            assert got[fmt] == expected[fmt], fmt
    assert json.loads(expected["json"])["exit_code"] == 2


def test_changed_byte_policy_or_version_is_a_miss(tmp_path, counted, monkeypatch):
    files = small_set(tmp_path / "in", real=False)[:3]
    gated(files, GateCache(tmp_path / "c"))
    counted.clear()
    # one byte more (a STEP comment line keeps the geometry: still a new key)
    step = next(f for f in files if f.suffix == ".step")
    step.write_bytes(step.read_bytes() + b"\n")
    again, *_ = gated(files, GateCache(tmp_path / "c"))
    assert counted == [str(step)]
    counted.clear()
    gated(files, GateCache(tmp_path / "c"), tol=2 * TOL)  # the policy of every file changed
    assert counted == [str(f) for f in files]
    counted.clear()
    gated(files, GateCache(tmp_path / "c"))  # back to the first policy: all hits
    assert counted == []
    monkeypatch.setattr(cadartifact, "__version__", cadartifact.__version__ + ".post1")
    gated(files, GateCache(tmp_path / "c"))
    assert counted == [str(f) for f in files]


def test_key_covers_content_policy_verify_and_version(tmp_path, monkeypatch):
    from cadartifact.gate.policy import FileSettings

    f = tmp_path / "a.step"
    f.write_bytes(b"abc")
    s = FileSettings(tolerance=0.1)
    k = cache_key(file_digest(f), s, False)
    assert len(k) == 64 and cache_key(file_digest(f), FileSettings(tolerance=0.1), False) == k
    variants = [cache_key(file_digest(f), FileSettings(tolerance=0.1, ignore_faces=(2,)), False),
                cache_key(file_digest(f), FileSettings(tolerance=0.1, metric="rms"), False),
                cache_key(file_digest(f), s, True)]
    f.write_bytes(b"abd")
    variants.append(cache_key(file_digest(f), s, False))
    monkeypatch.setattr(cadartifact, "__version__", "9.9.9")
    f.write_bytes(b"abc")
    variants.append(cache_key(file_digest(f), s, False))
    assert len(set(variants + [k])) == len(variants) + 1


@pytest.mark.parametrize("damage", ["truncate", "garbage", "tamper", "other key"])
def test_a_corrupt_entry_is_ignored_and_rewritten(tmp_path, counted, damage):
    files = [small_set(tmp_path / "in", real=False)[2]]  # clean_panel.step
    first, policy, cli = gated(files, GateCache(tmp_path / "c"))
    entry_file = next((tmp_path / "c").glob("*/*.json"))
    text = entry_file.read_text()
    if damage == "truncate":
        entry_file.write_text(text[: len(text) // 2])
    elif damage == "garbage":
        entry_file.write_bytes(b"\x00\xff not json")
    elif damage == "tamper":  # valid JSON, but the verdict flipped: the checksum no longer matches
        head, body = text.split("\n", 1)
        assert '"verdict":"pass"' in body
        entry_file.write_text(head + "\n" + body.replace('"verdict":"pass"', '"verdict":"fail"'))
    else:  # a whole entry, but of another key
        head, body = text.split("\n", 1)
        meta = json.loads(head)
        meta["key"] = "0" * 64
        entry_file.write_text(json.dumps(meta) + "\n" + body)
    counted.clear()
    cache = GateCache(tmp_path / "c")
    second, *_ = gated(files, cache)
    assert counted == [str(files[0])] and cache.rejected == 1
    assert documents(second, policy, cli, tmp_path) == documents(first, policy, cli, tmp_path)
    counted.clear()
    gated(files, GateCache(tmp_path / "c"))  # rewritten whole: a hit now
    assert counted == []


def test_an_identical_copy_elsewhere_is_a_hit_relocated_to_its_path(tmp_path, counted):
    src = small_set(tmp_path / "a", real=False)[:2]
    gated(src, GateCache(tmp_path / "c"))
    copies = small_set(tmp_path / "b" / "deeper", real=False)[:2]
    counted.clear()
    warm, policy, cli = gated(copies, GateCache(tmp_path / "c"))
    assert counted == []
    plain, *_ = gated(copies)
    assert documents(warm, policy, cli, tmp_path) == documents(plain, policy, cli, tmp_path)
    assert [e["path"] for e in warm] == [str(p) for p in copies]


def test_concurrent_writers_never_expose_a_partial_entry(tmp_path):
    cache = GateCache(tmp_path / "c")
    key = "ab" * 32
    entry = {"path": "x.step", "verdict": "pass", "faces": [{"n": i, "v": [0.1] * 50} for i in range(200)]}
    seen, stop = [], threading.Event()

    def write():
        for _ in range(40):
            assert GateCache(tmp_path / "c").store(key, entry)

    def read():
        while not stop.is_set():
            got = cache.load(key, "x.step")
            seen.append(got is None or got == entry)

    readers = [threading.Thread(target=read) for _ in range(2)]
    writers = [threading.Thread(target=write) for _ in range(3)]
    for t in readers + writers:
        t.start()
    for t in writers:
        t.join()
    stop.set()
    for t in readers:
        t.join()
    assert seen and all(seen) and cache.rejected == 0
    assert cache.load(key, "x.step") == entry
    assert not list((tmp_path / "c").glob("*/*.tmp"))  # no temporary file left behind


def test_error_entries_are_not_stored(tmp_path):
    cache = GateCache(tmp_path / "c")
    assert not cache.store("cd" * 32, {"path": "x", "verdict": "error", "error": "x: broken", "faces": []})
    assert not list((tmp_path / "c").glob("*/*"))


# ---------------------------------------------------------------- command line
def run(*args):
    result = CliRunner().invoke(app, ["gate", *map(str, args)])
    no_traceback(result)
    return result


def test_cli_cache_option_and_policy_key(tmp_path, monkeypatch):
    import shutil

    monkeypatch.chdir(tmp_path)
    shutil.copy(SAMPLES / "clean_panel.step", tmp_path / "clean_panel.step")
    (tmp_path / "sub").mkdir()
    (tmp_path / "cadartifact.toml").write_text(f'tolerance = {TOL}\ncache = "store"\n')
    monkeypatch.chdir(tmp_path / "sub")  # the policy's cache folder is relative to the policy file
    cold = run("../clean_panel.step", "--jobs", "1", "--format", "json")
    warm = run("../clean_panel.step", "--jobs", "1", "--format", "json")
    assert cold.exit_code == warm.exit_code == 0
    assert cold.stdout == warm.stdout
    assert list((tmp_path / "store").glob("*/*.json"))
    assert "(cached)" in warm.stderr and "(cached)" not in cold.stderr
    assert "[1/1] pass" in warm.stderr
    other = run("../clean_panel.step", "--jobs", "1", "--format", "json", "--cache", tmp_path / "other")
    assert other.stdout == cold.stdout and "(cached)" not in other.stderr
    assert list((tmp_path / "other").glob("*/*.json"))


def test_cli_cache_errors_are_one_line(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile").write_text("x")
    result = run(SAMPLES / "clean_panel.step", "--tol", TOL, "--cache", tmp_path / "afile")
    assert result.exit_code == 2 and "gate cache" in result.output and len(result.output.strip().splitlines()) == 1
    (tmp_path / "cadartifact.toml").write_text("tolerance = 1\ncache = 3\n")
    result = run(SAMPLES / "clean_panel.step")
    assert result.exit_code == 2 and "'cache'" in result.output and "expected a folder path" in result.output


def test_progress_counts_done_cached_and_failed():
    import io

    from rich.console import Console

    from cadartifact.gate.progress import GateProgress

    entries = [({"path": "a.step", "verdict": "pass"}, True), ({"path": "b.step", "verdict": "fail"}, False),
               ({"path": "c.step", "verdict": "error"}, False)]
    buf = io.StringIO()
    with GateProgress(Console(file=buf, force_terminal=False, width=100), 3) as progress:
        for e, cached in entries:
            progress(e, cached=cached)
    assert buf.getvalue().splitlines() == ["[1/3] pass  a.step (cached)", "[2/3] fail  b.step", "[3/3] error c.step"]
    assert (progress.done, progress.cached, progress.failed) == (3, 1, 2)
    buf = io.StringIO()
    with GateProgress(Console(file=buf, force_terminal=True, width=100), 3) as progress:
        for e, cached in entries:
            progress(e, cached=cached)
        progress._bar.refresh()
        assert "1 cached, 2 failed" in buf.getvalue()
