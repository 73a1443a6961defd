"""A sixth held-out set of ordinary users' questions about the three rooms, judged like benchmarks.paraphrases.

    python -m benchmarks.paraphrases_heldout6 [--keep-home DIR | --home DIR] [--json]

Written blind, like the held-out sets before it: by someone who did not read the question
reader's code, grammar, vocabulary or tests, nor any earlier set's questions (only the oracle
helpers of benchmarks.paraphrases and the earlier held-out modules, and the "How answers are
judged" section of benchmarks/paraphrases.md), from the brief of forms (counting, existence,
attributes, where-is, relations, distance, size comparison, negation and quantity, rooms by
content, attribute-only sets, "a X"/"the X", imperative and indirect frames and possessives,
affordances, positions of all of a kind) and from what the built rooms hold (read through
World.load). 189 questions (kitchen 69, living room 44, study 59, whole building 17),
phrased as different people would ask a home robot: a nurse on a night shift, a student, a
grandparent, people whose first language is Spanish, German or Hindi, a tired office worker, a
curious child; with synonyms (mug, telly, fridge, monitor, screen, sofa, couch, armchair, bin,
cupboard, seat, worktop) and nine typos ("hwo", "shelfs", "dinning", "cabinett", "frige",
"telivision", "chiars", "wich", "wher"). The questions were not changed after the set was run.
Do not tune the reader on them, or they stop being held out.

"The X" is used only where the room holds exactly one X (or one X of that colour, or one X so
placed); "a X" means any X. Everything else is benchmarks.paraphrases': the rooms and store, the
oracle helpers over the stored graph (no expected answer is typed in), the judging of an answer
(right / wrong / refused) and the table. Added oracles, computed from the stored graph like the
others: `pick_extreme` (the biggest or smallest by volume of one kind, judged as a pick),
`pick_taller` (the taller by box height of the one A and the one B, judged as a pick) and
`nearest` (the one of a kind whose box centre is closest to the one Y, judged as a pick).
benchmarks/paraphrases.md ("Sixth held-out set") describes the set and its result.
"""
from __future__ import annotations

from benchmarks.paraphrases import (
    arguments, ask_set, report, dist, vol,
    CABINET, CHAIRS, COL, COUNTER, CUPS, DESKS, DRINKABLE, FLOOR, FRIDGE, PUT_PLACES, SHELVES, SINK, SITTABLE,
    STORE_PLACES, TABLE, THINGS, TVS, WORK_PLACES, L, NOT_COLOUR, NOT_LABEL, Oracle, Q, S, Truth, _q, afford,
    bigger, colour_of, count, dims, distance, exists, measure, none_of, objects, pick_bigger, quantity, rel,
    room_count, room_extreme, room_total, rooms_fewest, rooms_with, total_count, where, where_all,
)
from benchmarks.paraphrases_heldout import pick_smaller
from benchmarks.paraphrases_heldout2 import rooms_without
from benchmarks.paraphrases_heldout3 import anywhere, rooms_over
from benchmarks.paraphrases_heldout4 import has_colour
from benchmarks.paraphrases_heldout5 import taller

BOOKS = L("book")
WHITE_BOOK, PURPLE_BOOK = L("book", colour="white"), L("book", colour="purple")
GREY_CUP, WHITE_CUPS = L("cup", colour="grey"), L("cup", colour="white")
GREEN_CHAIRS = L("chair", colour="green")
COUCHES = L("couch", "sofa")
BINS = L("bin", "trash can", "waste bin", "garbage can")
ON_TABLE = rel(THINGS, "on", TABLE)
ON_SHELVES = rel(THINGS, "on", SHELVES)
TV_ON_SHELF = rel(TVS, "on", SHELVES)            # kitchen: one of its two tvs stands on a shelf
CUP_ON_SHELF = rel(CUPS, "on", SHELVES)          # kitchen: one cup, a white one, on a shelf
WHITE_CUP_ON_TABLE = rel(WHITE_CUPS, "on", TABLE)
BOOK_ON_TABLE = rel(BOOKS, "on", TABLE)
COLD = FRIDGE                                     # "keep food cold": only a refrigerator will do


def pick_extreme(xs: S, biggest: bool = True) -> tuple[Oracle, str]:
    """The biggest (or smallest) by volume of `xs`, judged as a pick among them."""
    def fn(w, r) -> Truth:
        os_ = xs(r)
        if not os_:
            return Truth("pick", None, {"candidates": set()})
        best = (max if biggest else min)(os_, key=vol)
        return Truth("pick", best["id"], {"candidates": {o["id"] for o in os_}})
    return fn, f"the {'biggest' if biggest else 'smallest'} by volume of {xs.desc}"


def pick_taller(a: S, b: S) -> tuple[Oracle, str]:
    """The taller by box height (size[2]) of the one A and the one B, judged as a pick."""
    def fn(w, r) -> Truth:
        xa, xb = a(r), b(r)
        if len(xa) != 1 or len(xb) != 1:
            return Truth("pick", None, {"candidates": {o["id"] for o in xa + xb}})
        winner = max(xa + xb, key=lambda o: float(o["size"][2]))
        return Truth("pick", winner["id"], {"candidates": {o["id"] for o in xa + xb}})
    return fn, f"the taller by box height of the one {a.desc} and the one {b.desc}"


def nearest(xs: S, ys: S) -> tuple[Oracle, str]:
    """The one of `xs` whose box centre is closest to the one Y of `ys`, judged as a pick."""
    def fn(w, r) -> Truth:
        xa, yb = xs(r), ys(r)
        if len(yb) != 1 or not xa:
            return Truth("pick", None, {"candidates": {o["id"] for o in xa}})
        y = yb[0]
        best = min((o for o in xa if o["id"] != y["id"]), key=lambda o: dist(o, y))
        return Truth("pick", best["id"], {"candidates": {o["id"] for o in xa}})
    return fn, f"the one of {xs.desc} whose box centre is closest to the one {ys.desc}"


def questions() -> list[Q]:
    K, LR, ST, B = "kitchen", "livingroom", "study", "building"
    qs = [
        # ---------------------------------------------------------------- kitchen
        # counting
        _q(K, "count", "how many chairs are in here?", count(CHAIRS)),
        _q(K, "count", "hwo many mugs are there", count(CUPS)),
        _q(K, "count", "How many things are sitting on the dining table?", count(ON_TABLE)),
        _q(K, "count", "number of books in the kitchen?", count(BOOKS), scope=None),
        _q(K, "count", "how many white cups have we got", count(WHITE_CUPS)),
        _q(K, "count", "how many objects are in this room altogether", count(THINGS)),
        _q(K, "count", "how many tellies does the kitchen have", count(TVS), scope=None),
        # existence
        _q(K, "exists", "is there a fridge in the kitchen?", exists(FRIDGE), scope=None),
        _q(K, "exists", "quick one - do we have a sink in here?", exists(SINK)),
        _q(K, "exists", "Is there a bin somewhere in this kitchen?", exists(BINS), scope=None),
        _q(K, "exists", "are there any books lying around?", exists(BOOKS)),
        _q(K, "exists", "is there a laptop here", exists(L("laptop"))),
        # attributes
        _q(K, "attribute", "what colour are the kitchen chairs", colour_of(CHAIRS), scope=None),
        _q(K, "attribute", "What color is the sink?", colour_of(SINK)),
        _q(K, "attribute", "how tall is the dinning table", measure(TABLE, "height")),
        _q(K, "attribute", "how long is the table?", measure(TABLE, "length")),
        _q(K, "attribute", "Are the chairs brown?", has_colour(CHAIRS, "brown")),
        _q(K, "attribute", "The cup on the shelf, which colour has it?", colour_of(CUP_ON_SHELF)),
        _q(K, "attribute", "how big is the sink", dims(SINK)),
        # where is
        _q(K, "where", "where is the sink", where(SINK)),
        _q(K, "where", "wheres the grey mug", where(GREY_CUP)),
        _q(K, "where", "Would you be so kind as to tell me where my purple book is, dear?", where(PURPLE_BOOK)),
        _q(K, "where", "where is the blue thing?", where(COL("blue"))),
        # relations
        _q(K, "relation", "what's on the worktop", objects(rel(THINGS, "on", COUNTER))),
        _q(K, "relation", "what is on the shelfs", objects(ON_SHELVES)),
        _q(K, "relation", "what is next to the sink?", objects(rel(THINGS, "next to", SINK))),
        _q(K, "relation", "which things are near the sink", objects(rel(THINGS, "near", SINK))),
        _q(K, "relation", "what is underneath the tv on the shelf?", objects(rel(THINGS, "under", TV_ON_SHELF))),
        _q(K, "relation", "is there anything above the sink", exists(rel(THINGS, "above", SINK))),
        _q(K, "relation", "Is the grey cup on the table?", exists(rel(GREY_CUP, "on", TABLE))),
        _q(K, "relation", "is the purple book lying on the dining table", exists(rel(PURPLE_BOOK, "on", TABLE))),
        _q(K, "relation", "which chairs are next to the table", objects(rel(CHAIRS, "next to", TABLE))),
        # distance
        _q(K, "distance", "how far is the sink from the dining table?", distance(SINK, TABLE)),
        _q(K, "distance", "how far apart are the two books", distance(BOOKS)),
        _q(K, "distance", "distance between the two tvs?", distance(TVS)),
        _q(K, "distance", "How far is the grey cup from the white book?", distance(GREY_CUP, WHITE_BOOK)),
        _q(K, "distance", "how far are the two white mugs from each other", distance(WHITE_CUPS)),
        # size comparison
        _q(K, "size", "is the white book bigger than the purple one?", bigger(WHITE_BOOK, PURPLE_BOOK)),
        _q(K, "size", "which is bigger, the sink or the grey cup", pick_bigger(SINK, GREY_CUP)),
        _q(K, "size", "is the dining table smaller than the tv on the shelf", bigger(TABLE, TV_ON_SHELF, smaller=True)),
        _q(K, "size", "Which chair is the biggest?", pick_extreme(CHAIRS)),
        _q(K, "size", "which one is smaller - the purple book or the white book?", pick_smaller(PURPLE_BOOK, WHITE_BOOK)),
        # negation and quantity
        _q(K, "negation", "is there anything on the table besides cups?", exists(ON_TABLE - CUPS)),
        _q(K, "negation", "What is on the table other than the cups?", objects(ON_TABLE - CUPS)),
        _q(K, "negation", "are there at least three chairs", quantity(CHAIRS, ">=", 3)),
        _q(K, "negation", "are there more than 4 chairs in the kitchen", quantity(CHAIRS, ">", 4), scope=None),
        _q(K, "negation", "exactly two tvs in here?", quantity(TVS, "==", 2)),
        _q(K, "negation", "so there's no fridge in here?", none_of(FRIDGE)),
        _q(K, "negation", "anything on the shelves that is not a cup?", exists(ON_SHELVES - CUPS)),
        # attribute-only sets
        _q(K, "attr_set", "what is red", objects(COL("red"))),
        _q(K, "attr_set", "which things in here are white?", objects(COL("white"))),
        _q(K, "attr_set", "show me everything that's grey", objects(COL("grey"))),
        # "a X" and "the X"
        _q(K, "article", "is there a cup on a shelf", exists(CUP_ON_SHELF)),
        _q(K, "article", "is a chair near the grey cup?", exists(rel(CHAIRS, "near", GREY_CUP))),
        _q(K, "article", "is the white cup on the table next to a book", exists(rel(WHITE_CUP_ON_TABLE, "next to", BOOKS))),
        _q(K, "article", "what colour is the book on the table?", colour_of(BOOK_ON_TABLE)),
        # imperative and indirect frames, possessives
        _q(K, "indirect", "could you tell me how many chairs the kitchen has", count(CHAIRS), scope=None),
        _q(K, "indirect", "I'd like to know where the sink is, please", where(SINK)),
        _q(K, "indirect", "count the cups for me please", count(CUPS)),
        _q(K, "indirect", "The kitchen's TVs - where are they?", where_all(TVS), scope=None),
        _q(K, "indirect", "kindly tell me what all is there on the dining table", objects(ON_TABLE)),
        # affordances
        _q(K, "affordance", "where can I sit down?", afford(SITTABLE, SITTABLE, "one")),
        _q(K, "affordance", "what could I drink out of", afford(DRINKABLE, DRINKABLE, "all")),
        _q(K, "affordance", "where can I put my plate down", afford(PUT_PLACES, PUT_PLACES, "one")),
        _q(K, "affordance", "where could I store things in this kitchen?", afford(STORE_PLACES, STORE_PLACES, "one"), scope=None),
        _q(K, "affordance", "I need to write a report, where can I work in here?", afford(WORK_PLACES, WORK_PLACES, "one")),
        # positions of all of a kind
        _q(K, "where_all", "where are all the chairs", where_all(CHAIRS)),
        _q(K, "where_all", "where are the cups?", where_all(CUPS)),
        _q(K, "where_all", "wher are the books", where_all(BOOKS)),

        # ---------------------------------------------------------------- living room
        # counting
        _q(LR, "count", "how many chairs are in the living room?", count(CHAIRS), scope=None),
        _q(LR, "count", "How many white things are in here?", count(COL("white"))),
        _q(LR, "count", "how many things are standing on the floor", count(rel(THINGS, "on", FLOOR))),
        _q(LR, "count", "how many armchairs do you see", count(CHAIRS)),
        # existence
        _q(LR, "exists", "is there a sofa in here", exists(COUCHES)),
        _q(LR, "exists", "do we have a telly in the living room?", exists(TVS), scope=None),
        _q(LR, "exists", "any cupboard in this room?", exists(CABINET)),
        _q(LR, "exists", "is there a couch I could lie on", exists(COUCHES)),
        # attributes
        _q(LR, "attribute", "what colour is the cupboard", colour_of(CABINET)),
        _q(LR, "attribute", "how wide is the cabinet?", measure(CABINET, "width")),
        _q(LR, "attribute", "is the armchair white", has_colour(CHAIRS, "white")),
        _q(LR, "attribute", "How tall is the chair?", measure(CHAIRS, "height")),
        _q(LR, "attribute", "what colour's the telly", colour_of(TVS)),
        # where is
        _q(LR, "where", "where is the tv", where(TVS)),
        _q(LR, "where", "where's the armchair?", where(CHAIRS)),
        _q(LR, "where", "Where is the cabinett?", where(CABINET)),
        # relations
        _q(LR, "relation", "what is on the cupboard", objects(rel(THINGS, "on", CABINET))),
        _q(LR, "relation", "what's under the tv?", objects(rel(THINGS, "under", TVS))),
        _q(LR, "relation", "is the tv above the cabinet", exists(rel(TVS, "above", CABINET))),
        _q(LR, "relation", "what is next to the chair", objects(rel(THINGS, "next to", CHAIRS))),
        _q(LR, "relation", "is there something inside the cabinet?", exists(rel(THINGS, "in", CABINET))),
        _q(LR, "relation", "what is near the television", objects(rel(THINGS, "near", TVS))),
        # distance
        _q(LR, "distance", "how far is the chair from the tv", distance(CHAIRS, TVS)),
        _q(LR, "distance", "distance from the armchair to the cupboard?", distance(CHAIRS, CABINET)),
        # size comparison
        _q(LR, "size", "is the chair bigger than the cabinet?", bigger(CHAIRS, CABINET)),
        _q(LR, "size", "which is larger: the telly or the cupboard", pick_bigger(TVS, CABINET)),
        _q(LR, "size", "is the tv taller than the chair", taller(TVS, CHAIRS)),
        _q(LR, "size", "which is taller, the chair or the cabinet?", pick_taller(CHAIRS, CABINET)),
        # negation and quantity
        _q(LR, "negation", "is there anything on the cabinet besides the tv", exists(rel(THINGS, "on", CABINET) - TVS)),
        _q(LR, "negation", "is there more than one chair?", quantity(CHAIRS, ">", 1)),
        _q(LR, "negation", "no sofa in this room, right?", none_of(COUCHES)),
        _q(LR, "negation", "is there anything in here that isn't white", exists(NOT_COLOUR(THINGS, "white"))),
        # attribute-only sets
        _q(LR, "attr_set", "what is black here?", objects(COL("black"))),
        _q(LR, "attr_set", "which things are brown", objects(COL("brown"))),
        # "a X" and "the X"
        _q(LR, "article", "is a chair next to the cabinet?", exists(rel(CHAIRS, "next to", CABINET))),
        _q(LR, "article", "is the tv near a chair", exists(rel(TVS, "near", CHAIRS))),
        # imperative and indirect frames, possessives
        _q(LR, "indirect", "I'd like to know how many things the living room has", count(THINGS), scope=None),
        _q(LR, "indirect", "tell me the colour of the living room's chair please", colour_of(CHAIRS), scope=None),
        _q(LR, "indirect", "Please tell me what is lying on the cupboard.", objects(rel(THINGS, "on", CABINET))),
        # affordances
        _q(LR, "affordance", "where can I sit in here?", afford(SITTABLE, SITTABLE, "all")),
        _q(LR, "affordance", "where can I keep my stuff", afford(STORE_PLACES, STORE_PLACES, "one")),
        _q(LR, "affordance", "where could I set down my tea?", afford(PUT_PLACES, PUT_PLACES, "one")),
        # positions of all of a kind
        _q(LR, "where_all", "where are all the seats", where_all(SITTABLE)),
        _q(LR, "where_all", "where are all the chairs in the living room?", where_all(CHAIRS), scope=None),

        # ---------------------------------------------------------------- study
        # counting
        _q(ST, "count", "how many desks are there", count(DESKS)),
        _q(ST, "count", "how many green chairs are in the study?", count(GREEN_CHAIRS), scope=None),
        _q(ST, "count", "How many chiars are there?", count(CHAIRS)),
        _q(ST, "count", "how many screens in this room", count(TVS)),
        _q(ST, "count", "count the things that stand on the floor", count(rel(THINGS, "on", FLOOR))),
        _q(ST, "count", "How many shelves has the study?", count(SHELVES), scope=None),
        # existence
        _q(ST, "exists", "there is a fridge in the study?", exists(FRIDGE), scope=None),
        _q(ST, "exists", "is there a monitor here?", exists(TVS)),
        _q(ST, "exists", "any cups in this room?", exists(CUPS)),
        _q(ST, "exists", "do you see a bed anywhere in here", exists(L("bed"))),
        _q(ST, "exists", "is there a sofa", exists(COUCHES)),
        # attributes
        _q(ST, "attribute", "what colour is the fridge", colour_of(FRIDGE)),
        _q(ST, "attribute", "how tall is the frige?", measure(FRIDGE, "height")),
        _q(ST, "attribute", "what colour are the desks", colour_of(DESKS)),
        _q(ST, "attribute", "are the chairs green?", has_colour(CHAIRS, "green")),
        _q(ST, "attribute", "what are the dimensions of the fridge", dims(FRIDGE)),
        _q(ST, "attribute", "how wide is the tv", measure(TVS, "width")),
        _q(ST, "attribute", "is the monitor blue", has_colour(TVS, "blue")),
        # where is
        _q(ST, "where", "where is the fridge?", where(FRIDGE)),
        _q(ST, "where", "where is the telivision", where(TVS)),
        _q(ST, "where", "ugh, where's the monitor", where(TVS)),
        # relations
        _q(ST, "relation", "what is next to the fridge", objects(rel(THINGS, "next to", FRIDGE))),
        _q(ST, "relation", "what's below the tv?", objects(rel(THINGS, "under", TVS))),
        _q(ST, "relation", "which chairs are next to a desk", objects(rel(CHAIRS, "next to", DESKS))),
        _q(ST, "relation", "Stands something on the shelves?", exists(ON_SHELVES)),
        _q(ST, "relation", "what stands near the tv", objects(rel(THINGS, "near", TVS))),
        _q(ST, "relation", "is the fridge next to a desk?", exists(rel(FRIDGE, "next to", DESKS))),
        _q(ST, "relation", "what is above the desks", objects(rel(THINGS, "above", DESKS))),
        _q(ST, "relation", "is the tv on the floor", exists(rel(TVS, "on", FLOOR))),
        # distance
        _q(ST, "distance", "how far is the fridge from the tv?", distance(FRIDGE, TVS)),
        _q(ST, "distance", "how far is the fridge from the nearest desk", distance(FRIDGE, DESKS)),
        _q(ST, "distance", "what is the distance between the monitor and the closest chair?", distance(TVS, CHAIRS)),
        # size comparison
        _q(ST, "size", "is the fridge bigger than the tv", bigger(FRIDGE, TVS)),
        _q(ST, "size", "which is smaller, the tv or the fridge?", pick_smaller(TVS, FRIDGE)),
        _q(ST, "size", "which desk is the biggest", pick_extreme(DESKS)),
        _q(ST, "size", "is the fridge taller than the tv?", taller(FRIDGE, TVS)),
        _q(ST, "size", "which chair is closest to the tv", nearest(CHAIRS, TVS)),
        # negation and quantity
        _q(ST, "negation", "is there anything next to the fridge other than a chair?", exists(rel(THINGS, "next to", FRIDGE) - CHAIRS)),
        _q(ST, "negation", "are there at least 3 desks", quantity(DESKS, ">=", 3)),
        _q(ST, "negation", "exactly two fridges?", quantity(FRIDGE, "==", 2)),
        _q(ST, "negation", "are there more than two chairs in the study?", quantity(CHAIRS, ">", 2), scope=None),
        _q(ST, "negation", "no cups in here, right?", none_of(CUPS)),
        _q(ST, "negation", "What is next to the fridge that is not a chair?", objects(NOT_LABEL(rel(THINGS, "next to", FRIDGE), "chair"))),
        # attribute-only sets
        _q(ST, "attr_set", "what is green", objects(COL("green"))),
        _q(ST, "attr_set", "which things are blue?", objects(COL("blue"))),
        _q(ST, "attr_set", "is anything red in here", exists(COL("red"))),
        # "a X" and "the X"
        _q(ST, "article", "is there a chair next to a desk?", exists(rel(CHAIRS, "next to", DESKS))),
        _q(ST, "article", "is the fridge near a chair", exists(rel(FRIDGE, "near", CHAIRS))),
        # imperative and indirect frames, possessives
        _q(ST, "indirect", "could you tell me how many desks the study has?", count(DESKS), scope=None),
        _q(ST, "indirect", "I'd like to know the colour of the study's fridge", colour_of(FRIDGE), scope=None),
        _q(ST, "indirect", "show me where the tv is, please", where(TVS)),
        _q(ST, "indirect", "Please list the study's chairs.", objects(CHAIRS), scope=None),
        # affordances
        _q(ST, "affordance", "where can I sit?", afford(SITTABLE, SITTABLE, "one")),
        _q(ST, "affordance", "where could I work on my laptop", afford(WORK_PLACES, WORK_PLACES, "one")),
        _q(ST, "affordance", "where can I keep food cold?", afford(COLD, COLD, "all")),
        _q(ST, "affordance", "where could I put my books away", afford(STORE_PLACES, STORE_PLACES, "one")),
        _q(ST, "affordance", "is there anything to drink out of in the study?", afford(DRINKABLE, DRINKABLE, "one"), scope=None),
        # positions of all of a kind
        _q(ST, "where_all", "where are all the desks", where_all(DESKS)),
        _q(ST, "where_all", "where are the chairs?", where_all(CHAIRS)),

        # ---------------------------------------------------------------- whole building
        _q(B, "rooms", "in how many rooms is there a tv", room_count(TVS), scope=None),
        _q(B, "rooms", "which room has the most chairs?", room_extreme(CHAIRS), scope=None),
        _q(B, "rooms", "what are the two rooms with the fewest objects", rooms_fewest(THINGS, 2), scope=None),
        _q(B, "rooms", "which rooms have no cups?", rooms_without(CUPS), scope=None),
        _q(B, "rooms", "which room is the fridge in", rooms_with(FRIDGE), scope=None),
        _q(B, "rooms", "which rooms have more than two chairs", rooms_over(CHAIRS, 2), scope=None),
        _q(B, "rooms", "which room has the fewest things in it?", room_extreme(THINGS, most=False), scope=None),
        _q(B, "rooms", "in which rooms can I find a desk", rooms_with(DESKS), scope=None),
        _q(B, "rooms", "wich room has the most tvs", room_extreme(TVS), scope=None),
        _q(B, "rooms", "which rooms don't have a fridge?", rooms_without(FRIDGE), scope=None),
        _q(B, "rooms", "where in the house can I find a mug?", rooms_with(CUPS), scope=None),
        _q(B, "rooms", "which has more chairs, the kitchen or the study?", room_extreme(CHAIRS, among=(K, ST)), scope=None),
        _q(B, "count", "how many chairs are there in the whole house", total_count(CHAIRS), scope=None),
        _q(B, "count", "how many televisions are there in the entire flat?", total_count(TVS), scope=None),
        _q(B, "count", "how many rooms are there", room_total(), scope=None),
        _q(B, "exists", "is there a sofa anywhere?", anywhere(COUCHES), scope=None),
        _q(B, "exists", "do we have a cupboard anywhere in the house", anywhere(CABINET), scope=None),
    ]
    return qs


def main(argv: list[str] | None = None) -> int:
    args = arguments((__doc__ or "").splitlines()[0]).parse_args(argv)
    report(ask_set(args, questions(), "sg3d-heldout6-"), args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
