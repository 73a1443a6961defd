"""A third held-out set of ordinary users' questions about the three rooms, judged like benchmarks.paraphrases.

    python -m benchmarks.paraphrases_heldout3 [--keep-home DIR | --home DIR] [--json]

benchmarks/paraphrases.py, benchmarks/paraphrases_heldout.py and benchmarks/paraphrases_heldout2.py
have all been seen while the question reader was worked on, so none of them measures any longer
how the reader copes with questions nobody has tuned it on. These 160 questions (kitchen 57,
living room 39, study 48, whole building 16) are new: written blind, without reading the
reader's code, grammar, vocabulary or tests and without reading any earlier set's questions
(only the README, the judging rules of benchmarks/paraphrases.md and the oracle helpers of the
earlier modules), from the brief of forms (counting, existence, attributes, where-is, relations,
distance, size, negation and quantity, rooms by content, attribute-only sets, "a X"/"the X",
indirect frames and possessives, affordances, positions of all of a kind) and from what the
built rooms hold (their stored objects and edges, dumped through the oracle's own World.load),
as different people would ask a home robot: terse, chatty, non-native, with synonyms (mug,
telly, fridge, monitor, sofa, couch, armchair, bin) and seven typos ("were", "kichen",
"refrigerater", "Wich", "frigde", "cabniet", "chiars"). They were written once and run once; no
question was changed after its answer was seen. Do not tune the reader on them, or they stop
being held out.

Everything else is benchmarks.paraphrases': the rooms and store, the oracle helpers over the
stored graph (no expected answer is typed in), the judging of an answer (right / wrong /
refused) and the table; `footprint` and `rooms_without` come from
benchmarks.paraphrases_heldout2, `pick_smaller` from benchmarks.paraphrases_heldout. Added
oracles: `anywhere` (yes iff some room of the building holds one of a kind, or none does) and
`rooms_over` (the rooms holding more than N of a kind). A question that names its room in words
is asked of the whole building (no --room), as in the earlier sets.
benchmarks/paraphrases.md ("Third held-out set") describes the set and its last result.
"""
from __future__ import annotations


from benchmarks.paraphrases import (
    arguments, ask_set, report,
    CABINET, CHAIRS, COL, COUNTER, CUPS, DESKS, DRINKABLE, FRIDGE, NOT_COLOUR, NOT_LABEL, PUT_PLACES,
    SHELVES, SINK, SITTABLE, STORE_PLACES, TABLE, THINGS, TVS, WORK_PLACES, L, Oracle, Q, S, Truth, _q, afford,
    bigger, colour_of, count, dims, distance, exists, measure, none_of, objects, pick_bigger, quantity, rel,
    room_count, room_extreme, room_total, rooms_fewest, rooms_with, total_count, where, where_all,
)
from benchmarks.paraphrases_heldout import pick_smaller
from benchmarks.paraphrases_heldout2 import footprint, rooms_without

BOOKS = L("book")
WHITE_BOOK, PURPLE_BOOK = L("book", colour="white"), L("book", colour="purple")
GREY_CUP, WHITE_CUPS = L("cup", colour="grey"), L("cup", colour="white")
COUCHES = L("couch", "sofa")
BLUE_OBJECT = L("object", colour="blue")
ON_TABLE = rel(THINGS, "on", TABLE)
ON_CABINET = rel(THINGS, "on", CABINET)
NEXT_TO_FRIDGE = rel(THINGS, "next to", FRIDGE)


def anywhere(xs: S, want: bool = True) -> tuple[Oracle, str]:
    """Yes iff some room of the building holds one of `xs` (want=False: iff no room does)."""
    def fn(w, r) -> Truth:
        return Truth("yesno", any(xs(room) for room in w.rooms.values()) == want)
    return fn, ("yes iff some room holds any " if want else "yes iff no room holds any ") + xs.desc


def rooms_over(xs: S, n: int) -> tuple[Oracle, str]:
    """The rooms holding more than n of `xs`."""
    def fn(w, r) -> Truth:
        return Truth("rooms", {name for name, room in w.rooms.items() if len(xs(room)) > n})
    return fn, f"the rooms holding more than {n} of {xs.desc}"


def questions() -> list[Q]:
    K, LR, ST, B = "kitchen", "livingroom", "study", "building"
    return [
        # ----------------------------------------------------------------- kitchen (57)
        _q(K, "count", "how many chairs?", count(CHAIRS)),
        _q(K, "count", "How many mugs are there in here?", count(CUPS)),
        _q(K, "count", "How much books is in this kitchen?", count(BOOKS), None),
        _q(K, "count", "how many things are sitting on the table right now?", count(ON_TABLE)),
        _q(K, "exists", "is there a fridge?", exists(FRIDGE)),
        _q(K, "exists", "Do we have a microwave in the kitchen?", exists(L("microwave")), None),
        _q(K, "exists", "I need to wash my hands - is there a sink in here?", exists(SINK)),
        _q(K, "exists", "is there a bin somewhere?", exists(L("bin", "trash can", "waste bin", "garbage can"))),
        _q(K, "attribute", "what colour is the sink", colour_of(SINK)),
        _q(K, "attribute", "What color are the chairs?", colour_of(CHAIRS)),
        _q(K, "attribute", "What's the height of the table?", measure(TABLE, "height")),
        _q(K, "attribute", "how long is the dining table?", measure(TABLE, "length")),
        _q(K, "attribute", "how big is the grey cup?", dims(GREY_CUP)),
        _q(K, "where", "where's the sink?", where(SINK)),
        _q(K, "where", "Where did I leave the purple book?", where(PURPLE_BOOK)),
        _q(K, "where", "were is the grey mug?", where(GREY_CUP)),
        _q(K, "where", "the blue thing, where is it?", where(COL("blue"))),
        _q(K, "relation", "What's on the counter?", objects(rel(THINGS, "on", COUNTER))),
        _q(K, "relation", "what is on the shelves?", objects(rel(THINGS, "on", SHELVES))),
        _q(K, "relation", "what's next to the white book?", objects(rel(THINGS, "next to", WHITE_BOOK))),
        _q(K, "relation", "Is the purple book next to a chair?", exists(rel(PURPLE_BOOK, "next to", CHAIRS))),
        _q(K, "relation", "Is anything under the table?", exists(rel(THINGS, "under", TABLE))),
        _q(K, "relation", "What is near the sink?", objects(rel(THINGS, "near", SINK))),
        _q(K, "distance", "how far apart are the two books?", distance(BOOKS)),
        _q(K, "distance", "distance between the two TVs", distance(TVS)),
        _q(K, "distance", "How far is the sink from the dining table?", distance(SINK, TABLE)),
        _q(K, "size", "is the table bigger than the sink?", bigger(TABLE, SINK)),
        _q(K, "size", "Which is bigger: the white book or the purple book?", pick_bigger(WHITE_BOOK, PURPLE_BOOK)),
        _q(K, "size", "is the grey cup smaller than the white book?", bigger(GREY_CUP, WHITE_BOOK, smaller=True)),
        _q(K, "size", "which one is larger, the sink or the grey mug?", pick_bigger(SINK, GREY_CUP)),
        _q(K, "negation", "Is there anything on the table besides the cups?", exists(NOT_LABEL(ON_TABLE, "cup"))),
        _q(K, "negation", "anything on the table other than books and cups?", exists(NOT_LABEL(ON_TABLE, "cup", "book"))),
        _q(K, "negation", "Are there at least four chairs?", quantity(CHAIRS, ">=", 4)),
        _q(K, "negation", "more than three mugs in here?", quantity(CUPS, ">", 3)),
        _q(K, "negation", "Exactly two TVs in the kitchen, right?", quantity(TVS, "==", 2), None),
        _q(K, "negation", "Is it true there's no fridge in here?", none_of(FRIDGE)),
        _q(K, "negation", "is there anything on the counter that isn't white?",
           exists(NOT_COLOUR(rel(THINGS, "on", COUNTER), "white"))),
        _q(K, "attr_set", "what is red?", objects(COL("red"))),
        _q(K, "attr_set", "Which things in here are purple?", objects(COL("purple"))),
        _q(K, "attr_set", "show me everything black", objects(COL("black"))),
        _q(K, "attr_set", "anything blue?", exists(COL("blue"))),
        _q(K, "article", "Is there a cup on the table?", exists(rel(CUPS, "on", TABLE))),
        _q(K, "article", "Is a chair next to the sink?", exists(rel(CHAIRS, "next to", SINK))),
        _q(K, "article", "What colour is the cup on the shelf?", colour_of(rel(CUPS, "on", SHELVES))),
        _q(K, "article", "where is the TV that's on the shelf?", where(rel(TVS, "on", SHELVES))),
        _q(K, "indirect", "Could you tell me how many chairs the kitchen has?", count(CHAIRS), None),
        _q(K, "indirect", "I'd like to know what is on the dining table, please.", objects(ON_TABLE)),
        _q(K, "indirect", "Please tell me the colour of the kitchen's table.", colour_of(TABLE), None),
        _q(K, "indirect", "tell me where the sink is", where(SINK)),
        _q(K, "indirect", "Would you mind counting the cups in the kichen?", count(CUPS), None),
        _q(K, "affordance", "where can I sit down?", afford(SITTABLE, SITTABLE, "one")),
        _q(K, "affordance", "I'm thirsty, what could I drink from?", afford(DRINKABLE, DRINKABLE, "one")),
        _q(K, "affordance", "where can i put my shopping bags down?", afford(PUT_PLACES, PUT_PLACES, "one")),
        _q(K, "affordance", "Where could I store some plates?", afford(STORE_PLACES, STORE_PLACES, "one")),
        _q(K, "where_all", "where are all the chairs?", where_all(CHAIRS)),
        _q(K, "where_all", "Where are the cups?", where_all(CUPS)),
        _q(K, "where_all", "where are the two books?", where_all(BOOKS)),

        # ----------------------------------------------------------------- living room (39)
        _q(LR, "count", "how many armchairs?", count(CHAIRS)),
        _q(LR, "count", "How many white things are in here?", count(COL("white"))),
        _q(LR, "count", "how many objects does the living room have?", count(THINGS), None),
        _q(LR, "exists", "is there a sofa?", exists(COUCHES)),
        _q(LR, "exists", "Got a telly in here?", exists(TVS)),
        _q(LR, "attribute", "what colour is the armchair?", colour_of(CHAIRS)),
        _q(LR, "attribute", "Which colour has the cabinet?", colour_of(CABINET)),
        _q(LR, "attribute", "how tall is the cabinet?", measure(CABINET, "height")),
        _q(LR, "attribute", "how wide is the TV?", footprint(TVS, "width")),
        _q(LR, "where", "where's the telly?", where(TVS)),
        _q(LR, "where", "the cabinet, where it is?", where(CABINET)),
        _q(LR, "relation", "what's on the cabniet?", objects(ON_CABINET)),
        _q(LR, "relation", "What's above the cabinet?", objects(rel(THINGS, "above", CABINET))),
        _q(LR, "relation", "is the chair next to the cabinet?", exists(rel(CHAIRS, "next to", CABINET))),
        _q(LR, "relation", "what's under the TV?", objects(rel(THINGS, "under", TVS))),
        _q(LR, "relation", "what is near the armchair?", objects(rel(THINGS, "near", CHAIRS))),
        _q(LR, "relation", "Is the TV on the cabinet?", exists(rel(TVS, "on", CABINET))),
        _q(LR, "distance", "how far is the chair from the tv?", distance(CHAIRS, TVS)),
        _q(LR, "distance", "What's the distance between the armchair and the cabinet?", distance(CHAIRS, CABINET)),
        _q(LR, "size", "is the chair bigger than the cabinet?", bigger(CHAIRS, CABINET)),
        _q(LR, "size", "which is bigger, the tv or the cabinet?", pick_bigger(TVS, CABINET)),
        _q(LR, "size", "Is the telly smaller than the armchair?", bigger(TVS, CHAIRS, smaller=True)),
        _q(LR, "negation", "is there anything on the cabinet besides the tv?", exists(NOT_LABEL(ON_CABINET, "tv"))),
        _q(LR, "negation", "Are there more than five white things here?", quantity(COL("white"), ">", 5)),
        _q(LR, "negation", "at least two TVs?", quantity(TVS, ">=", 2)),
        _q(LR, "negation", "Is it true that the living room has no sofa?", none_of(COUCHES), None),
        _q(LR, "attr_set", "what is white?", objects(COL("white"))),
        _q(LR, "attr_set", "anything black in here?", exists(COL("black"))),
        _q(LR, "attr_set", "which things are brown?", objects(COL("brown"))),
        _q(LR, "article", "is there a chair near the tv?", exists(rel(CHAIRS, "near", TVS))),
        _q(LR, "article", "what colour is the tv?", colour_of(TVS)),
        _q(LR, "indirect", "Can you tell me what colour the living room's cabinet is?", colour_of(CABINET), None),
        _q(LR, "indirect", "I would like to know how many chairs the living room has.", count(CHAIRS), None),
        _q(LR, "indirect", "Show me where the cabinet is, please.", where(CABINET)),
        _q(LR, "affordance", "where can I sit?", afford(SITTABLE, SITTABLE, "one")),
        _q(LR, "affordance", "Where could I keep my DVDs?", afford(STORE_PLACES, STORE_PLACES, "one")),
        _q(LR, "affordance", "where can I put my cup down?", afford(PUT_PLACES, PUT_PLACES, "one")),
        _q(LR, "affordance", "something to drink out of in here?", afford(DRINKABLE, DRINKABLE, "one")),
        _q(LR, "where_all", "where are all the chairs?", where_all(CHAIRS)),

        # ----------------------------------------------------------------- study (48)
        _q(ST, "count", "how many chairs in here?", count(CHAIRS)),
        _q(ST, "count", "How many desks does the study have?", count(DESKS), None),
        _q(ST, "count", "how many green things are there?", count(COL("green"))),
        _q(ST, "exists", "is there a laptop?", exists(L("laptop"))),
        _q(ST, "exists", "do you see a fridge in the study?", exists(FRIDGE), None),
        _q(ST, "exists", "any mugs in here?", exists(CUPS)),
        _q(ST, "exists", "is there a monitor?", exists(TVS)),
        _q(ST, "attribute", "what colour is the fridge?", colour_of(FRIDGE)),
        _q(ST, "attribute", "What colour are the desks?", colour_of(DESKS)),
        _q(ST, "attribute", "How tall is the refrigerator?", measure(FRIDGE, "height")),
        _q(ST, "attribute", "how wide is the fridge?", footprint(FRIDGE, "width")),
        _q(ST, "attribute", "the monitor, which color it has?", colour_of(TVS)),
        _q(ST, "where", "Where's the monitor?", where(TVS)),
        _q(ST, "where", "where is the blue object?", where(BLUE_OBJECT)),
        _q(ST, "where", "can u tell me where the refrigerater is", where(FRIDGE)),
        _q(ST, "relation", "what is next to the fridge?", objects(NEXT_TO_FRIDGE)),
        _q(ST, "relation", "what's under the tv?", objects(rel(THINGS, "under", TVS))),
        _q(ST, "relation", "Is any chair next to the fridge?", exists(rel(CHAIRS, "next to", FRIDGE))),
        _q(ST, "relation", "what is near the monitor?", objects(rel(THINGS, "near", TVS))),
        _q(ST, "relation", "is there something in the fridge?", exists(rel(THINGS, "in", FRIDGE))),
        _q(ST, "relation", "which desks are next to the fridge?", objects(rel(DESKS, "next to", FRIDGE))),
        _q(ST, "distance", "how far is the fridge from the tv?", distance(FRIDGE, TVS)),
        _q(ST, "distance", "How far is the telly from the closest desk?", distance(TVS, DESKS)),
        _q(ST, "distance", "how far apart are the two black objects?", distance(COL("black"))),
        _q(ST, "size", "is the fridge bigger than the telly?", bigger(FRIDGE, TVS)),
        _q(ST, "size", "which is bigger, the refrigerator or the blue object?", pick_bigger(FRIDGE, BLUE_OBJECT)),
        _q(ST, "size", "which is smaller: the monitor or the fridge?", pick_smaller(TVS, FRIDGE)),
        _q(ST, "negation", "anything next to the fridge other than chairs?", exists(NOT_LABEL(NEXT_TO_FRIDGE, "chair"))),
        _q(ST, "negation", "Is there anything under the tv that is not blue?",
           exists(NOT_COLOUR(rel(THINGS, "under", TVS), "blue"))),
        _q(ST, "negation", "are there at least three desks?", quantity(DESKS, ">=", 3)),
        _q(ST, "negation", "more than 3 chairs in the study?", quantity(CHAIRS, ">", 3), None),
        _q(ST, "negation", "is it true that there are no cups in here?", none_of(CUPS)),
        _q(ST, "attr_set", "what's green?", objects(COL("green"))),
        _q(ST, "attr_set", "which things are blue?", objects(COL("blue"))),
        _q(ST, "attr_set", "is anything red in here?", exists(COL("red"))),
        _q(ST, "article", "is there a chair next to a desk?", exists(rel(CHAIRS, "next to", DESKS))),
        _q(ST, "article", "Is the fridge next to a desk?", exists(rel(FRIDGE, "next to", DESKS))),
        _q(ST, "article", "where is the chair next to the fridge?", where(rel(CHAIRS, "next to", FRIDGE))),
        _q(ST, "indirect", "Could you please tell me how many chairs there are in the study?", count(CHAIRS), None),
        _q(ST, "indirect", "I'd like to know where the fridge is.", where(FRIDGE)),
        _q(ST, "indirect", "What colour are the study's chairs?", colour_of(CHAIRS), None),
        _q(ST, "indirect", "Please count the desks.", count(DESKS)),
        _q(ST, "affordance", "where can I sit?", afford(SITTABLE, SITTABLE, "one")),
        _q(ST, "affordance", "Where can I work?", afford(WORK_PLACES, WORK_PLACES, "one")),
        _q(ST, "affordance", "where can I keep my milk cold?", afford(FRIDGE, FRIDGE, "all")),
        _q(ST, "affordance", "where can I store my files?", afford(STORE_PLACES, STORE_PLACES, "one")),
        _q(ST, "where_all", "where are all the desks?", where_all(DESKS)),
        _q(ST, "where_all", "Where are all the chiars?", where_all(CHAIRS)),

        # ----------------------------------------------------------------- whole building (16)
        _q(B, "rooms", "in how many rooms is there a chair?", room_count(CHAIRS), None),
        _q(B, "rooms", "which room has the most chairs?", room_extreme(CHAIRS), None),
        _q(B, "rooms", "Wich room has the fewest objects?", room_extreme(THINGS, most=False), None),
        _q(B, "rooms", "what are the two rooms with the fewest things?", rooms_fewest(THINGS, 2), None),
        _q(B, "rooms", "which rooms have no fridge?", rooms_without(FRIDGE), None),
        _q(B, "rooms", "Which rooms have a TV?", rooms_with(TVS), None),
        _q(B, "rooms", "which room has desks?", rooms_with(DESKS), None),
        _q(B, "rooms", "how many tvs are there in the whole house?", total_count(TVS), None),
        _q(B, "rooms", "how many rooms are there?", room_total(), None),
        _q(B, "rooms", "Is there a fridge anywhere in the house?", anywhere(FRIDGE), None),
        _q(B, "rooms", "is there a sofa anywhere?", anywhere(COUCHES), None),
        _q(B, "rooms", "which rooms have more than two chairs?", rooms_over(CHAIRS, 2), None),
        _q(B, "rooms", "In which room are the most mugs?", room_extreme(CUPS), None),
        _q(B, "rooms", "how many chairs are there altogether?", total_count(CHAIRS), None),
        _q(B, "rooms", "which rooms don't have any cups?", rooms_without(CUPS), None),
        _q(B, "rooms", "how many rooms got a frigde?", room_count(FRIDGE), None),
    ]


def main(argv: list[str] | None = None) -> int:
    args = arguments((__doc__ or "").splitlines()[0]).parse_args(argv)
    report(ask_set(args, questions(), "sg3d-heldout3-"), args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
