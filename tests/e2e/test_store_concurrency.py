"""Two builds merging into the same new room at once: both succeed, and the room ends up as one
sequential build leaves it (no duplicate-room failure, no lost update)."""
from __future__ import annotations

import threading

from sg3d.graphdb.merge import merge_local_graph
from sg3d.graphdb.values import room_id
from tests.factories import graph, hist_of, obj

OBJECTS = [("cup", (0.0, 0.0, 1.0), (0.1, 0.1, 0.1), {7: 80}),
           ("bowl", (0.5, 0.0, 1.0), (0.15, 0.15, 0.08), {40: 80}),
           ("dining table", (0.2, -0.4, 1.0), (1.5, 0.8, 0.7), {30: 500}),
           ("chair", (1.5, -0.5, 0.5), (0.5, 0.5, 0.9), {60: 200}),
           ("tv", (3.0, 1.0, 0.5), (1.0, 0.1, 0.6), {90: 200}),
           ("potted plant", (-1.5, 0.5, 0.3), (0.3, 0.3, 0.5), {120: 200})]


def local_graph(room: str, view: int):
    """One view of the room: the same six objects, seen from `view` (a small shift)."""
    shift = 0.01 * view
    objects = [obj(f"v{view}_{i}", label, (m[0] + shift, m[1], m[2]), size=size, hist=hist_of(h), frame=view)
               for i, (label, m, size, h) in enumerate(OBJECTS)]
    return graph(objects, relations=[(f"v{view}_0", "ON", f"v{view}_2", 0.9)], room=room, building="race",
                 key=f"race/{room}/view{view}")


def summary(store, room: str):
    rows = store.run_raw("MATCH (o:Object) WHERE o.room = $room RETURN o.label AS label, o.observations AS n "
                         "ORDER BY label", {"room": room_id("race", room)})[1]
    rooms = store.run_raw("MATCH (r:Room) WHERE r.id = $room RETURN count(r)", {"room": room_id("race", room)})[1]
    return rooms[0][0], [tuple(r) for r in rows]


def test_two_concurrent_merges_of_one_new_room_equal_a_sequential_merge(store):
    for view in (1, 2):
        merge_local_graph(store, local_graph("sequential", view))
    expected = summary(store, "sequential")
    assert expected[0] == 1 and len(expected[1]) == len(OBJECTS)
    assert all(n == 2 for _, n in expected[1])

    for attempt in range(3):
        room = f"concurrent{attempt}"
        barrier = threading.Barrier(2)
        errors, reports = [], []

        def build(view, room, barrier, errors, reports):
            g = local_graph(room, view)
            barrier.wait()
            try:
                reports.append(merge_local_graph(store, g))
            except Exception as exc:  # noqa: BLE001 - the test reports what failed
                errors.append(exc)

        threads = [threading.Thread(target=build, args=(view, room, barrier, errors, reports)) for view in (1, 2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(120)
        assert not errors, errors
        assert len(reports) == 2
        assert summary(store, room) == expected, attempt



def elsewhere(room: str, prefix: str, label, dx: float):
    """The test's six objects moved `dx` along x (nothing there yet), labelled `label` or their own."""
    return graph([obj(f"{prefix}{i}", label or own, (dx + m[0], m[1], m[2]), size=size, hist=hist_of(h))
                  for i, (own, m, size, h) in enumerate(OBJECTS)], room=room, building="race")


def map_publish(store, room: str) -> None:
    import time

    from sg3d.core.model import ScanInfo
    from sg3d.graphdb.live import publish

    publish(store, elsewhere(room, "m", "vase", 20.0), ScanInfo(f"map:race/{room}", time.time(), closes=False),
            {"state": "live", "frames": 1})


def build_merge(store, room: str) -> None:
    merge_local_graph(store, elsewhere(room, "b", None, 10.0))


def at_once(store, room: str, writers) -> list:
    """Run each writer(store, room) on its own thread, released together; the errors they raised."""
    barrier = threading.Barrier(len(writers))
    errors = []

    def run(write):
        barrier.wait()
        try:
            write(store, room)
        except Exception as exc:  # noqa: BLE001 - the test reports what failed
            errors.append(exc)

    threads = [threading.Thread(target=run, args=(w,)) for w in writers]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    return errors


def test_a_live_publish_and_a_build_racing_on_one_room_both_commit_with_their_own_ids(store):
    """A map publishing while a build merges into the same room, each making new objects:
    neither fails, every node of both is there once with its own id, and the room's revision
    went up once for each write."""
    def revision(room):
        return store.run_raw("MATCH (r:Room) WHERE r.id = $room RETURN r.revision", {"room": room_id("race", room)})[1][0][0]

    for attempt in range(4):
        room = f"mixed{attempt}"
        merge_local_graph(store, local_graph(room, 1))
        before = revision(room)
        errors = at_once(store, room, [map_publish, build_merge])
        assert not errors, [str(e) for e in errors]
        rows = store.run_raw("MATCH (o:Object) WHERE o.room = $room RETURN o.id, o.label",
                             {"room": room_id("race", room)})[1]
        assert len(rows) == len({r[0] for r in rows}) == 3 * len(OBJECTS)
        assert sum(1 for r in rows if r[1] == "vase") == len(OBJECTS)
        assert revision(room) == before + 2
