"""`sg3d ask`: a question about the stored scene graph, answered in one line (paper Sec. VI-A)."""
from __future__ import annotations

from typing import TYPE_CHECKING

import json
from pathlib import Path

import click

if TYPE_CHECKING:
    from sg3d.settings import Settings


@click.command()
@click.argument("question")
@click.option("--room", default=None, help="Only this room (its name).")
@click.option("--building", default=None, help="Only this building.")
@click.option("--explain", is_flag=True, help="Also print the logical form the question was read into, the "
                                              "templates, parameters and the objects the answer rests on (with ids).")
@click.option("--json", "as_json", is_flag=True, help="The answer as JSON (templates, parameters, ids, provenance).")
@click.option("--viewpoint", default=None, metavar="X,Y,Z|OBJECT",
              help="Where 'in front of/behind/left of/right of' are seen from: a point in the room's "
                   "world frame or an object name (or say 'as seen from the sink' in the question).")
@click.option("--out", type=click.Path(dir_okay=False), default=None,
              help="Where an answer with a picture ('which cup is the biggest', 'show me the cup closest "
                   "to the sink') writes it: .png or .jpg/.jpeg (without --out no file is written).")
@click.pass_obj
def ask(settings: Settings, question: str, room, building, explain: bool, as_json: bool, viewpoint, out) -> None:
    """Answer QUESTION from the scene graph, e.g. sg3d ask "how many red chairs are there?"

    Counting (by group, colour, size, in a room, on/under/next to/near an object, within a
    distance, not ...), yes/no, comparisons ("more books than tvs"), listing, colour/size/height,
    where, extremes ("the smallest chair", "the cup farthest from the tv"; its picture goes to --out),
    distances ("how far is the cup from the sink"), rooms ("which room has the most chairs").
    Typos are fixed and said. Objects are named ("chair 2"), and the names are accepted back.
    """
    from sg3d.app.ask import ask as ask_question
    from sg3d.app.ask import parse_viewpoint
    from sg3d.app.errors import AppError
    from sg3d.app.stores import reader
    from sg3d.errors import UserError

    if out is not None and not Path(out).expanduser().absolute().parent.is_dir():
        raise UserError(f"--out {out}: the folder {Path(out).expanduser().absolute().parent} does not exist")
    try:
        point_of_view = parse_viewpoint(viewpoint)     # a bad one is refused before the store starts
        asked = ask_question(reader(settings), question, room=room, building=building,
                             picture=False if out is None else out, viewpoint=point_of_view)
    except AppError as exc:
        raise UserError(str(exc)) from exc
    result, path = asked.answer, asked.picture
    if as_json:
        click.echo(json.dumps(asked.to_json(), default=str))
    else:
        click.echo(result.text if result.ok else f"cannot answer: {result.text}", err=not result.ok)
        if path:
            click.echo(f"picture: {path}")
        elif result.ok and result.thumbnail and out is None:
            click.echo("(this answer has a picture: add --out FILE.png to write it)", err=True)
    if explain and not as_json:
        for line in result.explain_lines():     # the explanation asked for is a result: stdout
            click.echo(line)
    if not result.ok:
        raise SystemExit(2)   # a refusal is not an answer: scripts see a non-zero status
    if out is not None and not path:
        raise UserError(f"--out {out}: this answer has no picture, nothing was written (pictures come with "
                        f"'which cup is the biggest?' or 'show me the cup closest to the sink')")


commands = [ask]
