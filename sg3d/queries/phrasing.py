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
    # "could you check the telly's colour", "let me know how many ...": asking to find out
    "could you please check", "can you please check", "could you check", "can you check", "please check",
    "would you check", "check", "could you find out", "can you find out", "find out", "let me know",
    "let us know", "i need to know", "i would like to know", "i wish to know", "any idea", "any ideas",
    "do you have any idea", "have you any idea", "have you got any idea", "got any idea", "any clue",
    "quick question", "question", "just wondering", "out of curiosity", "by the way", "btw", "um", "uh",
    "erm", "well", "yo", "do you remember", "do you recall", "can you remind me", "could you remind me",
    "remind me",
    # leading interjections and forms of address: "quick, where's the sink", "robot, how many ..."
    "quick", "quickly", "sorry", "sorry to bother you", "sorry to bother", "pardon me", "robot", "hello", "hiya",
    "hey there", "hi there", "hello there", "hmm", "hm", "oh", "ah", "alright", "all right", "oi", "dear robot",
    # more polite frames: "would you be so kind as to tell me ...", "would it be possible to ..."
    "would you be so kind as to tell me", "could you be so kind as to tell me", "would you be so kind as to",
    "could you be so kind as to", "be so kind as to", "would you kindly tell me", "could you kindly tell me",
    "kindly tell me", "would it be possible to tell me", "would it be possible for you to tell me",
    "is it possible to tell me", "is it possible for you to tell me", "would it be possible to know",
    "would it be possible for you to", "would it be possible to", "i was wondering if you could tell me",
    "i was wondering whether you could tell me", "i wondered", "may i ask", "might i ask", "can i ask",
    "could i ask", "i would appreciate it if you could tell me", "i would be grateful if you could tell me",
    "do you happen to remember", "would you know", "you would not happen to know",
    "you wouldnt happen to know", "you dont happen to know", "you do not happen to know",
    # "kindly tell me ...", "ugh where's the monitor", "quick one do we have ...": said before a question
    "kindly", "ugh", "argh", "oops", "whoops", "er", "uh oh", "oh well", "gosh", "quick one", "one more thing",
    "one more question", "one last thing", "one last question", "another thing", "last question",
    "hey robot", "hi robot", "ok robot", "okay robot",
)
_FRAME_RE = re.compile(r"^(?:(?:" + "|".join(map(re.escape, sorted(FRAMES, key=len, reverse=True))) + r")\b[ ,]*)+")
_TAIL_RE = re.compile(r"[ ,]*\b(?:please|thanks|thank you|thx|cheers|for me|for us|if you can|if you could|"
                      r"if possible|if you know|by any chance|do you know|you know|mate|buddy|quick|quickly|robot|kindly)$")
# "can you show me what is on the table", "tell me whether ...": a request that frames a question
_SHOW_FRAME = re.compile(r"^(?:(?:can|could|would|will) you )?(?:show|tell|list|give) (?:me|us) "
                         r"(?=(?:what|which|where|how|whether|if|the (?:number|color|height|width|length|depth|"
                         r"size|distance) of)\b)")
# "tell me where the sink is" -> "where is the sink": the embedded question's verb moves back
_EMBEDDED = re.compile(r"^(what color|what size|where|what|which|how many \w+(?: \w+)?|how far|how tall|how high|how big) "
                       r"(the [\w\s-]+?|[\w\s-]+?) (is|are)$")
_EMBEDDED_THERE = re.compile(r"^how many (.+?) there (?:is|are)\b(.*)$")

# "in the room", "here": the scope given by --room (or the whole store); "my room" may be a
# room's name and is left to the room look-up
HERE = re.compile(r"\b(?:(?:in|inside|within) (?:the|this|our) (?:room|place|space|area)|in here|here)\b")
# "what is in the room next to the kitchen": what the rooms a doorway joins to it hold (the
# grammar's `rooms_next_hold`), never "in the room" as the scope
_ROOM_NEXT = re.compile(r"^(?:what|which things?|what things?) (?:is|are) (?:there )?(?:in|inside) the rooms? "
                        r"(next to|adjacent to|beside|near) (.+)$")

CONTRACTIONS = {
    "what's": "what is", "whats": "what is", "where's": "where is", "wheres": "where is",
    "there's": "there is", "theres": "there is", "which's": "which is", "that's": "that is",
    "how's": "how is", "it's": "it is", "isn't": "is not", "aren't": "are not", "don't": "do not",
    "doesn't": "does not", "arent": "are not", "isnt": "is not", "whos": "who is", "r": "are",
    "u": "you", "pls": "please", "plz": "please",
    # spoken forms: "I wanna sit", "lemme know", "how many chairs ya got"
    "wanna": "want to", "gonna": "going to", "gotta": "have to", "hafta": "have to", "lemme": "let me",
    "gimme": "give me", "ya": "you", "y'all": "you", "dunno": "do not know", "i'm": "i am", "i'd": "i would",
    "i've": "i have", "we've": "we have", "we're": "we are", "you're": "you are", "they're": "they are",
    "you've": "you have", "can't": "can not", "cannot": "can not", "won't": "will not", "didn't": "did not",
    "haven't": "have not", "hasn't": "has not", "wasn't": "was not", "weren't": "were not",
    "where'd": "where did", "where're": "where are", "what're": "what are", "how're": "how are",
    "there're": "there are", "couldn't": "could not", "wouldn't": "would not", "shouldn't": "should not",
    # the commonest slips of short words (too short for the typo fixer)
    "teh": "the", "hte": "the", "adn": "and", "taht": "that", "thier": "their", "si": "is",
}
# posture verbs say nothing the graph stores beyond the relation after them: "what sits on X"
_REL_AHEAD = (r"(?= (?:on|under|in|inside|above|below|next|near|beside|by|over|underneath|beneath|close|within|"
              r"less|more|closer|nearer|farther|further|between)\b)")
POSTURE = [
    # "does a tv sit on a shelf", "do the cups stand near the sink": is it there
    (re.compile(r"^does (?!(?:one|someone|anyone)\b)(.+?) (?:sit|stand|lie|rest|hang|stay)" + _REL_AHEAD), r"is \1"),
    (re.compile(r"^do (?!(?:i|we|you|they|people)\b)(.+?) (?:sit|stand|lie|rest|hang|stay)" + _REL_AHEAD), r"are \1"),
    # "the chairs pulled up to the table": how they stand says nothing the graph stores
    (re.compile(r"\b(is|are) (?:pulled up|pulled|pushed up|pushed in|pushed|tucked in|tucked|drawn up|lined up|grouped|"
                r"gathered|clustered|arranged)\b" + _REL_AHEAD), r"\1"),
    (re.compile(r"\b(is|are) (?:mounted|placed|located|sitting|standing|lying|hanging|kept|stored|resting|put|"
                r"positioned|found|situated|set|lieing)\b"), r"\1"),
    (re.compile(r"\b(?:lies|sits|stands|rests|hangs|stays)\b" + _REL_AHEAD), "is"),
    # "the cups that sit on the table", but not "what can i sit on" (an activity)
    (re.compile(r"(?<!\bcan i )(?<!\bcould i )(?<!\bshould i )(?<!\bmight i )(?<!\bmay i )(?<!\bto )"
                r"(?<!\bi can )(?<!\bi could )(?<!\bi might )(?<!\bi may )(?<!\bi should )(?<!\bwe can )"
                r"(?<!\bwe could )\b(?:lie|sit|stand|rest|hang)\b" + _REL_AHEAD), "are"),
    (re.compile(r" (?:lying|sitting|standing|resting|hanging|placed|located|kept|stored|positioned|situated|"
                r"mounted|found|put)\b" + _REL_AHEAD), ""),
]
# "is there somewhere i can sit" -> "where can i sit"
_PLACE_TO = re.compile(r"^(?:(?:is there|are there|do you know|do you have|have you got|you got|got|know of) )?"
                       r"(?:somewhere|anywhere|a place|any place|some place|a spot|any spot|something|anything|"
                       r"any thing|things|stuff|places|spots)(?: where| that| which)? i (?:can|could|might|may) (.+)$")
_TRAILING = re.compile(r"\b(?:anywhere|at all|around here|in here|here|located|situated|placed|kept|stored|"
                       r"(?:lying|sitting|standing|hanging|kicking|floating|knocking) (?:around|about)|"
                       r"around the (?:place|house)|around|somewhere|or not|right now|at the moment|now|"
                       r"by any chance|at present|at home|altogether|all together|in total|overall|in all|"
                       r"all in all|combined|total|put together)$")
# adverbs that change nothing the graph can answer
# "exactly" stays before a number ("exactly 4 chairs" is a condition)
_ADVERBS = re.compile(r"\b(?:precisely|actually|currently|roughly|approximately|really|just|"
                      r"exactly(?! (?:\d|zero|one|two|three|four|five|six|seven|eight|nine|ten)\b))\b ?")
# "the cups that are near the sink": a relative clause says what the set's filters say
_RELATIVE = re.compile(r"(?<=\w) (?:that|which|who) (?:are|is) ")
# "how many of the chairs": the chairs
_OF_THE = re.compile(r"^how many of (?:the|these|those|all the) ")
# "the smallest chair, what colour is it": the phrase goes where "it" stands
_DISLOCATED = re.compile(r"^(.+?) (what color|what size|how big|how tall|how high|how wide|how long|how deep|where)"
                         r"(?: (is|are) (?:it|they|that)| (?:it|they|that) (is|are)| (is|are))?(?: at)?$")
_VERBAL = re.compile(r"\b(?:is|are|was|were|can|could|do|does|did|i|you|we|have|has|there|what|which|how|where)\b")


def dislocated(text: str) -> str:
    """"the smallest chair, what colour is it", "the cabinet, where it is?", "the telly - how big?":
    a noun phrase said first, then the question about it (its verb and pronoun in any order, or
    none): the phrase goes where the pronoun stands. Only when what comes first is a noun phrase
    (no verb, no question word of its own)."""
    m = _DISLOCATED.match(text)
    if not m or _VERBAL.search(m.group(1)):
        return text
    verb = m.group(3) or m.group(4) or m.group(5) or "is"
    return f"{m.group(2)} {verb} {m.group(1)}"
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
    notes: list[str] = field(default_factory=list)      # words read as others ("read 'whre' as 'where'")


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


# "I'm thirsty, what could I drink out of", "im tired": a need says what the asker wants to do
NEEDS = {"thirsty": "drink from", "parched": "drink from", "tired": "sit", "exhausted": "sit", "sleepy": "sleep",
         "hungry": "eat", "starving": "eat"}
_NEED = re.compile(r"^(?:i am|im|i feel|i m) (?:so |very |really |a bit |quite |pretty |kind of |kinda |super )?(" + "|".join(NEEDS)
                   + r")\b(?: (?:and|so|now))?\s*(.*)$")
_NEED_ALONE = re.compile(r"^(?:|where|where to|what now|help|help me|any ideas?|suggestions?|what should i do|"
                         r"what can i do|what do you suggest|what do you recommend|anything|somewhere|any place)$")


def needs(text: str) -> str:
    """"i am thirsty" alone (or with "where?", "any ideas?") asks where the asker can do what the
    need calls for (NEEDS: thirsty -> drink from); followed by a question, the question says it."""
    m = _NEED.match(text)
    if not m:
        return text
    rest = m.group(2).strip()
    return f"where can i {NEEDS[m.group(1)]}" if _NEED_ALONE.match(rest) else rest


# "I wanna sit down, where?", "I need to put my cup down somewhere": where the asker can do it
_WANT_TO = re.compile(r"^i (?:want|need|have|would like|wish|am going|would love|got) to (.+?)"
                      r"(?: (?:where|somewhere|anywhere|where can i do that|where can i|where to))?$")


def wanting(text: str) -> str:
    """"i want to sit (down) (where)", "i have to put my cup down somewhere": "where can i ...",
    when the verb is one the affordance table knows (vocabulary.AFFORDANCE_VERBS)."""
    from sg3d.queries.vocabulary import AFFORDANCE_VERBS, EXTRA_AFFORDANCES

    m = _WANT_TO.match(text)
    if not m:
        return text
    verb = m.group(1).split()[0]
    known = {k.split()[0] for k in list(AFFORDANCE_VERBS) + list(EXTRA_AFFORDANCES)}
    return f"where can i {m.group(1)}" if verb in known else text


# "I need to wash my hands - is there a sink in here?", "ok, I'm cooking; where's the fridge?":
# a statement of the asker's own (first person) before the question says why it is asked
_CONTEXT = re.compile(r"^(?:(?:ok|okay|so|hey|well|right|hmm|um|oh)[ ,]+)*(?:i|i'm|im|i've|i'd|we|we're|my|our|me)\b"
                      r"[^?]*?(?: [-\u2013\u2014]+ ?|[-\u2013\u2014]{2} ?| ?[,;:] ?|\. )"
                      r"((?:is|are|where|what|which|how|do|does|can|could|any|anything|something|anywhere|somewhere|have|has|got|"
                      r"would|will)\b.+)$")
_DO_THAT = re.compile(r"\b(?:do|doing) (?:that|it|so|this)\b|\bthere\s*\??$")


def context_clause(text: str) -> str:
    """The question of "<a statement about me>, <a question>" (split at a dash, comma, semicolon,
    colon or full stop): the statement says why, the question what. Kept whole when the question
    leans on the statement ("... - where can I do that?") or is a bare "where?" / "any ideas?"
    (`needs` reads those). A pronoun of the question ("I can't find the purple book. Where is
    it?") is the statement's last noun phrase (`antecedent`)."""
    m = _CONTEXT.match(text) or (None if _TAG.search(text) else _STATED.match(text))
    if not m:
        return text
    rest = m.group(1).strip()
    plain = " ".join(re.sub(r"[^\w' ]+", " ", rest).split())
    if len(plain.split()) < 2 or _NEED_ALONE.match(plain) or _DO_THAT.search(rest):
        return text
    rest = activity_pronoun(rest)
    purpose = need_for_it(text[:m.start(1)], rest)
    if purpose is not None:
        return purpose
    if _PRONOUN.search(rest) and not _TAG.search(text):
        said = antecedent(text[:m.start(1)])
        return _PRONOUN.sub(said, rest) if said else text
    return rest if m.re is _CONTEXT else text


# "I need to put my shopping down. Is there a counter or a table for it?": the statement's activity
# is what "for it" asks for
_NEED_TO = re.compile(r"^(?:(?:ok|okay|so|hey|well|right|hmm|um|oh)[ ,]+)*(?:i|we) (?:need|want|have|would like|wish|"
                      r"am going|are going|got|d like|must|am trying|are trying) to ([\w' -]+?)[\s,.;:!?\u2013\u2014-]*$")
_FOR_IT = re.compile(r"^((?:is|are) there .+?) (?:for|to do) (?:it|them|that|this|so)\s*[?.!]*\s*$")


def need_for_it(statement: str, question: str) -> str | None:
    """"I need to put my shopping down. Is there a counter or a table for it?": "is there a
    counter or a table I could put my shopping down" (the activity asked of those kinds), when
    the statement wants an activity the affordance table knows; None otherwise."""
    from sg3d.queries.vocabulary import AFFORDANCE_VERBS, EXTRA_AFFORDANCES

    said, asked = _NEED_TO.match(statement.strip()), _FOR_IT.match(question.strip())
    if not said or not asked:
        return None
    doing = said.group(1).strip()
    if doing.split()[0] not in {k.split()[0] for k in list(AFFORDANCE_VERBS) + list(EXTRA_AFFORDANCES)}:
        return None
    return f"{asked.group(1)} i could {doing}"


# "there's a purple book somewhere, where is it?", "the grey mug is missing - where is it?": a
# statement about a thing (not the asker), then a question with a pronoun for it
_STATED = re.compile(r"^(?:(?:ok|okay|so|hey|well|right|hmm|um|oh)[ ,]+)*(?:there(?:'s| is| are| was| were)\b|"
                     r"(?:the|my|our|a|an|some)\b[^?]*?\b(?:is|are|was|were|has|have|had|'s|went|got|seems?)\b)[^?]*?"
                     r"(?: [-\u2013\u2014]+ ?|[-\u2013\u2014]{2} ?| ?[,;:] ?|\. )"
                     r"((?:is|are|where|what|which|how|do|does|can|could|any|anything|something|anywhere|somewhere|have|has|got|"
                      r"would|will)\b.+)$")
# the pronouns a question uses for a thing said before it
_PRONOUN = re.compile(r"\b(?:it|them|they)\b")
_NP_AFTER = re.compile(r"\b(the|a|an|my|our|your|some|this|that|these|those)\s+([\w'-]+(?:\s+[\w'-]+){0,3})")
# words that end a noun phrase (a preposition, an adverb, a verb): "the cup somewhere", "my keys again"
_NP_END = frozenset({
    "somewhere", "anywhere", "here", "there", "again", "now", "today", "yesterday", "earlier", "before", "down",
    "away", "back", "up", "off", "out", "in", "on", "at", "to", "from", "with", "into", "onto", "under", "near",
    "by", "next", "for", "of", "and", "but", "so", "or", "is", "are", "was", "were", "has", "have", "had", "it",
    "them", "i", "we", "you", "last", "this", "that", "anymore", "too", "either", "please", "around", "about",
    "lately", "recently", "just", "still", "can", "cannot", "can't", "seems", "seem", "went", "got",
    "missing", "gone", "lost",
})


def antecedent(statement: str) -> str | None:
    """The last noun phrase of `statement` ("i can't find the purple book" -> "the purple book",
    "i lost my keys again" -> "my keys"), said definite ("a mug" -> "the mug"); None when it names
    none."""
    found = None
    for m in _NP_AFTER.finditer(re.sub(r"[^\w' -]+", " ", statement)):
        words = []
        for w in m.group(2).split():
            if w in _NP_END:
                break
            words.append(w)
        if words:
            det = "the" if m.group(1) in ("a", "an", "some", "this", "that") else m.group(1)
            found = f"{det} {' '.join(words)}"
    return found


# "right, where is the sink", "listen - how many chairs": a word said before the comma that is no
# part of the question (as a frame word it could start one: "right of the sink", "look for")
# forms of address: "excuse me, dear, where is ...", "where's the sink, love?"
VOCATIVES = ("dear", "love", "mate", "buddy", "sir", "madam", "maam", "ma'am", "honey", "darling", "sweetie",
             "sweetheart", "pal", "friend", "my friend", "my dear", "dude", "bro", "robot", "dear robot", "guys")
_INTERJECTION = re.compile(r"^(?:(?:(?:hey|hi|hello|oh|ok|okay|yo|ah|so|and|sorry) )?"
                           r"(?:right|listen|look|say|now|wait|alright|great|cool|thanks|thank you|also|and|next|"
                           r"then|ok then|okay then|one more thing|another question|oh and|and also|yes|yeah|"
                           r"good|fine|perfect|got it|i see|excuse me|pardon me|pardon|sorry|hey|hi|hello|oh|ok|okay|"
                           r"um|so|well|please|"
                           # fragments and noises: "quick one -", "question:", "ugh,", "oh well,", "ok so,"
                           r"quick one|quick question|question|a question|one more|one more question|one last thing|"
                           r"one last question|last one|last question|another one|another thing|real quick|quickly|"
                           r"quick|ugh|argh|oops|whoops|uh|uh oh|er|erm|hmm|hm|ah|aha|gosh|jeez|huh|meh|kindly|"
                           + "|".join(map(re.escape, VOCATIVES)) + r")"
                           r"\s*(?:[,!:;]|\.\.\.|\s-+)+\s*)+(?=\w)")
# "..., dear?", "where is the sink, love": a form of address after a comma at the end
_VOCATIVE_TAIL = re.compile(r"\s*,\s*(?:" + "|".join(map(re.escape, VOCATIVES)) + r")\s*(?=[?.!]*\s*$)")


def interjection(text: str) -> str:
    """"right, where is the sink", "excuse me, dear, where is the tv", "listen - how many
    chairs": the words before the commas go, any number of them in a row (only with the comma:
    "right of the sink" is a place); a form of address after a last comma ("..., love?") too."""
    return _VOCATIVE_TAIL.sub("", _INTERJECTION.sub("", text))


# "excuse me dear where is ...": a form of address said without a comma, before the question
_VOCATIVE_HEAD = re.compile(r"^(?:" + "|".join(map(re.escape, VOCATIVES)) + r") (?=(?:what|where|which|how|is|are|"
                            r"do|does|did|can|could|would|will|have|has|any|tell|show|list|count|find|locate)\b)")


def vocative(text: str) -> str:
    """"dear where is the tv" (what is left of "excuse me dear, ..."): the form of address
    before a question word goes; "dear" elsewhere stays."""
    return _VOCATIVE_HEAD.sub("", text)


# "what can I drink it from", "where could I put them down": the object of an activity is the
# asker's own thing (the tea, the keys), filler for what the activity asks of the furniture
_ACTIVITY_PRONOUN = re.compile(r"\b((?:can|could|should|might|may) (?:i|we) (?!do\b)[\w-]+) (?:it|them|this|that|these|those)"
                               r"(?=(?: (?:from|out|on|onto|in|into|at|with|under|down|away|up|off|inside|cold|cool|fresh|warm|dry|"
                               r"safe|clean)\b|\s*[?.!]*\s*$))")


def activity_pronoun(text: str) -> str:
    """"what can I drink it from", "where can I put them down", "where can i keep it": the
    pronoun after the activity's verb goes (the furniture is asked for, not the thing)."""
    return _ACTIVITY_PRONOUN.sub(r"\1", text)


# "exactly two tvs in the kitchen, right?", "there's a fridge, isn't there?": a tag asks for the
# statement's truth and adds nothing to it
_TAG = re.compile(r"\s*[,;-]+\s*(?:right|correct|true|yes|yeah|no|ok|okay|eh|huh|am i right|is that right|"
                  r"is that correct|is that so|is it|isn't it|isnt it|is there|isn't there|isnt there|are there|"
                  r"aren't there|arent there|aren't they|arent they|isn't that so|don't we|dont we|do we|"
                  r"don't you|dont you|haven't we|havent we|right or wrong)\s*[?.!]*\s*$")


def tag_question(text: str) -> str:
    """A statement with a tag ("..., right?", "..., isn't there?") as the question it states:
    the tag goes, the rest is asked (a statement is read as a question, see REPHRASE)."""
    return _TAG.sub("", text)


def were_for_where(text: str) -> tuple[str, list[str]]:
    """"were is the grey mug", "were are the cups", "tell me were the sink is": "were" where it
    cannot be the verb (before "is"/"are"/"can", or an embedded question ending in "is"/"are")
    is a slip of "where"; the note says so. "were the cups on the table" stays a question in the
    past."""
    if re.match(r"^were (?:is|are|can|could|do|does|did|should|would|might)\b", text) \
            or re.match(r"^were (?!there\b).+ (?:is|are)$", text):
        return "where" + text[len("were"):], ["read 'were' as 'where'"]
    return text, []


# "would you mind counting the cups", "can you count the cups", "could u list the books": a
# request is the imperative it asks for
_GERUNDS = {"counting": "count", "listing": "list", "showing": "show", "naming": "name", "finding": "find",
            "checking": "check", "telling": "tell"}
_MIND = re.compile(r"^(?:would|do|could|will) you (?:please )?mind (" + "|".join(_GERUNDS) + r")\b")
_CAN_YOU = re.compile(r"^(?:can|could|would|will) you (?:please |kindly |just )?(count|list|show|name|find|locate|"
                     r"spot|look for|track down)\b")


def requests(text: str) -> str:
    """"would you mind counting X" / "can you count X": "count X" (and "list", "show", "name",
    "find"); "would you mind telling me ..." is a frame (FRAMES)."""
    text = _MIND.sub(lambda m: _GERUNDS[m.group(1)], text)
    return _CAN_YOU.sub(r"\1", text)


# "(can you) find the grey mug", "locate my keys", "help me find the sink", "i am looking for the
# purple book": where it is. "find" before a definite noun phrase only ("find all red things",
# "find red things" list them); "locate", "look for", "track down" before any. Never before
# "the number of", "the colour of" ...: those ask for the number, the colour
_FIND = re.compile(r"^(?:(?:please )?help (?:me|us) (?:to )?|(?:i|we) (?:am|m|are|re|have been|was|were) |im |"
                   r"(?:i|we) (?:want|need|would like|am trying|m trying|are trying|have) to |"
                   r"(?:i|we) (?:can not|could not|cant|do not|dont) (?:seem to )?|(?:can|could) (?:i|we) )?"
                   r"(?:(?:find|spot|finding|spotting)(?: me)? (?=(?:the|my|our|your|this|that|these|those)\b)|"
                   r"(?:locate|look for|looking for|track down|search for|searching for|hunt for|hunting for|"
                   r"locating|tracking down)(?: me)? )"
                   r"(?!(?:the |a |an )?(?:total )?(?:number|count|colou?r|size|height|width|length|depth|"
                   r"distance|gap) (?:of|between|from)\b)(?=\w)")


def find_is_where(text: str) -> str:
    """"find the grey mug", "locate my keys", "i am looking for the tv", "help me find the
    sink": "where is ..." (where it is, not a list of the kind)."""
    m = _FIND.match(text)
    return f"where is {text[m.end():]}" if m else text


_NUMBER_OR_BOTH = r"(?:\d+|both|both of the|both the|all|all of the|all the)"
# "where are the two books", "what colour are both chairs": all of them, the number aside
_THE_N = re.compile(r"^((?:where|what color|what size|how (?:big|tall|high|wide|long|deep)) (?:is|are) )"
                    r"(?:the (\d+)|(both|both of the|both the)) (?=[a-z])")


def the_n(text: str) -> tuple[str, list[str]]:
    """"where are the two books", "what colour are both chairs": the question is about every one
    of them; the number is said back as read ("read 'the 2 books' as 'the books'")."""
    m = _THE_N.match(text)
    if not m:
        return text, []
    said = f"the {m.group(2)}" if m.group(2) else m.group(3)
    rest = text[m.end():]
    return f"{m.group(1)}the {rest}", [f"read '{said} {rest}' as 'the {rest}' (every one)"]


# "is it true (that) there's no fridge", "is it correct that the kitchen has a sink": the
# statement asked as a yes/no question
_IS_IT_TRUE = re.compile(r"^(?:is it|it is|is that|its|is this) (?:true|correct|right|the case|so) (?:that )?")


def is_it_true(text: str) -> str:
    """"is it true (that) S": S asked ("there is X" -> "is there X", "the kitchen has X" ->
    "does the kitchen have X", "the cup is on X" -> "is the cup on X")."""
    m = _IS_IT_TRUE.match(text)
    return asked(text[m.end():]) if m else text


# "this room has no books", "the kitchen doesn't have a sink", "the cup is on the table": a
# statement (said with "?" or a tag) asked as a question, when it holds no question word
_STATEMENT = re.compile(r"^(?:the|this|that|these|those|my|our|your) (?:(?!has\b|have\b|is\b|are\b|does\b|do\b)[\w-]+ ?)"
                        r"{1,6} (?:has|have|is|are|does not have|do not have)\b")
_QUESTION_WORD = re.compile(r"\b(?:what|where|which|how|who|whose|when|why|whether)\b")


def statement(text: str) -> str:
    """A statement whose subject is a noun phrase ("this room has no books", "the chairs are
    near the table", "the kitchen does not have a fridge") as its yes/no question (`asked`)."""
    if not _STATEMENT.match(text) or _QUESTION_WORD.search(text):
        return text
    return asked(text)


def asked(rest: str) -> str:
    """A statement as its yes/no question: "there is X" -> "is there X", "the kitchen has X" ->
    "does the kitchen have X", "the kitchen does not have X" -> "does the kitchen not have X",
    "the cup is on X" -> "is the cup on X"."""
    rest = re.sub(r"^there (is|are)\b", r"\1 there", rest)
    rest = re.sub(r"^((?:the|a|an|my|our|this|your|that|these|those) (?:(?!has\b|have\b|is\b|are\b|does\b|do\b)[\w-]+ ?)"
                  r"{1,3}) (does|do) not have\b", r"\2 \1 not have", rest)
    rest = re.sub(r"^((?:the|a|an|my|our|this|your|that|these|those) (?:(?!has\b|have\b|is\b|are\b)[\w-]+ ?){1,6}) "
                  r"(has|have)\b", lambda m: f"{'does' if m.group(2) == 'has' else 'do'} {m.group(1)} have", rest)
    rest = re.sub(r"^((?:the|a|an|my|our|this|your|that|these|those) (?:(?!has\b|have\b|is\b|are\b)[\w-]+ ?){1,6}) "
                  r"(is|are)\b", r"\2 \1", rest)
    return " ".join(rest.split())


def fold(text: str) -> str:
    """Lower case, curly quotes straightened, accents kept (room names like 'küche')."""
    text = unicodedata.normalize("NFC", text).lower()
    return text.replace("\u2019", "'").replace("\u2018", "'").replace("\u00d7", " x ")


def _contractions(text: str) -> str:
    # "which one's bigger": "one's" is "one is" after a question word, a possessive elsewhere
    text = re.sub(r"\b(which|what) one's\b", r"\1 one is", text)
    # "which room's got books", "we've got": 's and 've before "got" are has and have
    text = re.sub(r"(?<=\w)'s got\b", " has got", text)
    text = re.sub(r"(?<=\w)'ve got\b", " have got", text)
    # "how tall's the fridge", "how far's the sink": 's after a question is "is"
    text = re.sub(r"\b(how (?:big|tall|high|wide|long|deep|far|many|much))'s\b", r"\1 is", text)
    # "what colour's the tv", "which room's the biggest": a possessive never comes before an article
    text = re.sub(r"(?<=\w)'s (?=(?:the|a|an|this|that|these|those|my|your|our|any|some)\b)", " is ", text)
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
    # "how many white things are": already in question order (an embedded count names its room:
    # "how many chairs the kitchen is" is no English)
    if m and m.group(1).startswith("how many") and not m.group(2).startswith("the "):
        return text
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
        text = vocative(text)
    return text


# round-two phrasings, rewritten to forms the grammar reads
_COLOURS = r"(red|orange|yellow|green|blue|purple|pink|brown|black|white|grey|gray|silver|golden)"
REPHRASE: list[tuple[re.Pattern[str], str | Callable[[re.Match[str]], str]]] = [
    # "where can someone take a seat" = "where can i sit"
    (re.compile(r"^(where|what) (can|could) (?:someone|somebody|anyone|anybody|one|people|we|a person) "),
     r"\1 \2 i "),
    (re.compile(r"\b(?:take|have) a seat\b"), "sit"),
    # "where could i take a nap", "somewhere to have a rest": to nap, to rest (vocabulary.EXTRA_AFFORDANCES)
    (re.compile(r"\b(?:take|have|grab|get) a (nap|rest|snooze|lie down|lie-down)\b"),
     lambda m: "lie down" if m.group(1) in ("lie down", "lie-down") else m.group(1)),
    # "how far are the two mugs from each other", "how close are the cups to one another": how far apart
    (re.compile(r"^how (?:far(?: away| apart)?|close|near)(?: together)? (is|are) (?:(?:the )?(?:2|both|both of the|both the) "
                r"(?=\w))?(?:the )?(.+?) (?:away |apart )?(?:from|to) (?:each other|one another)\b(.*)$"), r"how far apart \1 the \2\3"),
    (re.compile(r"^how (?:far(?: away| apart)?|close|near) (?:from|to) (?:each other|one another) (is|are) "
                r"(?:(?:the )?(?:2|both|both of the|both the) (?=\w))?(?:the )?(.+)$"), r"how far apart \1 the \2"),
    # "what all is there on the table", "which all rooms have chairs" (Indian English): what, which
    (re.compile(r"^(what|which|where|who) all\b"), r"\1"),
    # "no sofa (in here), right?", "no cups?": whether there are none (a yes or a no)
    (re.compile(r"^no (?!(?:more|fewer|less) than\b)(?!.*\b(?:is|are|was|were|can|could|do|does|did|have|has|there|"
                r"what|which|how|where|who|why|when|not|no)\b)(?=[a-z])"), "are there no "),
    # "which room is the fridge in", "what room are the chairs in": the rooms holding it
    (re.compile(r"^(which|what) (rooms?) (?:is|are) (.+?) (?:in|inside|kept in|found in)$"), r"\1 \2 have \3"),
    # "where in the house can I find a mug": the rooms holding one
    (re.compile(r"^where (?:in|inside|within|around) (?:the |our |my )?(?:whole |entire )?(?:house|building|home|flat|"
                r"apartment) (?:can|could|do|would|will|might|should|may) (?:i|you|we|one) (?:find|get|see|spot|locate) "),
     "which rooms have "),
    # "which has more chairs, the kitchen or the study": the rooms named
    (re.compile(r"^(?:which|what)(?: one)? (has|have) (more|fewer|less) (.+?) (the [\w -]+?) or (the [\w -]+)$"),
     r"which room \1 \2 \3 \4 or \5"),
    # "how far apart are the 2 cups": the cups, two of them
    (re.compile(r"^how far apart (is|are) (?:the )?(?:2|both|both of the|both the) "), r"how far apart \1 the "),
    # "what is red (in the kitchen)", "which things are white": the things of that colour
    (re.compile(r"^(what|which)(?: (?:things|objects|items))? (?:is|are) " + _COLOURS + r"\b"),
     r"\1 \2 things are there"),
    # "which things in the study are purple", "which chairs in the kitchen are red": the place goes last
    (re.compile(r"^(what|which) (?!one\b|ones\b)([a-z-]+) (in (?:the |this |that |my )?[\w-]+(?: room)?) (?:is|are) "
                + _COLOURS + r"$"), r"\1 \2 are \4 \3"),
    # "which chairs are red": the red chairs
    (re.compile(r"^(what|which) (?!one\b|ones\b)([a-z-]+) (?:is|are) " + _COLOURS + r"((?: in [\w -]+)?)$"),
     r"\1 \3 \2 are there\4"),
    # "report the total number of desks", "give me a count of the chairs", "state the number of
    # cups": an imperative asking for the number
    (re.compile(r"^(?:(?:report|state|give|tell|provide|calculate|compute|find|get|say|work out|figure out|output|"
                r"return|display|show|count|determine)(?: (?:me|us))? )?(?:the |a )?(?:total |overall |whole )?"
                r"(?:number|count) of "), "what is the number of "),
    # "find the colour of the sink", "report the height of the desk": what it is
    (re.compile(r"^(?:report|state|give|provide|calculate|compute|find|get|say|work out|figure out|determine|measure)"
                r"(?: (?:me|us))? (?:the )?(color|size|height|width|length|depth|distance|gap) (of|between|from)\b"),
     r"what is the \1 \2"),
    # "the number of chairs in the kitchen" (what is left of "could you tell me ...")
    (re.compile(r"^(?:the )?number of "), "what is the number of "),
    # "desks how many?": the dislocated noun phrase goes back in
    (re.compile(r"^(?:the |all the )?(.+?) how many$"), r"how many \1"),
    # "how much chairs" (a countable noun, said by a non-native speaker): how many
    (re.compile(r"^how much (?=[a-z-]+[^s\W]s\b)"), "how many "),
    # "there is a fridge here?": a statement asked as a question
    (re.compile(r"^there (is|are) "), r"\1 there "),
    # "what color the fridge", "where the fridge?", "how big the table": the missing verb
    (re.compile(r"^(what color|what size|how (?:big|tall|high|wide|long|deep|far)|where) "
                r"(?=(?:the|a|an|this|that|my|your|these|those)\b)(?!.* (?:is|are)$)"), r"\1 is "),
    # "what is the fridge colour", "the fridges colour": the colour (size, height ...) of it
    (re.compile(r"^(?:what|which) (is|are) the ([\w -]+?) (color|size|height|width|length|depth)$"),
     r"what \1 the \3 of the \2"),
    # "dimensions of the fridge", "what are the measurements of the desk": its size
    (re.compile(r"\b(?:dimensions|measurements|measures|dimension)\b"), "size"),
    # "the chair nearest the fridge", "which cup is closest the sink": nearest to
    (re.compile(r"\b(closest|nearest|farthest|furthest) (?=(?:the|a|an|this|that|my)\b)"), r"\1 to "),
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
    (re.compile(r"\b(?:does|do) (?:this|the|our|my|that) (?:room|place|space) not (?:have|hold|contain)(?: (?:a|an|any))?\b"),
     "are there no"),
    # "the total number of chairs", "how many chairs in total are there": the number (of the scope)
    (re.compile(r"\bthe total (?=number of\b)"), "the "),
    (re.compile(r"^(how many .+?) (?:in total|altogether|all together|in all) (?=(?:are|is|do|does|can|could) )"),
     r"\1 "),
    # "how many chairs across all the rooms": everywhere the scope holds (a count only: "is there
    # a chair in every room" asks something else, and "in each room" asks for a count per room)
    (re.compile(r"^(how many .+?|what is the number of .+?|count .+?) (?:across|in|throughout|over) "
                r"(?:all (?:of )?(?:the )?rooms|the whole house|every room)\b"), r"\1 in the house"),
    # "is there a sofa in any of the rooms", "... in any room", "anywhere in the rooms": in the house
    (re.compile(r"\b(?:anywhere |somewhere )?(?:in|inside|within|across) (?:any|one|either|some)(?: of)?"
                r"(?: (?:the|these|those|our|my|your))? rooms?\b"), "in the house"),
    (re.compile(r"\b(?:anywhere|somewhere) (?:in|inside|within|across) (?:the|these|those|our|my|your) rooms\b"),
     "in the house"),
    # "is there a fridge anywhere in the house": in the house (the whole scope)
    (re.compile(r"\b(?:anywhere|somewhere|everywhere) (?=(?:in|inside|within|around) (?:the |this |our |my )?"
                r"(?:whole |entire )?(?:house|building|home|flat|apartment|place)\b)"), ""),
    (re.compile(r"\b(?:in|inside|within|around) (?:the |this |our |my )?(?:whole |entire )?(?:flat|apartment|place)$"),
     "in the house"),
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
    # "how close is the desk to the fridge", "how near are the cup and the sink (to each other)": how far
    (re.compile(r"^how (?:close|near) (?:together )?(is|are) (.+?) and (.+?)(?: to (?:each other|one another))?$"),
     r"how far apart \1 \2 and \3"),
    (re.compile(r"^how (?:close|near) (is|are) (?=.+ (?:to|from) )"), r"how far \1 "),
    # "how far is the closest chair from the fridge": the distance of the closest pair
    (re.compile(r"^how far (is|are) (?:the )?(?:closest|nearest) (.+?) (from|to) "), r"how far \1 the \2 \3 "),
    # "exactly one tv", "more than one chair": a number
    (re.compile(r"\b(exactly|than|least|most) one\b"), r"\1 1"),
    # "which room has got books", "we have got 3 chairs": has / have ("have you got" stays)
    (re.compile(r"\b(has|have) got\b(?! to\b)"), r"\1"),
    # "how many shelves has the study" (British, without "does"): how many ... does the study have
    (re.compile(r"^how many (?!rooms?\b)([\w -]+?) (has|have) ((?:the|this|that|our|my|your) [\w-]+(?: room)?)(?: got)?$"),
     lambda m: f"how many {m.group(1)} {'does' if m.group(2) == 'has' else 'do'} {m.group(3)} have"),
    # "how many chairs have you got", "how many chairs you got": how many ... do you have
    (re.compile(r"^how many (.+?) (?:have |do )?(you|we) (?:got|have)$"), r"how many \1 do \2 have"),
    # "which rooms have books in them": "in it/them" is the room itself
    (re.compile(r"^((?:which|what) rooms? .+?) in (?:it|them|there)$"), r"\1"),
    # "where did i leave the book", "where have i put my cup": where it is
    (re.compile(r"^where (?:did|have|had) (?:i|we|you|someone|somebody|they) (?:last )?"
                r"(?:leave|left|put|place|placed|set|keep|kept|store|stored|drop|dropped|see|seen|saw|lose|lost|"
                r"stash|stashed|hide|hid|hidden|misplace|misplaced)(?: down)? (.+?)(?: down)?(?: last(?: time)?)?$"),
     r"where is \1"),
    # "(check) whether the cup is on the table", "if the sink is next to the oven": the question
    (re.compile(r"^(?:whether|if) (?!there\b)(.+?) (is|are) (?!there\b)(.+)$"), r"\2 \1 \3"),
    # colour asked in other word orders: "what colour do the chairs have", "which colour have
    # the chairs", "the chairs, which colour (do) they have", "colour of the table?"
    (re.compile(r"^(?:what|which) color (?:do|does|have|has) (.+?)(?: have| has)?$"), r"what color are \1"),
    (re.compile(r"^(.+?) (?:what|which) colors? (?:do |does |is |are |has |have )?(?:it|they|that|those|these|this)"
                r"(?: have| has| is| are| got)?$"), r"what color are \1"),
    (re.compile(r"^(?!what\b|which\b|how\b)(.+?) (?:(?:what|which) )?colors?$"), r"what color are \1"),
    (re.compile(r"^(color|height|width|length|depth|size) of "), r"what is the \1 of "),
    # "where could i do some work", "where can i do my homework": the activity's own verb
    (re.compile(r"\b(can|could|should|might|may) i do (?:some |my |a bit of )?(work|homework|reading)\b"),
     r"\1 i \2"),
    # "how high up is the tv": how high
    (re.compile(r"^how high up\b"), "how high"),
    # "the sink and the table, how far apart (are they)": the phrase goes back in
    (re.compile(r"^(.+?) how far apart(?: (?:are|is) (?:they|them|these|those|it))?$"), r"how far apart are \1"),
    # "distance sink to table", "distance between the sink and the table?"
    (re.compile(r"^(?:the )?distance (?!from\b|between\b|of\b)(.+) (?:to|from) "), r"the distance from \1 to "),
    (re.compile(r"^(?:the )?distance (?!from\b|between\b|of\b)(?=.+ and )"), "the distance between "),
    # "red things?", "anything white?", "white stuff": the things of that colour
    (re.compile(r"^(?:any |all |the |some )?" + _COLOURS + r" (?:things|stuff|objects|items|ones)$"),
     r"what \1 things are there"),
    (re.compile(r"^(?:everything|things|stuff|objects|items)(?: that is| that are| in| colored)? "
                + _COLOURS + r"$"), r"what \1 things are there"),
    # "anything blue?", "something red in here?": whether there is (a yes or a no first)
    (re.compile(r"^(?:anything|something)(?: that is| colored)? " + _COLOURS + r"$"), r"are there any \1 things"),
    # "anything on the table other than the cups?": whether there is
    (re.compile(r"^(anything|something|anyone|anybody) (?!to\b|for\b|else\b)"), r"is there \1 "),
    # "how many rooms got a fridge", "which room got desks": got = have
    (re.compile(r"\b(rooms?|which one|what one) got\b"), r"\1 have"),
    # "where could i work on my laptop", "where can i sit with my book": the asker's own thing
    # goes with the activity, it is no place in the graph
    (re.compile(r"^((?:where|what|which [\w-]+) (?:can|could|should|might|may) i [\w-]+(?: down)?) "
                r"(?:on|with|using|at) (?:my|our) [\w-]+(?: [\w-]+)?$"), r"\1"),
    # "objects with colour white", "things of the colour red", "chairs coloured black", "cups in
    # white": the colour describes them ("objects with white": the grammar's "with" clause)
    (re.compile(r"\b(?:with|having|of|in) (?:the |a )?colors? " + _COLOURS + r"\b"), r"with \1"),
    (re.compile(r"^(?!(?:is|are)\b)(.*?[a-z]) (?:colored|coloured|in the color|in color|painted) " + _COLOURS + r"\b"),
     r"\1 with \2"),
    (re.compile(r"^((?:is|are) .*?[a-z]) (?:colored|coloured|in the color|in color|painted) " + _COLOURS + r"\b"),
     r"\1 \2"),
    (re.compile(r"\b(?!(?:is|are|was|were|what|which|anything|something|everything|it|them|they|one|ones)\b)"
                r"([a-z-]+) in " + _COLOURS + r"(?=$| (?:on|in|under|near|next|by|beside|above|below)\b)"), r"\1 with \2"),
]
# "desks with a chair next to them", "which desk has a chair beside it": a symmetric relation
# said back to the head by a pronoun is the head's own relation ("desks next to a chair")
_SYMMETRIC_WORDS = r"(next to|near|beside|by|close to|adjacent to|alongside)"
_SELF_RELATION = [
    (re.compile(r"^(which|what) ([\w-]+(?: [\w-]+)?) (has|have) ((?:a|an|any|some|\d+) )?((?:[\w-]+ ){0,2}[\w-]+?) "
                + _SYMMETRIC_WORDS + r" (?:it|them)$"),
     lambda m: f"{m.group(1)} {m.group(2)} {'is' if m.group(3) == 'has' else 'are'} {m.group(6)} "
               f"{m.group(4) or ''}{m.group(5)}"),
    (re.compile(r"\b([\w-]+) (?:with|having|that have|that has|which have|which has) ((?:a|an|any|some|\d+) )?"
                r"((?:[\w-]+ ){0,2}[\w-]+?) " + _SYMMETRIC_WORDS + r" (?:it|them)\b"),
     lambda m: f"{m.group(1)} {m.group(4)} {m.group(2) or ''}{m.group(3)}"),
]


def self_relation(text: str) -> str:
    """"desks with a chair next to them", "which desk has a chair near it": for a symmetric
    relation (next to, near, beside) the pronoun is the head, so the head stands in that relation
    to the other ("desks next to a chair"). An asymmetric one ("a desk with a cup on it") is
    left as said, and refused naming the pronoun."""
    for regex, repl in _SELF_RELATION:
        text = regex.sub(repl, text)
    return text


@functools.cache
def _predicate_re() -> re.Pattern[str]:
    from sg3d.queries.vocabulary import COLOURS, RELATIONS, SIZES

    rel = "|".join(map(re.escape, sorted(RELATIONS, key=len, reverse=True)))
    adj = "|".join(map(re.escape, sorted(set(COLOURS) | set(SIZES), key=len, reverse=True)))
    return re.compile(rf"^((?:is|are) (?:the|this|that|these|those|my|our|your|a|an|any|all the) "
                      rf"(?:(?!(?:{rel})\b)[\w-]+ ){{1,3}}?)((?:{rel}) .+?) ((?:{adj})(?: (?:{adj}))?)$")


def predicate_adjective(text: str) -> str:
    """"is the book on the table white", "are the chairs near the table black": the colour or
    size word at the end of "is NP ADJ" is said of the noun phrase's head (the book), not of
    the relation's other end (the table): it goes next to the head ("is the book white on the
    table")."""
    return _predicate_re().sub(r"\1\3 \2", text)


# "do any of the rooms have mugs", "is there a room with a sofa": whether there is one anywhere
# (the whole scope); a word that changes the question ("no", "not") is left for the grammar
_ANY_ROOM = re.compile(r"^(?:(?:do|does) (?:any (?:of (?:the|these|those|our|my|your) )?rooms?|any of them|"
                       r"some (?:of (?:the )?)?rooms?|either (?:of the )?rooms?|one of the rooms) "
                       r"(?:have|has|hold|contain|got)|(?:is|are) there (?:a|any|some|one)? ?rooms? "
                       r"(?:with|having|containing|that (?:has|have|contains?)|which (?:has|have|contains?)|"
                       r"where there (?:is|are)|in which there (?:is|are)))\b(?! (?:no|not|none|without)\b)(.+)$")


def any_room(text: str) -> str:
    """"do any of the rooms have mugs", "does any room have a sofa", "is there a room with a
    fridge": whether there are such things in the house ("are there mugs in the house")."""
    return _ANY_ROOM.sub(r"are there\1 in the house", text)


# "more than 3 chairs (in here)?", "exactly 2 cups?": whether there are
_ELLIPTIC = re.compile(r"^(?:any |got |have you got |do you have |do we have )?((?:more|fewer|less) than|exactly) "
                       r"(\d+(?:\.\d+)?) (?!(?:m|cm|mm|ft|inch)\b)")
# "no more than 3", "not less than 2", "over 3 chairs", "3 or more chairs": as "fewer than" / "more than"
_BOUNDS = [
    (re.compile(r"\b(?:no|not) more than (\d+)\b(?!\.\d)"), lambda m: f"fewer than {int(m.group(1)) + 1}"),
    (re.compile(r"\b(?:no|not) (?:fewer|less) than (\d+)\b(?!\.\d)"), lambda m: f"more than {int(m.group(1)) - 1}"),
    (re.compile(r"\b(\d+) or more\b"), lambda m: f"more than {int(m.group(1)) - 1}"),
    (re.compile(r"\b(\d+) or (?:fewer|less)\b"), lambda m: f"fewer than {int(m.group(1)) + 1}"),
    (re.compile(r"\b(?:over|above) (\d+)\b(?!\.\d| (?:m|cm|mm|ft|inch)\b)"), lambda m: f"more than {m.group(1)}"),
    (re.compile(r"\b(?:under|below) (\d+)\b(?!\.\d| (?:m|cm|mm|ft|inch)\b)"), lambda m: f"fewer than {m.group(1)}"),
]
# "at least 2" = "more than 1", "at most 2" = "fewer than 3" (whole numbers)
_AT_LEAST = re.compile(r"\bat (least|most) (\d+)\b(?!\.\d)")


def rephrase(text: str) -> str:
    """The phrasings of REPHRASE and "at least / at most N" as the grammar's words."""
    for regex, repl in REPHRASE:
        text = regex.sub(repl, text)
    for regex, repl in _BOUNDS:
        text = regex.sub(repl, text)
    text = _AT_LEAST.sub(lambda m: f"more than {int(m.group(2)) - 1}" if m.group(1) == "least"
                         else f"fewer than {int(m.group(2)) + 1}", text)
    return _ELLIPTIC.sub(r"are there \1 \2 ", text)


# one spelling for phrases the grammar reads under another: "other than the sink" = "except
# the sink", "as seen from" = "seen from", "to the left of" = "left of", "A as well as B" = "A and B"
SAME_WORDS = [
    # "which rooms have a chair but not a fridge", "... and no fridge": none of the second kind
    # (before "but not" is read as "except", which would take fridges out of a set of chairs)
    (re.compile(r"^((?:which|what) rooms? .+?) (?:but|and) (?:not|no)(?: (?:a|an|any))? "), r"\1 but no "),
    (re.compile(r"\b(?:that|which|who) (?:is|are) not (a|an|the|any) "), r"except \1 "),
    # "something on the cabinet that is not white", "things that are not cups": all but those
    (re.compile(r"\b(?:that|which|who) (?:is|are) not(?! (?:on|under|in|inside|above|below|next|near|beside|by|"
                r"over|underneath|beneath|close|within|less|more|fewer|closer|nearer|farther|further|between|"
                r"behind|left|right|adjacent|alongside|around|onto|far)\b) "), "except "),
    # ("apart from each other" is a distance: `REPHRASE`)
    (re.compile(r"\b(?:other than|apart from|aside from|but not|save for)\b(?! (?:each other|one another)\b)"), "except"),
    (re.compile(r"\bas (seen|viewed|looking) from\b"), r"\1 from"),
    (re.compile(r"\bto the (left|right) of\b"), r"\1 of"),
    (re.compile(r"^(which|what) one (is|are)\b"), r"\1 \2"),
    # "somewhere to sit", "places to sit", "something to drink from": what affords it
    (re.compile(r"^(?:is there|are there|do you have|do you know) (?:somewhere|anywhere|a place|any place|"
                r"places|a spot|something|anything)(?: for me)? to "), "where can i "),
    # "anything to drink from?", "somewhere to sit": the same, said without a verb
    (re.compile(r"^(?:anything|something|anywhere|somewhere|any place|a place|a spot|any spot|any where|"
                r"some place)(?: for me)? to "), "where can i "),
    (re.compile(r"\b(places?|spots?|things?|somewhere|something|anything|anywhere) to (?=\w)"), r"\1 for "),
    (re.compile(r"\bas well as\b"), "and"),
    # "which objects are coloured white", "is the cup of the colour grey": the colour itself
    (re.compile(r"\b(is|are) (?:colored|coloured|painted|in the color|in color|of (?:the |a )?color|with (?:the |a )?color)"
                r" (?=(?:red|orange|yellow|green|blue|purple|pink|brown|black|white|grey|gray|silver|golden)\b)"), r"\1 "),
    # "is there a cup that I could drink from": the relative word before the asker's activity goes
    (re.compile(r"^((?:is|are) there .+?) (?:that|which|where|on which|in which|from which) (?=(?:i|we) "
                r"(?:can|could|should|might|may)\b)"), r"\1 "),
]
# "the kitchen's chairs" = "the chairs in the kitchen"; "the cup's colour" = "the colour of the cup"
_POSSESSIVE_MEASURE = re.compile(r"\b(?:the )?((?:[\w-]+ )?room|[\w-]+)'s (color|size|height|width|length)\b")
_POSSESSIVE_LIST = re.compile(r"^(what|which) (is|are) (?:the )?((?:[\w-]+ )?room|[\w-]+)'s ([\w-]+(?: [\w-]+)?)\s*[?.!]*\s*$")
_POSSESSIVE = re.compile(r"\b(?:the )?((?:[\w-]+ )?room|[\w-]+)'s ([\w-]+(?: (?!(?:is|are)\b)[\w-]+)?)"
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


# "..., the living room's chair please": a thanks or "please" at the very end, with or without a comma
_POLITE_TAIL = re.compile(r"[\s,]*\b(?:please|pls|plz|thanks|thank you|thx|cheers|kindly)\s*[?.!]*\s*$")


def polite_tail(text: str) -> str:
    """"tell me the colour of the living room's chair please": the trailing "please" (thanks,
    kindly) goes before possessives are read, so it is never taken for part of a noun; the
    question's own "?" stays."""
    m = _POLITE_TAIL.search(text)
    if not m or not text[:m.start()].strip():
        return text
    return text[:m.start()] + ("?" if "?" in m.group(0) else "")


# "is there a bin somewhere in this kitchen", "a cup anywhere on the table": "somewhere" before a
# place says nothing the place does not; "in this kitchen" is "in the kitchen" (the room named).
# Not after "there" or "is": "is there somewhere in the kitchen i can sit" asks for a place
_SOMEWHERE_IN = re.compile(r"(?<!\bthere)(?<!\bis)(?<!\bare)(?<!\bany)(?<!\ba)(?<=\w) (?:somewhere|anywhere) "
                           r"(?=(?:in|inside|within|on|around) (?:the|this|my|our|here)\b(?! rooms\b))")
_IN_THIS = re.compile(r"\b(in|inside|within|around) this (?=[a-z])")


def this_place(text: str) -> str:
    """"a bin somewhere in this kitchen" -> "a bin in the kitchen": "somewhere/anywhere" before a
    place goes, and "in this X" is "in the X" ("in this room" stays the scope, `HERE`)."""
    return _IN_THIS.sub(r"\1 the ", _SOMEWHERE_IN.sub(" ", text))


@functools.cache
def _afford_place_re() -> re.Pattern[str]:
    from sg3d.queries.vocabulary import ROOM_WORDS

    rooms = "|".join(map(re.escape, sorted(ROOM_WORDS, key=len, reverse=True)))
    return re.compile(r"^where (can|could|should|might|may) i (.+?) (?:in|inside|within) (?:the|my|our) (" + rooms + r")$")


def afford_place(text: str) -> str:
    """"where could I store things in the kitchen", "where can I sit in the living room": the
    room goes after "where" ("where in the kitchen could I store things", the grammar's
    `afford_in`), where the activity's words cannot swallow it. Only a room word
    (vocabulary.ROOM_WORDS): "put things in the cabinet" names the furniture itself."""
    return _afford_place_re().sub(r"where in the \3 \1 i \2", text)


def tidy(question: str) -> Phrased:
    """Question -> normalised words (no typo fixing yet): lower case, asides dropped,
    contractions and frames undone, numbers and units read, punctuation gone. A function of the
    text alone (no store, no room names): the last questions' results are kept (`_tidied`), a
    fresh copy for each caller."""
    kept = _tidied(question)
    return Phrased(kept.text, dropped=list(kept.dropped), notes=list(kept.notes))


@functools.lru_cache(maxsize=1024)
def _tidied(question: str) -> Phrased:
    dropped: list[str] = []
    text = polite_tail(tag_question(context_clause(interjection(fold(question)))))
    while True:
        found = re.findall(r"\([^()]*\)|\[[^\[\]]*\]", text)
        if not found:
            break
        dropped += [f.strip() for f in found]
        text = re.sub(r"\([^()]*\)|\[[^\[\]]*\]", " ", text)
    text = activity_pronoun(_contractions(text))
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
    text, notes = first_word_typo(text)
    text = strip_frames(text)
    text, more = first_word_typo(text)      # "hey whre is ...": the first word after the frame
    notes += more
    text, more = were_for_where(text)
    notes += more
    text = wanting(find_is_where(strip_frames(needs(requests(text)))))
    text = _PLACE_TO.sub(r"where can i \1", text)      # before "sit on" could be read as a posture
    for regex, repl in POSTURE:
        text = regex.sub(repl, text)
    text = _ADVERBS.sub("", text)
    for regex, repl in SAME_WORDS:
        text = regex.sub(repl, text)
    text = _RELATIVE.sub(" ", text)
    text = _OF_THE.sub("how many ", text)
    text = dislocated(text)
    text = _ONE.sub(r"\1", text)
    prev = None
    while prev != text:         # "any books lying around here at all"
        prev, text = text, _TRAILING.sub("", text).strip()
    text = _ROOM_NEXT.sub(r"what do the rooms \1 \2 hold", this_place(reorder_embedded(text)))
    text = " ".join(HERE.sub(" ", text).split())
    text, more = the_n(_numbers(text))
    notes += more
    text = rephrase(self_relation(predicate_adjective(is_it_true(statement(any_room(afford_place(text)))))))
    return Phrased(" ".join(text.split()), dropped=dropped, notes=notes)


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
