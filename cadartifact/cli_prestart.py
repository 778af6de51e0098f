"""Start OCCT's reader child at the very start of a CLI run that will read a B-rep file in this process.

The reader child (:mod:`cadartifact.exchange.isolation`) spends about a second importing OCP. Started
before the command line's own imports (typer, rich, the analysis modules), that second overlaps
them, which matters for ``gate`` on one file, whose whole cost should be close to OCCT's read. Only
the argument list is looked at (no imports beyond the standard library): a guess that is wrong costs
an idle child, stopped at exit, never a different result.
"""

from __future__ import annotations

import os

__all__ = ["BREP_SUFFIXES", "maybe_prestart", "will_read_here"]

#: Files the reader child reads (OBJ is read in this process).
BREP_SUFFIXES = (".step", ".stp", ".iges", ".igs", ".brep", ".brp")
_COMMANDS = ("advise", "gate", "inspect", "view")


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
    cad = [a for a in args if a.lower().endswith(BREP_SUFFIXES)]
    if not cad:
        return False
    if argv[1] == "gate" and not _one_job(args):
        several = len(cad) > 1 or any(any(c in a for c in "*?[") or os.path.isdir(a) for a in args
                                      if not a.startswith("-"))
        if several:
            return False
    return True


def maybe_prestart(argv) -> None:
    """Start the reader child if :func:`will_read_here` (the console script's first step)."""
    if will_read_here(argv):
        from .exchange import isolation

        isolation.prestart()
