"""The gate's settings of one file, each declared once: :class:`FileSettings` and the :class:`Key` of each field.

A field's :class:`Key` (its ``metadata["key"]``) says everything the package knows of the setting: how a policy
value is checked (the error message), its default, where a policy may set it (top level, ``[[override]]``), its
command-line option and that option's help. The policy's parsing and merging (:mod:`cadartifact.gate.policy`:
``TOP_KEYS``, ``OVERRIDE_KEYS``, ``DEFAULTS``, ``CHOICES``, ``check_cli``) and ``cadartifact gate``'s options
(:mod:`cadartifact.cli.gate_cmd`) are derived from them. Adding a setting is one field here.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, asdict, dataclass, field, fields
from functools import cached_property
from typing import Callable

from ..analysis.settings import METRICS, READINGS, RunSettings
from ..errors import OptionError
from .policy_error import PolicyError

__all__ = ["Key", "FileSettings", "MEASURED", "UNDECIDED", "ADVISE", "POLICY_ONLY", "keys"]

MEASURED = ("warn", "fail")
#: The verdict of a face the decision rule leaves undecided (ISO 14253-1).
UNDECIDED = ("warn", "fail", "pass")
#: Which faces get the (costly) density advice: the verdict needs today's budget only.
ADVISE = ("all", "failing", "none")


@dataclass(frozen=True)
class Key:
    """The declaration of one gate setting (a policy key).

    Attributes
    ----------
    listed : int
        Its place in the policy's keys, as the module's documentation and the "is unknown (valid: ...)" messages
        list them.
    check : callable ``(source, key, value) -> value`` or None
        Validates a policy or command-line value and returns it normalised; raises :class:`PolicyError` naming
        ``source`` and ``key`` with what was expected and what was received. None: the policy parses it itself
        (``profile``, ``cache``, ``override``: they need the policy's folder or hold tables).
    default : object
        Its value when neither the policy nor the command line sets it.
    where : {"both", "top", "override"}
        Where a policy may set it: anywhere, only at its top level, only in an ``[[override]]`` table.
    option : tuple of str
        ``cadartifact gate``'s option names (``("--tol", "-t")``); empty: policy only.
    help : str
        The option's help.
    param : str or None
        The option's parameter name in ``cadartifact gate``, when it is not the key (``tol``).
    choices : tuple
        The values a choice key accepts (the error lists them).
    """

    listed: int
    check: Callable | None
    default: object = None
    where: str = "both"
    option: tuple = ()
    help: str = ""
    param: str | None = None
    choices: tuple = ()


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _positive(source: str, key: str, value):
    if not _is_number(value) or not math.isfinite(value) or value <= 0:
        raise PolicyError(source, key, f"expected a positive number of model units, received {value!r}")
    return float(value)


def _fraction(source: str, key: str, value):
    if not _is_number(value) or not (0 < value <= 1):
        raise PolicyError(source, key, f"expected a number with 0 < f <= 1, received {value!r}")
    return float(value)


def _share(source: str, key: str, value):
    if not _is_number(value) or not (0 <= value <= 1):
        raise PolicyError(source, key, f"expected a share with 0 <= s <= 1, received {value!r}")
    return float(value)


def _flag(source: str, key: str, value):
    if not isinstance(value, bool):
        raise PolicyError(source, key, f"expected true or false, received {value!r}")
    return value


def _one_of(choices: tuple) -> Callable:
    def check(source: str, key: str, value):
        if value not in choices:
            listed = ", ".join(map(repr, choices))
            raise PolicyError(source, key, f"expected one of {listed}, received {value!r}")
        return value

    return check


def _scheme(source: str, key: str, value):
    if not isinstance(value, str) or not value:
        raise PolicyError(source, key, f"expected a scheme name, received {value!r}")
    from ..theory.catalogue import scheme as get_scheme

    try:
        get_scheme(value)
    except OptionError as exc:
        raise PolicyError(source, key, f"expected {exc.expected}, received {value!r}") from None
    return value


def _faces(source: str, key: str, value):
    if not isinstance(value, list) or not all(isinstance(i, int) and not isinstance(i, bool) and i >= 0
                                              for i in value):
        raise PolicyError(source, key, f"expected a list of face indices (integers >= 0), received {value!r}")
    return tuple(sorted(set(value)))


def _glob(source: str, key: str, value):
    if not isinstance(value, str) or not value:
        raise PolicyError(source, key, f"expected a non-empty glob pattern, received {value!r}")
    return value


def _key(listed: int, check, default=MISSING, **kw):
    """A dataclass field declared by its :class:`Key` (``default`` MISSING: a required field whose key defaults
    to None)."""
    key = Key(listed, check, None if default is MISSING else default, **kw)
    return field(default=default, metadata={"key": key})


def _choice(listed: int, choices: tuple, default, **kw):
    return _key(listed, _one_of(choices), default, choices=choices, **kw)


@dataclass(frozen=True)
class FileSettings:
    """The effective gate settings of one file (policy, overrides and command line resolved).

    Attributes
    ----------
    tolerance : float
        Model units.
    metric : {"peak", "rms"}
    warn_fraction : float
        ``0 < f <= 1``.
    include_signal_error : bool
    intent : {"surface", "net"}
        The reading of the design intent (SPEC §4).
    scheme : str or None
        None: each face's own degrees (Catmull-Clark for cages).
    measured : {"warn", "fail"}
    undecided : {"warn", "fail", "pass"}
        The verdict of a face the decision rule leaves undecided (``value - U <= t < value + U``).
    convert : bool
        Convert revolution/extrusion/offset faces to B-splines (and gate them) instead of skipping them.
    min_analysed_share : float
        ``0 <= s <= 1``: an OBJ cage whose analysis covers less than this share of its surface area fails
        (default 0.95; 0: never). B-rep files have no such share.
    advise : {"failing", "all", "none"}
        Which faces get the density advice (the verdict needs today's budget only): those that warn
        or fail, every face, or none; a face without advice has ``advice: null`` and a reason in
        ``advice_skipped``.
    ignore_faces : tuple of int
    profile : Profile or None
        The PDQ criteria's thresholds (:mod:`cadartifact.gate.profiles`); None: no criteria, the verdict is the
        ripple's alone.

    Each field's :class:`Key` is in its metadata (:func:`keys`); the fields' order is the order of the gate
    document's ``policy`` entries.
    """

    tolerance: float = _key(1, _positive, option=("--tol", "-t"), param="tol",
                            help="Tolerance in model units (overrides the policy).")
    metric: str = _choice(2, METRICS, "peak", option=("--metric",), help="peak or rms (overrides the policy).")
    warn_fraction: float = _key(3, _fraction, 0.8, option=("--warn-fraction",),
                                help="Warn at this fraction of the tolerance (0 < f <= 1; default 0.8).")
    include_signal_error: bool = _key(4, _flag, False)
    scheme: str | None = _key(6, _scheme, None, option=("--scheme", "-s"),
                              help="Scheme (overrides the policy); file:MASK.json for a designed mask.")
    measured: str = _choice(7, MEASURED, "fail")
    undecided: str = _choice(8, UNDECIDED, "warn", option=("--undecided",),
                             help="Verdict of a face whose value +/- the intent's uncertainty U straddles the "
                                  "tolerance: warn (default), fail or pass (policy: undecided).")
    intent: str = _choice(5, READINGS, "surface", option=("--intent",),
                          help="Design intent: surface or net (overrides the policy).")
    convert: bool = _key(9, _flag, False, option=("--convert/--no-convert",),
                         help="Convert revolution/extrusion/offset faces to B-splines and gate them (overrides the "
                              "policy's convert; default: skip them).")
    min_analysed_share: float = _key(10, _share, 0.95)
    advise: str = _choice(12, ADVISE, "failing", option=("--advise",),
                          help="Density advice for: failing (faces that warn or fail; default), all or none. The "
                               "verdict needs today's budget only (policy: advise).")
    ignore_faces: tuple = _key(15, _faces, (), where="override")
    profile: object = _key(13, None, None, option=("--profile",),
                           help="PDQ criteria beside the ripple (waviness, degree, control points, indistinct "
                                "knots, unused patches, area, width, curvature radius): 'default', a profile TOML "
                                "file, or 'none' (policy: profile; default none).")

    @cached_property
    def run(self) -> RunSettings:
        """The analysis's share of these settings, as the budget and the advice read them (validated once)."""
        return RunSettings(tolerance=self.tolerance, metric=self.metric, scheme=self.scheme, intent=self.intent,
                           include_signal_error=self.include_signal_error)

    def to_dict(self) -> dict:
        from .profiles import profile_dict

        d = asdict(self)
        d["ignore_faces"] = list(self.ignore_faces)
        d["profile"] = profile_dict(self.profile)
        return d


#: The policy's keys that are not a file's settings: the override's glob, the result cache, the overrides.
POLICY_ONLY = {
    "glob": Key(0, _glob, where="override"),
    "cache": Key(11, None, where="top"),
    "override": Key(14, None, where="top"),
}


def keys(settings_only: bool = False) -> dict:
    """Every policy key and its :class:`Key`, in the order they are listed (``settings_only``: the fields of
    :class:`FileSettings` alone)."""
    found = {f.name: f.metadata["key"] for f in fields(FileSettings)}
    if not settings_only:
        found.update(POLICY_ONLY)
    return dict(sorted(found.items(), key=lambda item: item[1].listed))
