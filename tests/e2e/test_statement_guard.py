"""Statements the store cannot stop (a nested reduce over ranges, a list of millions of strings in
one row) are refused at once on every user path, the real CLI and the real MCP server, and the
store answers the next statement at once (nothing keeps running in it)."""
from __future__ import annotations

import time

import anyio
import pytest

from tests.cli_helpers import one_error_line, sg3d

NESTED_REDUCE = "RETURN reduce(s=0, x IN range(1,10000) | s + reduce(t=0, y IN range(1,20000) | t+y)) AS n"
HUGE_LIST = "RETURN size([x IN range(1,26000000) | toString(x)+'aaaaaaaaaaaaaaaa']) AS n"


@pytest.mark.parametrize("statement", [NESTED_REDUCE, HUGE_LIST])
def test_sg3d_cypher_refuses_in_one_line_and_the_store_stays_free(store, embedded_home, statement):
    t0 = time.monotonic()
    out = sg3d(embedded_home, "cypher", statement)
    assert "range()" in one_error_line(out)
    assert time.monotonic() - t0 < 30          # a process start, not the 30 s statement limit (+65 s)
    t1 = time.monotonic()
    assert store.read("object_total")[0]["n"] == 0
    assert time.monotonic() - t1 < 2.0


def test_the_mcp_cypher_tool_refuses_them(store, embedded_home):
    from mcp.server.mcpserver.exceptions import ToolError

    from sg3d.server.mcp import build_server
    from sg3d.settings import Settings

    server = build_server(Settings(home=embedded_home))
    for statement in (NESTED_REDUCE, HUGE_LIST):
        t0 = time.monotonic()
        with pytest.raises(ToolError, match="range"):
            anyio.run(server.call_tool, "cypher", {"statement": statement})
        assert time.monotonic() - t0 < 2.0
