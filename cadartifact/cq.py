"""The CadQuery hook: check a model's B-spline faces for control-net ripple while it is built.

Reachable as ``cadartifact.cq`` (loaded on first use; ``import cadartifact`` does not import
cadquery)::

    import cadquery as cq
    import cadartifact

    part = (cq.Workplane().parametricSurface(wavy)
              .invoke(cadartifact.cq.check(tol=0.05))       # raises ArtifactToleranceError
              .faces(">Z"))                                  # ... or chain on
    rows = cadartifact.cq.report(part, tol=0.05)            # per-face budgets and advice

``check`` returns a one-argument function, which is what ``Workplane.invoke`` (cadquery 2.x)
calls with the workplane; it returns the workplane itself so the chain goes on unchanged.
Faces are read from the shapes in memory (:func:`cadartifact.exchange.from_shape`), no file
round trip. Only B-spline and Bezier faces are analysed; analytic faces (planes, cylinders...)
carry no control net and pass.
"""

from __future__ import annotations

import math
import warnings

from .errors import ArtifactToleranceError, check_option

__all__ = ["ArtifactToleranceWarning", "MODES", "check", "report", "register"]

#: What :func:`check` does when a face exceeds the tolerance.
MODES = ("raise", "warn")

_DIRECTIONS = ("x1", "x2", "diagonal", "lateral")


class ArtifactToleranceWarning(UserWarning):
    """Issued by ``check(mode="warn")`` when a face's artifact exceeds the tolerance."""


def _settings(tol, metric: str, scheme, intent: str, include_signal_error: bool):
    """The run's :class:`~cadartifact.analysis.settings.RunSettings`, checked once as the hook is called (the
    tolerance under this hook's own name, ``tol``)."""
    from .analysis.settings import RunSettings, check_tolerance

    t = None if tol is None else check_tolerance(tol, "tol")
    return RunSettings(tolerance=t, metric=metric, scheme=scheme, intent=intent,
                       include_signal_error=include_signal_error)


def _nets(obj, convert: bool, name):
    """Control nets of a workplane/shape; a shape with no analysable face gives [] quietly."""
    from .exchange.load import LoadWarning, from_shape

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", LoadWarning)
        nets = from_shape(obj, convert=convert, name=name)
    for w in caught:  # keep the readers' warnings about degenerate faces; a box simply has none
        if not (issubclass(w.category, LoadWarning) and "no analysable" in str(w.message)):
            warnings.warn(w.message, w.category, stacklevel=3)
    return nets


def report(shape_or_workplane, tol: float | None = None, *, metric: str = "peak", scheme=None,
           include_signal_error: bool = False, compare: bool = False, verify: bool = False,
           convert: bool = False, name: str | None = None, intent: str = "surface") -> list[dict]:
    """Per-face artifact budgets (and density advice when a tolerance is given) of a CadQuery model.

    Parameters
    ----------
    shape_or_workplane : cadquery.Workplane, cadquery.Shape or OCP TopoDS_Shape
    tol : float, optional
        Tolerance in model units (mm). With it each face gets shares, a verdict and advice.
    metric : {"peak", "rms"}
    scheme : str or Scheme, optional
        Default: each face's own B-spline degrees.
    include_signal_error : bool
        Let the tolerance cover the whole deviation from intent, not only the ripple.
    intent : {"surface", "net"}
        The reading of the design intent (SPEC §4): the surface less its ripple, or the shape the
        control points sample.
    compare, verify : bool
        As :func:`cadartifact.advise` (off by default: the hook runs inside a modelling script).
    convert : bool
        Also analyse revolution/extrusion/offset faces converted to B-splines.
    name : str, optional
        Label used as the file name in each face's origin.

    Returns
    -------
    list of dict
        One entry per analysable face, in face order, with the keys of a face of the advise
        document (:mod:`cadartifact.runs.records`): ``face, name, kind, net, degrees, rational, scheme,
        method, reason, budget {direction: {peak, rms}}, share, meets_tolerance, advice``.
        Without ``tol``: ``share``, ``meets_tolerance`` and ``advice`` are None.
    """
    from .runs.face import HOOK_REPORT, analyse_face

    settings = _settings(tol, metric, scheme, intent, include_signal_error)
    # without a tolerance: the budget under the intent as given; with one, the advice's reading (as advise's)
    options = (HOOK_REPORT.replace(reading="intent") if settings.tolerance is None else
               HOOK_REPORT.replace(compare=compare, verify=verify))
    return [analyse_face(net, settings, options) for net in _nets(shape_or_workplane, convert, name)]


def _describe(row: dict, settings, units: str = "mm") -> str:
    metric, t, key = settings.metric, settings.tolerance, settings.compared
    what = "deviation" if settings.include_signal_error else "ripple"
    label = f"face {row['face']}" + (f" ({row['name']})" if row["name"] else "")
    parts = ", ".join(f"{d} {row['budget'][d][metric]:.4g}" for d in _DIRECTIONS)
    text = (f"{label}: {what} {metric} {row['budget'][key][metric]:.4g} {units} exceeds tolerance {t:g} {units} "
            f"({parts}; net {row['net'][0]}x{row['net'][1]}, {row['scheme']}, {row['method']})")
    adv = row.get("advice")
    if adv:
        text += f"; advised net {adv['net'][0]}x{adv['net'][1]}"
        if list(adv["net"]) == list(row["net"]) and adv["meets_tolerance"]:
            text += " (same density: resample the intent with uniform knots)"
        if not adv["meets_tolerance"]:
            text += " (tolerance out of reach up to the search limit)"
    return text


def check(tol: float = 0.05, *, mode: str = "raise", metric: str = "peak", scheme=None,
          include_signal_error: bool = False, convert: bool = False, intent: str = "surface"):
    """A function for ``Workplane.invoke`` that checks every B-spline face against a tolerance.

    Parameters
    ----------
    tol : float
        Tolerance in model units (mm), compared with each face's ripple (SPEC §4 budget) under
        ``metric``.
    mode : {"raise", "warn"}
        ``raise``: :class:`~cadartifact.errors.ArtifactToleranceError` naming the worst face that does not
        conform (``value - U > tol``, ISO 14253-1 with the intent's uncertainty ``U``,
        :mod:`cadartifact.advice.decision`); ``warn``: :class:`ArtifactToleranceWarning` with the same message,
        and the chain goes on. A face the rule leaves undecided (``value - U <= tol < value + U``) only
        warns, in both modes.
    metric : {"peak", "rms"}
    scheme : str or Scheme, optional
        Default: each face's own B-spline degrees.
    include_signal_error : bool
        Compare the whole deviation from intent instead of the ripple.
    intent : {"surface", "net"}
        As :func:`report`.
    convert : bool
        Also analyse revolution/extrusion/offset faces converted to B-splines.

    Returns
    -------
    callable(workplane) -> workplane
        Returns the same workplane object. The error carries ``.faces`` (the rows of
        :func:`report` for the faces that exceed, worst first, the worst one with ``advice``).

    Examples
    --------
    >>> wp.invoke(cadartifact.cq.check(tol=0.05, mode="warn"))      # doctest: +SKIP
    """
    settings = _settings(tol, metric, scheme, intent, include_signal_error)
    check_option("mode", mode, MODES)
    if scheme is not None:
        from .theory.catalogue import scheme as get_scheme

        settings = settings.replace(scheme=get_scheme(scheme))  # a bad name fails when the check is built

    # Workplane.invoke reads the arity from __code__, so this must be a plain one-argument function.
    def artifact_check(workplane):
        from .advice.decision import NONCONFORMING, UNDECIDED
        from .runs.face import HOOK_CHECK, HOOK_REPORT, analyse_face

        rows, undecided = [], []
        for net in _nets(workplane, convert, None):
            rec = analyse_face(net, settings, HOOK_CHECK)
            value = rec["budget"][settings.compared][metric]  # None: not finite, the worst of all
            value = math.inf if value is None else value
            if rec["decision"] == NONCONFORMING:
                rows.append((value, net, rec))
            elif rec["decision"] == UNDECIDED:
                undecided.append(rec)
        for rec in undecided:  # the rule cannot decide: never an error, always said (ISO 14253-1)
            u = rec["uncertainty"]["peak"]
            label = f"face {rec['face']}" + (f" ({rec['name']})" if rec["name"] else "")
            warnings.warn(f"{label}: {settings.compared} {metric} {rec['budget'][settings.compared][metric]:.4g} "
                          f"+/- {u:.2g} is undecided against tolerance {settings.tolerance:g} (the intent's "
                          "uncertainty U straddles it)", ArtifactToleranceWarning, stacklevel=3)
        if not rows:
            return workplane
        rows.sort(key=lambda r: -r[0])
        _, worst_net, worst = rows[0]
        worst["advice"] = analyse_face(worst_net, settings, HOOK_REPORT)["advice"]  # the worst face's only
        message = _describe(worst, settings, worst_net.unit)
        if len(rows) > 1:
            message = f"{len(rows)} faces exceed the tolerance; worst {message}"
        if mode == "raise":
            exc = ArtifactToleranceError(message)
            exc.faces = [r[2] for r in rows]
            raise exc
        warnings.warn(message, ArtifactToleranceWarning, stacklevel=3)
        return workplane

    artifact_check.__doc__ = f"cadartifact check: tolerance {settings.tolerance:g}, {metric}, mode {mode}"
    return artifact_check


def _artifact_check(self, tol: float = 0.05, **options):
    """Check this workplane's B-spline faces for control-net ripple (see ``cadartifact.cq.check``)."""
    return self.invoke(check(tol, **options))


def register() -> None:
    """Add ``cq.Workplane.artifactCheck(tol=0.05, **options)`` (idempotent).

    ``wp.artifactCheck(0.05, mode="warn")`` is ``wp.invoke(check(0.05, mode="warn"))``.
    """
    from .dependencies import require

    cq = require("cadquery", "the CadQuery hook")
    if getattr(cq.Workplane, "artifactCheck", None) is not _artifact_check:
        cq.Workplane.artifactCheck = _artifact_check
