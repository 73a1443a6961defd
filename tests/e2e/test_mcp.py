"""`sg3d mcp` through the official SDK's stdio client, and the read-only Cypher path it uses."""
from __future__ import annotations

import json
import os
import sys

import anyio
import pytest

from sg3d.app.errors import Refused
from sg3d.app.graph import (
    explain_writes,
    read_only_cypher,
    run_rolled_back,
    write_words,
)
from tests.serve_helpers import kitchen_body

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOLS = {"ask", "plan", "list_rooms", "list_objects", "cypher", "graph_schema"}


@pytest.fixture
def kitchen(store):
    from sg3d.app.ingest import IngestRequest, ingest_graph

    ingest_graph(store, IngestRequest.model_validate(kitchen_body()))
    return store


def n_nodes(store) -> int:
    return sum(r["n"] for r in store.read("schema_node_counts"))


# -- the read-only path ---------------------------------------------------------------------------
def test_write_words_ignore_strings_comments_properties_and_parameters():
    assert write_words("MATCH (o) WHERE o.label = 'CREATE' // DELETE\nRETURN o.set, $merge, `remove`") == []
    assert write_words("match (o) detach delete o") == ["DELETE", "DETACH"]
    assert write_words("MATCH (o) CALL { WITH o SET o.x = 1 } RETURN o") == ["CALL", "SET"]


@pytest.mark.parametrize("statement", [
    "MATCH (o:Object) SET o.label = 'x'",
    "MATCH (o:Object) DETACH DELETE o",
    "MERGE (x:Object {id: 'new'})",
    "CREATE (x:Object {id: 'new'}) RETURN x",
    "CREATE INDEX nope IF NOT EXISTS FOR (n:Object) ON (n.volume)",
    "DROP INDEX object_label",
    "CALL db.labels()",
    "PROFILE MATCH (o) RETURN o",
    "MATCH (o:Object) RETURN o; MATCH (p) DELETE p",
    "LOAD CSV FROM 'file:///etc/passwd' AS line RETURN line",
    "MATCH (o:Object) FOREACH (x IN [1] | SET o.x = x)",
    "WITH 1 AS one MATCH (o:Object) REMOVE o.label",
])
def test_writing_statements_are_refused_and_the_store_is_unchanged(kitchen, statement):
    before = n_nodes(kitchen), kitchen.read("object_count", room="home/kitchen")
    labels = sorted(r["label"] for r in kitchen.read("plan_objects", room="home/kitchen"))
    with pytest.raises(Refused):
        read_only_cypher(kitchen, statement)
    assert (n_nodes(kitchen), kitchen.read("object_count", room="home/kitchen")) == before
    assert sorted(r["label"] for r in kitchen.read("plan_objects", room="home/kitchen")) == labels


def test_the_explain_plan_sees_writes_the_keywords_would_miss(kitchen):
    """Second guard on its own: the server's plan of a writing statement names its write steps."""
    assert explain_writes(kitchen, "MATCH (o:Object) SET o.flag = 1") == ["SET"]
    assert explain_writes(kitchen, "CREATE (x:Scratch {a: 1})") == ["CREATE"]
    assert explain_writes(kitchen, "MATCH (o:Object) WHERE o.label = 'cup' RETURN o.id") == []
    assert kitchen.read("object_count", room="home/kitchen")[0]["n"] == 10


def test_the_transaction_is_rolled_back_even_for_a_write(kitchen):
    """Third guard on its own: a statement that got past the checks still leaves nothing behind."""
    before = n_nodes(kitchen)
    out = run_rolled_back(kitchen, "CREATE (x:Scratch {a: 1}) RETURN x.a AS a", {})
    assert out["rows"] == [{"a": 1}]
    assert n_nodes(kitchen) == before


def test_reads_return_rows_with_parameters_and_a_limit(kitchen):
    out = read_only_cypher(kitchen, "MATCH (o:Object) WHERE o.label = $label RETURN o.colour AS colour ORDER BY colour",
                           {"label": "cup"})
    assert out == {"keys": ["colour"], "rows": [{"colour": "blue"}, {"colour": "red"}, {"colour": "white"}],
                   "truncated": False}
    assert read_only_cypher(kitchen, "MATCH (a:Appearance) RETURN a.hist AS h", limit=4)["truncated"] is True
    assert read_only_cypher(kitchen, "MATCH (a:Appearance) RETURN a.hist AS h LIMIT 1")["rows"][0]["h"].endswith("bytes>")


# -- the MCP server over stdio ---------------------------------------------------------------------
def payload(result):
    assert not result.is_error, result.content
    data = result.structured_content
    if isinstance(data, dict) and set(data) == {"result"}:
        return data["result"]
    return data if data is not None else json.loads(result.content[0].text)


async def _session_calls(home, calls):
    from mcp import ClientSession, StdioServerParameters
    from mcp.client.stdio import stdio_client

    env = {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}
    params = StdioServerParameters(command=sys.executable, args=["-m", "sg3d", "--home", str(home), "mcp"], env=env)
    with open(os.devnull, "w") as errlog:
        async with stdio_client(params, errlog=errlog) as (read, write):
            async with ClientSession(read, write) as session:
                await session.initialize()
                tools = await session.list_tools()
                results = [await session.call_tool(name, args) for name, args in calls]
    return {t.name for t in tools.tools}, results


def test_mcp_tools_over_stdio(kitchen, embedded_home):
    calls = [
        ("list_rooms", {}),
        ("list_objects", {"building": "home", "room": "kitchen", "label": "cup"}),
        ("ask", {"question": "how many cups are on the table?", "room": "kitchen"}),
        ("plan", {"command": "put the red cup in the sink", "room": "kitchen"}),
        ("graph_schema", {}),
        ("cypher", {"statement": "MATCH (o:Object) WHERE o.label = $l RETURN count(o) AS n", "params": {"l": "cup"}}),
        ("cypher", {"statement": "MATCH (o:Object) DETACH DELETE o"}),
        ("list_objects", {"building": "home", "room": "attic"}),
    ]
    names, results = anyio.run(_session_calls, embedded_home, calls)
    assert names == TOOLS
    rooms, cups, asked, plan, schema, count, delete, attic = results
    assert [r["id"] for r in payload(rooms)] == ["home/kitchen"]
    assert sorted(o["name"] for o in payload(cups)) == ["blue cup", "red cup", "white cup"]
    assert payload(asked)["value"] == 3 and payload(asked)["ok"] is True
    assert payload(plan)["valid"] and payload(plan)["goal"] == ["(in red_cup sink)"]
    assert "Object" in payload(schema)["nodes"] and payload(schema)["node_counts"]["Object"] == 10
    assert payload(count)["rows"] == [{"n": 3}]
    assert delete.is_error and "read-only" in delete.content[0].text
    assert attic.is_error and "attic" in attic.content[0].text
    assert kitchen.read("object_count", room="home/kitchen")[0]["n"] == 10
