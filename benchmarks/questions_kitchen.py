"""Compositional questions on the built kitchen, each judged from the graph itself.

    SG3D_HOME=<a home holding only the kitchen, built as room 'kitchen'> python -m benchmarks.questions_kitchen [--out FILE]

The questions are benchmarks/questions_kitchen.txt (written before the grammar) and a second
person's rewordings, benchmarks/paraphrases_kitchen.txt (--paraphrases). Each has an oracle: plain Python over the
room's exported objects and edges (cypher/object_all, cypher/relation_all), written apart from
the compiler, that computes the right answer; an answer is right when its value matches it.
Writes a markdown table (question, answer, right?) and prints the share right.
"""
from __future__ import annotations

import argparse
import math
import re
from pathlib import Path
from typing import Callable, Optional

from sg3d.core.model import RELATION_TYPES

HERE = Path(__file__).resolve().parent
QUESTIONS = HERE / "questions_kitchen.txt"
PARAPHRASES = HERE / "paraphrases_kitchen.txt"


class Graph:
    """The room as the store holds it: objects (with their printed names) and edges."""

    def __init__(self, store, room_id: str):
        from sg3d.queries.naming import names_in_store

        self.objects = [dict(r["o"]) for r in store.read("object_all", room=room_id)
                        if r["o"].get("removed_at") is None]
        self.edges = store.read("relation_all", room=room_id, types=list(RELATION_TYPES))
        self.rooms = store.read("vqa_rooms_all", building=None)
        self.room_name = room_id.split("/", 1)[-1]      # the store holds this one room
        names = names_in_store(store.read, self.objects)
        for o in self.objects:
            o["name"] = names.get(o["id"], o["label"])

    def structure(self, label: str) -> list[dict]:
        return [o for o in self.objects if (o.get("layer") or "object") == "structure" and o["label"] == label]

    def things(self) -> list[dict]:
        return [o for o in self.objects if (o.get("layer") or "object") != "structure"]

    def of(self, label: str, colour: Optional[str] = None) -> list[dict]:
        return [o for o in self.things() if o["label"] == label and (colour is None or o.get("colour") == colour)]

    def named(self, name: str) -> list[dict]:
        return [o for o in self.things() if o["name"] == name]

    def related(self, xs, types, ys, either=False) -> list[dict]:
        ids = {y["id"] for y in ys}
        hit = set()
        for e in self.edges:
            if e["type"] in types:
                if e["o"] in ids:
                    hit.add(e["s"])
                if either and e["s"] in ids:
                    hit.add(e["o"])
        return [x for x in xs if x["id"] in hit and x["id"] not in ids]

    @staticmethod
    def centre(o):
        return [float(v) for v in (o.get("box_centre") or [o["x"], o["y"], o["z"]])]

    def dist(self, a, b) -> float:
        return math.dist(self.centre(a), self.centre(b))

    def nearest(self, a, ys) -> float:
        return min((self.dist(a, y) for y in ys if y["id"] != a["id"]), default=math.inf)


NEXT, NEAR, ON, IN = ("NEXT_TO",), ("NEAR", "NEXT_TO"), ("ON",), ("IN",)


def _on_table_next_to_book(g: Graph):
    tables = g.related(g.of("dining table"), NEXT, g.of("book", "pink"), either=True)
    if tables:
        return ids(g.related(g.things(), ON, tables))
    return ids(g.related(g.related(g.things(), ON, g.of("dining table")), NEXT, g.of("book", "pink"), either=True))


def ids(objs) -> set:
    return {o["id"] for o in objs}


def _argmax(objs, key, sign=1):
    objs = list(objs)
    return {max(objs, key=lambda o: (sign * key(o), o["id"]))["id"]} if objs else set()


# question -> oracle(graph) -> the right value (int, bool, float, str, set of ids)
ORACLES: dict[str, Callable[[Graph], object]] = {
    "how many chairs are there?": lambda g: len(g.of("chair")),
    "how many chairs are within 1.5 m of the tv?": lambda g: sum(g.nearest(c, g.of("tv")) <= 1.5 for c in g.of("chair")),
    "how many cups are closer than 50 cm to a book?": lambda g: sum(g.nearest(c, g.of("book")) <= 0.5 for c in g.of("cup")),
    "how far is the white cup from the sink?": lambda g: min(
        (g.dist(a, b) for a in g.of("cup", "white") for b in g.of("sink")), default=None),
    "are there more books than tvs?": lambda g: len(g.of("book")) > len(g.of("tv")),
    "how many chairs are not near the tv?": lambda g: len(g.of("chair")) - len(g.related(g.of("chair"), NEAR, g.of("tv"), True)),
    "what is on the table next to the pink book?": _on_table_next_to_book,
    "what colour is the smallest chair?": lambda g: next(
        (o["colour"] for o in g.of("chair") if o["id"] in _argmax(g.of("chair"), lambda o: o["volume"], -1)), None),
    "which cup is farthest from the tv?": lambda g: _argmax(g.of("cup"), lambda o: g.nearest(o, g.of("tv"))),
    "how many rooms are there?": lambda g: len(g.rooms),
    "what is next to chair 1?": lambda g: ids(g.related(g.things(), NEXT, g.named("chair 1"), True)),
    "whats next to the sink?": lambda g: ids(g.related(g.things(), NEXT, g.of("sink"), True)),
    "how many tabels are there?": lambda g: len(g.of("dining table")),
    "could you tell me where the sink is?": lambda g: ids(g.of("sink")),
    "where can I sit?": lambda g: ids(g.of("chair") + g.of("couch") + g.of("bench")),
    "how many things are on the table?": lambda g: len(g.related(g.things(), ON, g.of("dining table"))),
    "what is on the table?": lambda g: ids(g.related(g.things(), ON, g.of("dining table"))),
    "what is the biggest object?": lambda g: _argmax(g.things(), lambda o: o.get("volume") or 0),
    "how tall is the table?": lambda g: (float(g.of("dining table")[0]["size"][2]) if len(g.of("dining table")) == 1 else None),
    "is there a keyboard?": lambda g: bool(g.of("keyboard")),
    "how many red cups are there?": lambda g: len(g.of("cup", "red")),
    "which rooms have a tv?": lambda g: {g.room_name} if g.of("tv") else set(),
    "which room has the most chairs?": lambda g: g.room_name,
    "are there fewer cups than chairs?": lambda g: len(g.of("cup")) < len(g.of("chair")),
    "how many books are on the dining table?": lambda g: len(g.related(g.of("book"), ON, g.of("dining table"))),
    "what is the distance between tv 1 and tv 2?": lambda g: min(
        (g.dist(a, b) for a in g.named("tv 1") for b in g.named("tv 2")), default=None),
    "is the pink book on the table?": lambda g: bool(g.related(g.of("book", "pink"), ON, g.of("dining table"))),
    "how many chairs are next to the table?": lambda g: len(g.related(g.of("chair"), NEXT, g.of("dining table"), True)),
    "which chair is closest to the white cup?": lambda g: _argmax(g.of("chair"), lambda o: g.nearest(o, g.of("cup", "white")), -1),
    "how many cups are within half a metre of the pink book?": lambda g: sum(
        g.nearest(c, g.of("book", "pink")) <= 0.5 for c in g.of("cup")),
    "what colour is the brown cup on the dining table?": lambda g: "brown" if g.related(
        g.of("cup", "brown"), ON, g.of("dining table")) else None,
    "how many objects are not on the table?": lambda g: len([
        o for o in g.things() if o["label"] != "dining table"]) - len(g.related(g.things(), ON, g.of("dining table"))),
    "which is the tallest chair?": lambda g: _argmax(g.of("chair"), lambda o: o["size"][2]),
    "how many white books are there?": lambda g: len(g.of("book", "white")),
    "what is near the white cup?": lambda g: ids(g.related(g.things(), NEAR, g.of("cup", "white"), True)),
    "can you tell me how many cups there are please?": lambda g: len(g.of("cup")),
    "how many chiars are next to the table?": lambda g: len(g.related(g.of("chair"), NEXT, g.of("dining table"), True)),
    "where is the white book on the dining table?": lambda g: ids(g.related(g.of("book", "white"), ON, g.of("dining table"))),
    "how many cups or books are on the table?": lambda g: len(g.related(g.of("cup") + g.of("book"), ON, g.of("dining table"))),
    "how big is the sink?": lambda g: [round(float(v), 2) for v in g.of("sink")[0]["size"]] if len(g.of("sink")) == 1 else None,
    "are there more than 3 chairs?": lambda g: len(g.of("chair")) > 3,
    "how many chairs are between 1 and 2 m from the table?": lambda g: sum(
        1 < g.nearest(c, g.of("dining table")) <= 2 for c in g.of("chair")),
    "how many books are farther than 1 m from the tv?": lambda g: sum(g.nearest(b, g.of("tv")) > 1 for b in g.of("book")),
    "what is in the sink?": lambda g: ids(g.related(g.things(), IN, g.of("sink"))),
    "how many cups are on the table and next to the pink book?": lambda g: len(g.related(
        g.related(g.of("cup"), ON, g.of("dining table")), NEXT, g.of("book", "pink"), True)),
    # asked only in the paraphrases
    "what is on the floor?": lambda g: ids(g.related(g.things(), ON, g.structure("floor"))),
    "are there any black tvs?": lambda g: bool(g.of("tv", "black")),
    "is the white cup on the table?": lambda g: bool(g.related(g.of("cup", "white"), ON, g.of("dining table"))),
}


def answer_ids(a) -> set:
    v = a.value
    if isinstance(v, dict) and v.get("id"):
        return {v["id"]}
    if isinstance(v, list) and v and isinstance(v[0], dict) and v[0].get("id"):
        return {x["id"] for x in v}
    if isinstance(v, list) and all(isinstance(x, str) for x in v) and v and str(v[0]).startswith("o-"):
        return set(v)
    return {o["id"] for o in a.objects if isinstance(o, dict) and o.get("id")}


def judge(a, truth) -> bool:
    """Whether answer `a` gives the oracle's value."""
    if not a.ok:
        # a printed name that no object has (the build names things differently): refusing with
        # the names there are is the right answer
        return truth is None and "no object is named" in a.text
    v = a.value
    if isinstance(truth, bool):
        return v is truth or v == truth
    if isinstance(truth, int):
        return v == truth
    if isinstance(truth, float):
        return isinstance(v, (int, float)) and abs(float(v) - truth) <= 0.02
    if isinstance(truth, str):
        if a.form == "room_most":
            return isinstance(v, dict) and v.get("room", "").split("/", 1)[-1] == truth
        return v == truth or (isinstance(v, list) and v == [truth])
    if isinstance(truth, list):
        if isinstance(v, str):          # "0.26x0.15x0.08 m"
            v = [float(x) for x in re.findall(r"\d+(?:\.\d+)?", v)]
        return isinstance(v, list) and [round(float(x), 2) for x in v] == truth
    if isinstance(truth, set):
        if a.form == "rooms":
            return {x["room"].split("/", 1)[-1] for x in v} == truth
        if not truth:
            return not answer_ids(a) and a.value in ([], None, 0, False)
        return answer_ids(a) == truth
    if truth is None:          # the graph holds no such object: an honest "not found" is right
        return bool(getattr(a, "absent_evidence", False))
    return False


def load_questions(paraphrases: Optional[Path] = PARAPHRASES) -> list[tuple[str, str, bool]]:
    """(question, oracle key, paraphrased?): the written questions, then paraphrases given as
    'paraphrase<TAB>original question' lines (the original names the oracle)."""
    out = [(q, q, False) for q in QUESTIONS.read_text().splitlines() if q.strip() and not q.startswith("#")]
    if paraphrases is not None and paraphrases.exists():
        for line in paraphrases.read_text().splitlines():
            if "\t" in line and not line.startswith("#"):
                para, original = (x.strip() for x in line.split("\t", 1))
                if original in ORACLES:
                    out.append((para, original, True))
    return out


def run(store, room_id: str, room: str, questions) -> list[dict]:
    from sg3d.queries.vqa import answer

    g = Graph(store, room_id)
    rows = []
    for q, key, paraphrased in questions:
        truth = ORACLES[key](g)
        a = answer(store, q, room=room)
        rows.append({"question": q, "answer": a.text if a.ok else f"refused: {a.text}",
                     "right": judge(a, truth), "truth": truth, "paraphrase": paraphrased})
    return rows


def markdown(rows: list[dict]) -> str:
    right = sum(r["right"] for r in rows)
    para = [r for r in rows if r["paraphrase"]]
    lines = [f"# Compositional questions on the kitchen: {right} of {len(rows)} right", "",
             f"{len(rows) - len(para)} written before the grammar (questions_kitchen.txt), "
             f"{len(para)} phrased by a second person who did not write it (paraphrases_kitchen.txt, "
             f"{sum(r['right'] for r in para)} right).", "",
             "Judged from the graph itself (benchmarks/questions_kitchen.py: an oracle per question "
             "over the room's objects and edges). Regenerate with "
             "`python -m benchmarks.questions_kitchen --out benchmarks/questions_kitchen.md`.", "",
             "| question | by | answer | right? |", "|---|---|---|---|"]
    for r in rows:
        ans = re.sub(r"\s+", " ", r["answer"]).replace("|", "/")
        by = "second person" if r["paraphrase"] else "grammar's author"
        lines.append(f"| {r['question']} | {by} | {ans} | {'yes' if r['right'] else 'NO'} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    from sg3d.settings import Settings

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--room", default="kitchen")
    ap.add_argument("--building", default="default")
    ap.add_argument("--paraphrases", type=Path, default=PARAPHRASES)
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args(argv)
    from sg3d.graphdb.values import room_id

    store = Settings.from_options().store()
    rows = run(store, room_id(args.building, args.room), args.room, load_questions(args.paraphrases))
    text = markdown(rows)
    if args.out:
        args.out.write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
