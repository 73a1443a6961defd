"""An honest account of what has no name: when no object of an asked kind is named in scope, the
unnamed objects (label "object") that could be one, said with what is known of them.

"is there a keyboard?" with no keyboard named but a flat black 45 x 14 cm slab on the desk:
"I have not named a keyboard; unnamed things of its size and shape: a flat black object 45x14 cm
on the desk". Never "no", and never a label stored or said as fact: the object stays unnamed.

Rule "could be one" (`could_be`): an unnamed object could be an object of a class when

- each of its box sides, sorted largest first, is within SIZE_FACTOR of the class's typical
  side (`sg3d/ingest/data/class_sizes.json`, "typical"), or within SIZE_SLACK_M of it: the same
  kind varies about that much (a compact keyboard is 30 cm, a full one 46; a mug 8 cm or 12 with
  its handle), and a thin side measured from depth is a centimetre or two off whatever its size
  (noise, and what the object lies on). A factor of 2 let a 28 cm box be a 50 cm microwave and a
  1.2 m cube a 0.7 m wide fridge in the benchmark rooms;
- the ratio of its two largest sides is within ASPECT_FACTOR of the class's: each side alone
  within the factor still lets a sheet of paper (30 x 21 cm) be a keyboard (45 x 15), whose
  outline is three times as long as it is deep;
- its shape class (`sg3d.core.shape`) is one the class's objects take (a keyboard is flat; a
  bottle tall, round or box-shaped when it lies);
- it rests on the class's usual support (`rests_on`): on a surface (a table, desk, counter,
  shelf, cabinet or sideboard top: `SURFACES`; or an unnamed object at least as wide and as deep
  as it is, such as a desk top no detector named in a scan that never saw the floor), on
  something one works at ('work': a desk or a table, where a laptop stands open), on the floor,
  or on the floor or a surface ('any'). An object resting on nothing is not listed: where it is
  is part of what makes it a candidate.

Classes without a typical entry are never guessed (the plain "I have not found" answer stays).

Rule "could be its top" (`could_be_top`): "what is on the desk?" with no desk or table named in
scope, but an unnamed object that things stand ON (a desk scanned from above, its legs never in
view: its top is an object of its own) lists what stands on that object, said as on an unnamed
object that could be the desk's top, when it is flat and at least TOP_MIN_AREA_M2 across
(`sg3d.ingest.discover.furniture.DESK_MIN_AREA`: a desk top has room for a person's work).
"""
from __future__ import annotations

import math
from typing import Optional, Sequence

from sg3d.core.model import UNNAMED_LABEL
from sg3d.core.shape import ROUNDING_M, SAID
from sg3d.core.stored import Row
from sg3d.queries.vocabulary import ACTIVITIES, LIST_SHOWN

SIZE_FACTOR = 1.5
SIZE_SLACK_M = 0.02
ASPECT_FACTOR = 1.5
# what a thing is put down on; the structure's "surface" is any horizontal one found from depth
SURFACES = frozenset(ACTIVITIES["put things down"]) | {"surface"}
WORKTOPS = frozenset(ACTIVITIES["work"])
SUPPORT_TYPES = ("ON", "IN")
READ_LIMIT = 5_000     # unnamed objects read per answer
TOP_MIN_AREA_M2 = 0.15     # = sg3d.ingest.discover.furniture.DESK_MIN_AREA (tests/unit pins both)


def typical(label: str) -> Optional[dict]:
    """The class's typical object (size, shapes, support), None when the data has none."""
    from sg3d.ingest.objects.existence import class_typical

    return class_typical().get(label)


def rests_on(support: Optional[str], support_size: Optional[Sequence[float]] = None,
             size: Optional[Sequence[float]] = None) -> set[str]:
    """What kind of support the thing an object is ON or IN is (`support`: its label, None for
    nothing): {"floor"}, {"surface"}, {"surface", "work"} (a desk or a table) or none. An unnamed
    support is a surface when its horizontal sides, sorted, are each at least the object's."""
    if support == "floor":
        return {"floor"}
    if support in SURFACES:
        return {"surface", "work"} if support in WORKTOPS else {"surface"}
    if support == UNNAMED_LABEL and support_size and size and len(support_size) == 3 and len(size) == 3:
        top = sorted((float(v) for v in support_size[:2]), reverse=True)
        own = sorted((float(v) for v in size[:2]), reverse=True)
        return {"surface"} if top[0] >= own[0] and top[1] >= own[1] else set()
    return set()


def could_be(size: Optional[Sequence[float]], shape: Optional[str], support: Optional[str],
             prior: dict, support_size: Optional[Sequence[float]] = None) -> bool:
    """Rule "could be one" (module docstring): size within SIZE_FACTOR (or SIZE_SLACK_M) on each
    sorted side, shape class among the prior's, resting on its usual support (`support`: the
    label of what the object is ON or IN, None for nothing; `support_size` its box, for an
    unnamed one: `rests_on`)."""
    if not size or len(size) != 3 or support is None:
        return False
    sides = sorted((float(v) for v in size), reverse=True)
    if any(s <= 0 or not (1 / SIZE_FACTOR <= s / t <= SIZE_FACTOR or abs(s - t) <= SIZE_SLACK_M + ROUNDING_M)
           for s, t in zip(sides, prior["size"])):
        return False
    if not _same_proportions(sides, prior["size"]):
        return False
    if shape not in prior["shapes"]:
        return False
    kinds = rests_on(support, support_size, size)
    want = {"any": {"floor", "surface"}}.get(prior["support"], {prior["support"]})
    return bool(kinds & want)


def _same_proportions(sides: Sequence[float], typical: Sequence[float]) -> bool:
    """The aspect part of rule "could be one": the ratio of the two largest sides (sorted) within
    ASPECT_FACTOR of the typical ratio."""
    ratio = (sides[0] / sides[1]) / (typical[0] / typical[1])
    return 1 / ASPECT_FACTOR <= ratio <= ASPECT_FACTOR


def misfit(size: Sequence[float], prior: dict) -> float:
    """How far a candidate's sides lie from the typical ones (sum of |log ratio|): best first."""
    sides = sorted((float(v) for v in size), reverse=True)
    return sum(abs(math.log(s / t)) for s, t in zip(sides, prior["size"]))


def candidates(run, label: str, rooms: Optional[list[str]], colour: Optional[str] = None) -> list[Row]:
    """The unnamed objects in `rooms` (None: all) that could be a `label` (`could_be`), of the
    asked colour when one is asked, best fit first; each row carries `support` ("on the desk")."""
    prior = typical(label)
    if prior is None:
        return []
    rows = run.read("vqa_unnamed", unnamed=UNNAMED_LABEL, rooms=rooms, support_types=list(SUPPORT_TYPES),
                    limit=READ_LIMIT)
    best: dict[str, dict] = {}
    for r in rows:      # one row per support edge: of each object, the best-scored one it fits
        here = best.setdefault(r["id"], {**r, "support_label": None})
        fits = colour in (None, r.get("colour")) and \
            could_be(r.get("size"), r.get("shape"), r.get("support_label"), prior, r.get("support_size"))
        if fits and (here["support_label"] is None or _rank(r) > _rank(here)):
            best[r["id"]] = {**r}
    out = [o for o in best.values() if o["support_label"] is not None]
    for o in out:
        o["support"] = support_phrase(o)
        o["could_be"] = label
    run.rows_by_id.update((o["id"], o) for o in out)       # their provenance, read with them
    return sorted(out, key=lambda o: (misfit(o["size"], prior), o["id"]))


def _rank(row: dict) -> tuple:
    """A named support before an unnamed one, then the better-scored edge."""
    return (row.get("support_label") != UNNAMED_LABEL, float(row.get("support_score") or 0.0))


def support_phrase(o: dict) -> str:
    """"on the desk", or for an unnamed support what it looks like, with its top's two sides:
    "on a grey object 215x85 cm"."""
    word = "in" if o.get("support_type") == "IN" else "on"
    if o.get("support_label") != UNNAMED_LABEL:
        return f"{word} the {o['support_label']}"
    noun = " ".join(x for x in (o.get("support_colour"), "object") if x)
    sides = sorted((float(v) for v in (o.get("support_size") or [])[:2]), reverse=True)    # its top
    size = (" " + "x".join(f"{v * 100:.0f}" for v in sides) + " cm") if len(sides) == 2 else ""
    return f"{word} {'an' if noun[:1] in 'aeiou' else 'a'} {noun}{size}"


def describe(o: dict, with_room: bool = False) -> str:
    """"a flat black object 45x14 cm on the desk": shape, colour, its two largest sides, support."""
    words = [SAID.get(o.get("shape") or "", o.get("shape") or ""), o.get("colour") or "", "object"]
    noun = " ".join(w for w in words if w)
    sides = sorted((float(v) for v in o["size"]), reverse=True)[:2]
    text = f"{'an' if noun[:1] in 'aeiou' else 'a'} {noun} " + "x".join(f"{v * 100:.0f}" for v in sides) + " cm"
    if o.get("support"):
        text += f" {o['support']}"
    if with_room and o.get("room"):
        text += f" in the {o['room'].split('/', 1)[-1]}"
    return text


def _listing(found: list[Row]) -> str:
    rooms = {o.get("room") for o in found}
    said = [describe(o, len(rooms) > 1) for o in found[:LIST_SHOWN]]
    more = [f"{len(found) - LIST_SHOWN} more"] if len(found) > LIST_SHOWN else []
    items = said + more
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def not_named(what: str, where: str, found: list[Row]) -> str:
    """"I have not named a keyboard; unnamed things of its size and shape: ...": the answer to
    "is there / where is a <what>" when none is named and `found` could be one."""
    article = "an" if what[:1] in "aeiou" else "a"
    head = "an unnamed thing" if len(found) == 1 else "unnamed things"
    return f"I have not named {article} {what}{where}; {head} of its size and shape: {_listing(found)}"


def none_named(plural_what: str, where: str, found: list[Row]) -> str:
    """"0 named keyboards; 1 unnamed thing could be one: ...": "how many" with none named."""
    n = len(found)
    return (f"0 named {plural_what}{where}; {n} unnamed {'thing' if n == 1 else 'things'} could be one: "
            f"{_listing(found)}")


def could_be_top(size: Optional[Sequence[float]], shape: Optional[str]) -> bool:
    """Rule "could be its top" (module docstring): flat, its two horizontal sides spanning at
    least TOP_MIN_AREA_M2."""
    if not size or len(size) != 3 or shape != "flat":
        return False
    return float(size[0]) * float(size[1]) >= TOP_MIN_AREA_M2


def tops(run, rooms: Optional[list[str]]) -> list[Row]:
    """The unnamed objects in `rooms` (None: all) that things stand ON and could be a desk's or a
    table's top (`could_be_top`), the most laden first."""
    rows = run.read("vqa_unnamed_tops", unnamed=UNNAMED_LABEL, rooms=rooms, limit=READ_LIMIT)
    out = [r for r in rows if could_be_top(r.get("size"), r.get("shape"))]
    run.rows_by_id.update((r["id"], r) for r in out)
    return sorted(out, key=lambda r: (-int(r["things"]), r["id"]))


def on_unnamed_top(what: str, where: str, top: dict, listing: str) -> str:
    """"I have not named a desk; on an unnamed flat black object 120x55 cm that could be its
    top: ...": what stands on the unnamed top (`listing`, already said)."""
    article = "an" if what[:1] in "aeiou" else "a"
    top_said = describe({**top, "support": None}).split(" ", 1)[1]       # without its article
    return f"I have not named {article} {what}{where}; on an unnamed {top_said} that could be its top: {listing}"
