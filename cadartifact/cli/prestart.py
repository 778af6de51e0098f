"""Start OCCT's reader child at the very start of a CLI run that will read a B-rep file in this process.

The reader child (:mod:`cadartifact.execution.child`) spends about a second importing OCP. Started
before the command line's own imports (typer, rich, the analysis modules), that second overlaps
them, which matters for ``gate`` on one file, whose whole cost should be close to OCCT's read. When
the command names one file, the child starts reading it at once (:func:`first_read`), while this
process is still importing. Only the argument list is looked at (no imports beyond the standard
library): a guess that is wrong costs an idle child or a second start, stopped at exit, never a
different result (the early answer serves only the identical request).
"""

from __future__ import annotations

import os

from ..exchange import formats
from ..exchange.reader_start import BREP_SUFFIXES

__all__ = ["BREP_SUFFIXES", "first_read", "maybe_prestart", "will_read_here"]

_COMMANDS = ("advise", "gate", "inspect", "view")
#: What the reader child imports while idle after its read, before ``gate`` or ``advise`` share a file's faces
#: with it: the analysis (:mod:`cadartifact.runs.face_sharing`, :mod:`cadartifact.gate.run`).
CHILD_IMPORTS = ("cadartifact.runs.face_sharing", "cadartifact.gate.run", "cadartifact.advice.advise")


def isolation_on(environ=None) -> bool:
    """Whether the environment leaves OCCT's reads in the reader child (``CADARTIFACT_READ_ISOLATION`` not off),
    read as :mod:`.environment` reads it; never raises (another variable's bad value is raised where it is used)."""
    from .environment import ENVIRONMENT

    var = next(v for v in ENVIRONMENT if v.field == "isolation")
    raw = (os.environ if environ is None else environ).get(var.name, var.default)
    return not raw.strip() or var.parse(var.name, raw)


def _one_job(args) -> bool:
    for k, a in enumerate(args):
        if a in ("--jobs", "-j") and k + 1 < len(args):
            return args[k + 1].strip() == "1"
        if a.startswith("--jobs=") or (a.startswith("-j") and a[2:].isdigit()):
            return a.split("=", 1)[-1].removeprefix("-j").strip() == "1"
    return False


def will_read_here(argv) -> bool:
    """Whether the command in ``argv`` (``sys.argv``) will read a STEP/IGES/BREP file in this process.

    ``gate`` with more than one file, a folder or a glob runs a pool of workers (each with its own
    reader) unless ``--jobs 1``; with ``--scheduler`` the workers read.
    """
    if len(argv) < 2 or argv[1] not in _COMMANDS:
        return False
    args = list(argv[2:])
    if any(a == "--scheduler" or a.startswith("--scheduler=") for a in args):
        return False
    cad = [a for a in args if a.lower().endswith(tuple(formats.brep_formats()))]
    if not cad:
        return False
    if argv[1] == "gate" and not _one_job(args):
        several = len(cad) > 1 or any(any(c in a for c in "*?[") or os.path.isdir(a) for a in args
                                      if not a.startswith("-"))
        if several:
            return False
    return True


#: Options of ``gate`` and ``advise`` whose value is a file (possibly a .step one written, never read first).
_PATH_OPTIONS = ("--write-resampled", "--output", "-o", "--report", "--policy", "--cache")


def first_read(argv):
    """The read ``gate`` or ``advise`` will send the reader child first, guessed from ``argv``, or None.

    The one STEP/IGES/BREP file named (an existing file, not an option's value; none when two or more
    are named), with ``--convert`` as given. For ``gate`` without ``--convert/--no-convert``, a policy
    (``--policy``, or ``cadartifact.toml`` / ``[tool.cadartifact]`` found upward) may set ``convert``, which
    is not read here: no guess then.

    Returns
    -------
    (str, tuple) or None
        ``(function, args)`` as :func:`cadartifact.exchange.reader_start.read_request` gives them.
    """
    from pathlib import Path

    from ..exchange.reader_start import read_request

    if len(argv) < 2 or argv[1] not in ("gate", "advise"):
        return None
    args = list(argv[2:])
    brep = formats.brep_formats()
    named = [a for k, a in enumerate(args) if not a.startswith("-") and Path(a).suffix.lower() in brep
             and (k == 0 or args[k - 1] not in _PATH_OPTIONS)]
    if len(named) != 1 or not os.path.isfile(named[0]):
        return None
    explicit = "--convert" in args or "--no-convert" in args
    if argv[1] == "gate" and not explicit and ("--policy" in args or any(a.startswith("--policy=") for a in args)
                                               or _policy_upward()):
        return None
    convert = "--convert" in args and "--no-convert" not in args
    return read_request(named[0], brep[Path(named[0]).suffix.lower()], convert)


def _policy_upward() -> bool:
    """Whether a gate policy may apply here (``cadartifact.gate.policy.find_policy``'s files, looked for
    without parsing them: a ``pyproject.toml`` counts when it mentions ``[tool.cadartifact``)."""
    from pathlib import Path

    here = Path.cwd()
    for folder in (here, *here.parents):
        if (folder / "cadartifact.toml").is_file():
            return True
        pyproject = folder / "pyproject.toml"
        if pyproject.is_file():
            try:
                if "[tool.cadartifact" in pyproject.read_text(errors="replace"):
                    return True
            except OSError:
                return True
    return False


def maybe_prestart(argv) -> None:
    """Start the reader child if :func:`will_read_here` (the console script's first step), already
    reading the file :func:`first_read` names. Only the standard library is imported before it starts."""
    if will_read_here(argv) and isolation_on():
        from ..exchange.reader_start import start

        start(first_read(argv), idle=CHILD_IMPORTS)
