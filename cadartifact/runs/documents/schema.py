"""The JSON Schema of each document, generated from its records (:mod:`.advise`, :mod:`.gate`, :mod:`.inspected`)
by pydantic (imported here only, when a schema is asked for)."""

from __future__ import annotations

import copy
import functools
import importlib
from typing import Any

__all__ = ["KINDS", "DIALECT", "json_schema", "key_docstrings"]

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
        The schema: ``title`` the document's version (``cadartifact.advise/4``), every record a ``$defs`` entry,
        closed (``additionalProperties: false``: a key the record does not list fails), each record and each
        documented key described by its docstring (:func:`key_docstrings`).

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
    schema: dict[str, Any] = TypeAdapter(getattr(module, record)).json_schema()
    records = _records()
    for name, part in [(record, schema), *schema.get("$defs", {}).items()]:
        _describe(part, records.get(name))
    schema.pop("title", None)
    return {"$schema": DIALECT, "title": getattr(module, version), **schema}


def _records() -> dict[str, type]:
    """Every record of the documents' modules by name (the names pydantic gives their ``$defs``)."""
    from . import advise, cage, face, gate, inspected

    return {name: value for module in (face, cage, advise, gate, inspected) for name, value in vars(module).items()
            if isinstance(value, type) and issubclass(value, dict) and hasattr(value, "__required_keys__")}


def _describe(part: dict[str, Any], record: type | None) -> None:
    """Each property of a record's schema gets its key's docstring as ``description`` (inherited keys too:
    pydantic's own reading of attribute docstrings sees the record's class body only)."""
    if record is None:
        return
    docs = key_docstrings(record)
    for key, prop in part.get("properties", {}).items():
        if key in docs:
            prop["description"] = docs[key]


def key_docstrings(record: type) -> dict[str, str]:
    """``{key: docstring}`` of a ``TypedDict``'s keys, its bases' first: the string literal under each annotated
    key in the class bodies (records made by the functional form have none)."""
    import ast
    import inspect
    import textwrap

    out: dict[str, str] = {}
    for cls in _lineage(record):
        try:
            tree = ast.parse(textwrap.dedent(inspect.getsource(cls)))
        except (OSError, TypeError, SyntaxError):  # no source (the functional form; a frozen package)
            continue
        body = tree.body[0].body if tree.body and isinstance(tree.body[0], ast.ClassDef) else []
        for node, after in zip(body, body[1:]):
            if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and isinstance(after, ast.Expr) \
                    and isinstance(after.value, ast.Constant) and isinstance(after.value.value, str):
                out[node.target.id] = inspect.cleandoc(after.value.value)
    return out


def _lineage(record: type) -> list[type]:
    """A ``TypedDict`` and the records it extends, bases first (a TypedDict's ``__mro__`` lists none of them:
    they are in ``__orig_bases__``)."""
    out: list[type] = []
    for base in getattr(record, "__orig_bases__", ()):
        if isinstance(base, type) and hasattr(base, "__required_keys__"):
            out += [b for b in _lineage(base) if b not in out]
    return out + [record]
