"""The execution wing: where work runs, one level above :mod:`cadartifact.errors` so that every wing may use it.

Standard library only at import (the CLI's first step imports :mod:`.start` before numpy).

- :mod:`.settings`: :class:`~.settings.ExecutionSettings` (timeouts, workers, backend, cluster options), validated
  once and passed down whole; the environment is read only at the CLI's edge (:mod:`cadartifact.cli.environment`);
- :mod:`.executors`: one interface, ``map(function, items, done)``, run serially or in a process pool;
- :mod:`.dask`: the Dask backend's connection (``distributed`` imported lazily);
- :mod:`.child`, :mod:`.start`: a long-lived child process that runs ``module:function`` requests with a timeout
  (OCCT's readers and evaluation), and its start-up;
- :mod:`.sharing`: one process's items shared with that idle child.

The modules a child imports are named by the callers (the higher wings), never here.
"""
