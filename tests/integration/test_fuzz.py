"""Fuzz: a few hundred seeded mutations of the samples and the small real files through the gate.

Every input ends in a documented outcome (:func:`fuzzing.check_entry`): a one-line ``error`` entry,
or a complete report with as many faces as the file declares and finite numbers; never an
exception, a crash of this process or a hang (the reader child is stopped after ``READ_TIMEOUT``).
Most inputs go through :func:`cadartifact.gate.run.gate_file` in this process (fast); a few through the
``cadartifact`` command in a subprocess (exit code, stderr, JSON). ``benchmarks/fuzz_campaign.py``
runs the same generator over 10 000 inputs and more.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import warnings

import pytest

from cadartifact.testing import fuzzing

pytest.importorskip("OCP")

#: Inputs per chunk x chunks (chunks spread the inputs over the xdist workers).
PER_CHUNK, CHUNKS = 50, 6
READ_TIMEOUT = 15.0
TOL = 0.05



def _gate_case(case, folder, settings):
    """``(path, entry)``: a mutated case written into ``folder`` and gated, its warnings silenced."""
    from cadartifact.gate.run import gate_file

    path = fuzzing.write_case(case, folder)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return path, gate_file(str(path), settings, read_timeout=READ_TIMEOUT)

@pytest.fixture(scope="module")
def sources():
    return fuzzing.default_sources(small=True)


@pytest.fixture(scope="module")
def baseline(sources):
    """Faces the gate analyses in each unmutated source."""
    from cadartifact.gate.run import gate_file
    from cadartifact.gate.policy import FileSettings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return {src.name: fuzzing.faces_analysed(gate_file(str(src), FileSettings(tolerance=TOL)))
                for src in sources}


@pytest.mark.slow
@pytest.mark.parametrize("chunk", range(CHUNKS))
def test_mutated_inputs_meet_the_contract_in_process(sources, baseline, tmp_path, chunk):
    from cadartifact.gate.policy import FileSettings

    settings = FileSettings(tolerance=TOL)
    violations, classes = [], {}
    for i, case in enumerate(fuzzing.mutations(sources, PER_CHUNK, seed=1400 + chunk)):
        path, entry = _gate_case(case, tmp_path / str(i), settings)
        cls = fuzzing.classify(entry, case)
        classes[cls] = classes.get(cls, 0) + 1
        for problem in fuzzing.check_entry(entry, path, case):
            violations.append(f"{case.source} {case.kind} -> {problem}")
        if fuzzing.silent_loss(entry, baseline[case.source]):
            violations.append(f"{case.source} {case.kind} -> silent loss: {fuzzing.faces_analysed(entry)} faces "
                              f"analysed, {baseline[case.source]} unmutated, nothing said")
    assert not violations, "\n".join(violations)
    assert sum(classes.values()) == PER_CHUNK


@pytest.mark.parametrize("kind", fuzzing.CHAIN_KINDS)
def test_every_break_of_the_chain_is_an_error_naming_the_entity(sources, tmp_path, kind):
    """Each chain mutation of every STEP source (samples, small real files), several seeds: an error entry
    whose message names the broken reference and the line of the entity that holds it."""
    from cadartifact.gate.policy import FileSettings

    settings = FileSettings(tolerance=TOL)
    steps = [src for src in sources if src.suffix.lower() != ".obj"]
    cases = list(fuzzing.mutations(steps, 3 * len(steps), seed=2700 + fuzzing.CHAIN_KINDS.index(kind), kinds=(kind,)))
    for i, case in enumerate(cases):
        path, entry = _gate_case(case, tmp_path / str(i), settings)
        assert entry["verdict"] == "error", (case.source, kind, entry["verdict"])
        assert fuzzing.classify(entry, case) == "error:reference", entry["error"]
        assert re.search(r"#\d+ .*\(line \d+\)", entry["error"]), entry["error"]


def test_mutated_inputs_through_the_command_line(sources, tmp_path):
    cases = list(fuzzing.mutations(sources, 8, seed=77, kinds=("flip", "truncate", "nan", "broken-ref",
                                                                 "multiplicity", "obj-index", "odd-name",
                                                                 "decreasing-knots")))
    for i, case in enumerate(cases):
        path = fuzzing.write_case(case, tmp_path / str(i))
        gate = subprocess.run([sys.executable, "-m", "cadartifact.cli", "gate", str(path), "--tol", str(TOL),
                               "--format", "json", "--jobs", "1", "--read-timeout", str(READ_TIMEOUT)],
                              capture_output=True, timeout=300, cwd=tmp_path)
        assert gate.returncode in (0, 1, 2) and b"Traceback" not in gate.stderr, (case.kind, gate.stderr)
        doc = json.loads(gate.stdout)  # a complete document whatever happened
        assert doc["exit_code"] == gate.returncode
        assert not fuzzing.check_entry(doc["files"][0], path, case), (case.kind, doc["files"][0])
        advise = subprocess.run([sys.executable, "-m", "cadartifact.cli", "advise", str(path), "--tol", str(TOL),
                                 "--json", "--no-compare", "--no-verify"], capture_output=True, timeout=300,
                                cwd=tmp_path)
        assert advise.returncode in (0, 1, 2) and b"Traceback" not in advise.stderr, (case.kind, advise.stderr)
        if advise.returncode == 2:
            assert advise.stdout == b"" and len(advise.stderr.strip().splitlines()) == 1, advise.stderr
        else:
            json.loads(advise.stdout)
        if doc["files"][0]["verdict"] == "error":  # what the gate could not read, advise refuses too
            assert advise.returncode == 2, (case.kind, doc["files"][0]["error"])


def test_the_generator_is_seeded(sources):
    a = [(c.source, c.kind, c.name, c.data) for c in fuzzing.mutations(sources, 40, seed=5)]
    b = [(c.source, c.kind, c.name, c.data) for c in fuzzing.mutations(sources, 40, seed=5)]
    assert a == b and len({c[3] for c in a}) > 30
    assert {c[1] for c in a} == set(fuzzing.KINDS)


@pytest.fixture(scope="module")
def iges_sources(tmp_path_factory):
    """IGES files OCCT writes from the samples (and MAINBODY_BACK when present), as faces and as B-rep."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fuzzing.iges_sources(tmp_path_factory.mktemp("iges"))


@pytest.mark.parametrize("kind", fuzzing.IGES_KINDS)
def test_every_break_of_an_iges_chain_is_an_error_naming_the_entities(iges_sources, tmp_path, kind):
    """Each IGES directory mutation of every IGES source, two seeds: an error entry naming the directory
    entries (``D<n>``) and a line, never a file that lost a face without a word."""
    from cadartifact.gate.policy import FileSettings

    settings = FileSettings(tolerance=TOL)
    cases = list(fuzzing.mutations(iges_sources, 2 * len(iges_sources), seed=2400 + fuzzing.IGES_KINDS.index(kind),
                                   kinds=(kind,)))
    changed = 0
    for i, case in enumerate(cases):
        original = next(s for s in iges_sources if s.name == case.source).read_bytes()
        if case.data == original:
            continue
        changed += 1
        path, entry = _gate_case(case, tmp_path / str(i), settings)
        assert entry["verdict"] == "error", (case.source, kind, entry["verdict"])
        assert fuzzing.classify(entry, case) == "error:reference", entry["error"]
        assert re.search(r"D\d+ .*line \d+", entry["error"]) and "\n" not in entry["error"], entry["error"]
    assert changed >= len(iges_sources)


@pytest.mark.slow
def test_mutated_iges_inputs_meet_the_contract(iges_sources, tmp_path):
    from cadartifact.gate.run import gate_file
    from cadartifact.gate.policy import FileSettings

    settings = FileSettings(tolerance=TOL)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        base = {src.name: fuzzing.faces_analysed(gate_file(str(src), settings)) for src in iges_sources}
        violations = []
        for i, case in enumerate(fuzzing.mutations(iges_sources, 40, seed=2424)):
            path = fuzzing.write_case(case, tmp_path / str(i))
            entry = gate_file(str(path), settings, read_timeout=READ_TIMEOUT)
            violations += [f"{case.source} {case.kind} -> {p}" for p in fuzzing.check_entry(entry, path, case)]
            if fuzzing.silent_loss(entry, base[case.source]):
                violations.append(f"{case.source} {case.kind} -> silent loss")
    assert not violations, "\n".join(violations)
