"""The graph as a whole: export (`sg3d export`, `GET /graph`), its schema (the MCP `graph_schema`
tool) and the read-only Cypher path (the MCP `cypher` tool)."""
from __future__ import annotations

import re
from dataclasses import replace
from typing import Optional

from sg3d.app.errors import AppError, NotFound, Refused
from sg3d.core.stored import Row, StoredGraph
from sg3d.graphdb.protocol import GraphStore
from sg3d.graphdb.values import jsonable

FORMATS = ("json", "graphml", "spark-dsg", "3dssg")
CYPHER_ROW_LIMIT = 1000
CYPHER_TIMEOUT_S = 10.0


# -- export -----------------------------------------------------------------------------------
def fetch_named_graph(store: GraphStore, building: str, room: Optional[str] = None, thumbnails: bool = False,
                      histograms: bool = False, room_transforms: bool = False) -> StoredGraph:
    """The room's (or building's) graph, each node with its readable name (and with
    `room_transforms`, {room name: 4x4 room-to-building or None}, which the spark-dsg form needs);
    NotFound when it holds no objects."""
    from sg3d.graphdb.export import fetch_graph
    from sg3d.queries.naming import name_graph

    graph = fetch_graph(store, building, room, thumbnails, histograms)
    if not graph.nodes:
        where = f"room {room!r} of building {building!r}" if room else f"building {building!r}"
        raise NotFound(f"nothing to export: {where} holds no objects (`sg3d rooms` lists the rooms)")
    if room_transforms:
        from sg3d.graphdb.building import list_rooms

        graph = replace(graph, room_transforms={r["name"]: r["to_building"] for r in list_rooms(store, building)})
    return name_graph(graph)     # each node's readable name, as ask, plan and show print it


def render_graph(graph: StoredGraph, fmt: str) -> str:
    """The graph as text: the paper's JSON form, GraphML or spark_dsg's JSON (Hydra's format,
    `sg3d.formats.spark_dsg`; positions in the building frame when `graph` has "room_transforms")."""
    from sg3d.formats.graphml import to_graphml
    from sg3d.formats.paper_json import to_json

    if fmt not in FORMATS:
        raise AppError(f"unknown format {fmt!r} (choose from {', '.join(FORMATS)})")
    if fmt == "spark-dsg":
        from sg3d.formats.spark_dsg import to_spark_json

        # spark-dsg and 3DSSG describe the scene as it stands now: without the removed objects
        return to_spark_json(graph.present(), graph.room_transforms)
    if fmt == "3dssg":  # both files in one document; `sg3d export --out DIR` writes them apart
        import json

        from sg3d.formats.threedssg import to_3dssg

        objects, relationships = to_3dssg(graph.present())
        return json.dumps({"objects": objects, "relationships": relationships}, indent=1)
    return to_json(graph) if fmt == "json" else to_graphml(graph)


def write_3dssg(graph: StoredGraph, folder) -> tuple[int, int]:
    """objects.json and relationships.json (3DSSG/3RScan form) into `folder`; (objects, relationships)."""
    import json
    from pathlib import Path

    from sg3d.formats.threedssg import to_3dssg

    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise Refused(f"{folder}: 3dssg writes objects.json and relationships.json into a folder, not a file")
    folder.mkdir(parents=True, exist_ok=True)
    graph = graph.present()
    objects, relationships = to_3dssg(graph)
    (folder / "objects.json").write_text(json.dumps(objects, indent=1))
    (folder / "relationships.json").write_text(json.dumps(relationships, indent=1))
    return len(graph.nodes), sum(len(s["relationships"]) for s in relationships["scans"])


# -- schema ------------------------------------------------------------------------------------
def graph_schema(store: GraphStore) -> dict:
    """What a Cypher author needs: node labels with their properties, relationship types (the
    whitelist) and how many of each the store holds now."""
    from sg3d.core.model import COLOUR_NAMES, RELATION_TYPES
    from sg3d.core.stored import NODE_FIELDS

    nodes = {
        "Building": ["id"],
        "Room": ["id ('building/room')", "name", "building", "up", "to_building (16 floats, row-major 4x4)"],
        "Object": list(NODE_FIELDS) + ["box_centre", "score", "updated_at"],
        "Appearance": ["id (the Object's id)", "hist (512 float32 bytes)", "thumbnail (JPEG bytes)"],
        "Category": ["name"],
        "MergeLog": ["key", "room", "frames", "created", "updated", "at"],
    }
    edges = {
        "HAS_ROOM": "(:Building)->(:Room)", "CONTAINS": "(:Room)->(:Object)",
        "ADJACENT_TO": "(:Room)->(:Room) {shared_objects, residual_m}",
        "SAME_AS": "(:Object)->(:Object) {distance}: one physical object seen from two rooms",
        "IS_A": "(:Category)->(:Category): taxonomy",
        **{t: "(:Object)->(:Object) {score, count}: spatial/size relation" for t in RELATION_TYPES},
    }
    counts_nodes = {":".join(r["labels"] or []) or "(none)": r["n"] for r in store.read("schema_node_counts")}
    counts_edges = {r["type"]: r["n"] for r in store.read("schema_edge_counts")}
    return {"nodes": nodes, "relationships": edges, "colours": list(COLOUR_NAMES),
            "node_counts": counts_nodes, "relationship_counts": counts_edges,
            "notes": ["positions are metres in the room's frame (x, y, z); size is width, depth, height",
                      "object names as people read them come from the list_objects tool, not from Cypher"]}


# -- read-only Cypher ----------------------------------------------------------------------------
# A reading statement starts with one of these; anything else (schema and admin commands, USE,
# EXPLAIN/PROFILE, which on ArcadeDB runs a schema command it explains: measured) is refused.
READ_STARTS = frozenset({"MATCH", "OPTIONAL", "WITH", "UNWIND", "RETURN"})
# Clauses that change data or run procedures (which may), anywhere in the statement.
WRITE_WORDS = frozenset({"CREATE", "MERGE", "DELETE", "DETACH", "SET", "REMOVE", "DROP", "LOAD", "FOREACH",
                         "CALL", "PROFILE", "EXPLAIN", "USE"})
# Steps of ArcadeDB's EXPLAIN text ("+ CREATE", "+ SET (1 items)") that write.
_PLAN_WRITE = re.compile(r"^\s*\+\s*(CREATE|MERGE|SET|DELETE|DETACH|REMOVE|FOREACH|CALL)\b", re.M | re.I)
# Strings, `names` and comments; one left open runs to the end of the text, so every opener
# matches where it stands and the scan stays linear (an unclosed "/*" repeated cannot make it
# search to the end again and again).
_STRINGS = re.compile(r"'(?:\\.|[^'\\])*(?:'|\Z)|\"(?:\\.|[^\"\\])*(?:\"|\Z)|`[^`]*(?:`|\Z)|//[^\n]*"
                      r"|/\*(?:[^*]|\*(?!/))*(?:\*/|\Z)", re.S)
# Functions that hold a worker without doing work, which no statement limit interrupts.
_BLOCKING = re.compile(r"(?<![\w$])sleep\s*\(", re.I)
_WORD = re.compile(r"(?<![.$\w])([A-Za-z_]\w*)")
# range(a, b[, step]) with numbers or parameters for bounds.
_RANGE = re.compile(r"(?<![\w$.])range\s*\(\s*([-+]?\d+|\$\w+)\s*,\s*([-+]?\d+|\$\w+)\s*(?:,\s*([-+]?\d+|\$\w+)\s*)?\)",
                    re.I)
_UNWOUND = re.compile(r"\bUNWIND\s*\Z", re.I)
# The store's statement time limit stops a statement between rows, not inside one: a list of
# range() items, or a reduce() over nested ranges, computed for one row runs on (measured: a
# reduce over range(1,10000) x range(1,20000) ran 65 s under a 30 s limit; three lists of 26
# million strings took the store's heap to 4.4 GB). Ranges that could build more items than
# this, alone or multiplied together, are refused before the store sees them.
MAX_RANGE_ITEMS = 1_000_000
MAX_RANGE_WORK = 10_000_000


def check_statement(statement: str, params: Optional[dict] = None) -> None:
    """Refuse a user's statement before it reaches the store: longer than
    `bounds.MAX_STATEMENT_CHARS`, calling a sleep function, or building lists too long to stop
    (`range_work`); the store's statement time limit (`sg3d.graphdb.embedded.store_timeout_s`)
    interrupts neither."""
    from sg3d.app.bounds import MAX_STATEMENT_CHARS

    if not isinstance(statement, str):
        raise AppError("the statement must be a text")
    if len(statement) > MAX_STATEMENT_CHARS:
        raise AppError(f"the statement is longer than {MAX_STATEMENT_CHARS} characters")
    bare = _STRINGS.sub(" ", statement)
    if _BLOCKING.search(bare):
        raise Refused("sleep functions are not allowed here")
    biggest, work = range_work(bare, params or {})
    if biggest > MAX_RANGE_ITEMS:
        raise Refused(f"a range() here holds {biggest:,} items, more than the {MAX_RANGE_ITEMS:,} one may "
                      f"(the store cannot stop a computation inside one row)")
    if work > MAX_RANGE_WORK:
        raise Refused(f"the range() calls here multiply to {work:,} items, more than the {MAX_RANGE_WORK:,} a "
                      f"statement may (the store cannot stop a computation inside one row)")


def range_work(bare: str, params: dict) -> tuple[int, int]:
    """(items of the longest range(), items of all ranges multiplied) computed inside a row (not
    those an UNWIND turns into rows) in a statement with its strings and comments blanked; bounds given as parameters are read from `params` (a bound
    that is not a whole number counts as nothing: the store refuses it anyway)."""
    def value(token: Optional[str]) -> Optional[int]:
        if token is None:
            return None
        if token.startswith("$"):
            v = params.get(token[1:])
            return int(v) if isinstance(v, (int, float)) and not isinstance(v, bool) and abs(v) < 1e18 else None
        return int(token)

    biggest, work = 0, 1
    found = False
    for m in _RANGE.finditer(bare):
        if _UNWOUND.search(bare, 0, m.start()):
            continue        # UNWIND range(...) makes rows: the time limit stops it between them
        a, b, step = value(m.group(1)), value(m.group(2)), value(m.group(3))
        if a is None or b is None or step == 0:
            continue
        step = 1 if step is None else step
        n = max(0, (b - a) // step + 1)
        biggest, work, found = max(biggest, n), work * max(1, n), True
    return biggest, (work if found else 0)


def write_words(statement: str) -> list[str]:
    """The writing keywords of a statement, outside strings, comments, `quoted` names, property
    keys (o.set) and parameters ($set)."""
    bare = _STRINGS.sub(" ", statement)
    return sorted({w.upper() for w in _WORD.findall(bare) if w.upper() in WRITE_WORDS})


def check_read_only(store: GraphStore, statement: str) -> None:
    """Refuse (Refused) a statement that writes: first by its keywords, then by the server's
    EXPLAIN plan (Neo4j: the summary's query type must be 'r'; ArcadeDB, whose query type is
    always 'w', by the write steps of its plan text)."""
    text = statement.strip().rstrip(";").strip()
    if not text:
        raise AppError("empty statement")
    if ";" in _STRINGS.sub(" ", text):
        raise Refused("one statement at a time")
    first = _WORD.search(_STRINGS.sub(" ", text))
    if first is None or first.group(1).upper() not in READ_STARTS:
        raise Refused(f"read-only: a statement here starts with {', '.join(sorted(READ_STARTS))}")
    words = write_words(text)
    if words:
        raise Refused(f"read-only: {', '.join(words)} is not allowed here (this path only reads)")
    steps = explain_writes(store, text)
    if steps:
        raise Refused(f"read-only: the plan writes ({', '.join(steps)})")


def explain_writes(store: GraphStore, statement: str) -> list[str]:
    """The writing steps of the server's EXPLAIN plan of a statement ([] for a read). Neo4j: the
    summary's query type must be 'r'. ArcadeDB reports 'w' for every statement, so there the
    steps of its plan text ("+ CREATE", "+ SET (1 items)") decide; a statement with no plan
    (a schema command) counts as writing. Only for statements `write_words` let through:
    EXPLAIN of a schema command runs it on ArcadeDB."""
    with store.session(default_access_mode="READ") as s:
        summary = s.run("EXPLAIN " + statement).consume()
    plan = summary.plan or {}
    if str(plan.get("operatorType", "")).startswith("ArcadeDB"):
        text = str((plan.get("args") or {}).get("string-representation", ""))
        return sorted({m.upper() for m in _PLAN_WRITE.findall(text)})
    if not plan:
        return ["no plan"]
    return [] if summary.query_type == "r" else [f"query type {summary.query_type!r}"]


def read_only_cypher(store: GraphStore, statement: str, params: Optional[dict] = None, limit: int = CYPHER_ROW_LIMIT,
                     timeout_s: float = CYPHER_TIMEOUT_S) -> dict:
    """Run one reading statement: {keys, rows (dicts), truncated}.

    Three guards, any one enough for what it covers: `check_read_only` refuses writing
    statements; the statement then runs in an explicit READ transaction that is always rolled
    back, never committed; and the store's read-only user (`sg3d.app.stores.reader`) where it exists.
    AppError for a Cypher error (its code and first line)."""
    from neo4j.exceptions import ClientError

    if params is not None and not isinstance(params, dict):
        raise AppError("params must be an object of parameter names to values")
    check_statement(statement, params)
    try:
        check_read_only(store, statement)
        return run_rolled_back(store, statement.strip().rstrip(";"), params or {}, limit, timeout_s)
    except ClientError as exc:
        raise AppError(f"{exc.code}: {(exc.message or str(exc)).strip().splitlines()[0]}") from exc


def run_rolled_back(store: GraphStore, statement: str, params: dict, limit: int = CYPHER_ROW_LIMIT,
                    timeout_s: float = CYPHER_TIMEOUT_S) -> dict:
    """Run a statement in an explicit READ transaction that is rolled back, never committed:
    {keys, rows (at most `limit`), truncated}."""
    with store.session(default_access_mode="READ") as s:
        tx = s.begin_transaction(timeout=timeout_s)
        try:
            result = tx.run(statement, params)
            keys = list(result.keys())
            rows: list[Row] = []
            for record in result:
                if len(rows) == limit:
                    return {"keys": keys, "rows": rows, "truncated": True}
                rows.append({k: jsonable(v) for k, v in zip(keys, record.values())})
            return {"keys": keys, "rows": rows, "truncated": False}
        finally:
            tx.rollback()


# -- import ------------------------------------------------------------------------------------
def import_spark_dsg(store: GraphStore, path, building: Optional[str] = None, room: Optional[str] = None,
                     embedding=None) -> dict:
    """Merge a spark_dsg scene graph file (Hydra's, or our own export) into the store, through the
    merge every observation takes (same-node detection, one transaction per room). Each room of
    the file becomes a room (`room`: all objects into that one room); the building is `building`,
    else the file's building node's name, else "default". The observation key is the file's
    content hash, so importing the same file again merges nothing."""
    import hashlib
    from pathlib import Path

    from pydantic import ValidationError

    from sg3d.app.ingest import IngestRequest, ingest_graph
    from sg3d.formats.spark_dsg import SparkError, read_spark

    try:
        data = read_spark(path)
    except SparkError as exc:
        raise Refused(str(exc)) from None
    digest = hashlib.sha256(Path(path).read_bytes()).hexdigest()[:16]
    building = building or data["building"] or "default"
    groups: dict[str, dict] = {}
    for source, g in data["rooms"].items():
        target = room or source or "unassigned"
        merged = groups.setdefault(target, {"objects": [], "relations": [], "sources": []})
        merged["objects"] += g["objects"]
        merged["relations"] += g["relations"]
        merged["sources"].append(source)
    reports = []
    for target, g in sorted(groups.items()):
        for o in g["objects"]:
            n = min(len(o["labels"]), len(o["scores"]), 20)
            o["labels"], o["scores"] = o["labels"][:n], o["scores"][:n]
        body = {"building": building, "room": target,
                "observation_id": f"spark-dsg:{digest}:{'+'.join(sorted(g['sources']))}",
                "graph": {"objects": g["objects"], "relations": g["relations"]}}
        try:
            req = IngestRequest.model_validate(body)
        except ValidationError as exc:
            first = exc.errors()[0]
            raise Refused(f"{path}: room {target[:60]!r}: {'.'.join(map(str, first['loc']))}: "
                          f"{str(first['msg'])[:200]}") from None
        reports.append({"from_rooms": g["sources"], **ingest_graph(store, req, embedding)})
    return {"file": str(path), "building": building, "layers": data["layers"], "rooms": reports}
