"""A seventh held-out set of ordinary users' questions about the three rooms, judged like benchmarks.paraphrases.

Written blind: its author read none of the question reader (sg3d/queries/), none of the tests or
docs pages about questions, none of the earlier question sets (benchmarks/questions_kitchen.*,
the paraphrase and held-out question lists) and no git history; only the oracle helpers of
benchmarks/paraphrases.py and of the earlier held-out modules, the section "How answers are
judged" of benchmarks/paraphrases.md, and the stored graph of each room (what it holds, so that
"the X" is used only where the room holds one X). The questions are what people say to a home
robot -- a plumber on a job, a flatmate, an elderly person, a teenager, people whose first
language is French, Chinese or Arabic, a home-care worker, a voice-assistant user speaking in
fragments -- with synonyms (mug, telly, fridge, monitor, screen, sofa, armchair, bin, cupboard,
seat, worktop) and a few typos, written before anything was asked of the reader.

Every oracle is computed from the stored graph on each run; no expected answer is typed in.

This is a measuring set, not a training set: do not tune the reader on its phrasings. Run:

    python -m benchmarks.paraphrases_heldout7 --home SG3D_HOME [--json]
"""

from __future__ import annotations

from benchmarks.paraphrases import (
    arguments, ask_set, report,
    CABINET, CHAIRS, COL, COUNTER, CUPS, DESKS, DRINKABLE, FRIDGE, NOT_COLOUR, NOT_LABEL, PUT_PLACES, SHELVES,
    SINK, SITTABLE, STORE_PLACES, TABLE, THINGS, TVS, WORK_PLACES, L, Q, _q, afford, bigger,
    colour_of, count, dims, distance, exists, measure, none_of, objects, pick_bigger, quantity, rel, room_count,
    room_extreme, room_total, rooms_fewest, rooms_with, total_count, where, where_all,
)
from benchmarks.paraphrases_heldout import pick_smaller
from benchmarks.paraphrases_heldout2 import rooms_without
from benchmarks.paraphrases_heldout3 import anywhere, rooms_over
from benchmarks.paraphrases_heldout4 import has_colour
from benchmarks.paraphrases_heldout5 import taller
from benchmarks.paraphrases_heldout6 import nearest, pick_extreme

BOOKS = L("book")
PURPLE_BOOK = L("book", colour="purple")
WHITE_BOOK = L("book", colour="white")
GREY_CUP = L("cup", colour="grey")
WHITE_CUPS = L("cup", colour="white")
COUCHES = L("couch", "sofa")
BINS = L("bin", "trash can", "waste bin", "garbage can")
ON_TABLE = rel(THINGS, "on", TABLE)
CUPS_ON_TABLE = rel(CUPS, "on", TABLE)
WHITE_CUP_ON_TABLE = rel(WHITE_CUPS, "on", TABLE)
CUP_ON_SHELF = rel(CUPS, "on", SHELVES)            # kitchen: one cup stands on a shelf
TV_ON_SHELF = rel(TVS, "on", SHELVES)              # kitchen: one of its two tvs stands on a shelf
ON_CABINET = rel(THINGS, "on", CABINET)
NEXT_TO_FRIDGE = rel(THINGS, "next to", FRIDGE)


def questions() -> list[Q]:
    K, V, S_, B = "kitchen", "livingroom", "study", "building"
    qs = [
        # ---------------------------------------------------------------- kitchen
        _q(K, "count", "How many chairs are there in the kitchen?", count(CHAIRS)),
        _q(K, "count", "hw many mugs r there", count(CUPS)),
        _q(K, "count", "Kitchen. Number of books?", count(BOOKS)),
        _q(K, "count", "How many things are sitting on the dining table?", count(ON_TABLE)),
        _q(K, "count", "how many tellies have we got in here", count(TVS)),
        _q(K, "count", "How many cups on the table?", count(CUPS_ON_TABLE)),
        _q(K, "exists", "Is there a fridge in the kitchen?", exists(FRIDGE)),
        _q(K, "exists", "do we have a sink in here", exists(SINK)),
        _q(K, "exists", "Is there a sofa in this kitchen?", exists(COUCHES)),
        _q(K, "exists", "Any bin in the kitchen? I need to throw this away", exists(BINS)),
        _q(K, "exists", "There is a book in the kitchen, no?", exists(BOOKS)),
        _q(K, "attribute", "What colour is the sink?", colour_of(SINK)),
        _q(K, "attribute", "what color is the dining tabel", colour_of(TABLE)),
        _q(K, "attribute", "The chairs in the kitchen, which colour they are?", colour_of(CHAIRS)),
        _q(K, "attribute", "How tall is the dining table?", measure(TABLE, "height")),
        _q(K, "attribute", "how high is the table off the floor", measure(TABLE, "height")),
        _q(K, "attribute", "What size is the sink? I need its measurements for the fitting", dims(SINK)),
        _q(K, "attribute", "What colour is the cup on the shelf?", colour_of(CUP_ON_SHELF)),
        _q(K, "where", "Where is the sink?", where(SINK)),
        _q(K, "where", "where's the purple book", where(PURPLE_BOOK)),
        _q(K, "where", "Excuse me, where did the grey mug go?", where(GREY_CUP)),
        _q(K, "where", "wher is the white book", where(WHITE_BOOK)),
        _q(K, "where", "Dining table... where?", where(TABLE)),
        _q(K, "relation", "What's on the dining table?", objects(ON_TABLE)),
        _q(K, "relation", "what is next to the sink", objects(rel(THINGS, "next to", SINK))),
        _q(K, "relation", "Is the white book on the table?", exists(rel(WHITE_BOOK, "on", TABLE))),
        _q(K, "relation", "What is sitting on the worktop?", objects(rel(THINGS, "on", COUNTER))),
        _q(K, "relation", "which chairs are beside the dining table", objects(rel(CHAIRS, "next to", TABLE))),
        _q(K, "relation", "What's underneath the TV on the shelf?", objects(rel(THINGS, "under", TV_ON_SHELF))),
        _q(K, "relation", "Is the purple book near the grey cup?", exists(rel(PURPLE_BOOK, "near", GREY_CUP))),
        _q(K, "relation", "What is on the shelves?", objects(rel(THINGS, "on", SHELVES))),
        _q(K, "distance", "How far apart are the two TVs?", distance(TVS)),
        _q(K, "distance", "what's the distance between the two books", distance(BOOKS)),
        _q(K, "distance", "How far is the grey cup from the sink?", distance(GREY_CUP, SINK)),
        _q(K, "distance", "distnace from the dining table to the sink please", distance(TABLE, SINK)),
        _q(K, "size", "Is the dining table bigger than the sink?", bigger(TABLE, SINK)),
        _q(K, "size", "Which is bigger, the purple book or the white book?", pick_bigger(PURPLE_BOOK, WHITE_BOOK)),
        _q(K, "size", "Is the grey mug smaller than the white cup on the table?",
           bigger(GREY_CUP, WHITE_CUP_ON_TABLE, smaller=True)),
        _q(K, "size", "which one is smaller: the sink or the grey cup", pick_smaller(SINK, GREY_CUP)),
        _q(K, "size", "Which is the biggest chair in the kitchen?", pick_extreme(CHAIRS)),
        _q(K, "negation", "Is there anything on the dining table besides cups?", exists(NOT_LABEL(ON_TABLE, "cup"))),
        _q(K, "negation", "What is on the table other than the cups?", objects(NOT_LABEL(ON_TABLE, "cup"))),
        _q(K, "negation", "Are there at least four chairs in the kitchen?", quantity(CHAIRS, ">=", 4)),
        _q(K, "negation", "more than 3 cups here?", quantity(CUPS, ">", 3)),
        _q(K, "negation", "Are there exactly two books?", quantity(BOOKS, "==", 2)),
        _q(K, "negation", "So there's no fridge in this kitchen, right?", none_of(FRIDGE)),
        _q(K, "negation", "Is there something on the table that is not white?",
           exists(NOT_COLOUR(ON_TABLE, "white"))),
        _q(K, "attr_set", "What is red in the kitchen?", objects(COL("red"))),
        _q(K, "attr_set", "Show me everything black in here.", objects(COL("black"))),
        _q(K, "attr_set", "Anything purple in the kitchen?", exists(COL("purple"))),
        _q(K, "attr_set", "what's blue", objects(COL("blue"))),
        _q(K, "article", "Is there a cup on the dining table?", exists(CUPS_ON_TABLE)),
        _q(K, "article", "Is a chair next to the table?", exists(rel(CHAIRS, "next to", TABLE))),
        _q(K, "article", "Is the cup on the shelf white?", has_colour(CUP_ON_SHELF, "white")),
        _q(K, "article", "Is there a book on a chair?", exists(rel(BOOKS, "on", CHAIRS))),
        _q(K, "article", "What colour is the TV on the shelf?", colour_of(TV_ON_SHELF)),
        _q(K, "indirect", "Could you tell me how many chairs the kitchen has?", count(CHAIRS), scope=None),
        _q(K, "indirect", "I'd like to know where the sink is, please.", where(SINK)),
        _q(K, "indirect", "Tell me what is on the dining table, please.", objects(ON_TABLE)),
        _q(K, "indirect", "Count the kitchen's cups for me.", count(CUPS), scope=None),
        _q(K, "indirect", "Please can you find me the purple book", where(PURPLE_BOOK)),
        _q(K, "affordance", "What can I sit on in the kitchen?", afford(SITTABLE, SITTABLE, "all")),
        _q(K, "affordance", "What can I drink out of here?", afford(DRINKABLE, DRINKABLE, "all")),
        _q(K, "affordance", "I need somewhere to put my shopping bags down", afford(PUT_PLACES, PUT_PLACES, "any")),
        _q(K, "affordance", "Where could I store some jars?", afford(STORE_PLACES, STORE_PLACES, "any")),
        _q(K, "affordance", "Where can I work on my laptop in the kitchen?", afford(WORK_PLACES, WORK_PLACES, "any")),
        _q(K, "where_all", "Where are all the chairs?", where_all(CHAIRS)),
        _q(K, "where_all", "where are the cups", where_all(CUPS)),
        _q(K, "where_all", "Where are the two TVs?", where_all(TVS)),
        _q(K, "where_all", "Where are all the books in the kitchen?", where_all(BOOKS)),

        # ---------------------------------------------------------------- living room
        _q(V, "count", "How many chairs are there in the living room?", count(CHAIRS)),
        _q(V, "count", "how many white things are in the lounge", count(COL("white"))),
        _q(V, "count", "Living room, number of TVs", count(TVS)),
        _q(V, "count", "How many cupboards are there?", count(CABINET)),
        _q(V, "exists", "Is there a sofa in the living room?", exists(COUCHES)),
        _q(V, "exists", "is there a telly", exists(TVS)),
        _q(V, "exists", "Any armchair in here?", exists(CHAIRS)),
        _q(V, "exists", "Do you see any cups in the living room?", exists(CUPS)),
        _q(V, "attribute", "What colour is the armchair?", colour_of(CHAIRS)),
        _q(V, "attribute", "how tall is the chair", measure(CHAIRS, "height")),
        _q(V, "attribute", "What colour is the cubpoard?", colour_of(CABINET)),
        _q(V, "attribute", "How high is the cabinet?", measure(CABINET, "height")),
        _q(V, "attribute", "The television, what size is it?", dims(TVS)),
        _q(V, "where", "Where is the TV?", where(TVS)),
        _q(V, "where", "where's the armchair", where(CHAIRS)),
        _q(V, "where", "Where is the cabinet in the living room?", where(CABINET)),
        _q(V, "relation", "What is on the cabinet?", objects(ON_CABINET)),
        _q(V, "relation", "What's under the telly?", objects(rel(THINGS, "under", TVS))),
        _q(V, "relation", "Is the TV above the cabinet?", exists(rel(TVS, "above", CABINET))),
        _q(V, "relation", "what's next to the chair", objects(rel(THINGS, "next to", CHAIRS))),
        _q(V, "relation", "Is the chair near the tv?", exists(rel(CHAIRS, "near", TVS))),
        _q(V, "distance", "How far is the chair from the TV?", distance(CHAIRS, TVS)),
        _q(V, "distance", "distance between the tv and the cabinet", distance(TVS, CABINET)),
        _q(V, "size", "Is the armchair bigger than the TV?", bigger(CHAIRS, TVS)),
        _q(V, "size", "Which is bigger, the cabinet or the chair?", pick_bigger(CABINET, CHAIRS)),
        _q(V, "size", "Is the chair taller than the cabinet?", taller(CHAIRS, CABINET)),
        _q(V, "negation", "Is there anything on the cabinet that isn't white?",
           exists(NOT_COLOUR(ON_CABINET, "white"))),
        _q(V, "negation", "Is there anything on the cabinet other than the TV?", exists(NOT_LABEL(ON_CABINET, "tv"))),
        _q(V, "negation", "No sofa in the living room?", none_of(COUCHES)),
        _q(V, "negation", "Are there more than two chairs in the living room?", quantity(CHAIRS, ">", 2)),
        _q(V, "negation", "Is there exactly one TV?", quantity(TVS, "==", 1)),
        _q(V, "attr_set", "Which things are white?", objects(COL("white"))),
        _q(V, "attr_set", "What's brown in the living room?", objects(COL("brown"))),
        _q(V, "attr_set", "anything black", exists(COL("black"))),
        _q(V, "article", "Is there a TV on the cabinet?", exists(rel(TVS, "on", CABINET))),
        _q(V, "article", "Is the chair next to a cabinet?", exists(rel(CHAIRS, "next to", CABINET))),
        _q(V, "article", "Is the chair white?", has_colour(CHAIRS, "white")),
        _q(V, "indirect", "Could you tell me what's on the living room's cabinet?", objects(ON_CABINET), scope=None),
        _q(V, "indirect", "I would like to know how many chairs the living room has", count(CHAIRS), scope=None),
        _q(V, "indirect", "Tell me where the telly is, please", where(TVS)),
        _q(V, "affordance", "Where can I sit?", afford(SITTABLE, SITTABLE, "all")),
        _q(V, "affordance", "Somewhere to put my cup down?", afford(PUT_PLACES, PUT_PLACES, "any")),
        _q(V, "affordance", "Where can I keep my DVDs?", afford(STORE_PLACES, STORE_PLACES, "any")),
        _q(V, "affordance", "What could I drink from in the living room?", afford(DRINKABLE, DRINKABLE, "all")),
        _q(V, "where_all", "Where are all the chairs in the living room?", where_all(CHAIRS)),
        _q(V, "where_all", "where are all the TVs", where_all(TVS)),

        # ---------------------------------------------------------------- study
        _q(S_, "count", "How many desks are in the study?", count(DESKS)),
        _q(S_, "count", "how many chiars", count(CHAIRS)),
        _q(S_, "count", "How many seats in the study room?", count(SITTABLE)),
        _q(S_, "count", "how many monitors do u see", count(TVS)),
        _q(S_, "count", "What number of green things are there?", count(COL("green"))),
        _q(S_, "exists", "Is there a fridge in the study?", exists(FRIDGE)),
        _q(S_, "exists", "Is there a bed in the study?", exists(L("bed"))),
        _q(S_, "exists", "any couch", exists(COUCHES)),
        _q(S_, "exists", "Is there a shelf?", exists(SHELVES)),
        _q(S_, "exists", "do we have a screen in here", exists(TVS)),
        _q(S_, "attribute", "What colour is the fridge?", colour_of(FRIDGE)),
        _q(S_, "attribute", "How tall is the refrigerator?", measure(FRIDGE, "height")),
        _q(S_, "attribute", "what colour are the desks", colour_of(DESKS)),
        _q(S_, "attribute", "What colour is the monitor?", colour_of(TVS)),
        _q(S_, "attribute", "How big is the fridge?", dims(FRIDGE)),
        _q(S_, "attribute", "how high is the televison", measure(TVS, "height")),
        _q(S_, "where", "Where's the fridge?", where(FRIDGE)),
        _q(S_, "where", "where is the tv in the study", where(TVS)),
        _q(S_, "where", "fridg where", where(FRIDGE)),
        _q(S_, "relation", "What is next to the fridge?", objects(NEXT_TO_FRIDGE)),
        _q(S_, "relation", "what is under the tv", objects(rel(THINGS, "under", TVS))),
        _q(S_, "relation", "What's on the desks?", objects(rel(THINGS, "on", DESKS))),
        _q(S_, "relation", "Which desk is next to the fridge?", objects(rel(DESKS, "next to", FRIDGE))),
        _q(S_, "relation", "What is near the fridge?", objects(rel(THINGS, "near", FRIDGE))),
        _q(S_, "relation", "Is anything above the TV?", exists(rel(THINGS, "above", TVS))),
        _q(S_, "relation", "Which chairs are beside a desk?", objects(rel(CHAIRS, "next to", DESKS))),
        _q(S_, "distance", "How far is the fridge from the TV?", distance(FRIDGE, TVS)),
        _q(S_, "distance", "distance from the fridge to the closest desk", distance(FRIDGE, DESKS)),
        _q(S_, "distance", "How far is the TV from the nearest chair?", distance(TVS, CHAIRS)),
        _q(S_, "size", "Is the fridge bigger than the TV?", bigger(FRIDGE, TVS)),
        _q(S_, "size", "Which is bigger, the fridge or the telly?", pick_bigger(FRIDGE, TVS)),
        _q(S_, "size", "Is the TV taller than the fridge?", taller(TVS, FRIDGE)),
        _q(S_, "size", "Which is the biggest desk?", pick_extreme(DESKS)),
        _q(S_, "size", "which chair is the smallest", pick_extreme(CHAIRS, biggest=False)),
        _q(S_, "distance", "Which desk is closest to the fridge?", nearest(DESKS, FRIDGE)),
        _q(S_, "negation", "Is there anything next to the fridge that isn't a chair?",
           exists(NOT_LABEL(NEXT_TO_FRIDGE, "chair"))),
        _q(S_, "negation", "What's next to the fridge besides the chair?", objects(NOT_LABEL(NEXT_TO_FRIDGE, "chair"))),
        _q(S_, "negation", "Are there at least three desks?", quantity(DESKS, ">=", 3)),
        _q(S_, "negation", "More than two chairs in the study?", quantity(CHAIRS, ">", 2)),
        _q(S_, "negation", "No cups in the study?", none_of(CUPS)),
        _q(S_, "negation", "Is there exactly one fridge?", quantity(FRIDGE, "==", 1)),
        _q(S_, "attr_set", "What is green in the study?", objects(COL("green"))),
        _q(S_, "attr_set", "which things are blue", objects(COL("blue"))),
        _q(S_, "attr_set", "What's white in here?", objects(COL("white"))),
        _q(S_, "attr_set", "Anything red in the study?", exists(COL("red"))),
        _q(S_, "article", "Is there a desk next to the fridge?", exists(rel(DESKS, "next to", FRIDGE))),
        _q(S_, "article", "Is the fridge grey?", has_colour(FRIDGE, "grey")),
        _q(S_, "article", "Is a chair near the tv?", exists(rel(CHAIRS, "near", TVS))),
        _q(S_, "article", "Is the tv on a desk?", exists(rel(TVS, "on", DESKS))),
        _q(S_, "indirect", "Could you tell me how many desks the study has?", count(DESKS), scope=None),
        _q(S_, "indirect", "I'd like to know what's next to the fridge", objects(NEXT_TO_FRIDGE)),
        _q(S_, "indirect", "Please tell me the colour of the study's chairs", colour_of(CHAIRS), scope=None),
        _q(S_, "indirect", "Would you mind telling me where the fridge is?", where(FRIDGE)),
        _q(S_, "affordance", "Where can I sit in the study?", afford(SITTABLE, SITTABLE, "all")),
        _q(S_, "affordance", "Where could I work on my laptop?", afford(WORK_PLACES, WORK_PLACES, "any")),
        _q(S_, "affordance", "I need to keep my milk cold, where?", afford(FRIDGE, FRIDGE, "any")),
        _q(S_, "affordance", "Where can I store my books?", afford(STORE_PLACES, STORE_PLACES, "any")),
        _q(S_, "affordance", "Where could I put my tea down?", afford(PUT_PLACES, PUT_PLACES, "any")),
        _q(S_, "where_all", "Where are all the desks?", where_all(DESKS)),
        _q(S_, "where_all", "where are the chairs in the study", where_all(CHAIRS)),
        _q(S_, "where_all", "Tell me where each chair is", where_all(CHAIRS)),

        # ---------------------------------------------------------------- whole building
        _q(B, "rooms", "How many chairs are there in the whole house?", total_count(CHAIRS), scope=None),
        _q(B, "rooms", "How many rooms have a TV?", room_count(TVS), scope=None),
        _q(B, "rooms", "In how many rooms is there a chair?", room_count(CHAIRS), scope=None),
        _q(B, "rooms", "Which room has the most chairs?", room_extreme(CHAIRS), scope=None),
        _q(B, "rooms", "which room has the fewest chairs", room_extreme(CHAIRS, most=False), scope=None),
        _q(B, "rooms", "Which rooms have no cups?", rooms_without(CUPS), scope=None),
        _q(B, "rooms", "What are the two rooms with the fewest objects?", rooms_fewest(THINGS, 2), scope=None),
        _q(B, "rooms", "Which room has the most stuff in it?", room_extreme(THINGS), scope=None),
        _q(B, "rooms", "which rooms have a fridge", rooms_with(FRIDGE), scope=None),
        _q(B, "exists", "Is there a sofa anywhere in the house?", anywhere(COUCHES), scope=None),
        _q(B, "exists", "Is there a fridge anywhere?", anywhere(FRIDGE), scope=None),
        _q(B, "count", "How many rooms are there?", room_total(), scope=None),
        _q(B, "rooms", "Which rooms have more than two chairs?", rooms_over(CHAIRS, 2), scope=None),
        _q(B, "count", "How many TVs in total?", total_count(TVS), scope=None),
        _q(B, "rooms", "In which room can I find a desk?", rooms_with(DESKS), scope=None),
        _q(B, "rooms", "Which room has the most cups?", room_extreme(CUPS), scope=None),
        _q(B, "rooms", "Which has fewer things in it, the living room or the study?",
           room_extreme(THINGS, most=False, among=("livingroom", "study")), scope=None),
    ]
    return qs


def main(argv: list[str] | None = None) -> int:
    args = arguments((__doc__ or "").splitlines()[0]).parse_args(argv)
    report(ask_set(args, questions(), "sg3d-heldout7-"), args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
