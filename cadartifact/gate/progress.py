"""Progress of ``cadartifact gate``: files done, taken from the cache, failed.

On a terminal a rich bar (transient: it leaves the report alone); elsewhere (CI logs, pipes) one
line per file on stderr, ``[  3/120] fail  parts/hood.step (cached)``. "Failed" counts the files
whose verdict is ``fail`` or ``error``.
"""

from __future__ import annotations

__all__ = ["GateProgress"]


class GateProgress:
    """A callable ``progress(entry, cached=False)`` for :func:`cadartifact.gate.run.run_gate`; a context manager.

    Parameters
    ----------
    console : rich.console.Console
        The stderr console.
    total : int
        Files to gate.
    """

    def __init__(self, console, total: int):
        self.console, self.total = console, total
        self.done = self.cached = self.failed = 0
        self._bar = self._task = None

    def __enter__(self):
        if self.console.is_terminal:
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

            self._bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                                 TextColumn("{task.fields[counts]}"), TimeElapsedColumn(), console=self.console,
                                 transient=True)
            self._bar.__enter__()
            self._task = self._bar.add_task("gating files", total=self.total, counts=self._counts())
        return self

    def __exit__(self, *exc):
        if self._bar is not None:
            self._bar.__exit__(*exc)
        return False

    def _counts(self) -> str:
        return f"{self.cached} cached, {self.failed} failed"

    def __call__(self, entry: dict, cached: bool = False) -> None:
        self.done += 1
        self.cached += bool(cached)
        self.failed += entry.get("verdict") in ("fail", "error")
        if self._bar is not None:
            from rich.markup import escape  # a path is not markup: [draft] stays in the name

            self._bar.update(self._task, advance=1, description=f"gated {escape(entry['path'])}",
                             counts=self._counts())
        else:
            width = len(str(self.total))
            self.console.print(f"[{self.done:>{width}}/{self.total}] {entry.get('verdict', 'error'):5s} "
                               f"{entry['path']}" + (" (cached)" if cached else ""),
                               soft_wrap=True, highlight=False, markup=False)
