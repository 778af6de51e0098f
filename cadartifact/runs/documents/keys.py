"""What every document module needs: ``TypedDict`` with PEP 728 (``closed``, ``extra_items``), and the length of
the fixed-size arrays (a pair per direction, a point in space) as JSON Schema sees it.

Standard library and ``typing_extensions`` only: the records are types, read by type checkers and, for the
published schema, by pydantic (imported by :mod:`.schema` alone)."""

from __future__ import annotations

from typing import Any

from typing_extensions import TypedDict

__all__ = ["TypedDict", "Length", "Pair", "Triple"]


class Length:
    """``Annotated`` metadata: an array of exactly ``n`` items (``minItems = maxItems = n`` in the schema)."""

    def __init__(self, n: int):
        self.n = n

    def __repr__(self) -> str:
        return f"Length({self.n})"

    def __get_pydantic_json_schema__(self, core_schema: Any, handler: Any) -> dict[str, Any]:
        schema: dict[str, Any] = handler(core_schema)
        schema.update(minItems=self.n, maxItems=self.n)
        return schema


#: One item per direction (u, v).
Pair = Length(2)
#: A point in space (x, y, z).
Triple = Length(3)
