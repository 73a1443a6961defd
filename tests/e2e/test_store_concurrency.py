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
