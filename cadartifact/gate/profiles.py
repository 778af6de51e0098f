"""PDQ profiles for the gate (``cadartifact gate --profile NAME|FILE``, policy key ``profile``).

A profile holds the thresholds of the product-data-quality criteria of :mod:`cadartifact.analysis.quality`
(waviness, degree, control points, indistinct knots, unused patches, area, width, curvature radius, patch gap and
angle inside the face, collapsed edge, corner angle, distance from itself). ``default``
is built in (docs/quality-criteria.md justifies its figures); ``none`` turns the criteria off (the gate's
verdicts are then the ripple's alone, as before profiles existed); any other value is a TOML file whose tables
change the default profile's thresholds, criterion by criterion::

    [waviness]            # inflections of the normal curvature along one isoparametric line
    warn = 1              # more than 1: warn
    fail = 3              # more than 3: fail
    flat_ratio = 100      # |curvature| <= 1 / (flat_ratio * the face's size) has no sign

    [knots]               # indistinct knots (G-SU-IK): spans short on the surface
    warn = 0.02           # model units: shorter warns
    fail = 0.01
    parameter = 1e-3      # optional: also short in parameter (under this share of the range)

    [radius]
    warn = "off"          # a level that is "off" is not judged
    fail = 0.5

    unused = false        # the criterion is off (reported as off, never silently missing)

Criteria whose bad side is above the threshold (``waviness``, ``degree``, ``points``, ``points_total``,
``unused``, ``patch_gap``, ``patch_angle``) need ``warn <= fail``; those whose bad side is below it (``knots``,
``area``, ``width``, ``radius``, ``collapsed``, ``corner``, ``self_distance``) need ``warn >= fail``. A bad file, table, key or value is a usage error (exit 2) of one line naming the file,
the key, what was expected and what was received.
"""

from __future__ import annotations

import dataclasses
import math
import os
import tomllib
from pathlib import Path

from ..analysis.quality import CRITERIA, Limit, Profile, default_profile
from ..errors import InputError
from ..registry import LiveMapping
from .policy_error import PolicyError

__all__ = ["BUILT_IN", "load_profile", "profile_dict", "resolve_profile"]

#: Built-in profiles by name (``none``: no criteria), from the criteria's registry
#: (:data:`cadartifact.analysis.quality.CRITERIA`).
BUILT_IN = LiveMapping(lambda: {"default": default_profile()})
#: Extra keys of some criteria's tables (:attr:`cadartifact.analysis.quality.CriterionSpec.settings`).
EXTRA = LiveMapping(lambda: {k: tuple(s.key for s in spec.settings) for k, spec in CRITERIA.items() if spec.settings})


def profile_dict(profile: Profile | None) -> dict | None:
    """A profile as JSON data: ``{"name", "source", <criterion>: {"warn", "fail", "sense"} | null, "flat_ratio",
    "flat_radius", "knot_parameter", "sharp_angle"}`` (flat_radius and knot_parameter null unless the profile sets
    them)."""
    if profile is None:
        return None
    out = {"name": profile.name, "source": profile.source}
    for key, lim in profile.limits:
        out[key] = None if lim is None else {"warn": lim.warn, "fail": lim.fail, "sense": CRITERIA[key][3]}
    out.update(flat_ratio=profile.flat_ratio, flat_radius=profile.flat_radius, knot_parameter=profile.knot_parameter,
               sharp_angle=profile.sharp_angle)
    return out


def resolve_profile(value, root: Path, where: str):
    """A ``profile`` value (policy key or ``--profile``) as a :class:`Profile`, or ``"none"``.

    Parameters
    ----------
    value : str
        ``"default"``, ``"none"`` or the path of a profile TOML (relative to ``root``).
    root : Path
        The policy file's folder, or the working directory for the command line.
    where : str
        How errors name the setting (``"policy cadartifact.toml: key 'profile'"`` is made by the caller).

    Raises
    ------
    PolicyError
    """
    if not isinstance(value, str) or not value:
        raise PolicyError(where, "profile", f"expected 'default', 'none' or a profile TOML file, received {value!r}")
    if value == "none":
        return "none"
    if value in BUILT_IN:
        return BUILT_IN[value]
    path = Path(value) if os.path.isabs(value) else root / value
    if not path.is_file():
        raise PolicyError(where, "profile", f"expected 'default', 'none' or a profile TOML file, received {value!r} "
                                            "(no such file)")
    return load_profile(path)


def load_profile(path) -> Profile:
    """Read and validate a profile TOML (see the module's documentation).

    Raises
    ------
    InputError
        The file cannot be read.
    PolicyError
        Not TOML, an unknown table or key, a value that is not a number, a negative number, or warn on the bad
        side of fail: one line naming the file and the key (``waviness.warn``).
    """
    path = Path(path)
    try:
        display = os.path.relpath(path)
    except ValueError:
        display = str(path)
    source = f"profile {display}"
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise PolicyError(source, None, f"not valid TOML ({exc})") from None
    except OSError as exc:
        raise InputError(path, f"profile file cannot be read ({exc.strerror or exc})") from None
    base_profile = default_profile()
    limits = dict(base_profile.limits)
    extra = {s.attribute: getattr(base_profile, s.attribute) for spec in CRITERIA.values() for s in spec.settings}
    for key, table in data.items():
        if key not in CRITERIA:
            raise PolicyError(source, key, f"is unknown (valid: {', '.join(CRITERIA)})")
        if table is False:
            limits[key] = None
            continue
        if not isinstance(table, dict):
            raise PolicyError(source, key, f"expected a table of thresholds or false, received {table!r}")
        base = limits[key] or Limit()
        values = {"warn": base.warn, "fail": base.fail}
        settings = {s.key: s for s in CRITERIA[key].settings}
        for k, v in table.items():
            name = f"{key}.{k}"
            if k in ("warn", "fail"):
                values[k] = None if v == "off" else _number(source, name, v, "a number >= 0 or \"off\"")
            elif k in settings:
                setting = settings[k]
                x = _number(source, name, v, setting.expected)
                if not setting.valid(x):
                    raise PolicyError(source, name, f"expected {setting.expected}, received {v!r}")
                extra[setting.attribute] = x
            else:
                valid = ", ".join(("warn", "fail") + tuple(settings))
                raise PolicyError(source, name, f"is unknown (valid: {valid})")
        w, f = values["warn"], values["fail"]
        if w is not None and f is not None:
            above = CRITERIA[key][3] == "above"
            if (above and w > f) or (not above and w < f):
                raise PolicyError(source, f"{key}.warn", f"expected warn {'<=' if above else '>='} fail ({f:g}: the "
                                                         f"bad side is {CRITERIA[key][3]} the threshold), received {w:g}")
        limits[key] = Limit(warn=w, fail=f)
    return dataclasses.replace(base_profile, name=path.stem, source=display,
                               limits=tuple((k, limits[k]) for k in CRITERIA), **extra)


def _number(source: str, key: str, value, expected: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
        raise PolicyError(source, key, f"expected {expected}, received {value!r}")
    return float(value)
