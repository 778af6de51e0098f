"""The exchange wing: files to control nets and back (STEP, IGES, BREP through OCCT; OBJ cages).

Formats only, no analysis. Importing this package loads nothing: the names below come from their
modules on first use, so that :mod:`.reader_start` (the reader child's start-up, standard library
only) can be imported before numpy.

- :mod:`.load`: :func:`read`, :func:`load`, :func:`from_shape`, :func:`write_step`, :func:`write_model`;
- :mod:`.formats`: the registry of the file formats (suffixes, readers), from which every format table is derived;
- :mod:`.files`: the file check, the suffix table, :class:`LoadResult`;
- :mod:`.step`, :mod:`.step_scan`, :mod:`.step_text`, :mod:`.occ`, :mod:`.canonical`: STEP/IGES/BREP through OCCT;
- :mod:`.obj`, :mod:`.quadmesh`: OBJ cages and their regular charts;
- :mod:`.model_writer`: a whole model with resampled faces; :mod:`.summary`: what ``inspect`` prints;
- :mod:`.reader_start`: what OCCT's reader child (:mod:`cadartifact.execution.child`) preloads and reads.

>>> from cadartifact.exchange import read
>>> result = read("samples/wavy_panel_diagonal.step")            # doctest: +SKIP
>>> result.nets[0].shape, result.skipped                          # doctest: +SKIP
((12, 12), {})
"""

from __future__ import annotations

import importlib

__all__ = ["LoadResult", "LoadWarning", "QuadMesh", "Chart", "SUPPORTED_EXTENSIONS", "read", "load", "from_shape",
           "write_step", "write_model", "occ_surface", "evaluate_grid"]


def __getattr__(name: str):
    if name not in __all__:
        raise AttributeError(f"module 'cadartifact.exchange' has no attribute {name!r}")
    value = getattr(importlib.import_module(".load", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
