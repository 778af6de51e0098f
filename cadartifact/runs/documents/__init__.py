"""The records of the documents cadartifact writes, defined once as ``TypedDict``\\ s: the advise document
(:mod:`.advise`), the gate document (:mod:`.gate`), the inspect document (:mod:`.inspected`) and the face
records they share (:mod:`.face`).

The documents stay plain dicts (their JSON is written from them as it is); the types tell a reader and a type
checker every key, and :func:`json_schema` publishes them as JSON Schema (``cadartifact schema KIND``,
docs/schema.md). Importing this package loads the standard library and ``typing_extensions`` only; the renderers
import the types under ``TYPE_CHECKING``.
"""

from __future__ import annotations

from .advise import ADVISE_SCHEMA, AdviseDocument, AdviseFile
from .face import AdviceRecord, AdviseFace, FaceRecord
from .gate import GATE_SCHEMA, CriterionRecord, GateDocument, GateFace, GateFile
from .inspected import INSPECT_SCHEMA, InspectDocument, InspectFile
from .schema import KINDS, json_schema

__all__ = ["ADVISE_SCHEMA", "GATE_SCHEMA", "INSPECT_SCHEMA", "KINDS", "json_schema", "AdviseDocument", "AdviseFile",
           "AdviseFace", "FaceRecord", "AdviceRecord", "GateDocument", "GateFile", "GateFace", "CriterionRecord",
           "InspectDocument", "InspectFile"]
