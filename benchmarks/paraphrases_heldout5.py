"""A fifth held-out set of ordinary users' questions about the three rooms, judged like benchmarks.paraphrases.

    python -m benchmarks.paraphrases_heldout5 [--keep-home DIR | --home DIR] [--json]

Written blind: its author never read the question reader (sg3d/queries/), its grammar or
vocabulary, its tests, the docs pages listing example questions, the earlier question sets
(benchmarks/paraphrases.py's questions(), paraphrases_heldout*.py's questions(), the kitchen
question files) or the git log. The author read only the oracle helpers of
benchmarks/paraphrases.py and the helper functions of the earlier held-out modules, the section
"How answers are judged" of benchmarks/paraphrases.md, and what the three rooms hold (their
stored objects and edges, through the oracle's World.load), so that "the X" is used only where
the room holds exactly one X (or one of that colour) and every answer is decidable from the
graph. The questions are written the way different people would ask a home robot (a busy
parent, a teenager texting, an elderly person, a non-native speaker, a child, an engineer
testing it), with synonyms and a few typos, covering every form of the brief.

Do not tune the reader on these questions: they measure how it copes with phrasings nobody
tuned it on. The set was run once, after it was complete; no question was changed after that.

Every oracle is computed from the stored graph on each run (no expected answer is typed in).
One new helper: `taller` (yes iff the one A's box height exceeds the one B's).
"""
from __future__ import annotations

from benchmarks.paraphrases import (
    arguments, ask_set, report,
    BOOKS, CABINET, CHAIRS, COUNTER, CUPS, DESKS, DRINKABLE, FLOOR, FRIDGE, PUT_PLACES, SHELVES, SINK,
    SITTABLE, STORE_PLACES, TABLE, THINGS, TVS, WORK_PLACES, COL, L, NOT_COLOUR, NOT_LABEL, Oracle, Q, S,
    Truth, _q, afford, bigger, colour_of, count, dims, distance, exists, measure, none_of, objects,
    pick_bigger, quantity, rel, room_count, room_extreme, room_total, rooms_fewest, rooms_with,
    total_count, where, where_all,
)
from benchmarks.paraphrases_heldout import pick_smaller
from benchmarks.paraphrases_heldout2 import footprint, rooms_without
from benchmarks.paraphrases_heldout3 import anywhere, rooms_over
from benchmarks.paraphrases_heldout4 import has_colour

COUCHES = L("couch", "sofa")
GREY_CUP = L("cup", colour="grey")
WHITE_CUPS = L("cup", colour="white")
PURPLE_BOOK = L("book", colour="purple")
WHITE_BOOK = L("book", colour="white")
TV_ON_SHELF = rel(TVS, "on", SHELVES)
CUP_ON_SHELF = rel(CUPS, "on", SHELVES)
BOOK_ON_TABLE = rel(BOOKS, "on", TABLE)
ON_TABLE = rel(THINGS, "on", TABLE)
ON_FLOOR = rel(THINGS, "on", FLOOR)
ON_CABINET = rel(THINGS, "on", CABINET)
NEXT_TO_FRIDGE = rel(THINGS, "next to", FRIDGE)
CHAIR_BY_FRIDGE = rel(CHAIRS, "next to", FRIDGE)


def taller(a: S, b: S) -> tuple[Oracle, str]:
    """Yes iff the one A's box height (size[2]) exceeds the one B's (None, never right, unless
    the room holds exactly one of each)."""
    def fn(w, r) -> Truth:
        xa, xb = a(r), b(r)
        if len(xa) != 1 or len(xb) != 1:
            return Truth("yesno", None)
        return Truth("yesno", float(xa[0]["size"][2]) > float(xb[0]["size"][2]))
    return fn, f"yes iff the box height of the one {a.desc} > that of the one {b.desc}"


def questions() -> list[Q]:
    K, LR, ST, B = "kitchen", "livingroom", "study", "building"
    qs = [
        # ------------------------------------------------------------------ kitchen
        _q(K, "count", "how many chairs are there", count(CHAIRS)),
        _q(K, "count", "hw many chiars r there", count(CHAIRS)),
        _q(K, "count", "How many cups are in here?", count(CUPS)),
        _q(K, "count", "number of mugs?", count(CUPS)),
        _q(K, "count", "How many tellies have we got?", count(TVS)),
        _q(K, "count", "how many white cups are there", count(WHITE_CUPS)),
        _q(K, "count", "How many things are sitting on the dining table?", count(ON_TABLE)),
        _q(K, "exists", "is there a sink", exists(SINK)),
        _q(K, "exists", "Is there a fridge in here?", exists(FRIDGE)),
        _q(K, "exists", "do we have a microwave", exists(L("microwave"))),
        _q(K, "exists", "r there any books", exists(BOOKS)),
        _q(K, "exists", "is there a bin", exists(L("bin", "trash can", "waste bin"))),
        _q(K, "attribute", "what colour is the dining table", colour_of(TABLE)),
        _q(K, "attribute", "What color are the chairs?", colour_of(CHAIRS)),
        _q(K, "attribute", "what colour is the cup on the shelf", colour_of(CUP_ON_SHELF)),
        _q(K, "attribute", "How tall is the table?", measure(TABLE, "height")),
        _q(K, "attribute", "how long is the dining table", measure(TABLE, "length")),
        _q(K, "attribute", "What are the dimensions of the TV on the shelf?", dims(TV_ON_SHELF)),
        _q(K, "attribute", "Is the sink white?", has_colour(SINK, "white")),
        _q(K, "where", "where is the sink", where(SINK)),
        _q(K, "where", "Where did I leave the purple book?", where(PURPLE_BOOK)),
        _q(K, "where", "wheres the grey mug", where(GREY_CUP)),
        _q(K, "where", "Where is the dining table, please?", where(TABLE)),
        _q(K, "relation", "what is on the dining table", objects(ON_TABLE)),
        _q(K, "relation", "What's on the shelves?", objects(rel(THINGS, "on", SHELVES))),
        _q(K, "relation", "what is next to the sink", objects(rel(THINGS, "next to", SINK))),
        _q(K, "relation", "is the grey cup on the table?", exists(rel(GREY_CUP, "on", TABLE))),
        _q(K, "relation", "What is under the TV on the shelf?", objects(rel(THINGS, "under", TV_ON_SHELF))),
        _q(K, "relation", "which books are near the grey mug", objects(rel(BOOKS, "near", GREY_CUP))),
        _q(K, "relation", "what's sitting on the counter", objects(rel(THINGS, "on", COUNTER))),
        _q(K, "distance", "how far is the sink from the dining table", distance(SINK, TABLE)),
        _q(K, "distance", "What is the distance between the two books?", distance(BOOKS)),
        _q(K, "distance", "how far apart are the two tvs", distance(TVS)),
        _q(K, "distance", "How far is the grey cup from the purple book?", distance(GREY_CUP, PURPLE_BOOK)),
        _q(K, "size", "is the dining table bigger than the sink", bigger(TABLE, SINK)),
        _q(K, "size", "Which is bigger, the purple book or the white book?", pick_bigger(PURPLE_BOOK, WHITE_BOOK)),
        _q(K, "size", "Is the grey cup smaller than the purple book?", bigger(GREY_CUP, PURPLE_BOOK, smaller=True)),
        _q(K, "size", "which one is larger: the sink or the grey mug?", pick_bigger(SINK, GREY_CUP)),
        _q(K, "size", "Which is smaller, the TV on the shelf or the dining table?", pick_smaller(TV_ON_SHELF, TABLE)),
        _q(K, "negation", "Is there anything on the dining table besides cups?",
           exists(NOT_LABEL(ON_TABLE, "cup"))),
        _q(K, "negation", "what's on the table that isn't a cup", objects(NOT_LABEL(ON_TABLE, "cup"))),
        _q(K, "negation", "are there at least 4 chairs", quantity(CHAIRS, ">=", 4)),
        _q(K, "negation", "Are there more than three cups?", quantity(CUPS, ">", 3)),
        _q(K, "negation", "exactly two tvs?", quantity(TVS, "==", 2)),
        _q(K, "negation", "Is there anything on the floor other than chairs?", exists(NOT_LABEL(ON_FLOOR, "chair"))),
        _q(K, "attr_set", "what is red?", objects(COL("red"))),
        _q(K, "attr_set", "which things are white", objects(COL("white"))),
        _q(K, "attr_set", "Show me everything that's black.", objects(COL("black"))),
        _q(K, "attr_set", "anything purple?", exists(COL("purple"))),
        _q(K, "article", "is there a cup on the table", exists(rel(CUPS, "on", TABLE))),
        _q(K, "article", "Is there a book on a chair?", exists(rel(BOOKS, "on", CHAIRS))),
        _q(K, "article", "what's next to the cup on the shelf?", objects(rel(THINGS, "next to", CUP_ON_SHELF))),
        _q(K, "article", "does a tv sit on a shelf", exists(TV_ON_SHELF)),
        _q(K, "article", "What colour is the book on the table?", colour_of(BOOK_ON_TABLE)),
        _q(K, "indirect", "Could you tell me how many chairs there are?", count(CHAIRS)),
        _q(K, "indirect", "I'd like to know where the sink is.", where(SINK)),
        _q(K, "indirect", "please count the cups for me", count(CUPS)),
        _q(K, "indirect", "Tell me how many chairs the kitchen has.", count(CHAIRS), scope=None),
        _q(K, "indirect", "what colour are the kitchen's chairs", colour_of(CHAIRS), scope=None),
        _q(K, "indirect", "Can you find the grey mug for me?", where(GREY_CUP)),
        _q(K, "affordance", "where can I sit", afford(SITTABLE, SITTABLE, "all")),
        _q(K, "affordance", "What can I drink from?", afford(DRINKABLE, DRINKABLE, "all")),
        _q(K, "affordance", "Is there a glass or a cup I could drink out of?", afford(DRINKABLE, DRINKABLE, "one")),
        _q(K, "affordance", "I need to put my shopping down. Is there a counter or a table for it?",
           afford(TABLE | COUNTER, PUT_PLACES, "one")),
        _q(K, "affordance", "where could I store some stuff", afford(STORE_PLACES, STORE_PLACES, "one")),
        _q(K, "affordance", "Is there somewhere I could work?", afford(WORK_PLACES, WORK_PLACES, "one")),
        _q(K, "where_all", "where are all the chairs", where_all(CHAIRS)),
        _q(K, "where_all", "Where are the cups?", where_all(CUPS)),
        _q(K, "where_all", "where r the books", where_all(BOOKS)),
        _q(K, "where_all", "Where are both televisions?", where_all(TVS)),

        # ------------------------------------------------------------------ living room
        _q(LR, "count", "how many chairs are in here", count(CHAIRS)),
        _q(LR, "count", "How many armchairs are there?", count(CHAIRS)),
        _q(LR, "count", "how many white things r there", count(COL("white"))),
        _q(LR, "count", "How many things are standing on the floor?", count(ON_FLOOR)),
        _q(LR, "exists", "is there a sofa", exists(COUCHES)),
        _q(LR, "exists", "Is there a telly?", exists(TVS)),
        _q(LR, "exists", "any cupboards?", exists(CABINET)),
        _q(LR, "exists", "Is there a lamp in this room?", exists(L("lamp"))),
        _q(LR, "attribute", "what colour is the armchair", colour_of(CHAIRS)),
        _q(LR, "attribute", "What colour is the cabinet?", colour_of(CABINET)),
        _q(LR, "attribute", "how tall is the tv", measure(TVS, "height")),
        _q(LR, "attribute", "How wide is the cupboard?", footprint(CABINET, "width")),
        _q(LR, "attribute", "is the chair white?", has_colour(CHAIRS, "white")),
        _q(LR, "attribute", "Is the chair taller than the cabinet?", taller(CHAIRS, CABINET)),
        _q(LR, "where", "where is the tv", where(TVS)),
        _q(LR, "where", "Where's the chair?", where(CHAIRS)),
        _q(LR, "where", "where is teh cupboard", where(CABINET)),
        _q(LR, "where", "Excuse me, dear, where is the television?", where(TVS)),
        _q(LR, "relation", "what's on the cabinet", objects(ON_CABINET)),
        _q(LR, "relation", "What is under the TV?", objects(rel(THINGS, "under", TVS))),
        _q(LR, "relation", "is the tv above the cabinet", exists(rel(TVS, "above", CABINET))),
        _q(LR, "relation", "what is next to the chair", objects(rel(THINGS, "next to", CHAIRS))),
        _q(LR, "relation", "Is the chair near the telly?", exists(rel(CHAIRS, "near", TVS))),
        _q(LR, "distance", "how far is the chair from the tv", distance(CHAIRS, TVS)),
        _q(LR, "distance", "What's the distance between the cabinet and the chair?", distance(CABINET, CHAIRS)),
        _q(LR, "size", "is the chair bigger than the cabinet", bigger(CHAIRS, CABINET)),
        _q(LR, "size", "Which is bigger, the TV or the cabinet?", pick_bigger(TVS, CABINET)),
        _q(LR, "size", "is the telly smaller than the armchair", bigger(TVS, CHAIRS, smaller=True)),
        _q(LR, "negation", "Is there anything on the cupboard that isn't white?",
           exists(NOT_COLOUR(ON_CABINET, "white"))),
        _q(LR, "negation", "are there at least two chairs", quantity(CHAIRS, ">=", 2)),
        _q(LR, "negation", "more than 5 white things?", quantity(COL("white"), ">", 5)),
        _q(LR, "negation", "What's on the floor apart from the chair?", objects(NOT_LABEL(ON_FLOOR, "chair"))),
        _q(LR, "attr_set", "what is black", objects(COL("black"))),
        _q(LR, "attr_set", "Which things are brown?", objects(COL("brown"))),
        _q(LR, "attr_set", "is anything red in here", exists(COL("red"))),
        _q(LR, "article", "is there a chair next to the cabinet", exists(rel(CHAIRS, "next to", CABINET))),
        _q(LR, "article", "Is the TV on a cabinet?", exists(rel(TVS, "on", CABINET))),
        _q(LR, "article", "is there a white thing on the cabinet", exists(rel(COL("white"), "on", CABINET))),
        _q(LR, "indirect", "tell me what's on the cabinet pls", objects(ON_CABINET)),
        _q(LR, "indirect", "I would like to know how many chairs the living room has.", count(CHAIRS), scope=None),
        _q(LR, "indirect", "Could you say what colour the living room's TV is?", colour_of(TVS), scope=None),
        _q(LR, "affordance", "where can i sit down", afford(SITTABLE, SITTABLE, "all")),
        _q(LR, "affordance", "Is there a couch or an armchair I could sit on?", afford(SITTABLE, SITTABLE, "one")),
        _q(LR, "affordance", "Where could I put my cup down?", afford(PUT_PLACES, PUT_PLACES, "one")),
        _q(LR, "affordance", "where can I keep my DVDs", afford(STORE_PLACES, STORE_PLACES, "one")),
        _q(LR, "where_all", "where are all the chairs", where_all(CHAIRS)),
        _q(LR, "where_all", "Where are all the white things?", where_all(COL("white"))),

        # ------------------------------------------------------------------ study
        _q(ST, "count", "how many chairs", count(CHAIRS)),
        _q(ST, "count", "how many desks r there", count(DESKS)),
        _q(ST, "count", "How many green chairs are there?", count(L("chair", colour="green"))),
        _q(ST, "count", "How many seats are there in here?", count(SITTABLE)),
        _q(ST, "count", "how many things are next to the fridge", count(NEXT_TO_FRIDGE)),
        _q(ST, "count", "How many monitors do I have?", count(TVS)),
        _q(ST, "count", "how many shelfs are there", count(SHELVES)),
        _q(ST, "exists", "is there a fridge", exists(FRIDGE)),
        _q(ST, "exists", "Is there a laptop?", exists(L("laptop"))),
        _q(ST, "exists", "is there a bed in here", exists(L("bed"))),
        _q(ST, "exists", "Are there any books in the study?", exists(BOOKS), scope=None),
        _q(ST, "attribute", "what colour are the desks", colour_of(DESKS)),
        _q(ST, "attribute", "What color is the fridge?", colour_of(FRIDGE)),
        _q(ST, "attribute", "what colur is the monitor", colour_of(TVS)),
        _q(ST, "attribute", "How tall is the refrigerator?", measure(FRIDGE, "height")),
        _q(ST, "attribute", "what are the dimensions of the fridge", dims(FRIDGE)),
        _q(ST, "attribute", "Are the chairs green?", has_colour(CHAIRS, "green")),
        _q(ST, "attribute", "is the fridge taller than the tv", taller(FRIDGE, TVS)),
        _q(ST, "where", "where is the fridge", where(FRIDGE)),
        _q(ST, "where", "Where's the monitor?", where(TVS)),
        _q(ST, "where", "where is the screen", where(TVS)),
        _q(ST, "relation", "what's next to the fridge", objects(NEXT_TO_FRIDGE)),
        _q(ST, "relation", "What is under the TV?", objects(rel(THINGS, "under", TVS))),
        _q(ST, "relation", "is there anything on the desks", exists(rel(THINGS, "on", DESKS))),
        _q(ST, "relation", "Which chairs are next to a desk?", objects(rel(CHAIRS, "next to", DESKS))),
        _q(ST, "relation", "what is near the monitor", objects(rel(THINGS, "near", TVS))),
        _q(ST, "relation", "What's on the shelves?", objects(rel(THINGS, "on", SHELVES))),
        _q(ST, "distance", "how far is the fridge from the tv", distance(FRIDGE, TVS)),
        _q(ST, "distance", "How close is the nearest desk to the fridge?", distance(DESKS, FRIDGE)),
        _q(ST, "distance", "distance between the fridge and the closest chair?", distance(FRIDGE, CHAIRS)),
        _q(ST, "size", "is the fridge bigger than the tv", bigger(FRIDGE, TVS)),
        _q(ST, "size", "Which is bigger, the monitor or the fridge?", pick_bigger(TVS, FRIDGE)),
        _q(ST, "size", "Is the monitor larger than the refrigerator?", bigger(TVS, FRIDGE)),
        _q(ST, "size", "which is smaller: the fridg or the tv", pick_smaller(FRIDGE, TVS)),
        _q(ST, "negation", "Is there anything next to the fridge besides chairs?",
           exists(NOT_LABEL(NEXT_TO_FRIDGE, "chair"))),
        _q(ST, "negation", "what's next to the fridge other than the desk", objects(NOT_LABEL(NEXT_TO_FRIDGE, "desk"))),
        _q(ST, "negation", "are there at least 3 desks", quantity(DESKS, ">=", 3)),
        _q(ST, "negation", "Are there more than three chairs?", quantity(CHAIRS, ">", 3)),
        _q(ST, "negation", "Is there exactly one fridge?", quantity(FRIDGE, "==", 1)),
        _q(ST, "negation", "Are there no books in here?", none_of(BOOKS)),
        _q(ST, "attr_set", "what's green", objects(COL("green"))),
        _q(ST, "attr_set", "Which things are grey?", objects(COL("grey"))),
        _q(ST, "attr_set", "what is blue", objects(COL("blue"))),
        _q(ST, "attr_set", "is anything yellow", exists(COL("yellow"))),
        _q(ST, "attr_set", "list all objects with colour white", objects(COL("white"))),
        _q(ST, "article", "is there a chair next to the fridge", exists(CHAIR_BY_FRIDGE)),
        _q(ST, "article", "Is the fridge next to a desk?", exists(rel(FRIDGE, "next to", DESKS))),
        _q(ST, "article", "what colour is the chair next to the fridge", colour_of(CHAIR_BY_FRIDGE)),
        _q(ST, "indirect", "Could you tell me how many desks there are?", count(DESKS)),
        _q(ST, "indirect", "i'd like to know where the fridge is", where(FRIDGE)),
        _q(ST, "indirect", "Tell me how many chairs the study has.", count(CHAIRS), scope=None),
        _q(ST, "indirect", "what colour are the study's desks?", colour_of(DESKS), scope=None),
        _q(ST, "indirect", "Show me the desks, please.", objects(DESKS)),
        _q(ST, "affordance", "where can I sit", afford(SITTABLE, SITTABLE, "all")),
        _q(ST, "affordance", "Where could I work?", afford(WORK_PLACES, WORK_PLACES, "one")),
        _q(ST, "affordance", "where can i put my laptop down", afford(PUT_PLACES, PUT_PLACES, "one")),
        _q(ST, "affordance", "Where can I keep my milk cold?", afford(FRIDGE, FRIDGE, "one")),
        _q(ST, "where_all", "where are all the chairs", where_all(CHAIRS)),
        _q(ST, "where_all", "Where are the desks?", where_all(DESKS)),
        _q(ST, "where_all", "where's every dsk", where_all(DESKS)),

        # ------------------------------------------------------------------ whole building
        _q(B, "rooms", "In how many rooms is there a chair?", room_count(CHAIRS), scope=None),
        _q(B, "rooms", "how many rooms have a tv", room_count(TVS), scope=None),
        _q(B, "rooms", "Which room has the most chairs?", room_extreme(CHAIRS), scope=None),
        _q(B, "rooms", "which room has the fewest things in it", room_extreme(THINGS, most=False), scope=None),
        _q(B, "rooms", "What are the two rooms with the fewest objects?", rooms_fewest(THINGS, 2), scope=None),
        _q(B, "rooms", "Which rooms have no desks?", rooms_without(DESKS), scope=None),
        _q(B, "rooms", "which rooms have a fridge", rooms_with(FRIDGE), scope=None),
        _q(B, "rooms", "In which room are the books?", rooms_with(BOOKS), scope=None),
        _q(B, "rooms", "which rooms have more than two chairs", rooms_over(CHAIRS, 2), scope=None),
        _q(B, "rooms", "Which room has the most white things?", room_extreme(COL("white")), scope=None),
        _q(B, "rooms", "which rooms don't have a tv", rooms_without(TVS), scope=None),
        _q(B, "count", "how many chairs are there in total", total_count(CHAIRS), scope=None),
        _q(B, "count", "How many TVs are there in the whole house?", total_count(TVS), scope=None),
        _q(B, "count", "how many rooms are there", room_total(), scope=None),
        _q(B, "count", "Report the total number of desks across all rooms.", total_count(DESKS), scope=None),
        _q(B, "exists", "Is there a fridge anywhere in the house?", anywhere(FRIDGE), scope=None),
        _q(B, "exists", "is there a sofa in any of the rooms", anywhere(COUCHES), scope=None),
    ]
    return qs


def main(argv: list[str] | None = None) -> int:
    args = arguments((__doc__ or "").splitlines()[0]).parse_args(argv)
    report(ask_set(args, questions(), "sg3d-heldout5-"), args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
