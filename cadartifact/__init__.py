"""cadartifact: measure the ripples a control net puts into a surface and advise its density.

The public API is loaded lazily: ``import cadartifact`` imports numpy only, and
OCP/cadquery, pyvista, matplotlib and trimesh load the first time a feature
needs them.

>>> import cadartifact as ca
>>> ca.scheme("bicubic").response(0.1, 0.2, stage="limit").percent   # doctest: +SKIP
"""

from __future__ import annotations

import importlib

from . import errors
from .errors import (  # the error hierarchy, so that callers can write ``except cadartifact.InputError``
    ArtifactToleranceError,
    CadArtifactError,
    FileFormatError,
    InputError,
    InvalidNetError,
    MissingDependencyError,
    OptionError,
    SchemeError,
    UnsupportedFormatError,
)
from .net import ControlNet, NetOrigin

__version__ = "0.1.0"

# The numerical core imports numpy only, so it is loaded eagerly. This also matters for names
# shared by a module and a function (``schemes``, ``budget``): importing a submodule binds the
# package attribute to the module, so the function must be bound after it.
from .schemes import Scheme, box, bspline, scheme, schemes  # noqa: E402
from .spectral import Response  # noqa: E402
from .artifact_budget import Budget, budget  # noqa: E402
from .advice import Advice, advise, resample  # noqa: E402

# public name -> (module, attribute) loaded on first use (OCP, cadquery); attribute None: the module
_LAZY = {
    "load": ("exchange", "load"),
    "read": ("exchange", "read"),
    "from_shape": ("exchange", "from_shape"),
    "write_step": ("exchange", "write_step"),
    "write_model": ("exchange", "write_model"),
    "cq": ("cadquery_plugin", None),
}

ERRORS = ("CadArtifactError", "InputError", "FileFormatError", "UnsupportedFormatError", "InvalidNetError",
          "OptionError", "SchemeError", "MissingDependencyError", "ArtifactToleranceError")

__all__ = ["ControlNet", "NetOrigin", *ERRORS, "errors", "__version__", "Scheme", "box", "bspline",
           "scheme", "schemes", "Response", "Budget", "budget", "Advice", "advise", "resample", *_LAZY]


def __getattr__(name: str):
    try:
        module, attr = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'cadartifact' has no attribute {name!r}") from None
    mod = importlib.import_module(f".{module}", __name__)
    value = mod if attr is None else getattr(mod, attr)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
