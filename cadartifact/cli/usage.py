"""Command-line plumbing: one-line usage messages for typer's parse errors, one-line warnings, and paths
escaped for rich's markup.

Kept apart from :mod:`cadartifact.cli` (the commands) so that each stays short.
"""

from __future__ import annotations

from enum import Enum

from ..errors import OptionError, check_option

__all__ = ["UsageError", "usage_message", "quiet_warnings", "escape"]

try:  # typer >= 0.2x vendors click
    from typer._click.exceptions import UsageError
except ImportError:  # pragma: no cover - older typer depends on click
    from click.exceptions import UsageError


def _option_name(param) -> str:
    """``--tol`` for an option (its long name), ``FILES`` for an argument."""
    opts = list(getattr(param, "opts", None) or [])
    if getattr(param, "param_type_name", "") == "option" and opts:
        return max(opts, key=len)
    return (param.name or "argument").upper()


#: What a value of the type was expected to be, by pydantic error type (typer's coercion).
_EXPECTED = {"float_parsing": "a number", "float_type": "a number", "finite_number": "a finite number",
             "int_parsing": "an integer", "int_type": "an integer", "int_from_float": "an integer",
             "bool_parsing": "true or false", "bool_type": "true or false"}


def _choices(param):
    """The valid values of a choice option (an Enum annotation, or a click Choice in older typer), else None."""
    annotation = getattr(getattr(param, "type_descriptor", None), "annotation", None)
    if isinstance(annotation, type) and issubclass(annotation, Enum):
        return [member.value for member in annotation]
    return getattr(getattr(param, "type", None), "choices", None)


def usage_message(exc: UsageError) -> str:
    """One line for a click/typer usage error: the option, what was expected, what was received.

    Parameters
    ----------
    exc : UsageError
        Raised by typer while parsing (bad type or choice, missing value, unknown option or command).

    Returns
    -------
    str
        ``"--tol: expected a number, received 'abc'"``; the choices for an Enum option, as
        :func:`~cadartifact.errors.check_option` words them; typer's own words (on one line) otherwise.
    """
    param = getattr(exc, "param", None)
    if param is None:  # no such option / command, extra argument, option without its value
        ctx = getattr(exc, "ctx", None)
        hint = f" (see '{ctx.command_path} --help')" if ctx is not None else ""
        text = " ".join(exc.format_message().split())
        return (text.rstrip(".") + hint) if hint else text
    name = _option_name(param)
    if type(exc).__name__ == "MissingParameter":
        return f"{name}: expected a value (it is required), received nothing"
    cause = exc.__cause__
    errors = cause.errors() if callable(getattr(cause, "errors", None)) else None
    if errors:  # typer >= 0.2x coerces with pydantic: the error knows the input
        err = errors[0]
        choices = _choices(param)
        if choices:
            try:
                check_option(name, err.get("input"), choices)
            except OptionError as bad:
                return str(bad)
        expected = _EXPECTED.get(err.get("type"))
        if expected is None and "expected" in (err.get("ctx") or {}):
            expected = "one of " + str(err["ctx"]["expected"]).replace(" or ", ", ")
        if expected is None:
            return f"{name}: {err.get('msg', exc.message)}, received {err.get('input')!r}"
        return str(OptionError(name, expected, err.get("input")))
    return f"{name}: " + " ".join(str(exc.message).split())


def _one_line_warning(message, category, filename, lineno, file=None, line=None):
    """``warnings.showwarning`` for the command line: one line, no source path or code line."""
    text = " ".join(str(message).split())
    from rich.console import Console

    Console(stderr=True, highlight=False).print(f"[yellow]cadartifact: warning:[/] {escape(text)}", soft_wrap=True)


def escape(text) -> str:
    """``text`` (a path, a name, a message) as rich markup that prints it as it is: ``[draft]`` in a file
    name is not a style tag to be eaten."""
    from rich.markup import escape as escape_markup

    return escape_markup(str(text))


def quiet_warnings() -> None:
    """No raw Python warnings on stderr: the readers' (LoadWarning) are part of every report already
    (tables, JSON, the error line), any other is shown once as one line without a source path."""
    import warnings

    from ..exchange.messages import LoadWarning

    warnings.simplefilter("ignore", LoadWarning)
    warnings.showwarning = _one_line_warning
