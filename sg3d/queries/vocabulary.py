"""The words of questions, written once: relations, colours, sizes, extremes, units, affordances,
scope words, row limits and the examples a refusal offers.

The grammar (sg3d/queries/grammar.py) builds its relation rule from `RELATIONS`; the sets
(sg3d/queries/sets.py), the per-form templates (sg3d/queries/vqa.py) and the answers read the
same tables, so a word the grammar reads is a word every answer knows.
"""
from __future__ import annotations

from sg3d.core.model import COLOUR_NAMES

# relation words -> (relation type, symmetric?). Types are a fixed whitelist (templates render
# them, sg3d/graphdb/cypher.py); IN_FRONT_OF, BEHIND, LEFT_OF and RIGHT_OF are never stored: they
# are computed from a viewpoint when asked (sg3d/queries/viewpoint.py).
RELATIONS: dict[str, tuple[str, bool]] = {
    "on": ("ON", False), "on top of": ("ON", False), "onto": ("ON", False),
    "in": ("IN", False), "inside": ("IN", False),
    "under": ("UNDER", False), "underneath": ("UNDER", False), "beneath": ("UNDER", False),
    "below": ("BELOW", False), "above": ("ABOVE", False), "over": ("ABOVE", False),
    "next to": ("NEXT_TO", True), "beside": ("NEXT_TO", True), "by": ("NEXT_TO", True),
    "adjacent to": ("NEXT_TO", True), "alongside": ("NEXT_TO", True),
    "near": ("NEAR", True), "close to": ("NEAR", True), "nearby": ("NEAR", True), "around": ("NEAR", True),
    "in front of": ("IN_FRONT_OF", False), "behind": ("BEHIND", False),
    "left of": ("LEFT_OF", False), "right of": ("RIGHT_OF", False),   # "to the left of": phrasing.py
}
# the stored relation types a set filter reads (the viewpoint ones are computed, never read)
STORED_TYPES = ("ON", "IN", "UNDER", "ABOVE", "BELOW", "NEXT_TO", "NEAR")
# A stored pair is either NEXT_TO or NEAR (one statement per pair): "next to" is the closer form
# of "near", so a question about what is near (around, close to) X also means what is next to it.
# Likewise UNDER (covered by the thing above) and BELOW (air between) are the graph's two kinds of
# beneath, and people say "under" and "below" for either: each word asks for both.
IMPLIED_BY: dict[str, tuple[str, ...]] = {"NEAR": ("NEAR", "NEXT_TO"), "UNDER": ("UNDER", "BELOW"),
                                          "BELOW": ("BELOW", "UNDER")}
# Stored edges that say the same read from the other end: "the chair is above the desk" also
# when the graph stores desk -UNDER-> chair (or -BELOW->); "X is under Y" when Y -ABOVE-> X. An
# answer reads a relation both ways, never reversing one (X -ON-> Y is never "Y is on X").
INVERSE: dict[str, tuple[str, ...]] = {"ABOVE": ("UNDER", "BELOW"), "UNDER": ("ABOVE",), "BELOW": ("ABOVE",)}
# how an answer says a stored relation
REL_WORDS = {"ON": "on", "IN": "in", "UNDER": "under", "BELOW": "below", "ABOVE": "above",
             "NEXT_TO": "next to", "NEAR": "near"}

COLOURS = {c: c for c in COLOUR_NAMES} | {"gray": "grey", "silver": "grey", "golden": "yellow"}
SIZES = {"big": "big", "large": "big", "huge": "big", "small": "small", "little": "small", "tiny": "small"}
SUPERLATIVES = {   # word -> (key, sign): key volume | height (box height) | top (height above floor)
    "biggest": ("volume", 1), "largest": ("volume", 1), "smallest": ("volume", -1),
    "tiniest": ("volume", -1), "tallest": ("height", 1), "shortest": ("height", -1),
    "highest": ("top", 1), "lowest": ("top", -1),
}
DISTANCE_SUPERLATIVES = {"closest": -1, "nearest": -1, "farthest": 1, "furthest": 1}
UNIT_M = {"m": 1.0, "cm": 0.01, "mm": 0.001, "ft": 0.3048, "inch": 0.0254}
ATTRIBUTES = {"big": "size", "large": "size", "tall": "tall", "high": "high", "wide": "width", "deep": "depth",
              "long": "length", "far": "far"}

# words that change what a sentence asks (negation, exclusion, "only"): never ignored beside a
# noun, as a colour-less "plain" may be; a question holding one where no rule reads it is refused
# naming it ("which rooms have no fridge" is never answered as "which rooms have a fridge")
NEVER_IGNORED = frozenset({"no", "not", "none", "never", "nor", "neither", "without", "except", "only", "non",
                           "nothing", "excluding", "but", "besides", "lacking"})

STRUCTURE_LABELS = {"floor": "floor", "ground": "floor", "wall": "wall", "counter": "counter",
                    "countertop": "counter", "worktop": "counter", "shelf": "shelf", "surface": "surface",
                    "window": "window"}
GENERIC = {"object", "thing", "item", "stuff", "everything", "something", "anything", "somewhere",
           "anywhere", "place", "spot"}
# "in the house": the whole store (or --building), not a room or an object
EVERYWHERE = {"house", "home", "building", "environment", "scene", "world", "map", "whole house",
              "whole building", "whole home", "total", "everywhere"}

# words that name a room or the home (never furniture): "where can I sit in this kitchen" scopes
# the activity to that place (sg3d/queries/phrasing.py)
ROOM_WORDS = ("kitchen", "study", "living room", "livingroom", "lounge", "sitting room", "dining room", "bedroom",
              "bathroom", "office", "hall", "hallway", "den", "house", "home", "flat", "apartment", "building")

# What a person may do -> the kinds of object that afford it: ONE curated table. Each activity
# lists the stored labels (detector classes and the furniture sg3d names from its shape: desk,
# cabinet, couch, counter, shelf, whichever layer holds them) and the words that ask for it.
ACTIVITIES: dict[str, list[str]] = {
    "sit": ["chair", "couch", "sofa", "bench", "stool", "bed"],
    "drink": ["cup", "mug", "wine glass", "glass", "bottle"],
    "put things down": ["dining table", "table", "desk", "counter", "shelf", "cabinet", "sideboard"],
    "store things": ["cabinet", "shelf", "drawer", "sideboard", "refrigerator"],
    "keep things cold": ["refrigerator"],
    "work": ["desk", "dining table", "table"],
}
# how an answer names an activity a set is for: "4 pieces of furniture for sitting"
GERUNDS = {"sit": "sitting", "drink": "drinking", "put things down": "putting things down",
           "store things": "storing things", "work": "working", "keep things cold": "keeping things cold"}
# the words that ask for an activity ("where can I <verb>", "something to <verb>",
# "furniture for <verb>ing") -> the activity
AFFORDANCE_VERBS: dict[str, str] = {
    "sit": "sit", "sit down": "sit", "sit on": "sit", "sitting": "sit", "seat": "sit", "seating": "sit", "take a seat": "sit",
    "drink": "drink", "drink from": "drink", "drinking": "drink", "drink out": "drink", "drink out of": "drink",
    "have a drink": "drink", "get a drink": "drink", "pour": "drink", "pour water into": "drink",
    "pour water in": "drink", "pour something into": "drink", "pour into": "drink", "pouring": "drink",
    "put": "put things down", "put things down": "put things down", "put something down": "put things down",
    "put things": "put things down", "put something": "put things down", "place": "put things down",
    "place things": "put things down", "set down": "put things down", "place down": "put things down",
    "leave": "put things down", "set": "put things down", "set things down": "put things down",
    "put my cup down": "put things down", "put down": "put things down", "putting things down": "put things down",
    "put away": "store things", "put things away": "store things", "tidy away": "store things",
    "store": "store things", "store things": "store things", "store something": "store things",
    "storing": "store things", "storage": "store things", "keep things": "store things", "keep": "store things",
    "work": "work", "work at": "work", "working": "work", "working at": "work", "work on": "work",
    "do some work": "work", "do work": "work", "do my work": "work", "do homework": "work",
    "do my homework": "work", "study": "work", "use my laptop": "work", "use a laptop": "work",
    "use the laptop": "work", "get some work done": "work", "get work done": "work",
    "keep cold": "keep things cold", "keep things cold": "keep things cold", "chill": "keep things cold",
    "cool": "keep things cold", "refrigerate": "keep things cold", "freeze": "keep things cold",
    "keep cool": "keep things cold", "keep fresh": "keep things cold",
}
# The words of an activity phrase that say how or where (kept, to be matched with the verb:
# "keep food cold" asks for "keep cold", never for "keep"); the other words after the verb name
# what is handled ("my cup", "water", "food") and change nothing the table answers.
AFFORDANCE_PARTICLES = {"down", "on", "in", "into", "at", "from", "up", "away", "off", "out", "cold", "cool",
                        "fresh", "warm", "hot", "dry", "clean", "safe", "frozen", "a", "seat", "to", "with"}
# words of an activity phrase that name nothing (never a reason to refuse)
AFFORDANCE_FILLER = {"my", "the", "a", "an", "some", "any", "this", "that", "these", "those", "our", "your", "it",
                     "them", "things", "something", "stuff", "anything"}
# verbs that name no activity of the table but were in the older table (kept: asked and answered)
EXTRA_AFFORDANCES: dict[str, list[str]] = {
    "lie down": ["bed", "couch", "sofa"], "sleep": ["bed", "couch", "sofa"], "eat": ["dining table"],
    # "a couch I could lie on", "where can I rest / have a nap": what one lies on (never a chair)
    "lie": ["bed", "couch", "sofa"], "lay down": ["bed", "couch", "sofa"], "rest": ["bed", "couch", "sofa"],
    "nap": ["bed", "couch", "sofa"], "snooze": ["bed", "couch", "sofa"], "stretch out": ["bed", "couch", "sofa"],
    "wash": ["sink"], "watch": ["tv"], "read": ["book"], "cook": ["oven", "microwave"],
}

MAX_QUESTION = 500     # characters; longer text is refused before any reading
PROVENANCE_MAX = 50    # objects whose provenance an answer carries (a count of more names none)
ROW_LIMIT = 100_000    # rows fetched for listing/size filtering; counts without size use count()
LIST_SHOWN = 12        # objects named in a one-line answer
ABSENT = "small or uncommon things may be missed"

# one example per kind of question; a refusal offers the one closest to what was asked
EXAMPLES = [
    "how many cups are there?", "how many chairs are in the room?", "how many red chairs are there?",
    "how many cups or mugs are on the table?", "how many pieces of furniture are there?",
    "is there a sink?", "is the cup on the table?", "what is on the table?", "what is next to the sink?",
    "what objects are in the kitchen?", "what colour is the couch?", "how big is the table?",
    "which cup is the biggest?", "show me the cup closest to the sink", "where is the keyboard?",
    "which rooms have a chair?", "how far is the cup from the sink?", "where can I sit?",
]


def example_for(question: str) -> str:
    """The example question closest to `question` (shared words first, then spelling)."""
    import difflib
    import re

    def words(text: str) -> set[str]:
        return set(re.sub(r"[^a-z0-9 ]+", " ", text.lower()).split())

    asked = words(question)
    return max(EXAMPLES, key=lambda e: (len(asked & words(e)),
                                        difflib.SequenceMatcher(None, question.lower(), e).ratio()))


def refusal(why: str, question: str) -> str:
    """One short line: what was not understood, and one example close to the question."""
    return f"{why}; try e.g. \"{example_for(question)}\""
