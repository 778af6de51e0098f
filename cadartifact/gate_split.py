"""One gated file's faces shared between this process and the reader child (a second core, one file).

``gate --jobs 1`` runs one process, and after OCCT's read its reader child (:mod:`cadartifact.exchange.isolation`)
sits idle on the second core. :func:`analyse_faces` hands it part of the file's faces, analyses the
rest here at the same time and returns one outcome per face in face order, as the serial loop would:
the same records (the child runs the same code, with the same one BLAS thread, so the numbers are the
same to the bit) and the same first error.

The faces are shared only when that pays: this process is the gate's only worker (:func:`enabled`;
``--jobs 2`` workers already fill the cores), the machine has a second core, the reader child is
running, and the file's estimated analysis time is long enough to repay the round trip. A child
that dies on the way costs nothing but time: its share is analysed here.
"""

from __future__ import annotations

import contextlib
import os

from .errors import CadArtifactError, FileFormatError

__all__ = ["analyse_faces", "enabled", "sharing", "estimated_ms"]

#: Estimated analysis time below which the faces are not shared (ms): a round trip costs a few ms.
MIN_SHARED_MS = 60.0
#: What the child's first share costs before its first face: importing the analysis (ms).
CHILD_START_MS = 60.0

_enabled = False


@contextlib.contextmanager
def sharing(on: bool = True):
    """Within the block, :func:`analyse_faces` may share faces with the reader child (``gate --jobs 1``)."""
    global _enabled
    from .exchange import isolation

    saved, _enabled = _enabled, bool(on)
    # the child imports the analysis while idle after its read, before the first share reaches it
    imports = isolation.set_idle_imports(("cadartifact.gate_split", "cadartifact.gate", "cadartifact.advice")
                                         if on else ())
    try:
        yield
    finally:
        _enabled = saved
        isolation.set_idle_imports(imports)


def enabled() -> bool:
    """Whether faces may be shared now: inside :func:`sharing`, with a second core and a running reader
    child (``CADARTIFACT_SHARE_FACES=0`` turns it off)."""
    from .exchange import isolation

    if not _enabled or os.environ.get("CADARTIFACT_SHARE_FACES", "1").strip() in ("0", "no", "off", "false"):
        return False
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    return cores >= 2 and isolation.warm()


def estimated_ms(net) -> float:
    """A face's estimated budget time (ms): a constant plus the fine grid's size, which the band split's
    FFTs over a continuation three times the face scale with (measured: 7x3 about 5 ms, 23x23 about 45)."""
    nu, nv = net.points.shape[:2]
    return 3.0 + 0.08 * nu * nv


def analyse_faces(nets: list, settings, verify: bool, key: str) -> list:
    """One outcome per net, in order: its gate record (``peak_at`` set, ``entity_line`` not) or a
    :class:`CadArtifactError` naming the face, exactly as :func:`face_outcome` gives it.

    Parameters
    ----------
    nets : list of ControlNet
    settings : FileSettings
    verify : bool
    key : {"total", "deviation"}
        The budget entry the peak is located on.

    Notes
    -----
    While the child works on its share it cannot evaluate surfaces for this process (peak locations
    and verification go through it when OCP is not imported here): this process's share is budgeted
    first and located after the child has answered, and ``verify`` runs are not shared.
    """
    costs = [estimated_ms(n) for n in nets]
    if len(nets) < 2 or sum(costs) < MIN_SHARED_MS or verify or not enabled():
        return [face_outcome(n, settings, verify, key) for n in nets]
    # longest first, each to the side that would finish first; the child starts later (its imports)
    mine, theirs, load = [], [], [0.0, CHILD_START_MS]
    for i in sorted(range(len(nets)), key=lambda i: -costs[i]):
        side = 0 if load[0] <= load[1] else 1
        (mine, theirs)[side].append(i)
        load[side] += costs[i]
    if not theirs:
        return [face_outcome(n, settings, verify, key) for n in nets]
    out: list = [None] * len(nets)
    pending: dict = {}

    def here():
        for i in sorted(mine):
            pending[i] = _budgeted(nets[i], settings, verify)

    from .exchange import isolation

    try:
        answers = isolation.call("cadartifact.gate_split:child_share", ([nets[i] for i in theirs], settings, verify,
                                                                          key),
                                 path=nets[0].origin.file or "<nets>", what="analysis", timeout=float("inf"),
                                 during=here)
    except FileFormatError:  # the child died or failed: analyse its share here
        answers = [_pack(face_outcome(nets[i], settings, verify, key)) for i in theirs]
    for i in sorted(mine):
        outcome, current = pending[i] if i in pending else _budgeted(nets[i], settings, verify)
        out[i] = _located(outcome, nets[i], key, current)
    for i, answer in zip(theirs, answers):
        out[i] = _unpack(answer)
    return out


def face_outcome(net, settings, verify: bool, key: str):
    """The gate record of one face with its peak location, or the :class:`CadArtifactError` the serial
    gate raises for it (other exceptions become ``analysis failed (Type: message)``, as the gate words them)."""
    outcome, current = _budgeted(net, settings, verify)
    return _located(outcome, net, key, current)


def _budgeted(net, settings, verify: bool):
    """``(record or error, today's budget where a peak is to be located, else None)``: no OCCT evaluation
    except the advice's verification."""
    import numpy as np

    from .gate import _face_entry

    try:
        if not np.isfinite(np.sum(net.points ** 2)):  # squared norms overflow: nothing finite would come out
            return CadArtifactError(f"face {net.origin.face}: coordinates too large to analyse "
                                    f"(max |x| = {np.abs(net.points).max():.3g})"), None
        try:
            rec, current = _face_entry(net, settings, verify)
        except CadArtifactError as exc:
            return CadArtifactError(f"face {net.origin.face}: {exc}"), None
        located = rec["meets_tolerance"] is False or rec.get("verdict") in ("warn", "fail")
        rec["peak_at"] = None
        return rec, (current, True) if located else None
    except Exception as exc:  # noqa: BLE001 - fail closed, worded as the gate words it
        return CadArtifactError(f"analysis failed ({type(exc).__name__}: {exc})"), None


def _located(outcome, net, key: str, pending):
    """The record with ``peak_at`` (:func:`cadartifact.report.peak_location`) where ``pending`` asks."""
    if pending is None or isinstance(outcome, BaseException):
        return outcome
    from .report import peak_location

    try:
        outcome["peak_at"] = peak_location(net, outcome["scheme"], key, pending[0])
    except (CadArtifactError, ValueError, KeyError):  # a location helps; it never fails a run
        outcome["peak_at"] = None
    except Exception as exc:  # noqa: BLE001 - fail closed, worded as the gate words it
        return CadArtifactError(f"analysis failed ({type(exc).__name__}: {exc})")
    return outcome


def child_share(nets: list, settings, verify: bool, key: str) -> list:
    """The reader child's side: :func:`face_outcome` per net under the gate's numerical settings, packed."""
    import warnings

    import numpy as np

    from .gate import _one_blas_thread

    with warnings.catch_warnings(), np.errstate(all="ignore"), _one_blas_thread():
        warnings.simplefilter("ignore")
        return [_pack(face_outcome(n, settings, verify, key)) for n in nets]


def _pack(outcome):
    return ("error", str(outcome)) if isinstance(outcome, BaseException) else ("ok", outcome)


def _unpack(answer):
    kind, value = answer
    return CadArtifactError(value) if kind == "error" else value
