"""The answer cache's bounds and counts, and the rule of which rooms a statement reads (no store)."""
from __future__ import annotations

from sg3d.app.answers import _ENTRY_BYTES, EVERY_ROOM, AnswerCache, Snapshot, normalised, rooms_read

NOW = Snapshot({"h/a": (1, 1), "h/b": (2, 1)}, (("h/a", "a", "h", 1), ("h/b", "b", "h", 2)))
ROOM_A = frozenset({"h/a"})


def test_the_least_recently_used_answer_goes_first_at_the_entry_bound():
    cache = AnswerCache(entries=2)
    cache.put(NOW, ROOM_A, ("a",), {"v": 1})
    cache.put(NOW, ROOM_A, ("b",), {"v": 2})
    assert cache.get(NOW, ("a",)) == {"v": 1}          # a used: b is now the oldest
    cache.put(NOW, ROOM_A, ("c",), {"v": 3})
    assert len(cache) == 2 and cache.get(NOW, ("b",)) is None and cache.get(NOW, ("a",)) and cache.get(NOW, ("c",))
    assert (cache.hits, cache.misses) == (3, 1)


def test_the_byte_bound_counts_a_pictures_base64_on_both_sides():
    picture = "x" * 10_000
    cache = AnswerCache(entries=100, max_bytes=2 * (_ENTRY_BYTES + len(picture)))
    cache.put(NOW, ROOM_A, ("a",), {"thumbnail_jpeg_base64": picture})
    cache.put(NOW, ROOM_A, ("b",), {"thumbnail_jpeg_base64": picture})
    assert len(cache) == 2                         # exactly at the bound: both kept
    cache.put(NOW, ROOM_A, ("c",), {"thumbnail_jpeg_base64": picture})
    assert len(cache) == 2 and cache.get(NOW, ("a",)) is None
    cache.put(NOW, ROOM_A, ("huge",), {"thumbnail_jpeg_base64": "x" * cache.max_bytes})
    assert cache.get(NOW, ("huge",)) is None and len(cache) == 2   # larger than the whole cache: not kept


def test_no_entries_keeps_nothing_and_a_key_list_is_one_look_up():
    cache = AnswerCache(entries=0)
    cache.put(NOW, ROOM_A, ("a",), {"v": 1})
    assert cache.get(NOW, ("a",), ("b",)) is None and (cache.hits, cache.misses) == (0, 1)


def test_an_answer_outlives_a_write_to_a_room_it_did_not_read_and_no_write_to_one_it_did():
    cache = AnswerCache()
    cache.put(NOW, ROOM_A, ("over a",), {"v": 1})
    cache.put(NOW, EVERY_ROOM, ("over all",), {"v": 2})
    b_written = Snapshot({"h/a": (1, 1), "h/b": (2, 2)}, NOW.listing)
    a_written = Snapshot({"h/a": (1, 2), "h/b": (2, 1)}, NOW.listing)
    a_made_again = Snapshot({"h/a": (3, 1), "h/b": (2, 1)}, (("h/a", "a", "h", 3), ("h/b", "b", "h", 2)))
    assert cache.get(b_written, ("over a",)) == {"v": 1}
    assert cache.get(b_written, ("over all",)) is None
    assert cache.get(a_written, ("over a",)) is None
    assert cache.get(a_made_again, ("over a",)) is None


def test_which_rooms_a_statement_reads():
    known = {"h/a": 1, "h/b": 1}
    assert rooms_read("vqa_count_in_rooms", {"labels": ["cup"], "rooms": ["h/a"], "colour": None}, known) == ROOM_A
    assert rooms_read("changes_objects", {"room": "h/a", "scans": []}, known) == ROOM_A
    assert rooms_read("vqa_room_names", {"building": None}, known) == frozenset()     # the room list only
    assert rooms_read("vqa_where", {"ids": ["x"], "types": ["ON"], "incoming": False}, known) == frozenset()
    assert rooms_read(None, {"ids": ["x"], "types": ["ON"]}, known) == frozenset()      # a relation read by id
    # any statement not scoped to rooms the store holds may read every room
    assert rooms_read("vqa_count_any", {"labels": None, "rooms": None, "colour": None}, known) is EVERY_ROOM
    assert rooms_read("vqa_rooms_all", {"building": None}, known) is EVERY_ROOM
    assert rooms_read("object_total", {}, known) is EVERY_ROOM
    assert rooms_read("vqa_median", {"label": "cup", "sample": 10}, known) is EVERY_ROOM
    assert rooms_read("vqa_count_in_rooms", {"rooms": ["h/a", "h/gone"]}, known) is EVERY_ROOM
    assert rooms_read("history_objects", {"labels": None, "room": None, "building": "h"}, known) is EVERY_ROOM


def test_the_question_is_keyed_without_case_or_extra_spaces():
    assert normalised("  How many\tcups  ARE there? ") == "how many cups are there?"
