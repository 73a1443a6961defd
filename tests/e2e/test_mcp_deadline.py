"""The MCP tools' store calls run under a deadline (a real embedded store): a slow statement is a
tool error when its time is up, the next call is answered, and every transaction of the call
carries the limit as its Bolt transaction timeout (Neo4j stops the statement; ArcadeDB's Bolt
plugin ignores it and stops any statement after its own limit, 30 s)."""
from __future__ import annotations

import time

import anyio
import pytest

from sg3d.graphdb.store import current_transaction_timeout, transaction_timeout

SLOW = "UNWIND range(1, 10000000) AS x RETURN count(x) AS n"   # seconds of work on the embedded store


@pytest.fixture
def calls():
    """The MCP server's dispatcher; afterwards, waits for the calls it gave up on to end in the store."""
    from sg3d.server.dispatch import Dispatcher

    dispatcher = Dispatcher()
    yield dispatcher
    deadline = time.monotonic() + 90
    while dispatcher.threads._stuck and time.monotonic() < deadline:
        time.sleep(0.2)


@pytest.fixture
def mcp_server(store, embedded_home, calls):
    from sg3d.server.mcp import build_server
    from sg3d.settings import Settings

    return build_server(Settings(home=embedded_home), dispatcher=calls, timeouts={"cypher": 0.5, "read": 20.0})


def test_a_slow_statement_through_mcp_is_a_tool_error_by_its_deadline(mcp_server):
    from mcp.server.mcpserver.exceptions import ToolError

    t0 = time.monotonic()
    with pytest.raises(ToolError, match="did not answer within 0.5 s"):
        anyio.run(mcp_server.call_tool, "cypher", {"statement": SLOW})
    assert time.monotonic() - t0 < 3.0
    # the agent's next call is answered (the abandoned worker does not hold the server)
    rooms = anyio.run(mcp_server.call_tool, "list_rooms", {})
    assert rooms is not None


def test_the_tool_call_carries_its_limit_as_the_transaction_timeout(store, monkeypatch):
    """What the MCP worker sets is what every transaction of the call asks the store for."""
    from neo4j import Query, Session

    from sg3d.graphdb import store as store_mod

    seen = []
    real = Session.begin_transaction

    def begin(self, *args, **kwargs):        # the driver's own session: what is sent
        seen.append(kwargs.get("timeout"))
        return real(self, *args, **kwargs)

    monkeypatch.setattr(Session, "begin_transaction", begin)
    assert current_transaction_timeout() is None
    with transaction_timeout(7.0):
        assert store_mod._timed(lambda tx: None).timeout == 7.0
        assert store.read("schema_node_counts") is not None          # a unit of work with a timeout
        with store.session() as s:
            tx = s.begin_transaction()
            tx.rollback()
            assert isinstance(Query("RETURN 1", timeout=7.0), Query)
            assert s.run("RETURN 1 AS one").single()["one"] == 1   # sent as Query(text, timeout=7)
    assert current_transaction_timeout() is None
    assert seen == [7.0]
