"""The gate's usage error: a policy or profile file (or a gate option) with an unknown key or a bad value.

Its own module so that :mod:`cadartifact.gate.policy` and :mod:`cadartifact.gate.profiles` both raise it without
importing each other (``from cadartifact.gate.policy import PolicyError`` keeps working).
"""

from __future__ import annotations

from ..errors import CadArtifactError

__all__ = ["PolicyError"]


class PolicyError(CadArtifactError):
    """A policy file (or a gate option) with an unknown key or a bad value; names the file and the key."""

    def __init__(self, source: str, key: str | None, problem: str):
        self.source, self.key, self.problem = source, key, problem
        if key is None:
            text = f"{source}: {problem}"
        else:  # "key 'k' is unknown ..." reads as a sentence; "key 'k': expected ..." for a bad value
            text = f"{source}: key {key!r}{' ' if problem.startswith('is ') else ': '}{problem}"
        super().__init__(text)
