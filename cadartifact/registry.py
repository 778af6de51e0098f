"""Live read-only views of a registry: what is derived from a registry and read at each use.

A registry (the file formats, the named schemes, the gate's criteria) is one dict; tables derived from it
(suffix -> format, the names of the schemes) are these views, computed from the registry whenever they are read,
so that an entry added later (a plugin, a test's fixture) is in every one of them. Standard library only.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Callable

__all__ = ["LiveMapping", "LiveTuple"]


class _Live:
    """What both views share: the function that computes the table from the registry, at each use."""

    def __init__(self, compute: Callable):
        self._compute = compute

    def __len__(self):
        return len(self._compute())

    def __iter__(self):
        return iter(self._compute())

    def __repr__(self):
        return repr(self._compute())


class LiveMapping(_Live, Mapping):
    """A read-only mapping computed from the registry at each use (an entry registered later is in it)."""

    def __getitem__(self, key):
        return self._compute()[key]


class LiveTuple(_Live, Sequence):
    """A read-only sequence computed from the registry at each use (``tuple(view)`` for ``str.endswith``)."""

    def __getitem__(self, index):
        return self._compute()[index]

    def __contains__(self, item):
        return item in self._compute()

    def __eq__(self, other):
        return tuple(self._compute()) == (tuple(other) if isinstance(other, LiveTuple) else other)

    __hash__ = None
