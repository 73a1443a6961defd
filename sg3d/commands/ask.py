"""`sg3d ask`: a question about the stored scene graph, answered in one line (paper Sec. VI-A)."""
from __future__ import annotations

import json

import click


@click.command()
@click.argument("question")
@click.option("--room", default=None, help="Only this room (its name).")
@click.option("--building", default=None, help="Only this building.")
@click.option("--explain", is_flag=True, help="Also print the query form, templates and parameters.")
@click.option("--json", "as_json", is_flag=True, help="The answer as JSON.")
@click.option("--viewpoint", default=None, metavar="X,Y,Z|OBJECT",
              help="Where 'in front of/behind/left of/right of' are seen from: a point in the room's "
                   "world frame or an object name (or say 'as seen from the sink' in the question).")
@click.option("--out", type=click.Path(dir_okay=False), default=None,
              help="Where 'show me ...' writes the thumbnail (default: a temporary .jpg, printed).")
@click.pass_obj
def ask(settings, question: str, room, building, explain: bool, as_json: bool, viewpoint, out) -> None:
    """Answer QUESTION from the scene graph, e.g. sg3d ask "how many red chairs are there?"

    Counting (simple, by group: furniture/cutlery/..., by colour, big/small, in a room, on/under/
    next to an object), existence, listing, colour/size lookup, and "show me the biggest bowl"
    (writes its thumbnail). Unanswerable questions are refused with the forms it understands.
    """
    from queries.vqa import answer

    result = answer(settings.store(), question, room=room, building=building, viewpoint=_viewpoint(viewpoint))
    path = None
    if result.ok and result.thumbnail:
        path = _write_thumbnail(result.thumbnail, out)
    if as_json:
        data = result.to_json()
        data["thumbnail"] = path
        click.echo(json.dumps(data, default=str))
    else:
        click.echo(result.text if result.ok else f"cannot answer: {result.text}", err=not result.ok)
        if path:
            click.echo(f"thumbnail: {path}")
    if explain and not as_json:
        if result.query is not None:
            click.echo(f"form: {json.dumps(result.query.summary())}", err=True)
        for step in result.steps:
            click.echo(f"template: {step['template']}"
                       + (f" [{step['rel_type']}]" if step.get("rel_type") else "")
                       + f" params: {json.dumps(step['params'])}", err=True)
    if not result.ok:
        raise SystemExit(2)   # a refusal is not an answer: scripts see a non-zero status


def _viewpoint(text):
    if not text:
        return None
    parts = text.split(",")
    if len(parts) == 3:
        try:
            return {"position": [float(p) for p in parts]}
        except ValueError:
            pass
    return {"object": text.strip()}


def _write_thumbnail(data: bytes, out) -> str:
    import os
    import tempfile

    if out is None:
        fd, out = tempfile.mkstemp(prefix="sg3d-answer-", suffix=".jpg")
        os.close(fd)
    with open(out, "wb") as f:
        f.write(data)
    return str(out)


commands = [ask]
