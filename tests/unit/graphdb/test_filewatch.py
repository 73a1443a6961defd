"""The store's file watch and the index comparison of `db check`, on plain files and rows (no store)."""
from __future__ import annotations

import os

from sg3d.app.check import _index_vs_records, unique_keys
from sg3d.graphdb.filewatch import FileWatch, gone_from, kept_files, read_record, record_path, write_record


def _database(tmp_path):
    folder = tmp_path / "home" / "databases" / "databases" / "sg3d"
    folder.mkdir(parents=True)
    for name in ("Object_0.9.65536.v0.bucket", "dictionary.0.65536.v1.dict", "schema.json",
                 "Object_0_1.12.262144.v1.umtidx", "txlog_0.wal"):
        (folder / name).write_bytes(b"x")
    return folder


def test_the_record_lives_beside_the_store_folder(tmp_path):
    assert record_path(tmp_path / "home") == tmp_path / ".home.sg3d-database"


def test_only_files_arcadedb_never_deletes_are_kept(tmp_path):
    folder = _database(tmp_path)
    assert kept_files(folder) == {"Object_0.9.65536.v0.bucket", "dictionary.0.65536.v1.dict", "schema.json"}


def test_a_kept_file_missing_at_two_looks_is_lost_and_one_look_is_not(tmp_path):
    folder = _database(tmp_path)
    watch = FileWatch(folder, record_path(tmp_path / "home"))
    assert watch.problem is None and watch.lost() is None
    (folder / "schema.json").unlink()
    assert watch.lost() is None                     # a rewrite by rename is one look
    (folder / "schema.json").write_text("{}")
    assert watch.lost() is None
    (folder / "Object_0.9.65536.v0.bucket").unlink()
    assert watch.lost() is None
    assert "Object_0.9.65536.v0.bucket" in watch.lost()
    (folder / "Object_0_1.12.262144.v1.umtidx").unlink()    # index files are not watched


def test_a_replaced_or_vanished_folder_is_lost_at_once(tmp_path):
    folder = _database(tmp_path)
    watch = FileWatch(folder, record_path(tmp_path / "home"))
    folder.rename(folder.with_name("old"))
    assert "vanished" in watch.lost()
    folder.mkdir()
    assert "replaced" in watch.lost()


def test_the_record_names_what_is_gone_and_nothing_when_all_is_there(tmp_path):
    folder = _database(tmp_path)
    path = record_path(tmp_path / "home")
    FileWatch(folder, path)
    record = read_record(path)
    assert gone_from(record, folder) is None
    (folder / "dictionary.0.65536.v1.dict").unlink()
    assert "1 file(s)" in gone_from(record, folder) and "dictionary" in gone_from(record, folder)
    assert "is not there" in gone_from(record, tmp_path / "nowhere")
    assert gone_from({**record, "lost": "why"}, folder) == "why"


def test_a_record_of_another_kind_or_through_a_link_is_not_trusted(tmp_path):
    target = tmp_path / "elsewhere"
    write_record(target, {"created": "x"})
    link = tmp_path / ".home.sg3d-database"
    os.symlink(target, link)
    assert read_record(link) is None
    assert write_record(link, {}) is not None
    (tmp_path / "torn").write_text("{half")
    assert read_record(tmp_path / "torn") == {}     # unreadable: a database existed all the same


def test_index_entries_are_compared_with_the_records():
    records = [{"key": "a", "rid": "#9:0"}, {"key": "b", "rid": "#9:1"}]
    entries = [{"key": ["a"], "rid": "#9:0"}, {"key": ["b"], "rid": "#9:1"}]
    assert _index_vs_records("Object[id]", entries, records) == []
    assert "1 records the index does not hold" in _index_vs_records("Object[id]", entries[:1], records)[0]
    stale = entries + [{"key": ["c"], "rid": "#9:7"}]
    assert "1 index entries that point to no such record" in _index_vs_records("Object[id]", stale, records)[0]
    twice = records + [{"key": "a", "rid": "#9:2"}]
    lines = _index_vs_records("Object[id]", entries + [{"key": ["a"], "rid": "#9:2"}], twice)
    assert lines == ["Object[id]: 'a' is held by 2 records (#9:0, #9:2); a unique key repeats"]
    assert "missing" in _index_vs_records("Object[id]", None, records)[0]


def test_every_unique_constraint_of_the_schema_is_checked():
    assert ("Object", "id") in unique_keys() and ("MergeLog", "key") in unique_keys() and len(unique_keys()) == 7
