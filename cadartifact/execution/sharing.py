"""One process's items shared with the idle child process (:mod:`.child`): a second core for one file.

A lone process (``gate --jobs 1``, ``advise``) leaves the child idle on the second core once it has read a file.
:func:`share` hands it part of the items in rounds (half of what is left, longest first, whenever it has
answered), works on the rest here at the same time and returns one outcome per item in order, as the serial loop
would. The caller decides whether that may happen by passing a :class:`Sharing` (its leave, and what the child
imports while idle); no state is kept here.

The items are shared only when that pays: the caller passed a :class:`Sharing`, the machine has a second core,
the child is running, and the estimated work is long enough to repay the round trip. A child that dies on the
way costs nothing but time: its share is done here.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from ..errors import FileFormatError
from . import child

__all__ = ["MIN_SHARED_MS", "Sharing", "pack", "share", "unpack"]

#: Estimated work below which the items are not shared (ms): a round trip costs a few ms.
MIN_SHARED_MS = 60.0


@dataclass(frozen=True)
class Sharing:
    """A lone process's leave to share its items with the idle child.

    Attributes
    ----------
    imports : tuple of str
        Modules the child imports while idle after each answer, before the first share reaches it (the work
        the caller will send it), named by the caller.
    """

    imports: tuple = ()

    def active(self) -> bool:
        """Whether items may be shared now: a second core and a running child."""
        try:
            cores = len(os.sched_getaffinity(0))
        except (AttributeError, OSError):
            cores = os.cpu_count() or 1
        return cores >= 2 and child.warm()


def share(items: list, costs: list, here, finish, function: str, args: tuple, *, sharing: Sharing | None = None,
          done=None) -> list:
    """``finish(item, here(item))`` per item, in order, part of them done by the child.

    Parameters
    ----------
    items : list
        Picklable (e.g. control nets).
    costs : list of float
        Estimated milliseconds per item (they size the rounds only).
    here : callable(item) -> object
        The first phase in this process (nothing that needs the child: it is busy).
    finish : callable(item, first) -> outcome
        The second phase, after the child has answered.
    function : str
        ``"module:function"`` run in the child as ``function(items, *args)``: the two phases of its
        items, each packed by :func:`pack`.
    sharing : Sharing, optional
        The caller's leave to share (None: every item is done here, in order).
    done : callable(index), optional
        Called as each outcome is known (progress).

    Returns
    -------
    list
        One outcome per item; exceptions are outcomes too (the caller raises the first).

    Notes
    -----
    Rounds, longest items first: the child is sent the longest items up to half the estimated work
    left; meanwhile this process takes the next longest one at a time, and as soon as the child has
    answered (checked between items) the next round sends it half of what is left. The estimates
    only size the rounds, so a wrong one costs at most an item's time on either side, never an idle
    core for the rest of the file. Who computed an item does not change its outcome.
    """
    def serial():
        out = []
        for k, item in enumerate(items):
            out.append(finish(item, here(item)))
            if done:
                done(k)
        return out

    if sharing is None or len(items) < 2 or sum(costs) < MIN_SHARED_MS or not sharing.active():
        return serial()
    from collections import deque

    todo = deque(sorted(range(len(items)), key=lambda i: -costs[i]))
    mine: list = []
    first: dict = {}
    answers: dict = {}

    def work():
        while todo and not child.answered():
            i = todo.popleft()
            mine.append(i)
            first[i] = here(items[i])
            if done:  # progress as this process's items are done; their second phase is short
                done(i)

    path = getattr(getattr(items[0], "origin", None), "file", None) or "<nets>"
    while len(todo) >= 2:
        left, batch, taken = sum(costs[i] for i in todo), [], 0.0
        while todo and (not batch or taken + costs[todo[0]] <= left / 2):
            batch.append(todo.popleft())
            taken += costs[batch[-1]]
        try:
            got = child.call(function, ([items[i] for i in batch], *args), path=path, what="analysis",
                             timeout=float("inf"), during=work, idle=sharing.imports)
        except FileFormatError:  # the child died or failed: its share, and what is left, is done here
            mine.extend(batch)
            break
        answers.update(zip(batch, (unpack(a) for a in got)))
    mine.extend(todo)
    out: list = [None] * len(items)
    for i in sorted(mine):
        had = i in first
        out[i] = finish(items[i], first.pop(i) if had else here(items[i]))  # pop: its fields can go
        if done and not had:
            done(i)
    for i in sorted(answers):
        out[i] = answers[i]
        if done:
            done(i)
    return out


def pack(outcome):
    """An outcome as plain picklable data (errors as the child sends its own: :func:`.child.error_fields`)."""
    return ("error", *child.error_fields(outcome)) if isinstance(outcome, BaseException) else ("ok", outcome)


def unpack(answer):
    """The outcome :func:`pack` packed."""
    return answer[1] if answer[0] == "ok" else child.rebuilt_error(*answer[1:])
