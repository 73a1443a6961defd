"""The answer cache's bounds and counts (no store)."""
from __future__ import annotations

from sg3d.app.answers import _ENTRY_BYTES, AnswerCache, normalised


def test_the_least_recently_used_answer_goes_first_at_the_entry_bound():
    cache = AnswerCache(entries=2)
    cache.put(("a",), {"v": 1})
    cache.put(("b",), {"v": 2})
    assert cache.get(("a",)) == {"v": 1}          # a used: b is now the oldest
    cache.put(("c",), {"v": 3})
    assert len(cache) == 2 and cache.get(("b",)) is None and cache.get(("a",)) and cache.get(("c",))
    assert (cache.hits, cache.misses) == (3, 1)


def test_the_byte_bound_counts_a_pictures_base64_on_both_sides():
    picture = "x" * 10_000
    cache = AnswerCache(entries=100, max_bytes=2 * (_ENTRY_BYTES + len(picture)))
    cache.put(("a",), {"thumbnail_jpeg_base64": picture})
    cache.put(("b",), {"thumbnail_jpeg_base64": picture})
    assert len(cache) == 2                         # exactly at the bound: both kept
    cache.put(("c",), {"thumbnail_jpeg_base64": picture})
    assert len(cache) == 2 and cache.get(("a",)) is None
    cache.put(("huge",), {"thumbnail_jpeg_base64": "x" * cache.max_bytes})
    assert cache.get(("huge",)) is None and len(cache) == 2   # larger than the whole cache: not kept


def test_no_entries_keeps_nothing_and_a_key_list_is_one_look_up():
    cache = AnswerCache(entries=0)
    cache.put(("a",), {"v": 1})
    assert cache.get(("a",), ("b",)) is None and (cache.hits, cache.misses) == (0, 1)


def test_the_question_is_keyed_without_case_or_extra_spaces():
    assert normalised("  How many\tcups  ARE there? ") == "how many cups are there?"
