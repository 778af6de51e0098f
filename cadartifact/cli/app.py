"""The ``cadartifact`` command line: a thin typer layer over the library.

Exit codes: 0 success (or every face within tolerance), 1 some face needs work
(advise / gate), 2 usage or input error. Errors are one line on stderr, never a
traceback.

:data:`app` is the typer app with every command: the command group is in :mod:`.root`, and the command
modules (imported here, in the order ``--help`` lists them) register on it.
"""

from __future__ import annotations

import sys
import warnings

# the command modules register their commands on app, in this order (the order of --help)
from . import catalogue_cmds, advise_cmds, gate_cmd, files_cmds, design_cmd, schema_cmd  # noqa: F401, I001
from .root import app
from .usage import quiet_warnings

__all__ = ["app", "run"]


def run():
    """Run the command line on ``sys.argv`` (:func:`cadartifact.cli.main` starts the reader child first)."""
    quiet_warnings()
    from ..exchange.messages import LoadWarning

    # the reader's warnings are part of every report (tables, JSON); do not echo them with source lines
    warnings.filterwarnings("ignore", category=LoadWarning)
    for stream in (sys.stdout, sys.stderr):  # file names that are not UTF-8 print as \udcff instead of failing
        try:
            stream.reconfigure(errors="backslashreplace")
        except (AttributeError, ValueError):
            pass
    try:
        app()
    except KeyboardInterrupt:
        sys.exit(130)
