"""The JSON Schema of each document, generated from its records (:mod:`.advise`, :mod:`.gate`, :mod:`.inspected`)
by pydantic (imported here only, when a schema is asked for)."""

from __future__ import annotations

import copy
import functools
import importlib
from typing import Any

__all__ = ["KINDS", "DIALECT", "json_schema"]

#: Document kind -> (module, record type, the constant holding its version).
KINDS = {"advise": ("advise", "AdviseDocument", "ADVISE_SCHEMA"),
         "gate": ("gate", "GateDocument", "GATE_SCHEMA"),
         "inspect": ("inspected", "InspectDocument", "INSPECT_SCHEMA")}

#: The JSON Schema dialect pydantic writes.
DIALECT = "https://json-schema.org/draft/2020-12/schema"


def json_schema(kind: str) -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of a document.

    Parameters
    ----------
    kind : {"advise", "gate", "inspect"}

    Returns
    -------
    dict
        The schema: ``title`` the document's version (``cadartifact.advise/3``), every record a ``$defs`` entry,
        closed (``additionalProperties: false``: a key the record does not list fails), each key described by
        its docstring.

    Raises
    ------
    OptionError
        ``kind`` is not one of :data:`KINDS`.
    MissingDependencyError
        pydantic is not installed.
    """
    from ...errors import check_option

    check_option("kind", kind, KINDS)
    return copy.deepcopy(_generated(kind))


@functools.lru_cache(maxsize=None)
def _generated(kind: str) -> dict[str, Any]:
    """The schema of a known ``kind``, generated once per process (pydantic's generation takes a second)."""
    from ...dependencies import require

    require("pydantic", "the documents' JSON Schema")
    from pydantic import TypeAdapter

    module_name, record, version = KINDS[kind]
    module = importlib.import_module(f"{__package__}.{module_name}")
    _describe_keys()
    schema: dict[str, Any] = TypeAdapter(getattr(module, record)).json_schema()
    schema.pop("title", None)
    return {"$schema": DIALECT, "title": getattr(module, version), **schema}


def _describe_keys() -> None:
    """Let pydantic read each key's docstring as its description (``use_attribute_docstrings``), set on every
    record of the documents' modules: they stay plain typing, with no pydantic at run time."""
    from . import advise, face, gate, inspected

    for module in (face, advise, gate, inspected):
        for value in vars(module).values():
            if isinstance(value, type) and issubclass(value, dict) and hasattr(value, "__required_keys__"):
                value.__pydantic_config__ = {"use_attribute_docstrings": True}  # type: ignore[attr-defined]
