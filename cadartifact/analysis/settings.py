"""What a run decides once: the tolerance, the metric, the scheme, the reading of the intent, whether the signal
error counts, the fine grid, the component and the road and region of the statistics.

One frozen :class:`RunSettings` is made and validated at the edge (an API call such as
:func:`cadartifact.budget` or :func:`cadartifact.advise`, the command line through
:func:`cadartifact.runs.advising.advise_files`, a gate policy through
:attr:`cadartifact.gate.policy.FileSettings.run`) and passed down whole: the functions below it read what they
need from it instead of taking each choice as an argument of their own.

>>> from cadartifact.analysis.settings import RunSettings
>>> s = RunSettings(tolerance=0.05, metric="rms")
>>> s.replace(intent="net").reading
'net'
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from ..errors import OptionError, check_option

__all__ = ["RunSettings", "METRICS", "METHODS", "REGIONS", "READINGS", "COMPONENTS", "check_tolerance",
           "resolve_scheme"]

METRICS = ("peak", "rms")
METHODS = ("auto", "predicted", "measured", "both")
REGIONS = ("auto", "face", "interior")
#: The readings of the design intent (SPEC §4): the surface less its ripple, or the shape the points sample.
READINGS = ("surface", "net")
COMPONENTS = ("normal", "vector")


def check_tolerance(tolerance, parameter: str = "tolerance") -> float:
    """A tolerance as a positive finite float (model units), or :class:`OptionError` naming ``parameter``."""
    try:
        value = float(tolerance)
    except (TypeError, ValueError):
        raise OptionError(parameter, "a positive number of model units", tolerance) from None
    if not math.isfinite(value) or value <= 0:
        raise OptionError(parameter, "a positive number of model units", tolerance)
    return value


def resolve_scheme(net, scheme=None):
    """The :class:`~cadartifact.theory.catalogue.Scheme` a net is analysed with: ``scheme`` (a name or a
    Scheme), or by default the net's own B-spline degrees, Catmull-Clark for a cage."""
    from ..theory.catalogue import Scheme, bspline, scheme as by_name

    if scheme is None:
        return bspline(*net.degrees) if net.is_bspline else by_name("catmull-clark")
    return scheme if isinstance(scheme, Scheme) else by_name(scheme)


@dataclass(frozen=True)
class RunSettings:
    """The choices of one run, validated once.

    Attributes
    ----------
    tolerance : float or None
        Model units (mm for STEP); None where only the ripple is asked for (:func:`cadartifact.budget`).
    metric : {"peak", "rms"}
        What is compared with the tolerance.
    scheme : None, str or Scheme
        None: each face's own degrees (Catmull-Clark for cages); a catalogue name or a Scheme
        (:func:`resolve_scheme`).
    intent : {"surface", "net"}
        The reading of the design intent (SPEC §4).
    include_signal_error : bool
        The tolerance covers the signal error too (the whole deviation from the net reading).
    levels : int
        The fine grid has ``2**levels`` samples per control spacing.
    component : {"normal", "vector"}
        The displacement along the intent's normal, or its length.
    method : {"auto", "predicted", "measured", "both"}
        The road of the statistics (:func:`cadartifact.budget`).
    region : {"auto", "face", "interior"}
        Where the statistics are taken.
    """

    tolerance: float | None = None
    metric: str = "peak"
    scheme: object = None
    intent: str = "surface"
    include_signal_error: bool = False
    levels: int = 3
    component: str = "normal"
    method: str = "auto"
    region: str = "auto"

    def __post_init__(self):
        check_option("metric", self.metric, METRICS)
        check_option("method", self.method, METHODS)
        check_option("component", self.component, COMPONENTS)
        check_option("region", self.region, REGIONS)
        check_option("intent", self.intent, READINGS)
        if self.tolerance is not None:
            object.__setattr__(self, "tolerance", check_tolerance(self.tolerance))
        object.__setattr__(self, "include_signal_error", bool(self.include_signal_error))
        if isinstance(self.scheme, str):  # a name is checked here (SchemeError lists the catalogue); kept as given
            from ..theory.catalogue import scheme as by_name

            by_name(self.scheme)

    def replace(self, **changes) -> RunSettings:
        """A copy with ``changes`` (validated again)."""
        return dataclasses.replace(self, **changes)

    @property
    def reading(self) -> str:
        """The reading today's net is scored under: ``"net"`` when the signal error counts, else :attr:`intent`."""
        return "net" if self.include_signal_error else self.intent

    @property
    def compared(self) -> str:
        """The statistic compared with the tolerance: ``"deviation"`` when the signal error counts, else
        ``"total"`` (the whole ripple)."""
        return "deviation" if self.include_signal_error else "total"
