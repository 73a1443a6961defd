"""Regenerate the question reader's shipped parser tables in sg3d/queries/data (and remove stale ones):

    python scripts/make_query_tables.py

- question-parser-tables-<hash>.pickle: the LALR tables (lark's pickle) of the question grammar
  (sg3d/queries/data/question.lark),
  which a cold `sg3d ask` loads instead of building them (0.7 s); run after editing the grammar or
  its word lists, or after upgrading lark (the hash covers both; without a current file the
  parser is built and kept in the user cache, as before).

tests/e2e/test_cold_start.py checks that they are current.
"""
from __future__ import annotations

import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))


def main() -> int:
    from sg3d.queries.reader.grammar import build_parser, parser_grammar, shipped_tables

    grammar = parser_grammar()
    tables = shipped_tables(grammar)
    built = build_parser(grammar)         # first: a grammar with a conflict stops here, changing nothing
    for old in tables.parent.glob("question-parser-tables-*.pickle"):
        if old != tables:
            old.unlink()
            print(f"removed {old.relative_to(REPO)}")
    with tables.open("wb") as f:
        built.save(f)
    print(f"wrote {tables.relative_to(REPO)} ({tables.stat().st_size:,} bytes)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
