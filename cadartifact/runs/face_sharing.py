"""One file's faces shared between this process and the reader child (a second core, one file).

``gate --jobs 1`` and ``advise`` run one process, and after OCCT's read its reader child
(:mod:`cadartifact.exchange.isolation`) sits idle on the second core. :func:`share` hands it part of
the file's faces in rounds (half of what is left, longest first, whenever it has answered), works on
the rest here at the same time and returns one outcome per face in face order, as the serial loop
would: the same records (the child runs the same code, with the same one BLAS thread, so the numbers
are the same to the bit) and the same first error.
:func:`analyse_faces` is the gate's per-face work, :func:`advise_faces` the advise document's: both run the one
face pipeline (:mod:`cadartifact.runs.face`, its two phases) under their door's options and word its errors as
their documents do; both analyse a face that repeats an earlier one moved rigidly only once (:func:`per_instance`).

The faces are shared only when that pays: this process is the only worker (:func:`enabled`;
``--jobs 2`` workers already fill the cores), the machine has a second core, the reader child is
running, and the file's estimated analysis time is long enough to repay the round trip. A child
that dies on the way costs nothing but time: its share is done here. While the child works it cannot
evaluate surfaces for this process (peak locations and verification go through it when OCP is not
imported here), so this process's share runs in two phases: the analysis, then, once the child has
answered, what needs OCCT.
"""

from __future__ import annotations

import contextlib
import os

from ..errors import CadArtifactError, FileFormatError
from ..exchange.isolation import ChildFailed
from ..exchange.reader_start import ANALYSIS_MODULES

__all__ = ["advise_faces", "analyse_faces", "enabled", "estimated_ms", "one_blas_thread", "per_instance",
           "quiet_analysis", "share", "sharing"]

#: Estimated analysis time below which the faces are not shared (ms): a round trip costs a few ms.
MIN_SHARED_MS = 60.0
#: What the child's first share costs before its first face: importing the analysis (ms).
CHILD_START_MS = 60.0
#: What a face's advice costs beyond its budgets, whatever its size (ms): the search's and the scheme
#: comparison's many small steps (measured: a 3x5 face of boxed_sphere 50 ms, a 23x23 one 130 ms).
ADVICE_MS = 40.0

_enabled = False


@contextlib.contextmanager
def sharing(on: bool = True):
    """Within the block, faces may be shared with the reader child (``gate --jobs 1``, ``advise``)."""
    global _enabled
    from ..exchange import isolation

    saved, _enabled = _enabled, bool(on)
    # the child imports the analysis while idle after its read, before the first share reaches it
    imports = isolation.set_idle_imports(ANALYSIS_MODULES if on else ())
    try:
        yield
    finally:
        _enabled = saved
        isolation.set_idle_imports(imports)


def one_blas_thread():
    """One BLAS thread while a file is analysed, in this process, a worker or the reader child.

    Workers already fill the cores (nested BLAS threads oversubscribe them: two workers with two
    threads each ran slower than one process), and the same thread count everywhere keeps the
    floating-point summation order, hence the document, identical for every ``--jobs``, with or
    without shared faces (OpenBLAS sums in another order on more threads: 1e-13 apart).
    """
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1, user_api="blas")


@contextlib.contextmanager
def quiet_analysis():
    """The gate's numerical settings: :func:`one_blas_thread`, no numpy floating-point warnings and no
    warnings at all (e.g. 1e300 coordinates overflow: the non-finite result becomes an error instead)."""
    import warnings

    import numpy as np

    with warnings.catch_warnings(), np.errstate(all="ignore"), one_blas_thread():
        warnings.simplefilter("ignore")
        yield


def enabled() -> bool:
    """Whether faces may be shared now: inside :func:`sharing`, with a second core and a running reader
    child (``CADARTIFACT_SHARE_FACES=0`` turns it off)."""
    from ..exchange import isolation

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


def share(items: list, costs: list, here, finish, child: str, args: tuple, *, done=None) -> list:
    """``finish(item, here(item))`` per item, in order, part of them done by the reader child.

    Parameters
    ----------
    items : list
        Picklable (control nets).
    costs : list of float
        Estimated milliseconds per item (:func:`estimated_ms`).
    here : callable(item) -> object
        The first phase in this process (no OCCT evaluation: the child is busy).
    finish : callable(item, first) -> outcome
        The second phase, after the child has answered.
    child : str
        ``"module:function"`` run in the child as ``function(items, *args)``: the two phases of its
        items, packed by :func:`pack`.
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

    if len(items) < 2 or sum(costs) < MIN_SHARED_MS or not enabled():
        return serial()
    from collections import deque

    from ..exchange import isolation

    todo = deque(sorted(range(len(items)), key=lambda i: -costs[i]))
    mine: list = []
    first: dict = {}
    answers: dict = {}

    def work():
        while todo and not isolation.answered():
            i = todo.popleft()
            mine.append(i)
            first[i] = here(items[i])
            if done:  # progress as this process's faces are analysed; their second phase is short
                done(i)

    path = getattr(getattr(items[0], "origin", None), "file", None) or "<nets>"
    while len(todo) >= 2:
        left, batch, taken = sum(costs[i] for i in todo), [], 0.0
        while todo and (not batch or taken + costs[todo[0]] <= left / 2):
            batch.append(todo.popleft())
            taken += costs[batch[-1]]
        try:
            got = isolation.call(child, ([items[i] for i in batch], *args), path=path, what="analysis",
                                 timeout=float("inf"), during=work)
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


def analyse_faces(nets: list, settings, verify: bool, *, only=None) -> list:
    """The gate's per-face work (:func:`face_outcome`), shared: records (``peak_at`` set, ``entity_line``
    not) or the :class:`CadArtifactError` naming the face, in face order. ``verify`` runs are not shared
    (the advice's verification needs OCCT in the first phase).

    Parameters
    ----------
    nets : list of ControlNet
    settings : FileSettings
        The file's settings; the peak is located on the budget entry its tolerance bounds
        (``settings.run.compared``).
    verify : bool
    only : list of int, optional
        The outcomes of these faces only (a batch of the file's faces), as the whole file's run gives them.
    """
    def run(faces, done):
        if verify:
            return [face_outcome(n, settings, verify) for n in faces]
        return share(faces, [estimated_ms(n) for n in faces], lambda n: _budgeted(n, settings, verify),
                     lambda n, first: _located(first, settings, verify), "cadartifact.runs.face_sharing:child_gate",
                     (settings, verify))

    from .face_instances import instance_record

    return per_instance(nets, run, instance_record, only=only)


def child_gate(nets: list, settings, verify: bool) -> list:
    """The reader child's side of :func:`analyse_faces`."""
    return _in_child(lambda n: face_outcome(n, settings, verify), nets)


def advise_faces(nets: list, settings, advice: dict, path, *, done=None, keep: bool = False) -> list:
    """The advise document's per-face work, shared: ``(record, advice)`` (``peak_at`` set, ``entity_line``
    not; the advice only with ``keep``, else None: each holds its budget's fields) or the exception, in
    face order.

    ``settings``: the run's :class:`~cadartifact.analysis.settings.RunSettings`; ``advice``: the advice's own
    options (``compare``, ``verify``: :func:`cadartifact.advice.advise.advise_for`).
    """
    def run(faces, done):
        costs = [ADVICE_MS + 4.0 * estimated_ms(n) for n in faces]  # a search and a comparison: several budgets
        return share(faces, costs, lambda n: _advised(n, settings, advice, path, later=True),
                     lambda n, work: _recorded(work, n, settings, path, keep),
                     "cadartifact.runs.face_sharing:child_advise", (settings, advice, str(path)), done=done)

    if keep:  # the Advice objects (advised nets to write) are each face's own
        return run(nets, done)
    from .face_instances import instance_record

    return per_instance(nets, run, lambda out, face, net, motion: (instance_record(out[0], face, net, motion), None),
                        done=done)


def per_instance(nets: list, run, moved, *, done=None, only=None) -> list:
    """``run(faces, done)``'s outcomes for the first face of each shape, and for the faces that repeat one
    (:func:`cadartifact.runs.face_instances.instances`) ``moved(outcome, face, net, motion)`` of it, in face order.

    A repeated face's error is its first face's (which comes earlier, so the run stops there first).
    ``done(index)`` is called as each outcome is known, the repeats' after the others'. ``only``: the
    outcomes of these indices only (the first faces they repeat are analysed whichever they are).
    """
    from .face_instances import enabled, instances

    plan = instances(nets) if enabled() and len(nets) > 1 else [(i, None) for i in range(len(nets))]
    wanted = list(range(len(nets))) if only is None else list(only)
    firsts = sorted({plan[i][0] for i in wanted})
    if firsts == wanted:
        return run([nets[i] for i in wanted], done)
    outs = dict(zip(firsts, run([nets[i] for i in firsts], (lambda k: done(firsts[k])) if done else None)))
    out = []
    for i in wanted:
        rep, motion = plan[i]
        got = outs[rep]
        if rep != i:
            got = got if isinstance(got, BaseException) else moved(got, nets[rep], nets[i], motion)
            if done:
                done(i)
        out.append(got)
    return out


def child_advise(nets: list, settings, advice: dict, path) -> list:
    """The reader child's side of :func:`advise_faces`: records only (an Advice stays where it was made)."""
    return _in_child(lambda n: _recorded(_advised(n, settings, advice, path, later=False), n, settings, path, False),
                     nets)


def _advise_options(advice: dict):
    """The advise door's :class:`~cadartifact.runs.face.FaceOptions`, with the run's ``compare`` and ``verify``."""
    from .face import ADVISE

    return ADVISE.replace(**advice)


def _advised(net, settings, advice: dict, path, later: bool):
    """Phase one of the advise work (:func:`cadartifact.runs.face.start_face`: the advice's verification left for
    later with ``later``) or the exception."""
    from . import face

    try:
        return face.start_face(net, settings, _advise_options(advice), later=later)
    except face.NonFiniteResult as exc:
        return FileFormatError(path, f"face {net.origin.face}: {exc}")
    except Exception as exc:  # noqa: BLE001 - raised by the caller, in face order
        return exc


def _recorded(work, net, settings, path, keep: bool):
    """Phase two (:func:`cadartifact.runs.face.finish_face`: the verification left for later, the peak's location):
    ``(record, advice if keep else None)`` or the exception."""
    from . import face

    if isinstance(work, BaseException):
        return work
    try:
        work = face.finish_face(work, settings, _advise_options({}))
        return work.record, (work.advice if keep else None)
    except Exception as exc:  # noqa: BLE001
        return exc


def _in_child(one, items) -> list:
    """``pack(one(item))`` per item under the gate's numerical settings (:func:`quiet_analysis`)."""
    with quiet_analysis():
        return [pack(one(item)) for item in items]


def pack(outcome):
    """An outcome as plain picklable data (errors as the reader child sends its own:
    :func:`cadartifact.exchange.isolation.error_fields`)."""
    from ..exchange.isolation import error_fields

    return ("error", *error_fields(outcome)) if isinstance(outcome, BaseException) else ("ok", outcome)


def unpack(answer):
    """The outcome :func:`pack` packed."""
    from ..exchange.isolation import rebuilt_error

    return answer[1] if answer[0] == "ok" else rebuilt_error(*answer[1:])


def face_outcome(net, settings, verify: bool):
    """The gate record of one face with its peak location, or the :class:`CadArtifactError` the serial
    gate raises for it (other exceptions become ``analysis failed (Type: message)``, as the gate words them)."""
    return _located(_budgeted(net, settings, verify), settings, verify)


def _gate_options(settings, verify: bool):
    """The gate door's :class:`~cadartifact.runs.face.FaceOptions` under a file's settings (its ``advise``)."""
    from .face import GATE

    return GATE.replace(advice=settings.advise, verify="failing" if verify else False)


def _budgeted(net, settings, verify: bool):
    """Phase one of the gate's work (:func:`cadartifact.runs.face.start_face`, no OCCT evaluation except the
    advice's verification) or the error, worded as the gate words it."""
    from . import face

    try:
        return face.start_face(net, settings, _gate_options(settings, verify))
    except ChildFailed as exc:  # OCCT's evaluation crashed or hung in the child: it names the face
        return exc
    except CadArtifactError as exc:
        return CadArtifactError(f"face {net.origin.face}: {exc}")
    except Exception as exc:  # noqa: BLE001 - fail closed, worded as the gate words it
        return CadArtifactError(f"analysis failed ({type(exc).__name__}: {exc})")


def _located(work, settings, verify: bool):
    """Phase two (:func:`cadartifact.runs.face.finish_face`: the peak's location) and the record, or the error."""
    from . import face

    if isinstance(work, BaseException):
        return work
    try:
        return face.finish_face(work, settings, _gate_options(settings, verify)).record
    except ChildFailed as exc:  # OCCT's evaluation crashed or hung in the child: the face's error, named
        return exc
    except Exception as exc:  # noqa: BLE001 - fail closed, worded as the gate words it
        return CadArtifactError(f"analysis failed ({type(exc).__name__}: {exc})")
