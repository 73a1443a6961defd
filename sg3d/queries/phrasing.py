"""People's phrasing -> the plain text the grammar reads: frames, apostrophes, units, typos.

Every rewrite that changes a word is reported (the notes of `fix_typos`, the asides in
`Phrased.dropped`), so an answer can say how it read the question ("read 'chiars' as 'chairs'"). Typos are fixed against a fixed vocabulary with
rapidfuzz (a small edit distance), never with the embedding model, so a typo costs no model load.
"""
from __future__ import annotations

import functools
import re
import unicodedata
from dataclasses import dataclass, field
from typing import Callable, Iterable

# question frames that carry no meaning: stripped from the front (longest first)
FRAMES = (
    "could you please tell me", "can you please tell me", "could you tell me", "can you tell me",
    "would you tell me", "please tell me", "tell me", "do you know", "i would like to know",
    "i want to know", "id like to know", "i d like to know", "i would love to know", "i wonder", "could you say", "can you say", "please", "hey", "hi", "so", "ok",
    "okay", "excuse me",
    # polite frames: "would you mind telling me ...", "i was wondering ..."
    "would you mind telling me", "would you mind telling us", "would you mind saying", "do you mind telling me",
    "do you happen to know", "would you happen to know", "could you let me know", "can you let me know",
    "i was wondering", "i am wondering", "im wondering", "i was curious", "i am curious", "im curious",
    "i was hoping you could tell me", "can you tell us", "could you tell us",
)
_FRAME_RE = re.compile(r"^(?:(?:" + "|".join(map(re.escape, sorted(FRAMES, key=len, reverse=True))) + r")\b[ ,]*)+")
_TAIL_RE = re.compile(r"[ ,]*\b(?:please|thanks|thank you|for me|for us)$")
# "can you show me what is on the table", "tell me whether ...": a request that frames a question
_SHOW_FRAME = re.compile(r"^(?:(?:can|could|would|will) you )?(?:show|tell|list|give) (?:me|us) "
                         r"(?=(?:what|which|where|how|whether|if)\b)")
# "tell me where the sink is" -> "where is the sink": the embedded question's verb moves back
_EMBEDDED = re.compile(r"^(what color|what size|where|what|which|how many \w+(?: \w+)?|how far|how tall|how high|how big) "
                       r"(the [\w\s-]+?|[\w\s-]+?) (is|are)$")
_EMBEDDED_THERE = re.compile(r"^how many (.+?) there (?:is|are)\b(.*)$")

# "in the room", "here": the scope given by --room (or the whole store); "my room" may be a
# room's name and is left to the room look-up
HERE = re.compile(r"\b(?:(?:in|inside|within) (?:the|this|our) (?:room|place|space|area)|in here|here)\b")

CONTRACTIONS = {
    "what's": "what is", "whats": "what is", "where's": "where is", "wheres": "where is",
    "there's": "there is", "theres": "there is", "which's": "which is", "that's": "that is",
    "how's": "how is", "it's": "it is", "isn't": "is not", "aren't": "are not", "don't": "do not",
    "doesn't": "does not", "arent": "are not", "isnt": "is not", "whos": "who is", "r": "are",
    "u": "you", "pls": "please", "plz": "please",
}
# posture verbs say nothing the graph stores beyond the relation after them: "what sits on X"
_REL_AHEAD = (r"(?= (?:on|under|in|inside|above|below|next|near|beside|by|over|underneath|beneath|close|within|"
              r"less|more|closer|nearer|farther|further|between)\b)")
POSTURE = [
    # "the chairs pulled up to the table": how they stand says nothing the graph stores
    (re.compile(r"\b(is|are) (?:pulled up|pulled|pushed up|pushed in|pushed|tucked in|tucked|drawn up|lined up|grouped|"
                r"gathered|clustered|arranged)\b" + _REL_AHEAD), r"\1"),
    (re.compile(r"\b(is|are) (?:mounted|placed|located|sitting|standing|lying|hanging|kept|stored|resting|put|"
                r"positioned|found|situated|set|lieing)\b"), r"\1"),
    (re.compile(r"\b(?:lies|sits|stands|rests|hangs|stays)\b" + _REL_AHEAD), "is"),
    # "the cups that sit on the table", but not "what can i sit on" (an activity)
    (re.compile(r"(?<!\bcan i )(?<!\bcould i )(?<!\bshould i )(?<!\bmight i )(?<!\bmay i )(?<!\bto )\b(?:lie|sit|stand|rest|hang)\b" + _REL_AHEAD), "are"),
    (re.compile(r" (?:lying|sitting|standing|resting|hanging|placed|located|kept|stored|positioned|situated|"
                r"mounted|found|put)\b" + _REL_AHEAD), ""),
]
# "is there somewhere i can sit" -> "where can i sit"
_PLACE_TO = re.compile(r"^(?:is there|do you know|do you have) (?:somewhere|anywhere|a place|any place|something|"
                       r"anything)(?: where| that| which)? i (?:can|could) (.+)$")
_TRAILING = re.compile(r"\b(?:anywhere|at all|around here|in here|here|located|situated|placed|kept|stored)$")
# adverbs that change nothing the graph can answer
# "exactly" stays before a number ("exactly 4 chairs" is a condition)
_ADVERBS = re.compile(r"\b(?:precisely|actually|currently|roughly|approximately|really|just|"
                      r"exactly(?! (?:\d|zero|one|two|three|four|five|six|seven|eight|nine|ten)\b))\b ?")
# "the cups that are near the sink": a relative clause says what the set's filters say
_RELATIVE = re.compile(r"(?<=\w) (?:that|which|who) (?:are|is) ")
# "how many of the chairs": the chairs
_OF_THE = re.compile(r"^how many of (?:the|these|those|all the) ")
# "the smallest chair, what colour is it": the phrase goes where "it" stands
_DISLOCATED = re.compile(r"^(.+?) (what color|what size|how big|how tall|how high|where) (is|are) (?:it|they|that)$")
# "the closest one to the cup": "one" stands for the noun already said
_ONE = re.compile(r"\b(closest|nearest|farthest|furthest|biggest|largest|smallest|tiniest|tallest|shortest|"
                  r"highest|lowest) ones?\b")

# number words the grammar reads as numbers
NUMBER_WORDS = {
    "zero": "0", "one": "1", "two": "2", "three": "3", "four": "4", "five": "5", "six": "6",
    "seven": "7", "eight": "8", "nine": "9", "ten": "10", "a couple of": "2", "half a": "0.5",
    "half": "0.5", "a quarter of a": "0.25", "quarter of a": "0.25",
}
UNITS = {"m": "m", "metre": "m", "metres": "m", "meter": "m", "meters": "m", "cm": "cm",
         "centimetre": "cm", "centimetres": "cm", "centimeter": "cm", "centimeters": "cm",
         "mm": "mm", "millimetre": "mm", "millimetres": "mm", "millimeter": "mm", "millimeters": "mm",
         "ft": "ft", "foot": "ft", "feet": "ft", "inch": "inch", "inches": "inch"}
_UNIT_RE = re.compile(r"(\d+(?:\.\d+)?)\s*(" + "|".join(sorted(map(re.escape, UNITS), key=len, reverse=True))
                      + r")\b")


@dataclass
class Phrased:
    text: str
    dropped: list[str] = field(default_factory=list)    # asides not used ("(the big one)")


def fold(text: str) -> str:
    """Lower case, curly quotes straightened, accents kept (room names like 'küche')."""
    text = unicodedata.normalize("NFC", text).lower()
    return text.replace("\u2019", "'").replace("\u2018", "'").replace("\u00d7", " x ")


def _contractions(text: str) -> str:
    # "which one's bigger": "one's" is "one is" after a question word, a possessive elsewhere
    text = re.sub(r"\b(which|what) one's\b", r"\1 one is", text)
    for k, v in CONTRACTIONS.items():
        text = re.sub(rf"(?<![\w']){re.escape(k)}(?![\w'])", v, text)
    return text


def _numbers(text: str) -> str:
    """Number words -> digits ("half a metre" -> "0.5 m", "one and a half" -> "1.5"), units
    glued to numbers split ("50cm" -> "50 cm") and unit words made one spelling."""
    for word, digit in (("one", "1"), ("two", "2"), ("three", "3"), ("four", "4"), ("five", "5")):
        text = re.sub(rf"\b{word} and a half\b", f"{digit}.5", text)
    text = re.sub(r"\b(\d+) and a half\b", r"\1.5", text)
    for k in sorted(NUMBER_WORDS, key=len, reverse=True):
        if k == "one":      # also a pronoun ("the red one"): a number only before a unit
            text = re.sub(r"\bone(?= (?:" + "|".join(UNITS) + r")\b)", "1", text)
        else:
            text = re.sub(rf"\b{re.escape(k)}\b", NUMBER_WORDS[k], text)
    text = re.sub(r"(\d)(?=[a-z])", r"\1 ", text)
    return _UNIT_RE.sub(lambda m: f"{m.group(1)} {UNITS[m.group(2)]}", text)


def reorder_embedded(text: str) -> str:
    """'where the sink is' -> 'where is the sink' (what is left of 'can you tell me where ...')."""
    m = _EMBEDDED_THERE.match(text)
    if m:
        return f"how many {m.group(1)} are there{m.group(2)}"
    m = _EMBEDDED.match(text)
    if m and not re.search(r"\b(is|are)\b", m.group(2)):
        return f"{m.group(1)} {m.group(3)} {m.group(2)}"
    return text


def strip_frames(text: str) -> str:
    """Politeness and question frames off both ends: "can you tell me ... please"."""
    prev = None
    while prev != text:
        prev = text
        text = _FRAME_RE.sub("", text).strip(" ,")
        text = _TAIL_RE.sub("", text).strip(" ,")
        text = _SHOW_FRAME.sub("", text)
    return text


# round-two phrasings, rewritten to forms the grammar reads
_COLOURS = r"(red|orange|yellow|green|blue|purple|pink|brown|black|white|grey|gray|silver|golden)"
REPHRASE: list[tuple[re.Pattern[str], str | Callable[[re.Match[str]], str]]] = [
    # "where can someone take a seat" = "where can i sit"
    (re.compile(r"^(where|what) (can|could) (?:someone|somebody|anyone|anybody|one|people|we|a person) "),
     r"\1 \2 i "),
    (re.compile(r"\b(?:take|have) a seat\b"), "sit"),
    # "how far apart are the 2 cups": the cups, two of them
    (re.compile(r"^how far apart (is|are) (?:the )?(?:2|both|both of the|both the) "), r"how far apart \1 the "),
    # "what is red (in the kitchen)", "which things are white": the things of that colour
    (re.compile(r"^(what|which)(?: (?:things|objects|items))? (?:is|are) " + _COLOURS + r"\b"),
     r"\1 \2 things are there"),
    # "which chairs are red": the red chairs
    (re.compile(r"^(what|which) (?!one\b|ones\b)([a-z-]+) (?:is|are) " + _COLOURS + r"$"), r"\1 \3 \2 are there"),
    # "the number of chairs in the kitchen" (what is left of "could you tell me ...")
    (re.compile(r"^the number of "), "what is the number of "),
    # "whereabouts is the sink" = "where is the sink"
    (re.compile(r"^whereabouts\b"), "where"),
    # "any mugs around?", "any sinks about": whether there are
    (re.compile(r"^any (?!thing\b|one\b|body\b|where\b)(.+?)(?: around| about)?$"), r"are there any \1"),
    # "have you spotted a sink", "did you notice any mugs": whether there is
    (re.compile(r"^(?:have|did|do) you (?:ever )?(?:spotted|spot|seen|see|noticed|notice|found|find|come across|"
                r"came across|got)(?= (?:a|an|any|some)\b)"), "is there"),
    # "(i wonder) whether there is a tv" = "is there a tv"
    (re.compile(r"^(?:whether|if) there (is|are)\b"), r"\1 there"),
    # "the desks in the study, how many are there": the dislocated noun phrase goes back in
    (re.compile(r"^(?:the |all the )?(.+?) how many (are there|is there|do you see|do you have|do we have|"
                r"can you see|are in it|does it have)$"), r"how many \1 \2"),
    # "how many objects does this room hold": the room of the scope
    (re.compile(r"\b(?:does|do) (?:this|the|our|my|that) (?:room|place|space) (?:have|hold|contain)\b"), "are there"),
    # "how many chairs across all the rooms": everywhere the scope holds (a count only: "is there
    # a chair in every room" asks something else, and "in each room" asks for a count per room)
    (re.compile(r"^(how many .+?) (?:across|in|throughout|over) (?:all (?:of )?(?:the )?rooms|the whole house)\b"),
     r"\1 in the house"),
    # "in which rooms can i find cups" = "which rooms have cups"
    (re.compile(r"^in (which|what) rooms? (?:can|could|do|would|will) (?:i|you|we|one) (?:find|see|get|spot) "),
     r"\1 rooms have "),
    # "the distance between the 2 cups": between the cups, the two of them
    (re.compile(r"\bbetween (?:the )?(?:2|both|both of the|both the) "), "between the "),
    # "how many metres between the cup and the tv", "how many cm is it between ...": the gap, in that unit
    (re.compile(r"^how many (" + "|".join(sorted(map(re.escape, UNITS), key=len, reverse=True))
                + r") (?:(?:is|are) (?:it |there )?)?between\b"), lambda m: f"how many {UNITS[m.group(1)]} between"),
    # "how many metres is the cup from the sink", "how many cm away is it": how far
    (re.compile(r"^how many (?:m|cm|mm|ft|inch|metres|meters|centimetres|centimeters|millimetres|millimeters|feet|"
                r"inches|steps) (?:away )?(is|are) "), r"how far \1 "),
    # "how far is the tv from the fridge in centimetres": the unit of the answer, not a room
    (re.compile(r" in (?:m|cm|mm|ft|inch|metres|meters|centimetres|centimeters|millimetres|millimeters|feet|"
                r"inches)$"), ""),
    # "how far is the closest chair from the fridge": the distance of the closest pair
    (re.compile(r"^how far (is|are) (?:the )?(?:closest|nearest) (.+?) (from|to) "), r"how far \1 the \2 \3 "),
    # "exactly one tv", "more than one chair": a number
    (re.compile(r"\b(exactly|than|least|most) one\b"), r"\1 1"),
]
# "at least 2" = "more than 1", "at most 2" = "fewer than 3" (whole numbers)
_AT_LEAST = re.compile(r"\bat (least|most) (\d+)\b(?!\.\d)")


def rephrase(text: str) -> str:
    """The phrasings of REPHRASE and "at least / at most N" as the grammar's words."""
    for regex, repl in REPHRASE:
        text = regex.sub(repl, text)
    return _AT_LEAST.sub(lambda m: f"more than {int(m.group(2)) - 1}" if m.group(1) == "least"
                         else f"fewer than {int(m.group(2)) + 1}", text)


# one spelling for phrases the grammar reads under another: "other than the sink" = "except
# the sink", "as seen from" = "seen from", "to the left of" = "left of", "A as well as B" = "A and B"
SAME_WORDS = [
    (re.compile(r"\b(?:that|which|who) (?:is|are) not (a|an|the|any) "), r"except \1 "),
    # "something on the cabinet that is not white", "things that are not cups": all but those
    (re.compile(r"\b(?:that|which|who) (?:is|are) not(?! (?:on|under|in|inside|above|below|next|near|beside|by|"
                r"over|underneath|beneath|close|within|less|more|fewer|closer|nearer|farther|further|between|"
                r"behind|left|right|adjacent|alongside|around|onto|far)\b) "), "except "),
    (re.compile(r"\b(?:other than|apart from|aside from|but not|save for)\b"), "except"),
    (re.compile(r"\bas (seen|viewed|looking) from\b"), r"\1 from"),
    (re.compile(r"\bto the (left|right) of\b"), r"\1 of"),
    (re.compile(r"^(which|what) one (is|are)\b"), r"\1 \2"),
    # "somewhere to sit", "places to sit", "something to drink from": what affords it
    (re.compile(r"^(?:is there|are there|do you have|do you know) (?:somewhere|anywhere|a place|any place|"
                r"places|a spot|something|anything)(?: for me)? to "), "where can i "),
    (re.compile(r"\b(places?|spots?|things?|somewhere|something|anything|anywhere) to (?=\w)"), r"\1 for "),
    (re.compile(r"\bas well as\b"), "and"),
]
# "the kitchen's chairs" = "the chairs in the kitchen"; "the cup's colour" = "the colour of the cup"
_POSSESSIVE_MEASURE = re.compile(r"\b(?:the )?((?:[\w-]+ )?room|[\w-]+)'s (color|size|height|width|length)\b")
_POSSESSIVE_LIST = re.compile(r"^(what|which) (is|are) (?:the )?((?:[\w-]+ )?room|[\w-]+)'s ([\w-]+(?: [\w-]+)?)\s*[?.!]*\s*$")
_POSSESSIVE = re.compile(r"\b(?:the )?((?:[\w-]+ )?room|[\w-]+)'s ([\w-]+(?: [\w-]+)?)"
                         r"(?= (?:is|are|in|on|next|near|there)\b|\s*[?.!,]*\s*$|\s*[,:;])")


def _possessives(text: str) -> str:
    text = _POSSESSIVE_MEASURE.sub(r"the \2 of the \1", text)
    text = _POSSESSIVE_LIST.sub(r"\1 \4 \2 in the \3", text)     # "what are the kitchen's chairs"
    return _POSSESSIVE.sub(r"the \2 in the \1", text)


_UNIT_WORDS = r"(m|cm|mm|ft|inch|inches|metres|meters|centimetres|centimeters|millimetres|millimeters|feet|foot)"
_ASKED_UNIT = [re.compile(r"^how many " + _UNIT_WORDS + r" (?:away )?(?:is|are|between)\b"),
               re.compile(r"\bhow far\b.* in " + _UNIT_WORDS + r"$")]


def asked_unit(text: str) -> str | None:
    """The unit a distance is asked in ("how far ... in centimetres", "how many metres is ..."),
    as a key of vocabulary.UNIT_M; None when none is named."""
    said = " ".join(re.sub(r"[^\w' ]+", " ", _contractions(fold(text))).split())
    said = strip_frames(said)
    for regex in _ASKED_UNIT:
        m = regex.search(said)
        if m:
            return UNITS.get(m.group(1))
    return None


def tidy(question: str) -> Phrased:
    """Question -> normalised words (no typo fixing yet): lower case, asides dropped,
    contractions and frames undone, numbers and units read, punctuation gone."""
    dropped: list[str] = []
    text = fold(question)
    while True:
        found = re.findall(r"\([^()]*\)|\[[^\[\]]*\]", text)
        if not found:
            break
        dropped += [f.strip() for f in found]
        text = re.sub(r"\([^()]*\)|\[[^\[\]]*\]", " ", text)
    text = _contractions(text)
    text = text.replace("colour", "color")
    text = _possessives(text)
    # "A / B", "A + B", "A and/or B" name alternatives: read as "A or B"
    text = re.sub(r"\band\s*/\s*or\b", " or ", text)
    text = re.sub(r"\s*[/+&]\s*", " or ", text)
    # keep letters (any script), digits, decimal points between digits, hyphens inside words
    text = re.sub(r"(?<=\d)\.(?=\d)", "\u2024", text)
    text = re.sub(r"(?<=\w)-(?=\w)", "\u2010", text)
    text = re.sub(r"[^\w\u2024\u2010' ]+", " ", text).replace("_", " ")
    text = text.replace("\u2024", ".").replace("\u2010", "-").replace("'", "")
    text = " ".join(text.split())
    text = strip_frames(text)
    for regex, repl in POSTURE:
        text = regex.sub(repl, text)
    text = _PLACE_TO.sub(r"where can i \1", text)
    text = _ADVERBS.sub("", text)
    for regex, repl in SAME_WORDS:
        text = regex.sub(repl, text)
    text = _RELATIVE.sub(" ", text)
    text = _OF_THE.sub("how many ", text)
    text = _DISLOCATED.sub(r"\2 \3 \1", text)
    text = _ONE.sub(r"\1", text)
    text = _TRAILING.sub("", text).strip()
    text = reorder_embedded(text)
    text = HERE.sub(" ", text)
    text = rephrase(_numbers(text))
    return Phrased(" ".join(text.split()), dropped=dropped)


def max_edits(word: str) -> int:
    """The edit distance a typo may have: none for words under 4 letters (too many neighbours),
    one up to 6 letters, two beyond."""
    return 0 if len(word) < 4 else (1 if len(word) <= 6 else 2)


@functools.lru_cache(maxsize=4096)
def _closest(word: str, vocab: frozenset) -> str | None:
    from rapidfuzz import process
    from rapidfuzz.distance import DamerauLevenshtein

    limit = max_edits(word)
    if not limit:
        return None
    found = process.extract(word, vocab, scorer=DamerauLevenshtein.distance, score_cutoff=limit, limit=3)
    if not found:
        return None
    best = min(d for _, d, _ in found)
    winners = sorted({w for w, d, _ in found if d == best})
    if len(winners) > 1:
        # people rarely mistype a word's first letter: among equally close words, that decides
        winners = [w for w in winners if w[0] == word[0]]
    # still two words equally close: the typo is ambiguous and stays as written
    return winners[0] if len(winners) == 1 else None


# A word counts as common English when pyspellchecker's English frequency list saw it this often
# (25,246 ASCII words: "sitting" and "bowel" are in, typos such as "chiars" or "kitchn" are not).
COMMON_WORD_MIN_COUNT = 500


@functools.cache
def common_words() -> frozenset[str]:
    """Common English words, from the English word-frequency list the PyPI package
    pyspellchecker ships (read where it is installed): a correctly spelled word is never a typo,
    so "sitting" is not read as "cutting"."""
    import gzip
    import json
    from importlib import resources

    data = resources.files("spellchecker") / "resources" / "en.json.gz"
    counts = json.loads(gzip.decompress(data.read_bytes()))
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


def fix_typos(text: str, vocab: frozenset, known: Iterable[str] = ()) -> tuple[str, list[str]]:
    """Each unknown word (outside `vocab`, not a common English word, not a number) that is
    one edit from exactly one question word (QUESTION_WORDS), or else within `max_edits` of
    exactly one vocabulary word, is read as that word; the notes say so."""
    keep = set(known)
    out, notes = [], []
    words = text.split()
    for i, w in enumerate(words):
        if w in keep or is_word(w, vocab):
            out.append(w)
            continue
        fixed = _question_word(w, words[i + 1] if i + 1 < len(words) else None) or _closest(w, vocab)
        if fixed is None:
            out.append(w)
        else:
            out.append(fixed)
            notes.append(f"read '{w}' as '{fixed}'")
    return " ".join(out), notes


def said_word(question: str, text: str, word: str) -> str:
    """The words of `question` (as the user typed them) that `word` of the rewritten `text` came
    from: itself where the user typed it, else the span a rewrite or a typo fix put in its place
    ("except" <- "apart from", "what" <- "waht", "is" <- "what's")."""
    import difflib

    said = [w.strip(".'") for w in re.sub(r"[^\w'. -]+", " ", fold(question)).split()]
    said = [w for w in said if w]
    if word in said:
        return word
    words = text.split()
    if word not in words:
        return word
    at = words.index(word)
    shown = [w.lower() for w in said]
    # each typed word as the rewrite reads it alone (contractions undone, numbers as digits)
    parts: list[str] = []
    origin: list[int] = []
    for i, w in enumerate(shown):
        for p in _numbers(_contractions(w)).split() or [w]:
            parts.append(p)
            origin.append(i)
    for tag, i1, i2, j1, j2 in difflib.SequenceMatcher(a=parts, b=words, autojunk=False).get_opcodes():
        if j1 <= at < j2 and tag != "equal" and i2 > i1:
            typed = sorted({origin[i] for i in range(i1, i2)})
            return " ".join(said[i] for i in range(typed[0], typed[-1] + 1))
        if j1 <= at < j2 and tag == "equal":
            return said[origin[i1 + at - j1]]
    return word
