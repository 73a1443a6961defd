"""`sg3d mcp`: an MCP server (stdio, the official `mcp` SDK) giving LLM agents the application
layer as tools: ask, plan, list rooms, list objects, read-only Cypher, graph schema.

Nothing here writes: every tool reads through `sg3d.app.stores.reader`, and the Cypher tool refuses
writing statements and runs the rest in a transaction that is rolled back (`sg3d.app.graph`).

Every tool's store call runs under a deadline (`sg3d.server.dispatch.Dispatcher`, as for HTTP):
the agent gets a tool error when it passes (the cypher tool: its 10 s, `CYPHER_TIMEOUT_S`), and
every transaction the call opens carries the same limit as its Bolt transaction timeout
(`sg3d.graphdb.store.transaction_timeout`), so Neo4j stops the statement itself. ArcadeDB's Bolt
plugin ignores that timeout (26.10); the embedded store stops any statement after its own limit
(`sg3d.graphdb.embedded.store_timeout_s`, 30 s)."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Optional

from sg3d.app import ask as app_ask
from sg3d.app.graph import CYPHER_TIMEOUT_S
from sg3d.app import graph as app_graph
from sg3d.app import plan as app_plan
from sg3d.app import rooms as app_rooms
from sg3d.app.errors import AppError
from sg3d.app.stores import StoreHandle
from sg3d.server.dispatch import LONG_TIMEOUT_S, QUICK_TIMEOUT_S

if TYPE_CHECKING:
    from sg3d.settings import Settings

INSTRUCTIONS = (
    "sg3d holds 3-D scene graphs of scanned rooms: Object nodes (label, colour, position in metres, "
    "size) in Rooms of Buildings, with spatial relations (ON, NEXT_TO, IN, ...). Start with list_rooms; "
    "ask answers questions in English; list_objects gives readable names; graph_schema before cypher "
    "(read-only).")


# How long a tool's store call may take: the cypher tool's documented 10 s, the service's limits
# (`sg3d.server.dispatch`) for the rest.
TIMEOUTS = {"cypher": CYPHER_TIMEOUT_S, "read": QUICK_TIMEOUT_S, "plan": LONG_TIMEOUT_S}


STORE_MESSAGE_CHARS = 300   # an agent reads one line; a store's message may quote the whole statement


def store_message(exc: Exception) -> str:
    """One line for an agent from a store or driver error: the store's code and the first line of
    its message (e.g. "Neo.DatabaseError.General.UnknownError: TypeError: Cannot access property
    'foo' on Long value"), at most STORE_MESSAGE_CHARS characters."""
    code = getattr(exc, "code", None)
    message = (getattr(exc, "message", None) or str(exc) or type(exc).__name__).strip()
    line = message.splitlines()[0] if message else type(exc).__name__
    text = f"{code}: {line}" if code else f"{type(exc).__name__}: {line}"
    return text if len(text) <= STORE_MESSAGE_CHARS else text[:STORE_MESSAGE_CHARS - 1] + "…"


def build_server(settings: Settings, handle: Optional[StoreHandle] = None, dispatcher=None,
                 timeouts: Optional[dict[str, float]] = None):
    """The MCP server for `settings`' store (run it with `.run("stdio")`). `timeouts`: seconds per
    kind of call ("cypher", "read", "plan"), defaults `TIMEOUTS`."""
    from mcp.server.mcpserver import MCPServer
    from mcp.server.mcpserver.exceptions import ToolError

    from sg3d import __version__
    from sg3d.server.dispatch import Dispatcher

    stores = handle or StoreHandle(settings)
    calls = dispatcher or Dispatcher()
    limits = {**TIMEOUTS, **(timeouts or {})}
    server = MCPServer("sg3d", version=__version__, instructions=INSTRUCTIONS, log_level="WARNING")

    async def read(fn, kind: str = "read"):
        from sg3d.graphdb.embedded import EmbeddedStoreError
        from sg3d.graphdb.store import StatementTooLarge, transaction_timeout
        from sg3d.server.dispatch import StoreUnavailable

        seconds = limits[kind]

        def call():
            with transaction_timeout(seconds):     # in the worker's thread, where the driver runs
                return stores.call(fn)

        from neo4j.exceptions import DriverError, Neo4jError

        try:
            return await calls.run(call, seconds)
        except (AppError, EmbeddedStoreError, StatementTooLarge, StoreUnavailable) as exc:
            raise ToolError(str(exc)) from exc
        except (Neo4jError, DriverError) as exc:    # the store's own words, not a bare "Error executing tool"
            raise ToolError(store_message(exc)) from exc

    @server.tool()
    async def ask(question: str, room: Optional[str] = None, building: Optional[str] = None) -> dict[str, Any]:
        """Answer a question about the scanned rooms, e.g. "how many cups are on the table?",
        "what is on the table?", "where is the kettle?". room/building narrow the scope. The
        reply has `answer` (one line), `ok` (false: not understood, the reason is in answer),
        `value` and the objects it rests on."""
        return await read(lambda s: app_ask.ask(s, question, room=room, building=building).to_json())

    @server.tool()
    async def plan(command: str, room: str, building: Optional[str] = None) -> dict[str, Any]:
        """Plan a household task in a room ("clean up the table", "put the cups in the sink"): a
        validated sequence of steps with the PDDL domain and problem."""
        return await read(lambda s: app_plan.plan_json(s, command, room=room, building=building), "plan")

    @server.tool()
    async def list_rooms(building: Optional[str] = None) -> list[dict[str, Any]]:
        """The rooms in the store (of one building, or all): id, name, object count, adjacent rooms."""
        return await read(lambda s: app_rooms.list_rooms(s, building))

    @server.tool()
    async def list_objects(room: str, building: str = "default", label: Optional[str] = None,
                     colour: Optional[str] = None, near: Optional[list[float]] = None,
                     radius: Optional[float] = None) -> list[dict[str, Any]]:
        """The objects of a room with readable names, label, colour, position [x, y, z] (m) and size;
        filter by label ("cup"), colour ("red") or distance from a point `near` [x, y, z]."""
        return await read(lambda s: app_rooms.room_objects(s, building, room,
                                                           app_rooms.ObjectFilter(label, colour, near, radius)))

    @server.tool()
    async def cypher(statement: str, params: Optional[dict[str, Any]] = None) -> dict[str, Any]:
        """Run ONE read-only Cypher statement (MATCH/OPTIONAL MATCH/WITH/UNWIND/RETURN; writes,
        CALL and schema commands are refused) with $parameters; at most 1000 rows. Read
        graph_schema first."""
        return await read(lambda s: app_graph.read_only_cypher(s, statement, params, timeout_s=limits["cypher"]),
                          "cypher")

    @server.tool()
    async def graph_schema() -> dict[str, Any]:
        """Node labels and their properties, relationship types and how many of each are stored."""
        return await read(app_graph.graph_schema)

    return server
