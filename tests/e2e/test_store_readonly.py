"""Read-only is enforced by the store, not by the client: every read path connects as a user
whose group may only read, so writes, schema changes and LOAD CSV are refused by the server."""
from __future__ import annotations

import pytest
from click.testing import CliRunner
from neo4j.exceptions import ClientError

from sg3d.cli import cli
from sg3d.graphdb.store import ReadOnlyStoreError
from sg3d.settings import Settings

# a refused statement must leave nodes, edges, constraints and indexes as they were
REFUSED = [
    "CREATE (x:Object {id: 'new'}) RETURN 1",
    "CREATE (x:Intruder {id: 'new'}) RETURN 1",
    "MERGE (x:Object {id: 'merged'}) RETURN 1",
    "MATCH (o:Object {id: 'ro/a'}) SET o.label = 'hacked' RETURN 1",
    "MATCH (o:Object {id: 'ro/a'}) REMOVE o.label RETURN 1",
    "MATCH (:Object)-[r:ON]->(:Object) DELETE r RETURN 1",
    "MATCH (o:Object {id: 'ro/b'}) DETACH DELETE o RETURN 1",
    "MATCH (o:Object) WITH o LIMIT 1 DETACH DELETE o RETURN 1",
    "CREATE INDEX ro_probe IF NOT EXISTS FOR (o:Object) ON (o.colour)",
    "CREATE CONSTRAINT ro_probe IF NOT EXISTS FOR (o:Object) REQUIRE o.colour IS UNIQUE",
    "DROP CONSTRAINT object_id IF EXISTS",
    "DROP INDEX object_label IF EXISTS",
    "LOAD CSV FROM 'file:///etc/passwd' AS row RETURN row LIMIT 1",
]


@pytest.fixture
def populated(store):
    store.run_raw("CREATE (a:Object {id: 'ro/a', room: 'ro', label: 'cup'})-[:ON]->"
                  "(b:Object {id: 'ro/b', room: 'ro', label: 'table'})", write=True)
    return store


def counts(store) -> tuple[int, int, int, int, str]:
    def one(text):
        return store.run_raw(text)[1][0][0]
    _, constraints = store.run_raw("SHOW CONSTRAINTS YIELD name RETURN name")
    _, indexes = store.run_raw("SHOW INDEXES YIELD name RETURN name")
    return (one("MATCH (n) RETURN count(n)"), one("MATCH ()-[r]->() RETURN count(r)"),
            len(constraints), len(indexes), one("MATCH (o:Object {id: 'ro/a'}) RETURN o.label"))


def invoke(home, *args, input=None):
    return CliRunner().invoke(cli, list(args), input=input, env={"SG3D_HOME": str(home), "SG3D_URI": None,
                                                                 "SG3D_USER": None, "SG3D_PASSWORD": None,
                                                                 "SG3D_DATABASE": None})


@pytest.mark.parametrize("statement", REFUSED)
def test_cypher_without_write_is_refused_by_the_store(populated, embedded_home, statement):
    before = counts(populated)
    result = invoke(embedded_home, "cypher", statement)
    assert isinstance(result.exception, ClientError), result.output
    assert result.exception.code.startswith("Neo.ClientError.Security"), result.exception.code
    assert counts(populated) == before


def test_the_shell_without_write_is_refused_by_the_store(populated, embedded_home):
    before = counts(populated)
    text = ";\n".join(REFUSED) + ";\n:exit\n"
    result = invoke(embedded_home, "shell", input=text)
    assert result.exit_code == 0, result.output
    assert result.output.count("Neo.ClientError.Security.Forbidden") == len(REFUSED), result.output
    assert counts(populated) == before


def test_reads_work_and_write_still_writes(populated, embedded_home):
    result = invoke(embedded_home, "cypher", "MATCH (o:Object) RETURN count(o) AS n", "--json")
    assert result.exit_code == 0 and '"n": 2' in result.output, result.output
    result = invoke(embedded_home, "cypher", "--write", "CREATE (x:Object {id: 'ro/c', room: 'ro'}) RETURN 1")
    assert result.exit_code == 0, result.output
    assert counts(populated)[0] == 4  # 3 objects + the schema-version node
    result = invoke(embedded_home, "shell", "--write", input="MATCH (o:Object {id: 'ro/c'}) DETACH DELETE o;\n")
    assert result.exit_code == 0 and "error" not in result.output, result.output
    assert counts(populated)[0] == 3


def test_load_csv_of_a_file_is_refused_even_with_write(populated, embedded_home):
    result = invoke(embedded_home, "cypher", "--write", "LOAD CSV FROM 'file:///etc/passwd' AS row RETURN row")
    assert isinstance(result.exception, ClientError) and "root:" not in result.output


def test_the_reader_store_refuses_user_writes_but_sends_sg3ds_own_to_the_writer(populated, embedded_home):
    settings = Settings.from_options(home=str(embedded_home))
    reader = settings.reader()
    assert reader.read_only and not settings.store().read_only
    with pytest.raises(ReadOnlyStoreError):
        reader.run_raw("RETURN 1", write=True)
    with pytest.raises(ReadOnlyStoreError):
        reader.wipe()
    # the taxonomy mirror `ask` keeps is sg3d's own fixed template: it goes to the writer
    from sg3d.queries import taxonomy

    taxonomy.forget()
    assert taxonomy.ensure_taxonomy(reader, force=True) is True
    assert reader.run_raw("MATCH (c:Category) RETURN count(c)")[1][0][0] > 0
