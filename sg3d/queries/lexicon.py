"""Nouns -> COCO classes: lemmas, the synonym table, the taxonomy, then the label embedding.

Order matters for speed and safety: the table and the taxonomy answer known words without
loading the sentence-transformer (cold CLI < 2 s); the embedding is only a fallback for an
unknown noun, and it refuses rather than guess (see `EMBED_THRESHOLD`).
"""
from __future__ import annotations

import functools
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from sg3d.core.model import COLOUR_NAMES
from sg3d.queries.taxonomy import Taxonomy
from sg3d.queries.vocabulary import NEVER_IGNORED

SYNONYMS = Path(__file__).resolve().parent / "data" / "synonyms.json"
# Household nouns (singular): a word here is a real object name, so when it maps to no stored
# category the answer is "0 <word>s", not a refusal. The same list is the shipped-vector
# vocabulary (core/data/label_vectors.*, scripts/make_label_vectors.py).
VOCABULARY = Path(__file__).resolve().parent / "data" / "household_nouns.txt"

# Cosine threshold for the embedding fallback (all-MiniLM-L6-v2). Measured on household nouns:
# right mappings scored 0.71-0.96 (mug->cup 0.71, armchair->chair 0.73, sofa->couch 0.86,
# fridge->refrigerator 0.96), while the best WRONG candidates stayed at or below 0.68
# (stool->toilet 0.67, stove->oven 0.68, spaceship->boat 0.60, freezer->refrigerator 0.64).
# 0.70 sits above the wrong ones; the margin rule also refuses a noun that is about as close
# to two different targets (it is then ambiguous, e.g. a hypernym like "fruit").
EMBED_THRESHOLD = 0.70
EMBED_MARGIN = 0.05

IRREGULAR = {
    "knives": "knife", "people": "person", "men": "man", "women": "woman", "mice": "mouse",
    "skis": "skis", "scissors": "scissors", "glasses": "glass", "benches": "bench",
    "couches": "couch", "sandwiches": "sandwich", "toothbrushes": "toothbrush", "dishes": "dish",
    "buses": "bus", "shelves": "shelf", "leaves": "leaf", "sheep": "sheep", "electronics": "electronics",
    "pieces": "piece", "series": "series", "species": "species", "furniture": "furniture",
    "cutlery": "cutlery", "tableware": "tableware", "kitchenware": "kitchenware", "food": "food",
    "stuff": "stuff", "tv": "tv", "tvs": "tv", "glass": "glass", "bus": "bus", "canvas": "canvas",
}


# Words that may stand before a known head noun without changing what it is ("dining furniture",
# "wooden chairs"): adjectives of material, state, shape, colour, size and room use. Any other
# word before a known head noun is ignored and reported ("plain white mugs" -> white cups).
MODIFIERS = frozenset(COLOUR_NAMES) | {
    "gray", "silver", "golden", "big", "large", "huge", "small", "little", "tiny",
    "dining", "kitchen", "living", "bathroom", "bedroom", "office", "garden", "outdoor", "indoor",
    "wooden", "wood", "metal", "metallic", "plastic", "ceramic", "porcelain", "paper", "leather",
    "fabric", "steel", "stainless", "empty", "full", "clean", "dirty", "used", "old", "new",
    "open", "closed", "tall", "short", "long", "round", "square", "rectangular", "flat", "dark",
    "light", "bright", "striped", "patterned", "other", "different", "individual", "separate",
    "single", "visible", "main", "extra", "spare", "whole", "entire", "various",
}


def lemma(word: str) -> str:
    """Singular of one English noun (the few rules household nouns need)."""
    w = word.lower()
    if w in IRREGULAR:
        return IRREGULAR[w]
    if len(w) > 4 and w.endswith("ies"):
        return w[:-3] + "y"
    if w.endswith(("ches", "shes", "sses", "xes", "zes")):
        return w[:-2]
    if w.endswith("ves") and len(w) > 4:
        return w[:-3] + "fe" if w[:-3].endswith("i") else w[:-3] + "f"
    if w.endswith("s") and not w.endswith(("ss", "us", "is")) and len(w) > 3:
        return w[:-1]
    return w


def lemma_phrase(phrase: str) -> str:
    """Singular of a noun phrase: its last word ("wine glasses" -> "wine glass")."""
    words = phrase.split()
    return " ".join(words[:-1] + [lemma(words[-1])]) if words else phrase


@dataclass
class Target:
    """What a noun phrase means: the object labels to match (None = every object)."""

    phrase: str
    labels: Optional[list[str]]
    names: list[str] = field(default_factory=list)   # the class or group names it resolved to
    how: str = "label"                               # label | group | synonym | embedding | any | unknown
    similarity: Optional[float] = None
    ignored: list[str] = field(default_factory=list)  # words beside the noun that were not used

    def mapping(self) -> Optional[str]:
        """How the phrase was read, for --explain ("mugs -> cup (synonym)"); None when plain."""
        if self.how == "label" and not self.ignored:
            return None
        names = " + ".join(self.names) if self.names else ("every object" if self.labels is None else "no stored category")
        why = self.how + (f" {self.similarity:.2f}" if self.similarity is not None else "")
        out = f"'{self.phrase}' -> {names} ({why})"
        return out + (f", ignored: {' '.join(self.ignored)}" if self.ignored else "")

    def describe(self) -> str:
        if self.labels is None:
            return "objects"
        return " + ".join(self.names)


@functools.cache
def vocabulary() -> frozenset[str]:
    """The shipped household nouns (singular, lower case)."""
    if not VOCABULARY.exists():
        return frozenset()
    return frozenset(w.strip() for w in VOCABULARY.read_text().splitlines() if w.strip() and not w.startswith("#"))


def real_noun(phrase: str) -> Optional[str]:
    """The singular noun a phrase names when it is a known household word (the whole phrase, or
    its last word), else None."""
    vocab = vocabulary()
    for p in (lemma_phrase(phrase), phrase):
        if p in vocab:
            return p
    last = lemma(phrase.split()[-1]) if phrase.split() else ""
    return last if last in vocab else None


@functools.cache
def _synonyms() -> tuple[frozenset, dict[str, list[str]]]:
    data = json.loads(SYNONYMS.read_text())
    return frozenset(data["any"]), {k: list(v) for k, v in data["words"].items()}


def _labels_of(names: list[str]) -> list[str]:
    tax = Taxonomy.load()
    out: set[str] = set()
    for n in names:
        out |= tax.labels_under(n) if n in tax.groups else {n}
    return sorted(out)


def known(phrase: str) -> Optional[Target]:
    """Resolve without the embedding: the table, the class names, the group names."""
    any_words, words = _synonyms()
    tax = Taxonomy.load()
    for p in dict.fromkeys([phrase, lemma_phrase(phrase)]):
        if p in any_words:
            return Target(phrase, None, [], "any")
        if p in tax.leaves:
            return Target(phrase, [p], [p], "label")
        if p in tax.groups:
            return Target(phrase, _labels_of([p]), [p], "group")
        if p in words:
            return Target(phrase, _labels_of(words[p]), list(words[p]), "synonym")
    return None


def _candidates() -> dict[str, tuple[str, ...]]:
    """Every string the embedding may match, and the names it stands for."""
    _, words = _synonyms()
    tax = Taxonomy.load()
    out: dict[str, tuple[str, ...]] = {n: (n,) for n in tax.names if n != tax.root}
    for k, v in words.items():
        # one-word synonyms only: "coffee mug" would pull "coffee machine" to cup by its modifier
        if " " not in k:
            out.setdefault(k, tuple(v))
    return out


def by_embedding(phrase: str, embedding=None) -> tuple[Optional[Target], list[tuple[str, float]]]:
    """The nearest known name if it is close enough and unambiguous; else None (+ the top 3)."""
    if embedding is None:
        from sg3d.core.embedding import default_embedding

        embedding = default_embedding()
    import numpy as np

    cands = _candidates()
    keys = sorted(cands)
    vec = embedding.vectors(keys + [lemma_phrase(phrase)])
    q = vec[lemma_phrase(phrase)]
    sims = np.array([float(np.dot(vec[k], q)) for k in keys])
    order = np.argsort(-sims)
    best = keys[order[0]]
    top = [(keys[i], round(float(sims[i]), 2)) for i in order[:3]]
    runner_up = next((sims[i] for i in order[1:] if cands[keys[i]] != cands[best]
                      and not set(_labels_of(list(cands[keys[i]]))) <= set(_labels_of(list(cands[best])))), 0.0)
    if sims[order[0]] < EMBED_THRESHOLD or sims[order[0]] - runner_up < EMBED_MARGIN:
        return None, top
    names = list(cands[best])
    return Target(phrase, _labels_of(names), names, "embedding", round(float(sims[order[0]]), 3)), top


def head_noun(phrase: str) -> tuple[Optional[Target], str]:
    """An unknown multi-word phrase that contains a known name: (Target of the known head noun,
    '') when every word before it is a modifier; (None, why) when other words make the reading
    doubtful; (None, '') when it contains no known name (the embedding may then try it whole,
    which must not happen to a phrase holding a known word: it would be pulled by its parts)."""
    words = phrase.split()
    for i in range(1, len(words)):
        head = known(" ".join(words[i:]))
        if head is not None:
            others = [w for w in words[:i] if w not in MODIFIERS]
            kept = [w for w in others if w in NEVER_IGNORED]
            if kept:
                return None, f"I could not read '{kept[0]}' in '{phrase}'"
            if any(known(w) is not None for w in others):
                return None, f"'{phrase}' names more than one kind of object"
            if others and lemma_phrase(phrase) in vocabulary():
                return None, ""     # a compound noun of its own ("coffee table"): not its head
            # words before a known head noun describe it ("plain white mugs"): kept out of the
            # query and reported, rather than refusing the question
            return Target(phrase, head.labels, head.names, head.how, ignored=others), ""
    for i in range(len(words)):
        for j in range(len(words), i, -1):
            part = " ".join(words[i:j])
            if (j - i) < len(words) and known(part) is not None:
                return None, (f"I am not sure what '{phrase}' means: it holds the known '{part}' "
                              f"with other words")
    return None, ""


def unknown_real(phrase: str, noun: str) -> Target:
    """A real household object no stored category covers: it matches nothing (labels [])."""
    return Target(phrase, [], [noun], "unknown")


def resolve(phrase: str, embedding=None, use_embedding: bool = True):
    """(Target or None, why-not text): the synonym table and taxonomy, a known head noun, then
    the label embedding; a household word that maps to no category is an `unknown_real` target
    (it answers "0 ..."), any other word is not understood."""
    phrase = " ".join(phrase.split())
    if not phrase:
        return None, "no object named"
    hit = known(phrase)
    if hit is None and " " in phrase:
        hit, doubt = head_noun(phrase)
        if doubt:
            # "cup holder": a known word inside another noun; a household noun is then its own thing
            noun = real_noun(phrase)
            if noun and known(noun) is None:
                return unknown_real(phrase, noun), ""
            return None, doubt
    if hit is not None:
        return hit, ""
    noun = real_noun(phrase)
    if not use_embedding:
        return (unknown_real(phrase, noun), "") if noun else (None, f"unknown word '{phrase}'")
    hit, top = by_embedding(phrase, embedding)
    if hit is None:
        if noun:
            return unknown_real(phrase, noun), ""
        return None, f"I do not know the word '{phrase}'"
    return hit, ""
