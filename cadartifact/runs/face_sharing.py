"""One file's faces shared between this process and the reader child (a second core, one file).

``gate --jobs 1`` and ``advise`` run one process, and after OCCT's read its reader child
(:mod:`cadartifact.execution.child`) sits idle on the second core. The execution wing's
:func:`~cadartifact.execution.sharing.share` hands it part of the file's faces in rounds and returns one outcome
per face in face order, as the serial loop would: the same records (the child runs the same code, with the same
one BLAS thread, so the numbers are the same to the bit) and the same first error.
:func:`analyse_faces` is the gate's per-face work, :func:`advise_faces` the advise document's: both run the one
face pipeline (:mod:`cadartifact.runs.face`, its two phases) under their door's options and word its errors as
their documents do; both analyse a face that repeats an earlier one moved rigidly only once (:func:`per_instance`,
unless ``reuse`` is off).

The faces are shared only when the caller passes a :class:`~cadartifact.execution.sharing.Sharing` (it is the only
worker: ``--jobs 2`` workers already fill the cores; the run's ``share_faces`` is on), the machine has a second
core, the reader child is running, and the file's estimated analysis time is long enough to repay the round
trip. While the child works it cannot evaluate surfaces for this process (peak locations and verification go
through it when OCP is not imported here), so this process's share runs in two phases: the analysis, then, once
the child has answered, what needs OCCT.
"""

from __future__ import annotations

import contextlib

from ..errors import CadArtifactError, FileFormatError
from ..execution.child import ChildFailed
from ..execution.sharing import Sharing, pack, share, unpack

__all__ = ["CHILD_IMPORTS", "Sharing", "advise_faces", "analyse_faces", "estimated_ms", "one_blas_thread",
           "pack", "per_instance", "quiet_analysis", "share", "unpack"]

#: What the reader child imports while idle after a read, before its first share: the analysis of faces
#: (callers of higher wings add their own modules).
CHILD_IMPORTS = ("cadartifact.runs.face_sharing", "cadartifact.advice.advise")
#: What the child's first share costs before its first face: importing the analysis (ms).
CHILD_START_MS = 60.0
#: What a face's advice costs beyond its budgets, whatever its size (ms): the search's and the scheme
#: comparison's many small steps (measured: a 3x5 face of boxed_sphere 50 ms, a 23x23 one 130 ms).
ADVICE_MS = 40.0


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


def estimated_ms(net) -> float:
    """A face's estimated budget time (ms): a constant plus the fine grid's size, which the band split's
    FFTs over a continuation three times the face scale with (measured: 7x3 about 5 ms, 23x23 about 45)."""
    nu, nv = net.points.shape[:2]
    return 3.0 + 0.08 * nu * nv


def analyse_faces(nets: list, settings, verify: bool, *, only=None, sharing: Sharing | None = None,
                  reuse: bool = True) -> list:
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
    sharing : Sharing, optional
        Leave to share the faces with the idle reader child (None: all analysed here).
    reuse : bool
        Analyse a face that repeats an earlier one only once (:func:`per_instance`).
    """
    def run(faces, done):
        if verify:
            return [face_outcome(n, settings, verify) for n in faces]
        return share(faces, [estimated_ms(n) for n in faces], lambda n: _budgeted(n, settings, verify),
                     lambda n, first: _located(first, settings, verify), "cadartifact.runs.face_sharing:child_gate",
                     (settings, verify), sharing=sharing)

    from .face_instances import instance_record

    return per_instance(nets, run, instance_record, only=only, reuse=reuse)


def child_gate(nets: list, settings, verify: bool) -> list:
    """The reader child's side of :func:`analyse_faces`."""
    return _in_child(lambda n: face_outcome(n, settings, verify), nets)


def advise_faces(nets: list, settings, advice: dict, path, *, done=None, keep: bool = False,
                 sharing: Sharing | None = None, reuse: bool = True) -> list:
    """The advise document's per-face work, shared: ``(record, advice)`` (``peak_at`` set, ``entity_line``
    not; the advice only with ``keep``, else None: each holds its budget's fields) or the exception, in
    face order.

    ``settings``: the run's :class:`~cadartifact.analysis.settings.RunSettings`; ``advice``: the advice's own
    options (``compare``, ``verify``: :func:`cadartifact.advice.advise.advise_for`); ``sharing``, ``reuse``: as for
    :func:`analyse_faces`.
    """
    def run(faces, done):
        costs = [ADVICE_MS + 4.0 * estimated_ms(n) for n in faces]  # a search and a comparison: several budgets
        return share(faces, costs, lambda n: _advised(n, settings, advice, path, later=True),
                     lambda n, work: _recorded(work, n, settings, path, keep),
                     "cadartifact.runs.face_sharing:child_advise", (settings, advice, str(path)), sharing=sharing,
                     done=done)

    if keep:  # the Advice objects (advised nets to write) are each face's own
        return run(nets, done)
    from .face_instances import instance_record

    return per_instance(nets, run, lambda out, face, net, motion: (instance_record(out[0], face, net, motion), None),
                        done=done, reuse=reuse)


def per_instance(nets: list, run, moved, *, done=None, only=None, reuse: bool = True) -> list:
    """``run(faces, done)``'s outcomes for the first face of each shape, and for the faces that repeat one
    (:func:`cadartifact.runs.face_instances.instances`) ``moved(outcome, face, net, motion)`` of it, in face order.

    A repeated face's error is its first face's (which comes earlier, so the run stops there first).
    ``done(index)`` is called as each outcome is known, the repeats' after the others'. ``only``: the
    outcomes of these indices only (the first faces they repeat are analysed whichever they are). ``reuse=False``:
    every face is run on its own.
    """
    from .face_instances import instances

    plan = instances(nets) if reuse and len(nets) > 1 else [(i, None) for i in range(len(nets))]
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
        hint = " (coordinates or weights too large?)" if str(exc) == face.NON_FINITE_VALUE else ""
        return FileFormatError(path, f"face {net.origin.face}: {exc}{hint}")
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
        hint = " (coordinates too large?)" if str(exc) == face.NON_FINITE_VALUE else ""
        return CadArtifactError(f"face {net.origin.face}: {exc}{hint}")
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
