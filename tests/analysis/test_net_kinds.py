"""The two kinds of net: a B-spline face or a subdivision cage, told apart by ``ControlNet.form``.

No code path decides what a net is by its knots or degrees being None: an AST scan of the package finds every
``is None`` / ``is not None`` comparison (and every bare truth test) on a ``.knots`` or ``.degrees`` attribute, and
only the constructor, which settles the form from its arguments, and the schemes' optional degrees (a scheme, not
a net) may have one.
"""

from __future__ import annotations

import ast
import copyreg
import pickle
import warnings
from pathlib import Path

import numpy as np
import pytest

import cadartifact
from cadartifact.errors import InvalidNetError, OptionError
from cadartifact.exchange.load import read
from cadartifact.net import NET_FORMS, ControlNet, NetOrigin, clamped_uniform_knots, periodic_uniform_knots

PACKAGE = Path(cadartifact.__file__).resolve().parent
SAMPLES = PACKAGE.parent / "samples"
ATTRIBUTES = ("knots", "degrees")

#: Functions of net.py that settle a net's form and knots from the arguments they were given.
CONSTRUCTOR = {("net.py", "ControlNet.__post_init__"), ("net.py", "ControlNet._settle_spline")}

#: ``(module, subject)`` of the comparisons on a *scheme's* degrees: optional data of a subdivision scheme (None
#: unless it is a tensor B-spline scheme), not a net's kind.
SCHEME_DEGREES = {
    ("advice/scheme_comparison.py", "sch.degrees"),
    ("advice/scheme_comparison.py", "other.degrees"),
    ("advice/scorer.py", "scheme.degrees"),
    ("analysis/budget.py", "scheme.degrees"),
    ("analysis/clamped.py", "getattr(scheme, 'degrees', None)"),
    ("analysis/fields.py", "scheme.degrees"),
    ("analysis/measure.py", "scheme.degrees"),
    ("runs/advising.py", "get_scheme(adv.scheme).degrees"),
    ("theory/catalogue.py", "self.degrees"),  # Scheme.__post_init__ checks its own degrees
}


def _subject(node) -> ast.AST | None:
    """``x.knots`` / ``x.degrees`` or ``getattr(x, "knots", ...)``, else None."""
    if isinstance(node, ast.Attribute) and node.attr in ATTRIBUTES:
        return node
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "getattr"
            and len(node.args) >= 2 and isinstance(node.args[1], ast.Constant) and node.args[1].value in ATTRIBUTES):
        return node
    return None


def _is_none(node) -> bool:
    return isinstance(node, ast.Constant) and node.value is None


def none_decisions(tree: ast.AST):
    """``(function, subject source, line)`` of every None comparison or bare truth test on knots/degrees."""
    out = []

    def visit(node, where):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            where = f"{where}.{node.name}" if where else node.name
        subjects = []
        if isinstance(node, ast.Compare) and any(isinstance(op, (ast.Is, ast.IsNot, ast.Eq, ast.NotEq))
                                                 for op in node.ops):
            operands = [node.left, *node.comparators]
            if any(map(_is_none, operands)):
                subjects += [s for s in map(_subject, operands) if s is not None]
        tests = []
        if isinstance(node, (ast.If, ast.IfExp, ast.While, ast.Assert)):
            tests = [node.test]
        elif isinstance(node, ast.BoolOp):
            tests = node.values
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
            tests = [node.operand]
        elif isinstance(node, ast.comprehension):
            tests = node.ifs
        subjects += [s for s in map(_subject, tests) if s is not None]
        out.extend((where, ast.unparse(s), s.lineno) for s in subjects)
        for child in ast.iter_child_nodes(node):
            visit(child, where)

    visit(tree, "")
    return out


def package_decisions():
    """``(module relative to the package, function, subject, line)`` over every module of the package."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        module = path.relative_to(PACKAGE).as_posix()
        found += [(module, *hit) for hit in none_decisions(ast.parse(path.read_text(), filename=str(path)))]
    return found


def test_no_code_path_decides_a_net_kind_by_none():
    found = package_decisions()
    bad = [f"{module}:{line} {function}: {subject}" for module, function, subject, line in found
           if (module, function) not in CONSTRUCTOR and (module, subject) not in SCHEME_DEGREES]
    assert not bad, "ask net.is_bspline (ControlNet.form), not whether knots/degrees are None:\n" + "\n".join(bad)


def test_allow_list_has_no_stale_entries():
    """Each allowed comparison still exists: an entry left behind would hide a new one on a net."""
    found = package_decisions()
    assert {(m, s) for m, _, s, _ in found} >= SCHEME_DEGREES
    assert {(m, f) for m, f, _, _ in found} >= CONSTRUCTOR


@pytest.mark.parametrize("source, expected", [
    ("if net.knots is None:\n    pass", ["net.knots"]),
    ("x = 1 if face.degrees is not None else 2", ["face.degrees"]),
    ("ok = a and getattr(net, 'knots', None) is not None", ["getattr(net, 'knots', None)"]),
    ("y = [n for n in nets if n.degrees]", ["n.degrees"]),
    ("z = list(net.degrees) if net.degrees else None", ["net.degrees"]),
    ("if net.is_bspline:\n    k = net.knots[0]", []),
])
def test_the_scan_finds_what_it_should(source, expected):
    assert [subject for _, subject, _ in none_decisions(ast.parse(source))] == expected


# ---------------------------------------------------------------- the kind of the nets a reader makes
def _quiet_read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read(path)


def test_obj_charts_are_cages():
    nets = _quiet_read(SAMPLES / "cage.obj").nets
    assert nets
    for net in nets:
        assert net.form == "cage" and not net.is_bspline
        assert net.degrees is None and net.knots is None
        assert repr(net).startswith(f"<ControlNet {net.shape[0]}x{net.shape[1]} cage ")


def test_step_faces_are_bsplines():
    nets = _quiet_read(SAMPLES / "clean_panel.step").nets  # read in the reader child: the nets come pickled
    assert nets
    for net in nets:
        assert net.form == "bspline" and net.is_bspline
        assert len(net.degrees) == 2 and len(net.knots) == 2


# ---------------------------------------------------------------- settling, pickling, errors
def _points(nu=6, nv=5):
    i, j = np.meshgrid(np.arange(float(nu)), np.arange(float(nv)), indexing="ij")
    return np.stack([i, j, np.sin(i) * np.cos(j)], axis=-1)


def test_form_is_settled_from_the_arguments():
    assert ControlNet(points=_points()).form == "cage"
    assert ControlNet.from_points(_points(), degrees=None).form == "cage"
    face = ControlNet.from_points(_points(), degrees=(3, 2))
    assert face.form == "bspline" and face.degrees == (3, 2)
    assert ControlNet(points=_points(), form="cage").form == "cage"
    assert ControlNet(points=_points(), degrees=(3, 2), knots=face.knots, form="bspline").is_bspline


def test_a_bspline_net_without_knots_gets_uniform_ones():
    given = ControlNet(points=_points(), degrees=(3, 2))
    for k, (n, d) in enumerate(zip(given.shape, given.degrees)):
        np.testing.assert_array_equal(given.knots[k], clamped_uniform_knots(n, d))
    periodic = ControlNet.from_points(_points(), degrees=(3, 2), periodic=(True, False))
    assert periodic.is_bspline
    np.testing.assert_allclose(periodic.knots[0], periodic_uniform_knots(6, 3))
    assert len(periodic.knots[0]) == 6 + 2 * 3 + 1 and periodic.knots[0][3] == 0.0 and periodic.knots[0][9] == 1.0
    np.testing.assert_array_equal(periodic.knots[1], clamped_uniform_knots(5, 2))


def test_replace_settles_the_form_again():
    face = ControlNet.from_points(_points(), degrees=(3, 3))
    cage = face.replace(degrees=None, knots=None)
    assert cage.form == "cage" and cage.knots is None
    back = cage.replace(degrees=(2, 2))
    assert back.form == "bspline" and back.knots is not None
    assert face.replace(unit="m").form == "bspline"


@pytest.mark.parametrize("build", ["face", "cage", "periodic"])
def test_forms_round_trip_through_pickle(build):
    net = {"face": lambda: ControlNet.from_points(_points(), degrees=(3, 2)),
           "cage": lambda: ControlNet(points=_points(), origin=NetOrigin(kind="quad-chart")),
           "periodic": lambda: ControlNet.from_points(_points(), periodic=(True, False))}[build]()
    back = pickle.loads(pickle.dumps(net, protocol=pickle.HIGHEST_PROTOCOL))
    assert back.form == net.form and back.is_bspline == net.is_bspline
    np.testing.assert_array_equal(back.points, net.points)
    assert back.degrees == net.degrees and back.periodic == net.periodic
    if net.is_bspline:
        for a, b in zip(back.knots, net.knots):
            np.testing.assert_array_equal(a, b)
    assert repr(back) == repr(net)


class _OldPickle:
    """Pickles as a net did before nets carried their form (its state without ``form``)."""

    def __init__(self, net, **state):
        self.net, self.state = net, state

    def __reduce_ex__(self, protocol):
        state = {k: v for k, v in vars(self.net).items() if k != "form"}
        return copyreg._reconstructor, (ControlNet, object, None), {**state, **self.state}


def test_old_pickles_get_their_form():
    face = ControlNet.from_points(_points(), degrees=(3, 2))
    back = pickle.loads(pickle.dumps(_OldPickle(face)))
    assert type(back) is ControlNet and back.form == "bspline" and back.is_bspline
    cage = pickle.loads(pickle.dumps(_OldPickle(ControlNet(points=_points()))))
    assert cage.form == "cage" and not cage.is_bspline
    # a face pickled with degrees and no knots (as a periodic from_points net was) comes back with uniform knots
    bare = pickle.loads(pickle.dumps(_OldPickle(face, knots=None, periodic=(True, False))))
    assert bare.is_bspline and len(bare.knots[0]) == 6 + 2 * 3 + 1


def test_an_unknown_form_names_parameter_expected_received():
    with pytest.raises(OptionError) as info:
        ControlNet(points=_points(), form="nurbs")
    assert info.value.parameter == "form"
    assert all(repr(form) in info.value.expected for form in NET_FORMS)
    assert info.value.received == "nurbs"
    assert str(info.value) == "form: expected one of 'bspline', 'cage', received 'nurbs'"


@pytest.mark.parametrize("arguments, words", [
    ({"form": "cage", "degrees": (3, 3)}, ("degrees", "expected None for a cage", "received (3, 3)")),
    ({"form": "bspline"}, ("degrees", "expected two degrees", "received None")),
    ({"knots": (np.zeros(10), np.zeros(9))}, ("knots given without degrees",)),
    ({"degrees": (6, 3)}, ("degrees", "expected at most (5, 4)", "received (6, 3)")),
])
def test_a_form_at_odds_with_its_data_is_refused(arguments, words):
    with pytest.raises(InvalidNetError) as info:
        ControlNet(points=_points(), **arguments)
    assert all(w in str(info.value) for w in words), str(info.value)
