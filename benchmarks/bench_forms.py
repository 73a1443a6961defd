"""Each answer form's in-process time on a built kitchen: the question sets asked through
`sg3d.app.ask.ask` (what `sg3d serve` runs on a cache miss), p50 per question over `--repeat`
rounds, the slowest question of each form, and every answer written out to compare two trees.

    SG3D_HOME=<a home holding the kitchen built as room 'kitchen'> python -m benchmarks.bench_forms \
        [--repeat 7] [--dump FILE] [--compare FILE]

Questions: benchmarks/questions_kitchen.txt, benchmarks/paraphrases_kitchen.txt and the kitchen
questions of the paraphrase sets (benchmarks/paraphrases*.py), each scoped to the kitchen. A form
is `Answer.form` (count, list, yes/no, distance ...). Prints one table (form, questions, p50 of
the questions' p50s, the slowest question's p50, its statements and the question) and the load
average; `--dump` writes every answer's JSON (question, ok, form, answer text, value, objects),
`--compare` reads such a file and prints every answer that differs (exit 1 if any does).
Times are only comparable within one run on one machine: say the load.
"""
from __future__ import annotations

import argparse
import importlib
import json
import os
import statistics
import sys
import time
from pathlib import Path

from benchmarks.common import CountingStore

HERE = Path(__file__).resolve().parent
SETS = ("paraphrases", "paraphrases_heldout", "paraphrases_heldout2", "paraphrases_heldout3", "paraphrases_heldout4",
        "paraphrases_heldout5", "paraphrases_heldout6", "paraphrases_heldout7")
KEPT = ("question", "ok", "form", "answer", "value", "objects", "absent_evidence")


def questions() -> list[str]:
    """Every kitchen question of the sets, each once, in order."""
    out: list[str] = []
    for name in ("questions_kitchen.txt", "paraphrases_kitchen.txt"):
        out += [line.strip() for line in (HERE / name).read_text().splitlines()
                if line.strip() and not line.startswith("#")]
    for module in SETS:
        try:
            qs = importlib.import_module(f"benchmarks.{module}").questions()
        except (ImportError, AttributeError):
            continue
        out += [q.text for q in qs if q.room == "kitchen" and q.scope == "kitchen"]
    return list(dict.fromkeys(out))


def timed(store, question: str, room: str, repeat: int) -> tuple[float, int, dict]:
    """(p50 ms over `repeat` asks after one warm-up, statements one answer sends, its JSON)."""
    from sg3d.app.ask import ask

    counting = CountingStore(store)
    data = ask(counting, question, room=room).to_json()
    ms = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        ask(store, question, room=room)
        ms.append((time.perf_counter() - t0) * 1000)
    return statistics.median(ms), len(counting.sent), {k: data.get(k) for k in KEPT}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--room", default="kitchen")
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--dump", type=Path, help="write every answer's JSON here")
    ap.add_argument("--compare", type=Path, help="print the answers that differ from this dump")
    args = ap.parse_args(argv)

    from sg3d.settings import Settings

    store = Settings().store()
    load = os.getloadavg()
    rows, answers = [], []
    for q in questions():
        ms, sent, data = timed(store, q, args.room, args.repeat)
        rows.append((data["form"] or "refused", ms, sent, q))
        answers.append(data)
    by_form: dict[str, list] = {}
    for r in rows:
        by_form.setdefault(r[0], []).append(r)
    print(f"{len(rows)} questions, room {args.room!r}, p50 of {args.repeat} asks each; "
          f"load average {load[0]:.2f} before, {os.getloadavg()[0]:.2f} after\n")
    print("| form | questions | p50 ms | slowest ms | statements | slowest question |")
    print("|---|---|---|---|---|---|")
    for form, rs in sorted(by_form.items(), key=lambda kv: -max(r[1] for r in kv[1])):
        worst = max(rs, key=lambda r: r[1])
        print(f"| {form} | {len(rs)} | {statistics.median(r[1] for r in rs):.1f} | {worst[1]:.1f} | {worst[2]} "
              f"| {worst[3]} |")
    slow = [r for r in rows if r[1] > 10]
    print(f"\nquestions over 10 ms: {len(slow)}")
    for r in sorted(slow, key=lambda r: -r[1]):
        print(f"  {r[1]:6.1f} ms  {r[2]:2d} statements  [{r[0]}] {r[3]}")
    if args.dump:
        args.dump.write_text(json.dumps(answers, indent=1, default=str, sort_keys=True))
    if args.compare:
        before = {a["question"]: a for a in json.loads(args.compare.read_text())}
        now = json.loads(json.dumps(answers, default=str, sort_keys=True))
        differ = [a for a in now if before.get(a["question"]) != a]
        print(f"\nanswers differing from {args.compare.name}: {len(differ)} of {len(now)}")
        for a in differ:
            was = before.get(a["question"]) or {}
            print(f"  {a['question']}\n    before: {was.get('answer')}\n    now:    {a['answer']}")
        return 1 if differ else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
