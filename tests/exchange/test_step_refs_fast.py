"""The reference scan's fast paths (issue 27, the 5 % target) decide exactly what the exact scans decide.

- :func:`step_refs._references_defined` (every ``#N`` names a record, by array operations on the bytes) says
  True only when the exact scan (:func:`step_refs._missing_reference` on the set of every reference) finds no
  missing reference: over mutants of the samples with a byte flipped, inserted or deleted next to a ``#``, ids
  renumbered, leading zeros, long ids, spaces before ``=``.
- :func:`step_refs._point_shapes_ok` (a point statement's digit runs made one ``0``, the distinct shapes matched)
  accepts a list of point statements exactly when the point regex accepts every one of them.
"""

from __future__ import annotations

import random
import re

import pytest

from cadartifact.exchange import step_refs
from cadartifact.exchange.step_scan import clean_data, data_section, record_heads
from cadartifact.testing.paths import ROOT

SAMPLES = sorted((ROOT / "samples").glob("*.step"))


def _exact_all_defined(clean: str, heads) -> bool:
    return set(re.findall(r"#(\d+)", clean)) <= {ident for ident, _ in heads}


def _mutants(text: str, rng: random.Random, n: int):
    hashes = [m.start() for m in re.finditer("#", text)]
    noise = ["0", "9", "#", "=", " ", "\n", "  =", ";", "00", "#0", "1234567890123", " " * 20, "\xa0", "a", ","]
    for _ in range(n):
        at = rng.choice(hashes) + rng.randint(0, 6)
        kind = rng.randrange(3)
        if kind == 0:
            yield text[:at] + rng.choice(noise) + text[at:]
        elif kind == 1:
            yield text[:at] + text[at + rng.randint(1, 3):]
        else:
            yield text[:at] + rng.choice(noise) + text[at + 1:]


@pytest.mark.parametrize("path", SAMPLES, ids=lambda p: p.name)
def test_references_defined_never_says_yes_when_a_reference_is_missing(path):
    rng = random.Random(27)
    text = path.read_bytes().decode("latin-1")
    seen = {True: 0, False: 0}
    for mutant in _mutants(text, rng, 300):
        clean = clean_data(data_section(mutant))
        heads = record_heads(clean)
        exact = _exact_all_defined(clean, heads)
        fast = step_refs._references_defined(clean, heads)
        seen[exact] += 1
        if fast:
            assert exact, "the array scan passed a text with a missing reference"
    assert seen[True] and seen[False]


def test_references_defined_edge_cases():
    cases = [("#1=A(#2,#3);#2=B();#3=C(#7);#7=D();", True), ("#1=A(#2,#3);#2=B();#3=C(#9);#7=D();", False),
             ("#1=A(#2,#3);#2=B();#3=C(#007);#7=D();", False),  # a leading zero: the exact scan decides
             ("#1=A(#2,#3);#2=B();#3=C(#7=#2);#7=D();", False),  # '#7=' inside a record
             ("#1=A(#2,#30);#2=B();#30=C(#0);#0=D(#);", True),
             ("#1=A(#2,#1234567890123);#2=B();", False),
             ("#1=A(#2,#123456789012);#2=B();#123456789012\n\n=C();", True),
             ("#1=A(#2,#123456789013);#2=B();#123456789012=C();", False),
             ("#1=A(#2);#2" + " " * 20 + "=B();", False), ("#10=A(#99);#99=B(#10);", True),
             ("#10=A(#98);#99=B(#10);", False), ("#1=A(#2);#2\xa0=B();", True), ("#1=A(#3);#1=B();", False)]
    for body, want in cases:
        clean = clean_data("DATA;\n" + body + "\nENDSEC;\nEND-ISO-10303-21;\n")
        heads = record_heads(clean)
        assert step_refs._references_defined(clean, heads) == want, body
        if want:
            assert _exact_all_defined(clean, heads)


def test_point_shapes_agree_with_the_point_regex():
    rng = random.Random(2727)
    pieces = ["1.", "-2.5", "+.5", "3.E-4", "12", "1.5E+10", ".", "E", "1..2", "1.5 3", "1e", "-", "0.0", "7",
              " 4.25 ", "\n5.", "1,2", "(1)", "$", "''"]
    for _ in range(3000):
        count = rng.choice([2, 3, 3, 3, 4])
        coords = ",".join(rng.choice(pieces[:6] if rng.random() < 0.6 else pieces) for _ in range(count))
        name = rng.choice(["''", "$", "'a'", "''", "x"])
        space = rng.choice(["", " ", "\n  ", "\xa0"])
        stmt = f"\n#{rng.randint(1, 99999)}{space}={space}CARTESIAN_POINT{space}({name},({coords}){space})"
        if rng.random() < 0.05:
            stmt += rng.choice([",4)", "x", ";"])
        statements = [stmt, "#5=CARTESIAN_POINT('',(1.,2.,3.))"]
        rng.shuffle(statements)
        joined = ";".join(statements)
        regex = all(step_refs._BATCH_POINT.fullmatch(s) for s in joined.split(";"))
        assert step_refs._point_shapes_ok(joined) == regex, joined
