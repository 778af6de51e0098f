"""``cadartifact schema``: the JSON Schema of a document (advise, gate, inspect), generated from its records
(:mod:`cadartifact.runs.documents`), for a pipeline to validate what the commands write (docs/schema.md)."""

from __future__ import annotations

import typer

from .root import app, cli_errors, fail


@app.command("schema", short_help="The JSON Schema of a document (advise, gate, inspect).")
@cli_errors
def schema_cmd(
    kind: str = typer.Argument(..., metavar="KIND", help="advise, gate or inspect.", show_default=False),
):
    """Print the JSON Schema (draft 2020-12) of the document that 'advise --json', 'gate --format json' or
    'inspect --json' writes: its title is the document's version (its "schema" key; the gate's "gate" key),
    every record is closed and every key described. docs/schema.md shows how a pipeline validates with it.
    """
    import json

    from ..runs.documents.schema import KINDS, json_schema

    if kind not in KINDS:
        raise fail(f"KIND: expected one of {', '.join(KINDS)}, received {kind!r}")
    typer.echo(json.dumps(json_schema(kind), indent=2))
