"""Each answer form's in-process time on a built kitchen: the question sets asked through
`sg3d.app.ask.ask` (what `sg3d serve` runs on a cache miss), p50 per question over `--repeat`
rounds, the slowest question of each form, and every answer written out to compare two trees.

    SG3D_HOME=<a home holding the kitchen built as room 'kitchen'> python -m benchmarks.bench_forms \
        [--repeat 7] [--dump FILE] [--compare FILE] [--times FILE]
    python -m benchmarks.bench_forms --before B1.json B2.json --after A1.json A2.json   # one table

Questions: benchmarks/questions_kitchen.txt, benchmarks/paraphrases_kitchen.txt and the kitchen
questions of the paraphrase sets (benchmarks/paraphrases*.py), each scoped to the kitchen. A form
is `Answer.form` (count, list, yes/no, distance ...). Prints one table (form, questions, p50 of
the questions' p50s, the slowest question's p50, its statements and the question) and the load
average; `--dump` writes every answer's JSON (question, ok, form, answer text, value, objects),
`--compare` reads such a file and prints every answer that differs (exit 1 if any does);
`--times` writes each question's figures, and `--before ... --after ...` prints one table of two
trees' runs (run them alternately: PYTHONPATH names the tree whose `sg3d` is timed).
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


class _Rows(CountingStore):
    """Counts the statements and the rows they bring back (the scene reads: not the relation reads
    of `session`), figures that do not move with the machine's load."""

    rows = 0

    def read(self, name, **params):
        out = super().read(name, **params)
        self.rows += len(out)
        return out


def timed(store, question: str, room: str, repeat: int) -> tuple[float, int, dict]:
    """(p50 ms over `repeat` asks after one warm-up, statements one answer sends, its JSON with
    the rows read under "rows_read")."""
    from sg3d.app.ask import ask

    counting = _Rows(store)
    data = ask(counting, question, room=room).to_json()
    ms = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        ask(store, question, room=room)
        ms.append((time.perf_counter() - t0) * 1000)
    return statistics.median(ms), len(counting.sent), {**{k: data.get(k) for k in KEPT}, "rows_read": counting.rows}


def _merged(files: list[Path]) -> dict[str, dict]:
    """question -> its form, the median of its p50s over the runs, statements and rows."""
    runs = [json.loads(f.read_text()) for f in files]
    out = {}
    for r in runs[0]:
        ms = [x["ms"] for run in runs for x in run if x["question"] == r["question"]]
        out[r["question"]] = {**r, "ms": statistics.median(ms)}
    return out


def table(before: list[Path], after: list[Path]) -> None:
    """One table, form by form, of two trees' `--times` files (several runs each, alternated on
    one machine: only the ratio means anything on a busy one)."""
    b, a = _merged(before), _merged(after)
    forms: dict[str, list[str]] = {}
    for q, r in a.items():
        forms.setdefault(r["form"], []).append(q)
    print("| form | questions | p50 ms before | p50 ms after | slowest ms before | slowest ms after "
          "| statements before → after | rows read before → after |")
    print("|---|---|---|---|---|---|---|---|")
    for form, qs in sorted(forms.items(), key=lambda kv: -max(b[q]["ms"] for q in kv[1] if q in b)):
        qs = [q for q in qs if q in b]

        def mean(d, k, qs=qs):
            return statistics.mean(d[q][k] for q in qs)
        print(f"| {form} | {len(qs)} | {statistics.median(b[q]['ms'] for q in qs):.1f} "
              f"| {statistics.median(a[q]['ms'] for q in qs):.1f} | {max(b[q]['ms'] for q in qs):.1f} "
              f"| {max(a[q]['ms'] for q in qs):.1f} | {mean(b, 'statements'):.1f} → {mean(a, 'statements'):.1f} "
              f"| {mean(b, 'rows'):.0f} → {mean(a, 'rows'):.0f} |")
    print(f"\nall questions: p50 {statistics.median(r['ms'] for r in b.values()):.1f} ms before, "
          f"{statistics.median(r['ms'] for r in a.values()):.1f} ms after; slowest {max(r['ms'] for r in b.values()):.1f} "
          f"-> {max(r['ms'] for r in a.values()):.1f} ms; over 10 ms: {sum(r['ms'] > 10 for r in b.values())} -> "
          f"{sum(r['ms'] > 10 for r in a.values())}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--room", default="kitchen")
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--dump", type=Path, help="write every answer's JSON here")
    ap.add_argument("--compare", type=Path, help="print the answers that differ from this dump")
    ap.add_argument("--times", type=Path, help="write each question's form, p50 ms, statements and rows read here")
    ap.add_argument("--before", type=Path, nargs="+", help="with --after: print the table of two trees' --times files")
    ap.add_argument("--after", type=Path, nargs="+")
    args = ap.parse_args(argv)
    if args.before and args.after:
        table(args.before, args.after)
        return 0

    from sg3d.settings import Settings

    store = Settings().store()
    load = os.getloadavg()
    rows, answers = [], []
    for q in questions():
        ms, sent, data = timed(store, q, args.room, args.repeat)
        rows.append((data["form"] or "refused", ms, sent, q, data.pop("rows_read")))
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
    if args.times:
        args.times.write_text(json.dumps([{"form": r[0], "ms": r[1], "statements": r[2], "question": r[3],
                                           "rows": r[4]} for r in rows], indent=1))
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
