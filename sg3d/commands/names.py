"""The click callback that checks a room or building name given on the command line (the rule
is `sg3d.app.bounds.name_problem`, the same one `POST /ingest` applies)."""
from __future__ import annotations

import click


def checked_name(ctx, param, value):
    """click callback: `value` unchanged when it can name a room or building, else a usage error."""
    from sg3d.app.bounds import name_problem

    if value is None:
        return value
    problem = name_problem(value, f"--{param.name}")
    if problem:
        raise click.BadParameter(problem)
    return value
