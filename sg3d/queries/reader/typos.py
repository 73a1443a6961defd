"""Typos: a word that is no word the reader knows, read as the one word it is a slip of.

Typos are fixed against a fixed vocabulary with rapidfuzz (a small edit distance), never with
the embedding model, so a typo costs no model load; every word changed is said in a note
("read 'chiars' as 'chairs'").
"""
from __future__ import annotations

import functools
import re
from typing import Iterable


def first_word_typo(text: str) -> tuple[str, list[str]]:
    """The question's first word, when it is no English word and one edit from exactly one
    question word ("whre did I leave", "waht colour"), read as that word before the frames
    are read (the later typo fixing comes after them); the note says so."""
    words = text.split()
    if not words or words[0] in QUESTION_WORDS or any(c.isdigit() for c in words[0]) or words[0] in common_words():
        return text, []
    fixed = _question_word(words[0], words[1] if len(words) > 1 else None)
    if fixed is None or fixed == words[0]:
        return text, []
    return " ".join([fixed] + words[1:]), [f"read '{words[0]}' as '{fixed}'"]



def were_for_where(text: str) -> tuple[str, list[str]]:
    """"were is the grey mug", "were are the cups", "tell me were the sink is": "were" where it
    cannot be the verb (before "is"/"are"/"can", or an embedded question ending in "is"/"are")
    is a slip of "where"; the note says so. "were the cups on the table" stays a question in the
    past."""
    if re.match(r"^were (?:is|are|can|could|do|does|did|should|would|might)\b", text) \
            or re.match(r"^were (?!there\b).+ (?:is|are)$", text):
        return "where" + text[len("were"):], ["read 'were' as 'where'"]
    return text, []




def max_edits(word: str) -> int:
    """The edit distance a typo may have: none for words under 4 letters (too many neighbours),
    one up to 6 letters, two beyond."""
    return 0 if len(word) < 4 else (1 if len(word) <= 6 else 2)


@functools.lru_cache(maxsize=4096)
def _closest(word: str, vocab: frozenset, dropped_first: bool = False) -> str | None:
    from rapidfuzz import process
    from rapidfuzz.distance import DamerauLevenshtein, Indel

    limit = max_edits(word)
    if not limit:
        return None
    found = process.extract(word, vocab, scorer=DamerauLevenshtein.distance, score_cutoff=limit, limit=3)
    if not found:
        return None
    best = min(d for _, d, _ in found)
    # two spellings of one word ("colur": colour or color) are one winner, the spelling read
    winners = sorted({SPELLINGS.get(w, w) for w, d, _ in found if d == best})
    if len(winners) > 1:
        # people rarely mistype a word's first letter: among equally close words, that decides
        winners = [w for w in winners if w[0] == word[0]]
    if len(winners) > 1 and dropped_first:
        # a letter left out or typed twice is commoner than a wrong one ("colr": color, not cold)
        fewest = min(Indel.distance(word, w) for w in winners)
        winners = [w for w in winners if Indel.distance(word, w) == fewest]
    # still two words equally close: the typo is ambiguous and stays as written
    return winners[0] if len(winners) == 1 else None


# one word spelled two ways: the spelling the grammar reads (tidy makes "colour" "color")
SPELLINGS = {"colour": "color", "colours": "colors", "coloured": "colored", "gray": "grey", "centre": "center"}


def dropped_letter(word: str, nouns: frozenset) -> str | None:
    """A short unknown word (3 letters, too short for `max_edits`) that is one object noun with
    one letter left out ("dsk": desk, "snk": sink, "ovn": oven), when exactly one noun is."""
    if len(word) != 3 or not word.isalpha():
        return None
    hits = {n for n in nouns if len(n) == 4 and any(n[:i] + n[i + 1:] == word for i in range(4))}
    return hits.pop() if len(hits) == 1 else None


# A word counts as common English when pyspellchecker's English frequency list saw it this often
# (25,246 ASCII words: "sitting" and "bowel" are in, typos such as "chiars" or "kitchn" are not).
COMMON_WORD_MIN_COUNT = 500


@functools.cache
def common_words() -> frozenset[str]:
    """Common English words, from the English word-frequency list the PyPI package
    pyspellchecker ships (read where it is installed): a correctly spelled word is never a typo,
    so "sitting" is not read as "cutting". The words are picked once per machine and kept in
    sg3d's cache (`core.cache`; reading the list's JSON takes 0.1 s), named by a hash of the list
    and COMMON_WORD_MIN_COUNT."""
    import hashlib
    from importlib import resources

    from sg3d.core.cache import writable_cache_folder, write_atomically

    raw = (resources.files("spellchecker") / "resources" / "en.json.gz").read_bytes()
    key = hashlib.sha1(raw + f"\n{COMMON_WORD_MIN_COUNT}".encode()).hexdigest()[:12]
    folder = writable_cache_folder()
    kept = folder / f"common-words-{key}.txt" if folder else None
    if kept is not None and kept.is_file():
        return frozenset(kept.read_text().split())
    words = pick_common_words(raw)
    if kept is not None:
        write_atomically(kept, "".join(f"{w}\n" for w in sorted(words)).encode())
    return words


def pick_common_words(raw: bytes) -> frozenset[str]:
    """The common words of pyspellchecker's gzipped JSON word-frequency list `raw`."""
    import gzip
    import json

    counts = json.loads(gzip.decompress(raw))
    return frozenset(w for w, n in counts.items() if n >= COMMON_WORD_MIN_COUNT and w.isascii() and w.isalpha())


def is_word(word: str, vocab: frozenset) -> bool:
    """A word the typo fixer leaves alone: in `vocab`, a common English word, or a number."""
    return word in vocab or word in common_words() or any(c.isdigit() for c in word)


# the question words: a short unknown word one edit from exactly one of them is that word ("hw",
# "wher", "waht"), before any longer vocabulary word is tried
QUESTION_WORDS = frozenset({"what", "where", "which", "how", "many", "much", "who", "whose", "why", "when"})


def _question_word(word: str, after: str | None = None) -> str | None:
    """The one question word `word` is a typo of; between two, "how" before "many"/"much"
    ("hwo many"), else the one reached by adding or dropping a letter ("wher": where, not when)."""
    from rapidfuzz.distance import DamerauLevenshtein, Indel

    if len(word) < 2 or len(word) > 6:
        return None
    hits = sorted(q for q in QUESTION_WORDS if DamerauLevenshtein.distance(word, q) <= 1)
    if len(hits) > 1 and after in ("many", "much") and "how" in hits:
        return "how"
    if len(hits) > 1:
        best = min(Indel.distance(word, q) for q in hits)
        hits = [q for q in hits if Indel.distance(word, q) == best]
    return hits[0] if len(hits) == 1 else None


# after these a noun is said: an unknown word there that is as close to a noun as to another word
# is the noun ("the refrigerater": refrigerator, not refrigerate)
DETERMINERS = frozenset({"the", "a", "an", "any", "my", "this", "that", "these", "those", "your", "our", "some",
                         "no", "each", "every"})


def fix_typos(text: str, vocab: frozenset, known: Iterable[str] = (),
              nouns: frozenset = frozenset()) -> tuple[str, list[str]]:
    """Each unknown word (outside `vocab`, not a common English word, not a number) that is
    one edit from exactly one question word (QUESTION_WORDS), or else within `max_edits` of
    exactly one vocabulary word, is read as that word; the notes say so. After a determiner
    (DETERMINERS), a tie is settled by the object nouns `nouns` (one of them closest), and a
    three-letter word may be a noun with a letter left out ("every dsk": `dropped_letter`). A
    tie left is settled by the word reached by adding or dropping letters ("colr": color, not
    cold)."""
    keep = set(known)
    out, notes = [], []
    words = text.split()
    for i, w in enumerate(words):
        if w in keep or is_word(w, vocab):
            out.append(w)
            continue
        fixed = _question_word(w, words[i + 1] if i + 1 < len(words) else None) or _closest(w, vocab)
        if fixed is None and nouns and i > 0 and words[i - 1] in DETERMINERS:
            fixed = _closest(w, nouns) or dropped_letter(w, nouns)
        if fixed is None:
            fixed = _closest(w, vocab, dropped_first=True)
        if fixed is None:
            out.append(w)
        else:
            out.append(fixed)
            notes.append(f"read '{w}' as '{fixed}'")
    return " ".join(out), notes


def typo_vocabulary() -> frozenset:
    """Every word a question may use: the grammar's, the object nouns (singular and plural),
    colours, sizes, shapes, structure, affordance verbs and common question words."""
    return _vocabulary()


@functools.cache
def typo_nouns() -> frozenset:
    """The object nouns of the vocabulary (singular and plural): what a typo after "the" is read as
    when it is as close to another word (reader.typos.fix_typos)."""
    import json

    from sg3d.queries.lexicon import SYNONYMS, vocabulary
    from sg3d.queries.taxonomy import Taxonomy
    from sg3d.queries.answer.wording import plural

    nouns = set(vocabulary()) | set(Taxonomy.load().names)
    data = json.loads(SYNONYMS.read_text())
    nouns |= set(data["words"]) | set(data["any"])
    out = {n for n in nouns if n and " " not in n}
    return frozenset(out | {plural(n) for n in out})


@functools.cache
def _vocabulary() -> frozenset:
    import json

    from sg3d.core.model import SHAPE_WORDS
    from sg3d.queries.reader.data import lexicon_file
    from sg3d.queries.reader.grammar import RESERVED
    from sg3d.queries.vocabulary import (
        AFFORDANCE_VERBS, COLOURS, EVERYWHERE, EXTRA_AFFORDANCES, GENERIC, SIZES, STRUCTURE_LABELS)
    from sg3d.queries.answer.wording import plural
    from sg3d.queries.lexicon import SYNONYMS, vocabulary
    from sg3d.queries.taxonomy import Taxonomy

    words: set[str] = set(RESERVED) | set(COLOURS) | set(SIZES) | set(SHAPE_WORDS)
    words |= set(STRUCTURE_LABELS) | GENERIC | {w for x in EVERYWHERE for w in x.split()}
    words |= {w for k in list(AFFORDANCE_VERBS) + list(EXTRA_AFFORDANCES) for w in k.split()}
    words |= {"please", "tell", "know", "could", "would", "should", "me", "us", "find", "put", "my",
              "cup", "does", "kitchen", "bedroom", "bathroom", "office", "living", "dining", "objects",
              "things", "items", "walls", "shelves", "surfaces", "counters", "color", "colors", "whats",
              "everything", "total", "type", "types", "kind", "kinds", "piece", "pieces", "sort",
              "sorts", "ones", "visible", "present", "stored", "there", "up", "down", "yes", "no",
              "left", "right", "front", "behind", "seen", "as", "bigger", "smaller", "larger", "altogether",
              "currently", "one", "that", "here",
              "size", "sizes", "hello", "thanks", "thank", "get", "where", "on", "top", "something"}
    words |= set(lexicon_file()["typo_common_words"])
    nouns = set(vocabulary()) | set(Taxonomy.load().names)
    data = json.loads(SYNONYMS.read_text())
    nouns |= set(data["words"]) | set(data["any"])
    for n in nouns:
        parts = n.split()
        words |= set(parts)
        if parts:
            words.add(plural(parts[-1]))
    return frozenset(w for w in words if w)
