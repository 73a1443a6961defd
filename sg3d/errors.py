"""Turning failures into one clear line instead of a traceback."""
from __future__ import annotations

import os
import sys

import click

from sg3d.core.errors import Sg3dError


class UserError(Sg3dError, click.ClickException):
    """A failure the user can act on; printed as one line, exit status 2."""

    exit_code = 2


def run_cli(group: click.Group) -> int:
    try:
        group.main(standalone_mode=False, prog_name="sg3d")
        return 0
    except click.exceptions.Abort:
        click.echo("aborted", err=True)
        return 130
    except click.UsageError as exc:
        # click prints usage, a hint and the error on three lines; bad input is one line here
        path = exc.ctx.command_path if exc.ctx is not None else "sg3d"
        click.echo(f"Error: {exc.format_message()} (see '{path} --help')", err=True)
        return 2
    except click.ClickException as exc:
        exc.show()
        return exc.exit_code
    except KeyboardInterrupt:
        click.echo("interrupted", err=True)
        return 130
    except Exception as exc:  # noqa: BLE001 - last line of defence, the traceback on demand
        line = _store_error_line(exc)
        if line is not None:
            click.echo(f"error: {line}", err=True)
            return 2
        if os.environ.get("SG3D_DEBUG"):
            raise
        click.echo(f"error: {type(exc).__name__}: {_first_line(exc)} (SG3D_DEBUG=1 for the traceback)", err=True)
        return 1


def _store_error_line(exc: Exception):
    """The one line for a failure of the graph store or its driver, or None for any other.

    The driver and the store modules are looked at only when this process imported them (an
    error of a module never imported cannot have been raised): a command that never reaches the
    store, `sg3d --help` among them, does not pay for importing the driver (0.3 s)."""
    if "neo4j" in sys.modules:
        from neo4j.exceptions import (
            AuthError,
            ClientError,
            CypherSyntaxError,
            DatabaseError,
            ServiceUnavailable,
            TransientError,
        )

        if isinstance(exc, ServiceUnavailable):
            return f"cannot reach the graph store ({_first_line(exc).rstrip(':')})"
        if isinstance(exc, AuthError):
            return f"the graph store refused the credentials: {_first_line(exc)}"
        if isinstance(exc, (CypherSyntaxError, ClientError, DatabaseError, TransientError)):
            return _disk_full() or describe_store_error(exc)
    known: tuple = ()
    if "sg3d.graphdb.embedded" in sys.modules:
        from sg3d.graphdb.embedded import EmbeddedStoreError

        known += (EmbeddedStoreError,)
    if "sg3d.graphdb.store" in sys.modules:
        from sg3d.graphdb.store import ReadOnlyStoreError, StatementTooLarge

        known += (ReadOnlyStoreError, StatementTooLarge)
    return str(exc) if isinstance(exc, known) else None


def _disk_full():
    """The full-disk line for the embedded store's disk, or None (a commit that failed for lack of
    space reaches the driver only as a transaction error)."""
    from sg3d.graphdb.embedded import default_home, disk_full_message, store_dir

    try:
        return disk_full_message(store_dir(default_home().resolve()))
    except OSError:
        return None


def describe_store_error(exc) -> str:
    """One line for an error the store returned; a refused write on a read path says so."""
    text = f"{exc.code}: {_first_line(exc.message or str(exc))}"
    if exc.code and (exc.code.startswith("Neo.ClientError.Security.Forbidden")
                     or "AccessMode" in exc.code or "WriteOnReadOnly" in exc.code):
        text += (" (refused by the store's permissions: commands without --write run as a read-only user,"
                 " and no user may read files with LOAD CSV)")
    return text


def _first_line(exc: object) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__
