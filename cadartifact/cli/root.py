"""The command group every command registers on: the typer app and its root callback (``--version``), and
what the commands share: one-line errors (:func:`fail`, :func:`cli_errors`) and the consoles.

The commands live in :mod:`.catalogue_cmds`, :mod:`.advise_cmds`, :mod:`.gate_cmd` and :mod:`.files_cmds`;
:mod:`.app` gathers them on :data:`app`.
"""

from __future__ import annotations

import functools
import os
from typing import Optional

import typer
from typer.core import TyperGroup

from .usage import UsageError, escape, usage_message
from ..errors import CadArtifactError, OptionError


class _OneLineUsageErrors(TyperGroup):
    """The command group: usage errors (bad type, unknown option, missing value) are one line and exit 2."""

    def make_context(self, *args, **kwargs):
        try:
            return super().make_context(*args, **kwargs)
        except UsageError as exc:
            raise _usage_exit(exc) from None

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except UsageError as exc:
            raise _usage_exit(exc) from None


def _usage_exit(exc: UsageError):
    if type(exc).__name__ == "NoArgsIsHelpError":
        if getattr(exc, "ctx", None) is not None and exc.ctx.parent is None:
            # a bare ``cadartifact``: the help is what was asked for (stdout, exit 0)
            typer.echo(exc.ctx.get_help())
            return typer.Exit(0)
        return exc  # typer prints a subcommand's help for these
    return fail(usage_message(exc), exc.exit_code)


app = typer.Typer(
    cls=_OneLineUsageErrors,
    name="cadartifact",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # plain click help: it reflows hard-wrapped docstrings, never truncates option names at 80 columns and
    # shows text such as [tool.cadartifact] or the JSON schema's [...] as written (rich markup would eat them)
    rich_markup_mode=None,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _version(value: bool):
    if value:
        from .. import __version__

        typer.echo(f"cadartifact {__version__}")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", "-V", callback=_version, is_eager=True,
                                 help="Print the version and exit."),
):
    """Measure control-net artifacts (ripples) in NURBS and subdivision surfaces and advise control-point density.

    Run 'cadartifact COMMAND -h' for a command's options; 'cadartifact demo' runs the advisor on the bundled
    samples.
    """


def _console(stderr: bool = False):
    """The console of stdout (or stderr). Off a terminal (CI logs, pipes, files) it wraps nothing
    (``soft_wrap``): a path or a name stays one token on one line, to copy or grep, and tables take their
    content's width (:func:`cadartifact.runs.terminal.print_table`); its width (``$COLUMNS``, else 120)
    only chooses the tables' layout. On a terminal, tables are fitted to the terminal's width."""
    from rich.console import Console

    con = Console(stderr=stderr, highlight=False)
    if not con.is_terminal:
        width = None if stderr or os.environ.get("COLUMNS") else 120  # logs and pipes: do not squeeze tables to 80
        con = Console(stderr=stderr, highlight=False, width=width, soft_wrap=True)
    return con


def fail(message: str, code: int = 2) -> "typer.Exit":
    """Print a one-line error to stderr and return the Exit to raise."""
    # escaped: messages quote user text and names like [tool.cadartifact] that rich would eat as markup
    from ..errors import one_line

    _console(stderr=True).print(f"[bold red]cadartifact: error:[/] {escape(one_line(message))}", soft_wrap=True)
    return typer.Exit(code)


def cli_errors(func=None, *, aliases: Optional[dict] = None):
    """Run a command under the environment's execution settings (:mod:`.environment`), and turn
    :class:`CadArtifactError` into a one-line message and its exit code.

    An :class:`OptionError` about a library parameter is reported under the command's option:
    ``scheme`` becomes ``--scheme`` when the command has that option; ``aliases`` maps library
    names that differ from the command's parameter names (``{"tolerance": "tol"}``).
    """
    if func is None:
        return functools.partial(cli_errors, aliases=aliases)
    import inspect

    options = {}
    for name, par in inspect.signature(func).parameters.items():
        decls = [d for d in (getattr(par.default, "param_decls", None) or ()) if d.startswith("--")]
        if decls:
            options[name] = max(decls, key=len).split("/")[0]
    renames = {**options, **{lib: options[name] for lib, name in (aliases or {}).items()}}

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        from ..execution.child import configured
        from .environment import execution_settings

        try:
            # the environment is read here, at the edge: the command's reader child runs under it (gate and
            # advise pass their own settings down too), restored when the command ends (a command run from Python)
            with configured(execution_settings()):
                return func(*args, **kwargs)
        except CadArtifactError as exc:
            if isinstance(exc, OptionError) and exc.parameter in renames:  # name the option, not the library's name
                exc = OptionError(renames[exc.parameter], exc.expected, exc.received)
            raise fail(str(exc), exc.exit_code) from None
        except (typer.Exit, typer.Abort, UsageError, KeyboardInterrupt):
            raise
        except Exception as exc:  # noqa: BLE001 - no traceback and no exit 1 ("exceeds tolerance") for a failure
            raise fail(f"unexpected failure ({type(exc).__name__}: {exc}); please report it with the input", 2) \
                from None

    return wrapper
