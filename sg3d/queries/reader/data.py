"""The reader's data files, read once: the lexicon (sg3d/queries/data/lexicon.toml) and the rule
table (sg3d/queries/data/rephrase_rules.toml: its word tables and its plain patterns, for the
steps written in Python that share them)."""
from __future__ import annotations

import functools
import re
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:   # Python 3.10: the same parser, a dependency there (pyproject.toml)
    import tomli as tomllib  # type: ignore[import-not-found]

RULES = Path(__file__).resolve().parents[1] / "data" / "rephrase_rules.toml"
LEXICON = Path(__file__).resolve().parents[1] / "data" / "lexicon.toml"


@functools.cache
def lexicon_file() -> dict:
    """The words of questions (sg3d/queries/data/lexicon.toml), as sg3d/queries/vocabulary.py names them."""
    return tomllib.loads(LEXICON.read_text())


@functools.cache
def rules_file() -> dict:
    return tomllib.loads(RULES.read_text())


def dictionary(name: str) -> dict[str, str]:
    """A word table of the rules file (contractions, number words, units ...)."""
    return dict(rules_file()["dictionaries"][name])


@functools.cache
def pattern(name: str) -> re.Pattern[str]:
    """The compiled pattern of the rule `name` (one written without word lists)."""
    return re.compile(next(r["pattern"] for r in rules_file()["rule"] if r["name"] == name))
