"""Lazy loading of the heavy optional stack (OCP, cadquery, pyvista, matplotlib, trimesh).

``import cadartifact`` loads the standard library only (numpy comes with the first
net); everything else is imported the first time a feature needs it, through
:func:`require`, so that a missing package
gives a one-line error naming what to install rather than an ImportError deep
in a traceback.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from .errors import MissingDependencyError

# module name -> the pip package that provides it
_PACKAGES = {
    "OCP": "cadquery-ocp",
    "cadquery": "cadquery",
    "pyvista": "pyvista",
    "vtk": "vtk",
    "matplotlib": "matplotlib",
    "trimesh": "trimesh",
    "meshio": "meshio",
    "typer": "typer",
    "rich": "rich",
}


def require(module: str, feature: str | None = None) -> ModuleType:
    """Import ``module`` or raise :class:`MissingDependencyError` naming the package to install.

    Parameters
    ----------
    module : str
        Dotted module name, e.g. ``"OCP.STEPControl"``.
    feature : str, optional
        What the module is needed for, quoted in the error message.
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".")[0]
        package = _PACKAGES.get(top, top)
        what = f" for {feature}" if feature else ""
        raise MissingDependencyError(
            f"{module} is needed{what} but could not be imported ({exc}); install it with: pip install {package}"
        ) from exc
