"""Run the `sure` questions of a ground-truth file through `queries.vqa.answer` and score them.

    python scripts/eval_questions.py [--gt ../shared/eval/kitchen_gt.json] [--room kitchen]

Per question: the question, the expected answer, sg3d's answer and a verdict: right, wrong,
refused (ok=False), or check (a text answer that does not contain the expected text: judge by
eye). Numbers and yes/no are judged exactly; a refusal is never counted as right.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))


def verdict(expected, a) -> str:
    if not a.ok:
        return "refused"
    if isinstance(expected, bool) or (isinstance(expected, str) and expected.lower() in ("yes", "no")):
        want = expected if isinstance(expected, bool) else expected.lower() == "yes"
        return "right" if a.value is want else "wrong"
    if isinstance(expected, int):
        return "right" if isinstance(a.value, int) and not isinstance(a.value, bool) and a.value == expected else "wrong"
    return "right" if str(expected).lower() in a.text.lower() else "check"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gt", default=str(REPO / ".." / "shared" / "eval" / "kitchen_gt.json"))
    ap.add_argument("--room", default=None)
    ap.add_argument("--building", default=None)
    ap.add_argument("--all", action="store_true", help="also the questions not marked sure")
    args = ap.parse_args(argv)

    from queries.vqa import answer
    from sg3d.settings import Settings

    questions = [q for q in json.loads(Path(args.gt).read_text())["questions"] if args.all or q.get("sure")]
    store = Settings.from_options().store()
    tally: dict[str, int] = {}
    for q in questions:
        a = answer(store, q["text"], room=args.room, building=args.building)
        v = verdict(q["answer"], a)
        tally[v] = tally.get(v, 0) + 1
        print(f"[{v:7}] {q['text']}\n          expected: {q['answer']}\n          answer:   {a.text}")
    print(f"{len(questions)} questions: " + ", ".join(f"{tally.get(k, 0)} {k}" for k in ("right", "wrong", "refused", "check")))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
