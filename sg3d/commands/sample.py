"""`sg3d sample NAME`: a verified copy of a sample recording (local, cached or downloaded); its
folder is the only thing on stdout, so `sg3d build "$(sg3d sample kitchen)" --room kitchen` works."""
from __future__ import annotations

import json
from typing import Optional

import click

from sg3d.errors import UserError


class _Bar:
    """The download's bytes as a rich progress bar on stderr (`sg3d.app.samples.Progress`)."""

    def __init__(self, progress, label: str) -> None:
        self.progress, self.label, self.task = progress, label, None

    def start(self, total: int, completed: int) -> None:
        self.task = self.progress.add_task(self.label, total=total, completed=completed)

    def advance(self, nbytes: int) -> None:
        if self.task is not None:
            self.progress.advance(self.task, nbytes)


@click.command("sample")
@click.argument("name", required=False)
@click.option("--list", "list_only", is_flag=True, help="List the samples with their size and licence.")
@click.option("--json", "as_json", is_flag=True, help="Print the result (or the list) as JSON.")
def sample(name: Optional[str], list_only: bool, as_json: bool) -> None:
    """Get sample recording NAME and print its folder (only that, on stdout).

    A local copy that verifies is used in place ($SG3D_SAMPLES/<folder>, else
    ../shared/data/<folder> from the current directory); otherwise the files are downloaded once
    into the user cache ($SG3D_CACHE overrides it; $SG3D_SAMPLE_URL names a mirror), every file
    checked against its SHA-256. A killed download resumes where it stopped.
    """
    from sg3d.app.errors import AppError

    try:
        if list_only:
            _print_list(as_json)
            return
        if not name:
            raise click.UsageError("give a sample NAME (or --list)")
        found = locate_with_progress(name)
    except AppError as exc:
        raise UserError(str(exc)) from None
    if as_json:
        click.echo(json.dumps({"name": found.sample.name, "path": str(found.path), "origin": found.origin,
                               "files": len(found.sample.files), "bytes": found.sample.size,
                               "downloaded_bytes": found.downloaded_bytes, "licence": found.sample.licence}))
    else:
        click.echo(str(found.path))


def locate_with_progress(name: str):
    """`sg3d.app.samples.locate_sample` with its notes and download bar on stderr."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        DownloadColumn,
        Progress,
        TextColumn,
        TimeRemainingColumn,
        TransferSpeedColumn,
    )

    from sg3d.app.samples import locate_sample

    console = Console(stderr=True)
    with Progress(TextColumn(f"[bold]sample {name}"), BarColumn(), DownloadColumn(), TransferSpeedColumn(),
                  TimeRemainingColumn(), console=console, transient=console.is_terminal) as progress:
        return locate_sample(name, progress=_Bar(progress, name),
                             notice=lambda line: console.print(line, highlight=False, soft_wrap=True))


def _print_list(as_json: bool) -> None:
    from sg3d.app.samples import sample_listing

    rows = sample_listing()
    if as_json:
        click.echo(json.dumps(rows, indent=2))
        return
    for row in rows:
        where = f"\n  present: {row['present']}" if row["present"] else ""
        click.echo(f"{row['name']}  {row['bytes'] / 1e6:.1f} MB, {row['files']} files: {row['title']}\n"
                   f"  licence: {row['licence']}\n  source: {row['source']}{where}")


commands = [sample]
