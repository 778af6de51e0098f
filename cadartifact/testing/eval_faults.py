"""Faults injected into OCCT's evaluation in the reader child (tests/exchange/test_isolated_evaluation.py): the child
imports this module by name, as it imports the real evaluator (``cadartifact.exchange.load.EVALUATE``)."""

import os
import time


def _real(net, u, v):
    from cadartifact.exchange.occ import evaluate_grid

    return evaluate_grid(net, u, v)


def crash(net, u, v):
    """OCCT dies evaluating the hood's face (SIGABRT), evaluates the others."""
    if "hood" in (net.origin.file or ""):
        os.abort()
    return _real(net, u, v)


def hang(net, u, v):
    """OCCT loops on the hood's face, evaluates the others."""
    if "hood" in (net.origin.file or ""):
        time.sleep(600)
    return _real(net, u, v)
