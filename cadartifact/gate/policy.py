"""Gate policy (TOML) and gate inputs (files, folders, globs) for ``cadartifact gate``.

A policy is found from the working directory upward (the first folder holding ``cadartifact.toml``
or a ``pyproject.toml`` with a ``[tool.cadartifact]`` table wins; a ``pyproject.toml`` without that
table is passed over), or given with ``--policy FILE``::

    tolerance = 0.05              # model units (mm for STEP); required here or as --tol
    metric = "peak"               # or "rms"
    warn_fraction = 0.8           # value >= 0.8 * tolerance but within it: "warn"
    include_signal_error = false  # let the tolerance cover the attenuation too
    intent = "surface"            # or "net": the shape the control points sample (SPEC §4)
    scheme = "bicubic"            # default: each face's own B-spline degrees (Catmull-Clark for OBJ)
    measured = "fail"             # or "warn": see below
    undecided = "warn"            # faces whose value +/- U straddles the tolerance: "warn", "fail" or "pass"
    convert = false               # convert revolution/extrusion/offset faces to B-splines and gate them
    min_analysed_share = 0.95     # OBJ cages: fail a file whose analysis covers less of its area
    cache = ".cadartifact-cache"  # keep results by content (relative to this file's folder): --cache
    advise = "failing"            # density advice for faces that warn or fail; "all" or "none": --advise
    profile = "none"              # PDQ criteria beside the ripple: "default" or a profile TOML: --profile

    [[override]]                  # applied in order to files matching glob; later ones win
    glob = "legacy/**"
    tolerance = 0.2
    ignore_faces = [3, 7]         # face indices not gated in those files

Globs are matched (``fnmatch``, ``*`` also crosses folders) against the file's path relative to the
policy file's folder (so patterns read like repository paths whatever the working directory), and a
glob without ``/`` also against the file name. Command-line options win over the whole policy,
overrides included. An unknown key or a bad value is a usage error naming the file and the key.

``measured``: faces with non-uniform knots are measured on the real surface (SPEC §4); rational
faces are analysed in homogeneous coordinates, faces with knots of multiplicity >= the degree are
split at those junctions, and canonical faces (plane, cylinder, cone, sphere, torus; exactly
circular or straight directions) carry no artifact there. They are gated like any other face
(``"fail"``, the default). ``"warn"`` caps faces with non-uniform knots at warn, for users who
want the older, lenient gate.

``undecided``: a face's value is known to within the intent's uncertainty ``U``
(:mod:`cadartifact.analysis.uncertainty`); by the rule of ISO 14253-1 it conforms when ``value + U <= t``
(pass, or warn above ``warn_fraction``), does not conform when ``value - U > t`` (fail), and is undecided in
between: its verdict is this key's (``"warn"`` by default; ``"fail"`` fails the gate, exit code 1).
"""

from __future__ import annotations

import fnmatch
import glob as globmod
import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError
from ..exchange import formats
from .keys import ADVISE, MEASURED, UNDECIDED, FileSettings, Key, keys  # noqa: F401 - importable from here as before
from .policy_error import PolicyError

__all__ = [
    "CAD_SUFFIXES",
    "DEFAULTS",
    "FileSettings",
    "Key",
    "Policy",
    "PolicyError",
    "base_settings",
    "check_cli",
    "expand_paths",
    "find_policy",
    "keys",
    "load_policy",
    "parse_policy",
]

#: Extensions a directory or glob contributes (any case): the gated formats of the registry
#: (:func:`cadartifact.exchange.formats.cad_suffixes`).
CAD_SUFFIXES = formats.LiveTuple(formats.cad_suffixes)

POLICY_FILE = "cadartifact.toml"

#: Keys whose value is one of a fixed set (the error lists the set).
CHOICES = {name: key.choices for name, key in keys().items() if key.choices}

#: Keys of a policy's top level and of its ``[[override]]`` tables (from the settings' :class:`~.keys.Key`).
TOP_KEYS = tuple(name for name, key in keys().items() if key.where in ("both", "top"))
OVERRIDE_KEYS = tuple(name for name, key in keys().items() if key.where in ("both", "override"))

DEFAULTS = {name: key.default for name, key in keys(settings_only=True).items()}


@dataclass(frozen=True)
class Policy:
    """A validated gate policy.

    Attributes
    ----------
    source : str or None
        The file it was read from (None: no policy file, defaults only).
    root : Path
        Folder the override globs are relative to (the policy file's, else the working directory).
    values : dict
        Top-level settings given in the file.
    overrides : tuple of (glob, dict)
    cache : Path or None
        The result cache folder (``cache = "..."``, relative to ``root``); not a per-file setting.
    """

    source: str | None = None
    root: Path = field(default_factory=Path.cwd)
    values: dict = field(default_factory=dict)
    overrides: tuple = ()
    cache: Path | None = None

    def settings_for(self, path, cli: dict | None = None) -> FileSettings:
        """Resolve the settings of ``path``: defaults < policy < matching overrides (in order) < ``cli``.

        Raises
        ------
        PolicyError
            No tolerance anywhere for this file.
        """
        merged = dict(DEFAULTS)
        merged.update(self.values)
        rel = _relative_posix(Path(path), self.root)
        for pattern, values in self.overrides:
            if _glob_matches(pattern, rel):
                merged.update(values)
        merged.update({k: v for k, v in (cli or {}).items() if v is not None})
        if merged["tolerance"] is None:
            if self.source:
                raise PolicyError(self.source, None, f"no tolerance for {path}: set 'tolerance' or pass --tol")
            raise PolicyError(os.fspath(path), None, "no tolerance: pass --tol, or set 'tolerance' in "
                                                     "cadartifact.toml or [tool.cadartifact] in pyproject.toml "
                                                     "(none found from the working directory upward)")
        merged["ignore_faces"] = tuple(merged["ignore_faces"])
        if merged["profile"] == "none":
            merged["profile"] = None
        return FileSettings(**merged)


def _relative_posix(path: Path, root: Path) -> str:
    absolute = Path(os.path.abspath(path))
    try:
        return absolute.relative_to(Path(os.path.abspath(root))).as_posix()
    except ValueError:
        return absolute.as_posix()


def _glob_matches(pattern: str, rel: str) -> bool:
    if fnmatch.fnmatchcase(rel, pattern):
        return True
    # "**/x" should also match "x" at the root, as in .gitignore
    if pattern.startswith("**/") and fnmatch.fnmatchcase(rel, pattern[3:]):
        return True
    return "/" not in pattern and fnmatch.fnmatchcase(rel.rsplit("/", 1)[-1], pattern)


def _check_value(source: str, key: str, value):
    """Validate one policy value (its :class:`~.keys.Key`'s check); return it normalised."""
    return keys()[key].check(source, key, value)


def _unknown(source: str, key: str, valid) -> PolicyError:
    hint = " (face indices are per file: put it in an [[override]] with a glob)" if key == "ignore_faces" else ""
    return PolicyError(source, key, f"is unknown (valid: {', '.join(valid)}){hint}")


def parse_policy(table: dict, source: str, root: Path) -> Policy:
    """Validate a policy table (the TOML's top level or ``[tool.cadartifact]``).

    Raises
    ------
    PolicyError
        Unknown key or bad value, naming ``source`` and the key.
    """
    if not isinstance(table, dict):
        raise PolicyError(source, None, "the policy must be a table of keys")
    values = {}
    overrides = []
    cache = None
    for key, value in table.items():
        if key not in TOP_KEYS:
            raise _unknown(source, key, TOP_KEYS)
        if key == "cache":
            if not isinstance(value, str) or not value:
                raise PolicyError(source, key, f"expected a folder path, received {value!r}")
            cache = root / value
        elif key == "profile":
            values[key] = _profile(value, source, root, key)
        elif key == "override":
            if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
                raise PolicyError(source, key, f"expected [[override]] tables, received {value!r}")
            for n, tbl in enumerate(value, 1):
                where = f"override[{n}]"
                vals = {}
                for k, v in tbl.items():
                    if k not in OVERRIDE_KEYS:
                        raise _unknown(source, f"{where}.{k}", OVERRIDE_KEYS)
                    vals[k] = _profile(v, source, root, f"{where}.{k}") if k == "profile" else \
                        _check_value_named(source, where, k, v)
                if "glob" not in vals:
                    raise PolicyError(source, f"{where}.glob", "is missing (each [[override]] needs a glob)")
                overrides.append((vals.pop("glob"), vals))
        else:
            values[key] = _check_value(source, key, value)
    return Policy(source=source, root=root, values=values, overrides=tuple(overrides), cache=cache)


def _profile(value, source: str, root: Path, key: str):
    """A policy's ``profile`` value (a file relative to the policy's folder) resolved, errors naming the key."""
    from .profiles import resolve_profile

    try:
        return resolve_profile(value, root, source)
    except PolicyError as exc:
        if exc.key != "profile":  # the profile file's own error: it names its file and key
            raise
        raise PolicyError(source, key, exc.problem) from None


def _check_value_named(source: str, where: str, key: str, value):
    """As :func:`_check_value` but naming the key ``override[n].key`` in errors."""
    try:
        return _check_value(source, key, value)
    except PolicyError as exc:
        raise PolicyError(source, f"{where}.{key}", exc.problem) from None


def _display(path: Path) -> str:
    try:
        return os.path.relpath(path)
    except ValueError:
        return str(path)


def _read_toml(path: Path) -> dict:
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise PolicyError(f"policy {_display(path)}", None, f"not valid TOML ({exc})") from None
    except OSError as exc:
        raise InputError(path, f"policy file cannot be read ({exc.strerror or exc})") from None


def load_policy(path) -> Policy:
    """Read a policy file: ``pyproject.toml`` (its ``[tool.cadartifact]`` table) or a ``cadartifact.toml``-style file.

    Raises
    ------
    InputError
        Missing or unreadable file.
    PolicyError
        Invalid TOML, no ``[tool.cadartifact]`` in a pyproject.toml, unknown key or bad value.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "policy file not found")
    data = _read_toml(path)
    source = f"policy {_display(path)}"
    if path.name == "pyproject.toml":
        table = data.get("tool", {}).get("cadartifact") if isinstance(data.get("tool"), dict) else None
        if table is None:
            raise PolicyError(source, None, "has no [tool.cadartifact] table")
        return parse_policy(table, source, path.resolve().parent)
    return parse_policy(_own_table(data, source), source, path.resolve().parent)


def _own_table(data: dict, source: str) -> dict:
    """The policy of a ``cadartifact.toml``: its top level, or its ``[tool.cadartifact]`` table when the
    file holds only that (the form pyproject.toml uses, so a snippet works pasted into either file)."""
    if set(data) == {"tool"} and isinstance(data["tool"], dict):
        if set(data["tool"]) != {"cadartifact"}:
            others = sorted(set(data["tool"]) - {"cadartifact"})
            raise PolicyError(source, f"tool.{others[0]}", "is unknown (a cadartifact.toml holds the policy keys, "
                                                            "or only a [tool.cadartifact] table)")
        return data["tool"]["cadartifact"]
    return data


def find_policy(start=None) -> Policy:
    """The policy in effect in ``start`` (default: the working directory), looked up upward.

    In each folder from ``start`` to the filesystem root, ``cadartifact.toml`` is taken first, then a
    ``pyproject.toml`` holding ``[tool.cadartifact]``; the first found wins. Without any, an empty
    policy (defaults; the tolerance must then come from the command line).
    """
    here = Path(start or Path.cwd()).resolve()
    for folder in (here, *here.parents):
        own = folder / POLICY_FILE
        if own.is_file():
            return load_policy(own)
        pyproject = folder / "pyproject.toml"
        if pyproject.is_file():
            data = _read_toml(pyproject)
            tool = data.get("tool")
            if isinstance(tool, dict) and "cadartifact" in tool:
                return parse_policy(tool["cadartifact"], f"policy {_display(pyproject)}", folder)
    return Policy(source=None, root=here)


# ---------------------------------------------------------------- inputs
def _is_cad(path: Path) -> bool:
    return path.suffix.lower() in formats.cad_suffixes()


def _walk(folder: Path) -> list[Path]:
    """CAD files under ``folder``, recursively, sorted by name per folder; hidden sub-folders are skipped.

    A folder that cannot be listed is returned as it is: gating it gives an ``error`` entry (fail closed).
    """
    found = []

    def unreadable(exc: OSError):
        if exc.filename is not None:
            found.append(Path(exc.filename))

    for root, dirs, files in os.walk(folder, onerror=unreadable):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        found.extend(Path(root) / f for f in sorted(files) if _is_cad(Path(f)))
    return found


def expand_paths(args) -> list[Path]:
    """Files to gate, in input order without duplicates.

    Each argument is a file (taken whatever its extension: a wrong one is reported for that file),
    a directory (its CAD files, recursively) or a glob (expanded here too, for shells that do not;
    ``**`` recurses) whose matching CAD files and directories are taken.

    Raises
    ------
    PolicyError
        No argument, or an argument that matches no file (a usage error, exit 2).
    """
    out: list[Path] = []
    seen: set[str] = set()

    def add(p: Path):
        key = os.path.normcase(os.path.abspath(p))
        if key not in seen:
            seen.add(key)
            out.append(p)

    if not args:
        raise PolicyError("PATH", None, "expected at least one file, folder or glob")
    for arg in args:
        text = os.fspath(arg)
        p = Path(text)
        if p.is_file():
            found = [p]
        elif p.is_dir():
            found = _walk(p)
        elif any(c in text for c in "*?["):
            found = []
            for m in sorted(globmod.glob(text, recursive=True)):
                mp = Path(m)
                if mp.is_dir():
                    found.extend(_walk(mp))
                elif mp.is_file() and _is_cad(mp):
                    found.append(mp)
        else:
            found = []
        if not found:
            what = "no such file or folder" if not any(c in text for c in "*?[") and not p.exists() else \
                f"matches no {formats.labels()} file"
            raise PolicyError(f"PATH {text!r}", None, what)
        for f in found:
            add(f)
    return out


def base_settings(policy: Policy, cli: dict) -> dict:
    """The settings before per-file overrides: defaults < policy top level < command line."""
    merged = dict(DEFAULTS)
    merged.update(policy.values)
    merged.update({k: v for k, v in cli.items() if v is not None})
    merged.pop("ignore_faces", None)
    return merged


def check_cli(values: dict) -> dict:
    """Validate gate options given on the command line (same rules as the policy keys; errors name the option)."""
    out = {}
    declared = keys()
    for key, value in values.items():
        if value is None:
            continue
        try:
            out[key] = _check_value("option", key, value)
        except PolicyError as exc:
            option = declared[key].option
            raise PolicyError(option[0].split("/")[0] if option else key, None, exc.problem) from None
    return out
