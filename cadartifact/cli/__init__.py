"""The ``cadartifact`` command line: a thin typer layer over the library (the top wing).

Exit codes: 0 success (or every face within tolerance), 1 some face needs work (advise / gate), 2 usage
or input error. Errors are one line on stderr, never a traceback.

- :mod:`.prestart`: starts OCCT's reader child before anything heavy is imported (standard library only);
- :mod:`.usage`: one-line usage errors;
- :mod:`.root`: the command group and what the commands share (one-line errors, the consoles);
- :mod:`.catalogue_cmds` (schemes, maps), :mod:`.advise_cmds` (advise, demo), :mod:`.gate_cmd` (gate),
  :mod:`.files_cmds` (inspect, view), :mod:`.design_cmd` (design), :mod:`.schema_cmd` (schema): the commands;
- :mod:`.app`: the app with every command, and :func:`~.app.run`.
"""

from __future__ import annotations

__all__ = ["main"]


def main() -> None:
    """The console script: start the reader child (when this run will read a B-rep file here), then run
    the commands. The child's OCP import overlaps typer's, rich's and the analysis's."""
    import sys

    from .prestart import maybe_prestart

    maybe_prestart(sys.argv)
    from .app import run

    run()
