"""The read path of a cluster, on the one embedded node: a `neo4j://` routing URI (the routing
driver asks the node for its routing table), revisions read where the latest commit is, and the
store's bookmarks carried to the answer's reads."""
from __future__ import annotations

from sg3d.app.answers import AnswerCache, ask_kept
from sg3d.graphdb.store import Store
from sg3d.testing import graph, obj

QUESTION = "how many chairs are there?"


def test_a_routing_store_keys_answers_by_revisions_read_at_the_leader(house, store, embedded_home):
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.graphdb.merge import merge_local_graph

    info = EmbeddedServer(embedded_home).ensure_running()
    assert info.uri.startswith("bolt://")
    routed = Store("neo4j://" + info.uri.split("://", 1)[1], (info.user, info.password), info.database)
    try:
        cache = AnswerCache()
        first, hit = ask_kept(routed, cache, QUESTION, room="kitchen")
        assert not hit and first["value"] == 3
        assert routed.bookmarks.get_bookmarks(), "the revision read left no bookmark for the answer's reads"
        assert ask_kept(routed, cache, QUESTION, room="kitchen")[1]
        merge_local_graph(store, graph([obj("n", "chair", (20.0, 0.0, 0.0))], room="kitchen", building="home"))
        fresh, hit = ask_kept(routed, cache, QUESTION, room="kitchen")     # another handle's commit
        assert not hit and fresh["value"] == 4
    finally:
        routed.close()


def test_a_process_shares_one_bookmark_manager_per_database(store, embedded_home):
    """A server's reader and writer handles: what one wrote, the other's reads wait for."""
    from sg3d.graphdb.embedded import EmbeddedServer

    info = EmbeddedServer(embedded_home).ensure_running()
    reader = Store(info.uri, info.reader_auth, info.database, read_only=True)
    try:
        assert reader.bookmarks is store.bookmarks
        store.write("room_bump_all")
        assert store.bookmarks.get_bookmarks()
    finally:
        reader.close()
