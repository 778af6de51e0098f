"""How a run executes: timeouts, workers and backend, validated once and passed down whole.

:class:`ExecutionSettings` is built where the run starts (the CLI reads the environment there:
:mod:`cadartifact.cli.environment`; a library caller builds it or takes the defaults) and travels with the
run's work: into worker processes with each task, into :func:`cadartifact.execution.child.configured` for
the reader child. Nothing below reads the environment.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from ..errors import OptionError

__all__ = ["BACKENDS", "DEFAULT_READ_TIMEOUT", "ClusterOptions", "ExecutionSettings", "InvalidValue",
           "check_timeout"]

#: Seconds a reader (or an OCCT evaluation) may take in the child before it is stopped.
DEFAULT_READ_TIMEOUT = 120.0
#: Where a run's items are worked on: this process, a pool of local processes, a Dask cluster.
BACKENDS = ("serial", "process", "dask")


def check_timeout(value, parameter: str = "timeout") -> float:
    """``value`` as a positive finite number of seconds.

    Raises
    ------
    OptionError
        Naming ``parameter``, for anything else.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (0 < value < math.inf):
        raise OptionError(parameter, "a positive number of seconds", value)
    return float(value)


@dataclass(frozen=True)
class InvalidValue:
    """A setting's value that could not be read (an environment variable's text), kept as given so that its error
    is raised where the setting is used: a run that never needs it (no B-rep read, or an option that replaces it)
    is not stopped by it.

    Attributes
    ----------
    parameter : str
        What was given (the variable's name).
    expected : str
    received : object
    """

    parameter: str
    expected: str
    received: object

    def error(self) -> OptionError:
        """The :class:`~cadartifact.errors.OptionError` naming ``parameter``, ``expected`` and ``received``."""
        return OptionError(self.parameter, self.expected, self.received)


@dataclass(frozen=True)
class ClusterOptions:
    """Where and how to run on Dask.

    Attributes
    ----------
    address : str
        ``"local"`` or a scheduler address (``tcp://host:8786``, ``host:8786``).
    workers : int
        Worker processes of the local cluster (ignored for a remote scheduler).
    ship : bool
        Send the files' bytes instead of their paths.
    timeout : float
        Seconds to wait for the scheduler.
    retries : int
        Dask task retries on an exception.
    face_batches : int or None
        Face batches per big file (held to 1..8); None: as many as leave no thread idle (tests and benchmarks
        force it).
    worker_exit : str
        Test hook: ``NAME`` (a file's base name) makes the worker gating it exit at once, every time;
        ``NAME:MARKER`` only while the file MARKER does not exist (it is created first: one death).
        Several specs are separated by commas. Empty: none.
    """

    address: str
    workers: int = 1
    ship: bool = False
    timeout: float = 10.0
    retries: int = 2
    face_batches: int | None = None
    worker_exit: str = ""

    def __post_init__(self):
        if not isinstance(self.address, str) or not self.address.strip():
            raise OptionError("--scheduler", "'local' or a scheduler address such as tcp://host:8786", self.address)
        if not (self.timeout > 0):
            raise OptionError("--scheduler-timeout", "a number of seconds > 0", self.timeout)
        if int(self.workers) < 1:
            raise OptionError("--jobs", "a number of processes >= 1", self.workers)


@dataclass(frozen=True)
class ExecutionSettings:
    """How one run executes (validated once, then passed down whole).

    Attributes
    ----------
    read_timeout : float or InvalidValue
        Seconds OCCT's reader (or one evaluation) may take in the reader child before it is stopped; an
        :class:`InvalidValue` raises its error when a reader asks for it (:func:`.child.read_timeout`).
    isolation : bool
        Run OCCT's readers and evaluation in the reader child (False: in this process, for debugging; a
        crash then ends the run).
    share_faces : bool
        A lone process may share a file's faces with the idle reader child (:mod:`.sharing`).
    reuse_faces : bool
        Faces that repeat an earlier one moved rigidly reuse its analysis.
    workers : int
        Processes: 1 runs in this process.
    cluster : ClusterOptions or None
        Run on Dask instead of this machine's processes.
    """

    read_timeout: float | InvalidValue = DEFAULT_READ_TIMEOUT
    isolation: bool = True
    share_faces: bool = True
    reuse_faces: bool = True
    workers: int = 1
    cluster: ClusterOptions | None = None

    def __post_init__(self):
        if not isinstance(self.read_timeout, InvalidValue):  # else its error is raised where it is read
            object.__setattr__(self, "read_timeout", check_timeout(self.read_timeout, "read_timeout"))
        for name in ("isolation", "share_faces", "reuse_faces"):
            object.__setattr__(self, name, bool(getattr(self, name)))
        if isinstance(self.workers, bool) or not isinstance(self.workers, int) or self.workers < 1:
            raise OptionError("workers", "a whole number of processes >= 1", self.workers)
        if self.cluster is not None and not isinstance(self.cluster, ClusterOptions):
            raise OptionError("cluster", "ClusterOptions or None", type(self.cluster).__name__)

    @property
    def backend(self) -> str:
        """``"dask"`` with cluster options, ``"process"`` with more than one worker, else ``"serial"``."""
        return "dask" if self.cluster is not None else "process" if self.workers > 1 else "serial"

    def replace(self, **changes) -> ExecutionSettings:
        """A copy with ``changes`` (validated again)."""
        return dataclasses.replace(self, **changes)
