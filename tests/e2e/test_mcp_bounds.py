"""MCP `list_objects` and `list_rooms` keep the bounds HTTP keeps (one bound, in the application
layer): a 5 MB label, colour, room or building is a quick tool error naming its length and the
limit, never sent to the store nor repeated. A real MCP server over the real embedded store."""
from __future__ import annotations

import time

import anyio
import httpx
import pytest

from sg3d.app.bounds import MAX_LABEL_CHARS

HUGE = "x" * 5_000_000


@pytest.fixture
def mcp_server(store, embedded_home):
    from sg3d.server.mcp import build_server
    from sg3d.settings import Settings

    return build_server(Settings(home=embedded_home))


@pytest.mark.parametrize("tool, args", [
    ("list_objects", {"room": "kitchen", "label": HUGE}),
    ("list_objects", {"room": "kitchen", "colour": HUGE}),
    ("list_objects", {"room": HUGE}),
    ("list_objects", {"room": "kitchen", "building": HUGE}),
    ("list_rooms", {"building": HUGE}),
], ids=["label", "colour", "room", "building", "rooms of a building"])
def test_a_5_mb_filter_is_a_quick_tool_error_naming_the_limit(mcp_server, tool, args):
    from mcp.server.mcpserver.exceptions import ToolError

    t0 = time.monotonic()
    with pytest.raises(ToolError) as caught:
        anyio.run(mcp_server.call_tool, tool, args)
    message = str(caught.value)
    assert "5000000 characters; at most" in message and len(message) < 300
    assert time.monotonic() - t0 < 2


def test_a_label_at_the_limit_reaches_the_store(mcp_server):
    from mcp.server.mcpserver.exceptions import ToolError

    with pytest.raises(ToolError, match="no room"):       # past the bound: the room is looked up
        anyio.run(mcp_server.call_tool, "list_objects", {"room": "attic", "label": "x" * MAX_LABEL_CHARS})


def test_http_refuses_the_same_label(served):
    url, token = served
    r = httpx.get(url + "/rooms/default/kitchen/objects", params={"label": "x" * (MAX_LABEL_CHARS + 1)},
                  headers={"Authorization": f"Bearer {token}"})
    assert r.status_code == 422
