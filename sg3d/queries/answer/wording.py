"""Words of an answer: plurals, articles, and names that need not repeat their place."""
from __future__ import annotations


def plural(label: str, n: int = 2) -> str:
    if n == 1:
        return label
    irregular = {"knife": "knives", "shelf": "shelves", "person": "people", "mouse": "mice", "skis": "skis",
                 "scissors": "scissors", "sheep": "sheep", "cutlery": "cutlery", "furniture": "pieces of furniture",
                 "electronics": "electronics", "food": "food items", "tableware": "tableware items"}
    if label in irregular:
        return irregular[label]
    if label.endswith(("s", "x", "ch", "sh")):
        return label + "es"
    return label + "s"


def the(name: str) -> str:
    """A name with its article: "the white cup", but "chair 2" (a numbered name stands alone)."""
    return name if name[-1:].isdigit() else f"the {name}"


def without_place(name: str, said: str) -> str:
    """"brown cup on the dining table" -> "brown cup" when the sentence goes on to say "on the
    dining table": a name that tells objects apart by their support need not say it twice."""
    for word in (" on the ", " in the ", " under the ", " next to the "):
        i = name.find(word)
        if i > 0 and said.startswith(name[i + 1:]):
            return name[:i]
    return name
