"""Mirrored, reversed, transposed and moved copies of a face get the same advice.

Each face (jointed faces with a crease, faces extended past their trims with a bent join, a rational face) is
advised as it is and as five copies: ``u`` and ``v`` swapped, ``u`` reversed, ``v`` reversed (knots, poles, weights
and trim mapped), mirrored in ``x``, and rotated and moved in space. The copies are the same surface, so the advice
must be the same density (transposed where ``u`` and ``v`` swap), the same verdict, and the same value to rounding.
Before, a tie among the pieces' spans went to the first piece and a sample on a join was read by the first piece:
the reversed copy of a jointed face was advised 11x6 (0.00498) against the original's 12x6 (0.00246).
"""

from __future__ import annotations

import pytest

import cadartifact as ca
from cadartifact.testing.mirrored_faces import copies
from cadartifact.testing.extended_faces import extended_face, jointed_face, smooth_face
from cadartifact.testing.rational_faces import rational_face


FACES = {
    "jointed C0 a": lambda: jointed_face(pieces=2, seed=0),
    "jointed C0 b": lambda: jointed_face(pieces=2, seed=2),
    "jointed 3 pieces": lambda: jointed_face(pieces=3, seed=4),
    "extended u1, trimmed": lambda: extended_face(smooth_face(n=(7, 6), amplitude=6.0, seed=0), sides=("u1",),
                                                  ext=0.03, bend=0.02, trim="third"),
    "extended u0 v1, trimmed": lambda: extended_face(smooth_face(n=(7, 6), amplitude=6.0, seed=1),
                                                     sides=("u0", "v1"), ext=0.03, bend=0.02, trim="third"),
    "extended all sides, p-1": lambda: extended_face(smooth_face(n=(8, 7), amplitude=5.0, seed=3),
                                                     sides=("u0", "u1", "v0", "v1"), ext=0.02, mult=2),
    "rational": lambda: rational_face(3),
}


def _same(a, b, swapped: bool) -> None:
    assert (b.shape[::-1] if swapped else b.shape) == a.shape
    assert b.meets_tolerance == a.meets_tolerance and b.decision == a.decision
    assert b.value == pytest.approx(a.value, rel=1e-6, abs=1e-12)


#: The fast lane's cases; the rest are marked slow (each advises six copies).
FAST = {("jointed C0 b", 0.05), ("jointed 3 pieces", 0.05), ("rational", 0.05)}


@pytest.mark.parametrize("name, tolerance", [
    pytest.param(n, t, marks=() if (n, t) in FAST else pytest.mark.slow) for n in sorted(FACES) for t in (0.05, 0.005)])
def test_copies_get_the_same_advice(name, tolerance):
    net = FACES[name]()
    first = ca.advise(net, tolerance=tolerance, verify=False)
    for copy_name, copy in copies(net).items():
        _same(first, ca.advise(copy, tolerance=tolerance, verify=False), copy_name == "transpose")


def test_a_tie_among_pieces_follows_the_geometry():
    """Two pieces of equal spans and an odd count: the extra span goes to the piece that bends more, in either
    order of the pieces."""
    from cadartifact.advice.joins import join_plan, piece_spans

    net = jointed_face(pieces=2, seed=2)
    plan = join_plan(net, 0)
    rev = join_plan(copies(net)["reverse u"], 0)
    assert plan.spans == rev.spans == (4, 4)
    assert plan.demand == rev.demand[::-1]
    for total in (3, 5, 7, 9):
        assert plan.per(total) == rev.per(total)[::-1]
    assert piece_spans(5, (4, 4)) == [3, 2]  # no demand: the first piece, as before
    assert piece_spans(5, (4, 4), (0.5, 1.0)) == [2, 3]
