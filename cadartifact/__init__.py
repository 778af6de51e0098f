"""cadartifact: measure the ripples a control net puts into a surface and advise its density.

The public API is loaded lazily: ``import cadartifact`` imports the standard library only (so the
CLI starts OCCT's reader child before anything else), numpy loads with the first net, and
OCP/cadquery, pyvista, matplotlib and trimesh the first time a feature needs them.

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
__version__ = "0.1.0"

# public name -> (module, attribute) loaded on first use; attribute None: the module. The core is
# lazy too: the reader child (execution.child) imports this package and needs none of the analysis.
_LAZY = {
    "ControlNet": ("net", "ControlNet"),
    "NetOrigin": ("net", "NetOrigin"),
    "Scheme": ("theory.catalogue", "Scheme"),
    "box": ("theory.catalogue", "box"),
    "bspline": ("theory.catalogue", "bspline"),
    "scheme": ("theory.catalogue", "scheme"),
    "schemes": ("theory.catalogue", "schemes"),
    "Response": ("theory.spectral", "Response"),
    "design": ("theory.design", "design"),
    "Budget": ("analysis.budget", "Budget"),
    "budget": ("analysis.budget", "budget"),
    "Advice": ("advice.advise", "Advice"),
    "advise": ("advice.advise", "advise"),
    "resample": ("advice.advise", "resample"),
    "load": ("exchange.load", "load"),
    "read": ("exchange.load", "read"),
    "from_shape": ("exchange.load", "from_shape"),
    "write_step": ("exchange.load", "write_step"),
    "write_model": ("exchange.load", "write_model"),
    "cq": ("cq", None),
}

ERRORS = ("CadArtifactError", "InputError", "FileFormatError", "UnsupportedFormatError", "InvalidNetError",
          "OptionError", "SchemeError", "MissingDependencyError", "ArtifactToleranceError")

__all__ = [*ERRORS, "errors", "__version__", *_LAZY]


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
