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
from .errors import CadArtifactError
from .net import ControlNet, NetOrigin

__version__ = "0.1.0"

# public name -> (module, attribute); attribute None means the module itself
_LAZY = {
    "Scheme": ("schemes", "Scheme"),
    "scheme": ("schemes", "scheme"),
    "schemes": ("schemes", "schemes"),
    "box": ("schemes", "box"),
    "bspline": ("schemes", "bspline"),
    "Response": ("spectral", "Response"),
    "load": ("exchange", "load"),
    "from_shape": ("exchange", "from_shape"),
    "budget": ("budget", "budget"),
    "Budget": ("budget", "Budget"),
    "resample": ("advisor", "resample"),
    "advise": ("advisor", "advise"),
    "Advice": ("advisor", "Advice"),
    "write_step": ("exchange", "write_step"),
    "cq": ("cadquery_plugin", None),
}

__all__ = ["ControlNet", "NetOrigin", "CadArtifactError", "errors", "__version__", *_LAZY]


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
