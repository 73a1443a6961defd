"""The grammar of questions (lark, LALR, sg3d/queries/data/question.lark): normalised text -> logical
form (sg3d/queries/logic.py).

The grammar knows the frame words (how many, where, which ... is the biggest), relations,
distances with units, negation, comparisons and rooms; nouns are open words, resolved later to
stored labels (sg3d/queries/lexicon.py). The parser is built once per process (LALR: a table look-up
per word, well under a millisecond for a question).
"""
from __future__ import annotations

import functools
import logging
from dataclasses import replace
from pathlib import Path
from typing import Iterator, Optional, TypeVar

from lark import Lark, Token, Transformer, Tree, v_args
from lark.exceptions import LarkError, UnexpectedInput, VisitError

from sg3d.core.errors import Sg3dError
from sg3d.queries.logic import NP, Filter, Form

from sg3d.queries.vocabulary import (
    ATTRIBUTES,
    COLOURS,
    DISTANCE_SUPERLATIVES,
    NEVER_IGNORED,
    RELATIONS,
    SIZES,
    SUPERLATIVES,
    UNIT_M,
)

# the grammar (sg3d/queries/data/question.lark), over word lists filled in from the lexicon
# (RELATION_WORDS, SUPER_WORDS, DSUPER_WORDS, UNIT_WORDS: sg3d/queries/vocabulary.py); the text
# the parser tables are hashed from starts with a newline
GRAMMAR = "\n" + (Path(__file__).resolve().parents[1] / "data" / "question.lark").read_text()


def _alternatives(words) -> str:
    return " | ".join(f'"{w}"' for w in sorted(words, key=lambda w: (-len(w), w)))


def _grammar_text() -> str:
    """The grammar with its word lists filled in from sg3d/queries/vocabulary.py."""
    relations = " | ".join(" ".join(f'"{w}"' for w in phrase.split()) for phrase in sorted(RELATIONS))
    return (GRAMMAR.replace("RELATION_WORDS", relations)
            .replace("DSUPER_WORDS", _alternatives(DISTANCE_SUPERLATIVES))
            .replace("SUPER_WORDS", _alternatives(SUPERLATIVES))
            .replace("UNIT_WORDS", _alternatives(UNIT_M)))


def _reserved() -> list[str]:
    """Every literal of the grammar: never an object word (a noun phrase ends where one begins)."""
    import re

    text = _grammar_text().split("WORD: ")[0]
    return sorted({w for w in re.findall(r'"([a-z]+)"', text)} | {"a", "an"}, key=lambda w: (-len(w), w))


RESERVED = _reserved()
# "how do I get / go / walk from A to B": the verbs that ask for the way between two rooms
ROUTE_VERBS = frozenset({"get", "go", "walk", "move"})
log = logging.getLogger("sg3d.queries")
_T = TypeVar("_T")


class GrammarError(Sg3dError, ValueError):
    """The text is not a question of the grammar; `word` is where it stopped, if known."""

    def __init__(self, message: str, word: Optional[str] = None):
        super().__init__(message)
        self.word = word


class ReaderFailure(GrammarError):
    """The reader itself failed on the text (a bug in a rewrite or a rule's transformer, not a
    question outside the grammar): refused naming `word`, where reading stopped, and logged."""


@functools.cache
def parser() -> Lark:
    """The LALR parser, built once per process."""
    grammar = parser_grammar()
    shipped = shipped_tables(grammar)
    if shipped.is_file():       # the tables made for this grammar ship with sg3d: no build at all
        with shipped.open("rb") as f:
            return Lark.load(f)
    # the LALR tables are kept in sg3d's cache (not the temporary folder): a cold process loads
    # them instead of building them (0.7 s)
    return build_parser(grammar, cache=_table_cache(grammar))


def parser_grammar() -> str:
    """The grammar text the parser is built from."""
    return _grammar_text().replace("RESERVED", "|".join(RESERVED))


def build_parser(grammar: str, cache=False) -> Lark:
    return Lark(grammar, parser="lalr", maybe_placeholders=False, cache=cache)


def shipped_tables(grammar: str):
    """Where the parser tables of `grammar` ship (sg3d/queries/data, made by
    scripts/make_query_tables.py), named by a hash of the grammar and of lark's version: a
    grammar edited since has no file there, and is built (and cached) instead."""
    import hashlib

    import lark

    key = hashlib.sha1(f"{grammar}\n{lark.__version__}".encode()).hexdigest()[:12]
    return Path(__file__).resolve().parents[1] / "data" / f"question-parser-tables-{key}.pickle"


def _table_cache(grammar: str):
    """Where the parser tables of `grammar` are kept in sg3d's cache (`core.cache`); False (no
    cache) where none can be written."""
    import hashlib

    from sg3d.core.cache import writable_cache_folder

    folder = writable_cache_folder()
    if folder is None:
        return False
    return str(folder / f"question-parser-tables-{hashlib.sha1(grammar.encode()).hexdigest()[:12]}.pickle")


def _words(items) -> list[str]:
    return [str(t) for t in items if isinstance(t, Token) and t.type in ("WORD", "SIZE", "ATTR")]


def _describing(said: list[str]) -> tuple[list[str], list[str]]:
    """The words of a "with ..." clause: (colour and size words, which describe the object; the
    other words, said as not used). GrammarError naming a word that changes the question ("with
    no handle"): it is never left out."""
    kept = [w for w in said if w in NEVER_IGNORED]
    if kept:
        raise GrammarError(f"I could not read '{kept[0]}' in this question", kept[0])
    return [w for w in said if w in COLOURS or w in SIZES], [w for w in said if w not in COLOURS and w not in SIZES]


def _measured_from(nps: list[NP]) -> None:
    """"the nearest chair" names one only beside the thing it is nearest to ("the nearest chair
    to the tv", or the other end of a distance); alone it is refused naming the word."""
    for np in nps:
        if np.superlative in DISTANCE_SUPERLATIVES and np.toward is None:
            raise GrammarError(f"'{np.superlative}' to what? say e.g. 'the chair {np.superlative} to the tv'",
                               np.superlative)
        _measured_from(np.alternatives + [f.other for f in np.filters])


def _one(found: Iterator[_T]) -> _T:
    """The first of `found`, a part a rule's transformer needs; GrammarError when the rule has
    none (a rule edited without its transformer), never a StopIteration: lark would wrap that as
    a VisitError that no caller says as a refusal (`read` names the word where it stopped)."""
    for item in found:
        return item
    raise GrammarError(_STOPPED)


@v_args(inline=False)
class _ToForm(Transformer):
    def start(self, items):
        form = _one(i for i in items if isinstance(i, Form))
        form.filters.extend(i for i in items if isinstance(i, Filter))     # a fronted exception
        seen = [i for i in items if isinstance(i, NP)]
        if seen:
            form = replace(form, seen_from=seen[-1])
        _fill_ones(form)
        if form.op != "distance":
            _measured_from(form.sets + [f.other for f in form.filters])
        return form

    def fronted(self, items):
        return Filter("except", items[-1])

    def strand(self, items):
        return ("strand", items[-1])

    def stranded(self, items):
        """"what is the cup on", "what's the chair next to": the things the named object stands
        in that relation to (the relation's other end)."""
        relation = _one(i[1] for i in items if isinstance(i, tuple))
        number = next((int(float(t)) for t in items if isinstance(t, Token) and t.type == "NUMBER"), None)
        np = NP(_words(items), number=number, definite=True,
                indefinite=any(isinstance(t, Token) and t.type == "INDEF" for t in items))
        return Form("list", sets=[], filters=[Filter("rel", np, relation=relation, reverse=True)])

    def where_in(self, items):
        """"where in the house is there a tv": the place words scope the question (a room, or
        the whole house)."""
        np = _one(i for i in items if isinstance(i, NP))
        place = NP(_words(items[:items.index(np)]), definite=True)
        form = self._op("where", items)
        form.filters.append(Filter("rel", place, relation="in"))
        return form

    def exists_afford(self, items):
        """"is there a glass or a cup I could drink out of": whether any object of those kinds
        affords the activity (yes or no, naming them)."""
        return replace(self.afford_kind(items[1:]), compare="exists")         # after the "is" of "is there"

    def afford_kind(self, items):
        """"which desk could I work at": the affording objects of that kind only."""
        return replace(self.afford(items), sets=[i for i in items if isinstance(i, NP)])

    def seen(self, items):
        return items[-1]

    def owner(self, items):
        return NP(_words(items), definite=True)

    def verb(self, items):
        return " ".join(str(t) for t in items if isinstance(t, Token) and t.type in ("WORD", "SIZE", "ATTR", "PARTICLE"))

    def np_pronoun(self, items):
        """"the grey one", "the ones next to the fridge": a noun phrase whose noun is the one said
        before it in the question (filled in by `_fill_ones`)."""
        ones = [str(t) for t in items if isinstance(t, Token) and t.type == "ONE"]
        np = NP(_words(items), filters=[i for i in items if isinstance(i, Filter)], definite=True,
                indefinite=any(isinstance(t, Token) and t.type == "INDEF" for t in items), pronoun=ones[-1])
        return np

    def having(self, items):
        """"with a white glaze", "having a red pattern": colour and size words describe the
        object; the other words are kept to be said as not used."""
        return ("having", _words(items))

    def purpose(self, items):
        return ("purpose", " ".join(_words(items)))

    def except_filter(self, items):
        return Filter("except", items[-1])

    def be(self, items):
        return "be"

    def relation(self, items):
        return " ".join(str(t) for t in items)

    def length(self, items):
        return (float(items[0]), str(items[1]) if len(items) > 1 else None)

    @staticmethod
    def _metres(lengths, unit=None) -> list[float]:
        """(value, unit) pairs -> metres; a number without a unit takes `unit` ("between 1 and
        2 m") or is refused (a distance needs one)."""
        out = []
        for value, own in lengths:
            u = own or unit
            if u is None:
                n = f"{value:g}"
                raise GrammarError(f"'{n}' has no unit; say e.g. '{n} m' or '{n} cm'", n)
            out.append(value * UNIT_M[u])
        return out

    @staticmethod
    def _lengths(items):
        return [i for i in items if isinstance(i, tuple)]

    def within(self, items):
        return Filter("distance", items[-1], high_m=self._metres(self._lengths(items))[0])

    def beyond(self, items):
        return Filter("distance", items[-1], low_m=self._metres(self._lengths(items))[0])

    def more_less(self, items):
        word = str(items[0])
        metres = self._metres(self._lengths(items))[0]
        if word == "more":
            return Filter("distance", items[-1], low_m=metres)
        return Filter("distance", items[-1], high_m=metres)

    def between(self, items):
        lengths = self._lengths(items)
        lo, hi = sorted(self._metres(lengths, unit=lengths[-1][1]))
        return Filter("distance", items[-1], low_m=lo, high_m=hi)

    def rel_filter(self, items):
        negated = any(isinstance(i, Token) and i.type == "NOT" for i in items)
        word = _one(i for i in items if isinstance(i, str) and not isinstance(i, Token))
        return Filter("rel", items[-1], relation=word, negated=negated)

    def dist_filter(self, items):
        f = items[-1]
        f.negated = any(isinstance(i, Token) and i.type == "NOT" for i in items)
        return f

    def pred(self, items):
        return items[-1]

    def preds(self, items):
        return [i for i in items if isinstance(i, Filter)]

    def postmod(self, items):
        return items[-1]

    def np_one(self, items):
        if len(items) == 1 and isinstance(items[0], NP):
            return items[0]             # np_closest: already a noun phrase
        words = _words(items)
        number = next((int(float(t)) for t in items if isinstance(t, Token) and t.type == "NUMBER"), None)
        sup = next((str(t) for t in items if isinstance(t, Token) and t.type in ("SUPER", "DSUPER")), None)
        nps = [i for i in items if isinstance(i, NP)]
        np = NP(words, number=number, superlative=sup, filters=[i for i in items if isinstance(i, Filter)])
        for kind, said in (i for i in items if isinstance(i, tuple)):
            if kind == "purpose":
                np.purpose = said
            else:
                used, unused = _describing(said)
                np.words += used
                np.ignored += unused
        np.definite = True
        # "next to a cup": any cup, never the one whose printed name is "cup"
        np.indefinite = any(isinstance(t, Token) and t.type == "INDEF" for t in items)
        if nps:
            np.toward = nps[-1]
        return np

    def np_or(self, items):
        return self.np(items)

    def np_closest(self, items):
        return self.np_one(items)

    def np(self, items):
        nps = [i for i in items if isinstance(i, NP)]
        if len(nps) == 1:
            return nps[0]
        joins = {str(t) for t in items if isinstance(t, Token)}
        return NP([], alternatives=nps, joined="or" if "or" in joins else "and")

    # -- operations ------------------------------------------------------------------------
    @staticmethod
    def _op(op, items, **kw) -> Form:
        sets = [i for i in items if isinstance(i, NP)]
        filters = [f for i in items if isinstance(i, list) for f in i]
        return Form(op, sets=sets, filters=filters, **kw)

    def count(self, items):
        return self._op("count", items)

    def exists(self, items):
        return self._op("exists", items)

    def bare(self, items):
        """A noun phrase alone: "the biggest bowl?" shows it, "anything on the counter?" asks
        whether there is; a bare noun ("a joke about chairs") is no question."""
        np = items[0]
        if np.superlative:
            return Form("extreme", sets=[np])
        if not np.filters:
            raise GrammarError("a noun alone is not a question")
        return Form("exists", sets=[np])

    def exists_none(self, items):
        """"is there no fridge", "are there no cups (in here)": whether there are none, asked as
        "exactly 0" (yes when none is found, no with the count when some are)."""
        return self._op("at_least", items, compare="exactly", number=0.0)

    def exists_owned(self, items):
        """"does the living room have a sofa": a sofa in that room (the owner is the scope, or an
        object the others are in)."""
        owner = _one(i for i in items if isinstance(i, NP))
        form = self._op("exists", [i for i in items if i is not owner])
        form.filters.append(Filter("rel", owner, relation="in"))
        return form

    def exists_owned_none(self, items):
        """"does the living room have no sofa", "does the kitchen not have a fridge": none of it there."""
        return replace(self.exists_owned(items), op="at_least", compare="exactly", number=0.0)

    def at_least(self, items):
        word = _one(str(t) for t in items if isinstance(t, Token) and t.type in ("MORELESS", "EXACTLY"))
        n = _one(float(t) for t in items if isinstance(t, Token) and t.type == "NUMBER")
        compare = {"more": "more", "exactly": "exactly"}.get(word, "fewer")
        return self._op("at_least", items, compare=compare, number=n)

    def count_owned(self, items):
        """"how many chairs does the kitchen have", "how many chairs do we have": the owner
        is a room (the scope) or the asker (no filter)."""
        owner = _one(i for i in items if isinstance(i, NP) and i is not items[0])
        form = self._op("count", [items[0]] + [i for i in items if isinstance(i, list)])
        if owner.words and owner.words != ["we"] and owner.words != ["you"] and owner.words != ["i"]:
            form.filters.append(Filter("rel", owner, relation="in"))
        return form

    def count_purpose(self, items):
        """"how many things can I sit on": the things that afford it."""
        np = items[0]
        np.purpose = _one(i for i in items if isinstance(i, str) and not isinstance(i, Token))
        return self._op("count", [np] + [i for i in items if isinstance(i, list)])

    def count_having(self, items):
        """"how many mugs have a red pattern": the clause's colour and size words describe them."""
        np = items[0]
        used, unused = _describing(_words(items[1:]))
        np.words += used
        np.ignored += unused
        return self._op("count", [np] + [i for i in items if isinstance(i, list)])

    def changes(self, items):
        return self._op("changes", items)

    def gone(self, items):
        return self._op("gone", items)

    def before(self, items):
        return self._op("before", items)

    def extreme_after(self, items):
        """"which is the cup closest to the sink": the distance extreme on the named set."""
        sup = _one(str(t) for t in items if isinstance(t, Token) and t.type == "DSUPER")
        other = _one(i for i in items if isinstance(i, NP))
        np = NP(_words(items), superlative=sup, toward=other, definite=True)
        return Form("extreme", sets=[np])

    def compare(self, items):
        word = _one(str(t) for t in items if isinstance(t, Token) and t.type in ("MORELESS", "COMPARE"))
        more = word in ("more", "bigger", "larger", "greater", "higher")
        return self._op("compare", items, compare="more" if more else "fewer")

    def listing(self, items):
        return self._op("list", items)

    def where(self, items):
        return self._op("where", items)

    def colour_of(self, items):
        return self._op("attribute", items, attribute="colour")

    def size_of(self, items):
        return self._op("attribute", items, attribute="size")

    def measure_named(self, items):
        word = _one(str(t) for t in items if isinstance(t, Token) and t.type == "MEASURE")
        # "the height of the table" is its own height (the box), as "how tall"
        return self._op("attribute", items, attribute={"height": "tall", "width": "width", "length": "length",
                                                       "depth": "depth", "size": "size"}[word])

    def measure_of(self, items):
        word = _one(str(t) for t in items if isinstance(t, Token) and t.type == "ATTR")
        return self._op("attribute", items, attribute=ATTRIBUTES[word])

    def extreme(self, items):
        sup = next((str(t) for t in items if isinstance(t, Token) and t.type in ("SUPER", "DSUPER")), None)
        form = self._op("extreme", items)
        if sup is None:
            return form                 # "what is the closest chair to the tv": the set says it
        if sup in DISTANCE_SUPERLATIVES:
            head, other = form.sets[0], form.sets[1]
            head.superlative, head.toward = sup, other
            form = replace(form, sets=[head])
        else:
            # "which cup is the biggest" / "which is the biggest cup": one set, the word on it
            words = [w for s in form.sets for w in s.words]
            number = next((s.number for s in form.sets if s.number is not None), None)
            filters = [f for s in form.sets for f in s.filters]
            form = replace(form, sets=[NP(words, number=number, superlative=sup, filters=filters, definite=True)])
        return form

    def distance(self, items):
        """"how far is A from B", "the gap between A and B", "how far apart are A and the nearest
        B": two sets; a nearest / farthest one without its own other end is measured from the other."""
        form = self._op("distance", items)
        if len(form.sets) == 1 and len(form.sets[0].alternatives) == 2 \
                and any(a.superlative in DISTANCE_SUPERLATIVES for a in form.sets[0].alternatives):
            form = replace(form, sets=list(form.sets[0].alternatives))
        if len(form.sets) == 2:
            for mine, other in (form.sets, form.sets[::-1]):
                if mine.superlative in DISTANCE_SUPERLATIVES and mine.toward is None:
                    mine.toward = other
        return form

    def room_count(self, items):
        return Form("room_count", sets=[NP(_words(items))] if _words(items) else [])

    def rooms_with(self, items):
        return self._op("rooms", items)

    def rooms_counted(self, items):
        return self._op("rooms_counted", items)

    @staticmethod
    def _quantity(items) -> tuple[str, float]:
        word = _one(str(t) for t in items if isinstance(t, Token) and t.type in ("MORELESS", "EXACTLY"))
        n = _one(float(t) for t in items if isinstance(t, Token) and t.type == "NUMBER")
        return {"more": "more", "exactly": "exactly"}.get(word, "fewer"), n

    def rooms_over(self, items):
        """"which rooms have more than two chairs", "in which rooms are there exactly 2 cups": the
        rooms whose count of the kind holds the condition."""
        compare, n = self._quantity(items)
        form = self._op("rooms", items, compare=compare, number=n)
        for np in form.sets:        # "more than 1 chair": any chair, never the one named "chair"
            np.indefinite = True
        return form

    def rooms_counted_over(self, items):
        """"how many rooms have more than 2 chairs": the same rooms, counted."""
        return replace(self.rooms_over(items), op="rooms_counted")

    def rooms_but_not(self, items):
        """"which rooms have a chair but no fridge": the rooms holding the first, none of the second."""
        nps = [i for i in items if isinstance(i, NP)]
        return self._op("rooms", [nps[0]] + [i for i in items if isinstance(i, list)], lacking=[nps[1]])

    def rooms_without(self, items):
        """"which rooms have no fridge", "rooms without a fridge": the rooms holding none of it."""
        return self._op("rooms", [i for i in items if isinstance(i, list)],
                        lacking=[i for i in items if isinstance(i, NP)])

    def rooms_counted_without(self, items):
        """"how many rooms have no fridge": the same rooms, counted."""
        return replace(self.rooms_without(items), op="rooms_counted")

    @staticmethod
    def _bigger(items) -> str:
        word = _one(str(t) for t in items if isinstance(t, Token) and t.type == "COMPARE")
        return "more" if word in ("bigger", "larger", "greater", "higher", "taller", "wider", "longer") else "fewer"

    def bigger(self, items):
        """"is the cup bigger than the book": box volumes; higher / lower: box tops above the
        floor; taller / shorter: box heights; wider / narrower / longer: the box's larger
        horizontal side."""
        said = set(map(str, items))
        key = "top" if said & {"higher", "lower"} else "height" if said & {"taller", "shorter"} \
            else "width" if said & {"wider", "narrower", "longer"} else "volume"
        return self._op("size_compare", items, compare=self._bigger(items), attribute=key)

    def bigger_which(self, items):
        """"which is bigger, the cup or the book": the same, naming the winner. "the tv on the
        shelf or the table" (one phrase, the "or" read inside the relation) is two things here:
        the last alternative of the trailing relation is the second one (`_last_or`)."""
        form = self.bigger(items)
        if len(form.sets) == 1 and len(form.sets[0].alternatives) == 2:
            form = replace(form, sets=list(form.sets[0].alternatives))
        if len(form.sets) == 1:
            form = replace(form, sets=_last_or(form.sets[0]))
        if len(form.sets) != 2:
            raise GrammarError("compare two things, e.g. 'which is bigger, the cup or the book'")
        return replace(form, op="size_which")

    def room_most(self, items):
        word = _one(str(t) for t in items if isinstance(t, Token) and t.type in ("MOSTFEW", "MORELESS"))
        n = next((float(t) for t in items if isinstance(t, Token) and t.type == "NUMBER"), None)
        return self._op("room_most", items, compare="more" if word in ("most", "more") else "fewer", number=n)

    def room_more(self, items):
        """"which room has more chairs, the kitchen or the study": the most among the rooms named."""
        nps = [i for i in items if isinstance(i, NP)]
        form = self.room_most([i for i in items if not isinstance(i, NP)] + nps[:1])
        return replace(form, among=list(nps[1].alternatives) or [nps[1]])

    def rooms_next(self, items):
        return self._op("rooms_next_to", items)

    def rooms_next_hold(self, items):
        return self._op("rooms_next_hold", items)

    def route(self, items):
        verb = next(str(t) for t in items if isinstance(t, Token) and t.type == "WORD")
        if verb not in ROUTE_VERBS:
            raise GrammarError(f"I could not read '{verb}' in this question", verb)
        return Form("route", sets=[i for i in items if isinstance(i, NP)])

    def route_back(self, items):
        """"how do I get to the bedroom from the kitchen": the same way, said goal first."""
        form = self.route(items)
        form.sets.reverse()
        return form

    def afford(self, items):
        verb = _one(i for i in items if isinstance(i, str) and not isinstance(i, Token))
        filters = [f for i in items if isinstance(i, list) for f in i]
        return Form("affordance", verb=verb, filters=filters)

    def afford_in(self, items):
        """"where in the kitchen could I store things" (the pre-pass's order for "where could I
        store things in this kitchen"): the place words scope the activity, as in `where_in`."""
        form = self.afford([i for i in items if not isinstance(i, Token)])
        form.filters.append(Filter("rel", NP(_words(items), definite=True), relation="in"))
        return form


def _last_or(np: NP) -> list[NP]:
    """"the tv on the shelf or the dining table" as two things: [the tv on the shelf, the dining
    table] (the last "or" alternative of the phrase's trailing relation, at any depth); [np]
    when its last relation names no alternatives."""
    if np.alternatives or not np.filters or np.filters[-1].kind != "rel":
        return [np]
    other = np.filters[-1].other
    if other.alternatives:          # a relation's other end is always said with "or" (np_or)
        rest = other.alternatives[:-1]
        np.filters[-1].other = rest[0] if len(rest) == 1 else NP([], alternatives=rest, joined="or")
        return [np, other.alternatives[-1]]
    inner = _last_or(other)
    if len(inner) == 2:
        np.filters[-1].other = inner[0]
        return [np, inner[1]]
    return [np]


def _noun_phrases(form: Form) -> list[NP]:
    """Every noun phrase of a form in the order said: its sets, their filters, the form's filters."""
    out: list[NP] = []

    def visit(np: NP) -> None:
        out.append(np)
        for a in np.alternatives:
            visit(a)
        for f in np.filters:
            visit(f.other)
        if np.toward is not None:
            visit(np.toward)

    for np in list(form.sets) + [f.other for f in form.filters] + list(form.lacking) + list(form.among):
        visit(np)
    return out


def _fill_ones(form: Form) -> None:
    """"how many cups other than the grey one", "is the white book bigger than the purple one":
    "one" stands for the noun of the first noun phrase before it that names one (its colour and
    size words left out); "ones" for its plural. GrammarError naming 'one' when none is said."""
    from sg3d.queries.lexicon import lemma

    nps = _noun_phrases(form)
    for np in nps:
        if np.pronoun is None:
            continue
        noun = next(([w for w in x.words if w not in COLOURS and w not in SIZES] for x in nps
                     if x.pronoun is None and [w for w in x.words if w not in COLOURS and w not in SIZES]), [])
        if not noun:
            raise GrammarError(f"'{np.pronoun}' of what? name the kind, e.g. 'the grey cup'", np.pronoun)
        if np.pronoun == "one":
            noun = noun[:-1] + [lemma(noun[-1])]
        np.words = np.words + noun
        np.pronoun = None


def read(text: str) -> Form:
    """Normalised question text -> Form; GrammarError naming the word where reading stopped."""
    try:
        tree = parser().parse(text)
    except UnexpectedInput as exc:
        word = _word_at(text, exc)
        raise GrammarError("the grammar cannot read this question", word) from None
    except LarkError as exc:
        raise GrammarError(f"the grammar cannot read this question ({exc.__class__.__name__})") from None
    except Exception as exc:        # any other failure of the parser is a refusal
        raise _stopped(text, None, exc) from None
    try:
        return _ToForm().transform(tree)
    except VisitError as exc:       # a GrammarError raised while building the form
        err = exc.orig_exc
        if isinstance(err, GrammarError) and (err.word is not None or str(err) != _STOPPED):
            raise err from None
        raise _stopped(text, exc.obj, err) from None
    except Exception as exc:        # any other failure of the reader is a refusal
        raise _stopped(text, tree, exc) from None


_STOPPED = "the grammar stopped reading this question"


def _stopped(text: str, where, exc: BaseException) -> ReaderFailure:
    """A failure of a rule's transformer (a bug, e.g. a StopIteration or an IndexError) as a
    refusal naming the first word of the part being read there; logged with its traceback."""
    tokens = list(where.scan_values(lambda v: isinstance(v, Token))) if isinstance(where, Tree) else []
    word = str(tokens[0]) if tokens else next(iter(text.split()), None)
    log.warning("the question reader failed on %r at %r: %s: %s", text, word, exc.__class__.__name__, exc,
                exc_info=(type(exc), exc, exc.__traceback__))
    return ReaderFailure(f"{_STOPPED} at '{word}'", word)


def _word_at(text: str, exc: UnexpectedInput) -> Optional[str]:
    pos = getattr(exc, "pos_in_stream", None)
    if pos is None:
        token = getattr(exc, "token", None)
        pos = getattr(token, "start_pos", None)
    if pos is None or pos >= len(text):
        return None
    return text[pos:].split()[0] if text[pos:].split() else None
