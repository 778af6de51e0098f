"""Wall-clock limits that used to be test assertions: each timed here, printed with its limit and the ratio.

    python benchmarks/time_limits.py [--repeat 3] [--no-design]

- the 6x6 C1 scheme design (``design(support=(6, 6), degree=2, objective="energy", continuity=1)``): under 60 s
  (tests/theory/test_design.py checks what it finds);
- the IGES reference check of a hood whose pointer count is corrupted to 999999999: under 1 s per file (a slot
  list per counted pointer took 5.5 s and 1 GB per ten million; tests/exchange/test_iges_refs.py checks that the
  slots stay within the record's parameters);
- the pointer slots of one such corrupted record: under 0.1 s.

The machine's load changes the times, not what the tests check: a ratio over 1 is a finding to look at, not a
failure of the suite. Exit status 1 when a best time is over its limit.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from timing import best_of  # benchmarks/timing.py, beside this script

#: The corrupted pointer counts (entity type, parameters) of tests/exchange/test_iges_refs.py.
SLOT_CASES = [
    (514, ["999999999", "3", "1"]), (510, ["3", "999999999", "1", "5"]), (144, ["3", "1", "999999999", "5"]),
    (143, ["1", "3", "999999999", "5"]), (102, ["999999999", "9"]), (504, ["999999999", "9", "11", "1", "11", "2"]),
    (508, ["999999999", "0", "7", "1", "0", "999999999", "0", "19"]),
    (141, ["1", "1", "3", "999999999", "5", "1", "999999999", "7"]),
]
#: (IGES writer mode, entity type, parameter index) of the corrupted counts in the hood's IGES files.
COUNT_CASES = [(0, 102, 0), (0, 144, 2), (1, 510, 1)]


def _row(name: str, seconds: float, limit: float) -> bool:
    print(f"{name:<58} {seconds * 1e3:10.2f} ms   limit {limit * 1e3:g} ms   ratio {seconds / limit:.4f}", flush=True)
    return seconds <= limit


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-design", action="store_true", help="skip the scheme design (about half a minute)")
    args = ap.parse_args(argv)
    ok = True

    from cadartifact.exchange.iges_refs import _pointer_slots, iges_problem
    from cadartifact.testing.iges_texts import directory, hood_as_iges, set_parameter

    for kind, params in SLOT_CASES:
        ok &= _row(f"pointer slots of a corrupted type {kind} record", best_of(lambda: _pointer_slots(kind, params),
                                                                             args.repeat), 0.1)
    with tempfile.TemporaryDirectory() as tmp:
        texts = {mode: hood_as_iges(Path(tmp), mode) for mode in (0, 1)}
    for mode, kind, index in COUNT_CASES:
        text = texts[mode]
        broken = set_parameter(text, 2 * directory(text).index(kind) + 1, index, "999999999")
        assert iges_problem(broken) is not None
        ok &= _row(f"IGES check, {'B-rep' if mode else 'faces'} hood, type {kind} count corrupted",
                   best_of(lambda: iges_problem(broken), args.repeat), 1.0)

    if not args.no_design:
        from cadartifact.theory.design import design

        ok &= _row("design 6x6, degree 2, energy, C1 (one run)",
                   best_of(lambda: design(support=(6, 6), degree=2, objective="energy", continuity=1), 1), 60.0)
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
