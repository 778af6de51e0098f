"""The ``cadartifact`` command line: a thin typer layer over the library (the top wing).

Exit codes: 0 success (or every face within tolerance), 1 some face needs work (advise / gate), 2 usage
or input error. Errors are one line on stderr, never a traceback.

- :mod:`.prestart`: starts OCCT's reader child before anything heavy is imported (standard library only);
- :mod:`.usage`: one-line usage errors;
- :mod:`.app`: the commands.
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
