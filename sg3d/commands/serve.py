"""`sg3d serve` (HTTP API) and `sg3d mcp` (MCP server over stdio) for robots and agents."""
from __future__ import annotations

from typing import TYPE_CHECKING

import errno

import click

from sg3d.app.bounds import DEFAULT_MAX_BODY, DEFAULT_THREADS, DEFAULT_WORKERS

if TYPE_CHECKING:
    from sg3d.settings import Settings


@click.command()
@click.option("--host", default="127.0.0.1", show_default=True,
              help="Address to bind. Anything but loopback exposes the API to the network (a warning is printed).")
@click.option("--port", type=click.IntRange(1, 65535), default=8765, show_default=True,
              help="TCP port to listen on; a port in use is refused.")
@click.option("--access-log", is_flag=True, help="Log every request.")
@click.option("--max-body", type=click.IntRange(min=1024), default=DEFAULT_MAX_BODY, show_default=True,
              metavar="BYTES", help="Largest request body accepted; a larger one is refused (413) before it is "
                                    "read, and a request without the token (401) before its body is read.")
@click.option("--threads", type=click.IntRange(min=1), default=DEFAULT_THREADS, show_default=True,
              help="Store calls one process runs at once (threads); more wait their turn (within their deadline).")
@click.option("--workers", type=click.IntRange(min=1), default=DEFAULT_WORKERS, show_default=True,
              help="Worker processes (uvicorn's process model) sharing the one store, each with --threads threads. "
                   "The default is one, plus one per two cores beyond the store's two (at most 4).")
@click.pass_obj
def serve(settings: Settings, host: str, port: int, access_log: bool, max_body: int, threads: int, workers: int) -> None:
    """Serve the scene graph over HTTP: /ask, /plan, /rooms, /graph, /ingest (OpenAPI at /docs).

    Callers send `Authorization: Bearer <token>`; the token is generated into api-token (mode
    0600) in the store's private directory on first start (`sg3d db status` names it)."""
    import uvicorn

    from sg3d.errors import UserError
    from sg3d.server.auth import TokenError, ensure_token, token_path
    from sg3d.server.http import create_app, is_loopback

    sock = _bind(host, port)       # a taken port or unknown host: one line, before the store starts
    home = settings.embedded_home()
    try:
        token = ensure_token(home)
    except TokenError as exc:
        raise UserError(str(exc)) from None
    if not is_loopback(host):
        click.echo(f"warning: binding {host}: the API is reachable from other machines; anyone with the "
                   f"token can read and ingest (put TLS in front of it on an untrusted network)", err=True)
    if workers > 1:
        from sg3d.server.workers import serve_workers

        click.echo(f"sg3d serving http://{host}:{port} with {workers} workers (docs at /docs); token in "
                   f"{token_path(home)}", err=True)
        serve_workers(settings, sock, workers, max_body=max_body, threads=threads, access_log=access_log)
        return
    api = create_app(settings, token, max_body=max_body, max_threads=threads)
    api.state.stores.get()          # start or find the store now, not on the first request
    click.echo(f"sg3d serving http://{host}:{port} (docs at /docs); token in {token_path(home)}", err=True)
    # a stuck store call ends at its own deadline; SIGTERM waits at most 5 s for requests in flight
    config = uvicorn.Config(api, host=host, port=port, log_level="warning", access_log=access_log,
                            timeout_graceful_shutdown=5)
    uvicorn.Server(config).run(sockets=[sock])


def _bind(host: str, port: int):
    """The listening socket uvicorn would make (SO_REUSEADDR, IPv6 for a host with ':'), made here
    so that a failure is a UserError instead of uvicorn's log line and exit status 3."""
    import socket

    from sg3d.errors import UserError

    # proto IPPROTO_TCP: asyncio turns Nagle's algorithm off (TCP_NODELAY) only on sockets that
    # say they are TCP; with proto 0 every small response waited ~40 ms for the client's delayed ACK
    sock = socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET, socket.SOCK_STREAM, socket.IPPROTO_TCP)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    try:
        sock.bind((host, port))
    except OSError as exc:
        sock.close()
        reason = exc.strerror or str(exc)
        if exc.errno == errno.EADDRINUSE:
            reason = "the port is in use (another `sg3d serve`?); choose another with --port"
        raise UserError(f"cannot listen on {host}:{port}: {reason}") from None
    return sock


@click.command()
@click.pass_obj
def mcp(settings: Settings) -> None:
    """Run the MCP server on stdio for LLM agents (tools: ask, plan, list_rooms, list_objects,
    cypher (read-only), graph_schema). Configure your agent to start `sg3d mcp`."""
    from sg3d.server.mcp import build_server

    build_server(settings).run("stdio")


commands = [serve, mcp]
