"""Run the questions of a ground-truth file through `sg3d.queries.vqa.answer` and print each verdict.

    python scripts/eval_questions.py [--gt ../shared/eval/kitchen_gt.json] [--room kitchen] [--all]

The verdicts are `sg3d eval`'s own (`sg3d.evaluation.vqa.score`, with the node matching, so answers
citing objects are judged too): right, wrong, unsupported (a refusal: never right) or not
scorable. Only the `sure` questions unless --all.
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gt", default=str(REPO / ".." / "shared" / "eval" / "kitchen_gt.json"))
    ap.add_argument("--room", default="kitchen")
    ap.add_argument("--building", default="default")
    ap.add_argument("--all", action="store_true", help="also the questions not marked sure")
    args = ap.parse_args(argv)

    from sg3d.evaluation.evaluate import evaluate
    from sg3d.evaluation.ground_truth import load_gt
    from sg3d.graphdb.values import room_id
    from sg3d.settings import Settings

    gt = load_gt(args.gt)
    if args.all:
        gt.questions = [dataclasses.replace(q, sure=True) for q in gt.questions]
    store = Settings.from_options().store()
    vqa = evaluate(store, gt, room_id(args.building, args.room), room=args.room, building=args.building)["vqa"]
    tally: dict[str, int] = {}
    for q in vqa["questions"]:
        tally[q["status"]] = tally.get(q["status"], 0) + 1
        print(f"[{q['status']:12}] {q['question']}\n               expected: {q['expected']}\n"
              f"               answer:   {q.get('answer', q.get('got', q.get('reason')))}")
    print(f"{len(vqa['questions'])} questions: "
          + ", ".join(f"{tally.get(k, 0)} {k}" for k in ("right", "wrong", "unsupported", "not scorable")))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
