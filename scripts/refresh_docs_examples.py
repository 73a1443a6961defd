"""Rewrite the docs' console examples from real output, and the built kitchen's figures.

    python scripts/refresh_docs_examples.py [--check]

Needs nothing but ../shared (the kitchen and its ground truth). It builds the kitchen with the
README's command into a fresh store (a scratch SG3D_HOME, stopped at the end), then:

- runs every `$ sg3d ask|export|show` example of the pages tests/e2e/test_docs_examples.py checks, in
  a scratch folder holding the pages' own `mkdir -p` folders; an example whose output still reads
  as the page shows (tests/docs_examples.py `matches`) is left as it is, any other is rewritten
  from the new output, trimmed where the page trimmed it (the same table rows, the same lines, a
  line cut at the same place);
- rewrites the README's build table the same way;
- redraws docs/img/kitchen.png (`sg3d show`);
- writes `kitchen` in docs/figures.json: the graph's counts (`sg3d export`) and its quality
  against ../shared/eval/kitchen_gt.json (`sg3d eval`), which the pages quote
  (tests/repo/test_figures_quoted.py).

`--check` rewrites nothing and exits 1 when an example or a figure would change.
"""
from __future__ import annotations

import argparse
import difflib
import json
import os
import re
import subprocess
import sys
import tempfile
import textwrap
from collections import Counter
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from benchmarks.figures import FIGURES, load, update  # noqa: E402
from tests.docs_examples import (  # noqa: E402
    CHECKED,
    KITCHEN_BUILD,
    RERUN,
    SHARED,
    Example,
    examples,
    matches,
)

WIDTH = 100                     # the docs' console width (tests/e2e/test_docs_examples.py runs at it)
KITCHEN_GT = SHARED / "eval" / "kitchen_gt.json"
PICTURE = REPO / "docs" / "img" / "kitchen.png"
ELLIPSIS = "..."


def sg3d(home: Path, cwd: Path, *args: str, timeout: int = 1800) -> subprocess.CompletedProcess:
    env = {**os.environ, "SG3D_HOME": str(home), "COLUMNS": str(WIDTH), "PYTHONPATH": str(REPO)}
    return subprocess.run([sys.executable, "-m", "sg3d", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=timeout)


def printed(out: subprocess.CompletedProcess) -> str:
    """What a console shows: stdout, then stderr (as the docs examples test joins them)."""
    return out.stdout + ("\n" if out.stdout and out.stderr else "") + out.stderr


# ---------------------------------------------------------------------------------- trimming

def wrapped(text: str) -> list[str]:
    """The output's lines wrapped at the docs' width (tables and long words are left whole)."""
    lines: list[str] = []
    for line in text.rstrip("\n").splitlines():
        if len(line) <= WIDTH or any("\u2500" <= ch <= "\u257f" for ch in line):
            lines.append(line)
        else:
            lines += textwrap.wrap(line, WIDTH, break_long_words=False, break_on_hyphens=False)
    return [line.rstrip() for line in lines]


def _key(line: str) -> str:
    """What a line of output is about: the text before its first ':' ('rests on'), else its first word."""
    head = line.split(":", 1)[0] if ":" in line else line.split(" ", 1)[0]
    return head.strip()


def _cut(line: str, like: str) -> str:
    """`line` cut where the page cut `like` ('(score 0.418..., 1 observations, ...)'): at the
    page's length before its first '...', then '...' (after a space when the page had one)."""
    keep = len(like.split(ELLIPSIS, 1)[0])
    if len(line) <= keep:
        return line
    return line[:keep].rstrip() + (" " if like[keep - 1:keep] == " " else "") + ELLIPSIS


def _shown(line: str, like: str) -> str:
    """How the page shows `line` where it showed `like`: the page's own line when it still reads
    as the new one, else the new line (cut as the page cut it)."""
    if ELLIPSIS not in like:
        return line
    return like if matches(like, line) else _cut(line, like)


def _next(new: list[str], start: int, like: str) -> int | None:
    """The line of `new` from `start` on that the page's `like` shows: one it still reads as, else
    the most similar one about the same thing ('template: ...'), else None."""
    same = [j for j in range(start, len(new)) if _key(new[j]) == _key(like)]
    still = [j for j in same if matches(like, new[j])]
    if still or not same:
        return still[0] if still else None
    return max(same, key=lambda j: difflib.SequenceMatcher(None, new[j], like).ratio())


def trim_lines(new: list[str], old: list[str]) -> list[str]:
    """The new output trimmed as the page trimmed the old one: a '...' line stands for the lines it
    skipped (the next shown line is found by what it is about), a line that ended in '...' is cut
    at the same place, and a page that ended in '...' keeps as many lines."""
    if not any(ELLIPSIS in line for line in old):
        return new
    out: list[str] = []
    i, skipping = 0, False
    for line in old:
        if line.strip() == ELLIPSIS:
            if out[-1:] != [ELLIPSIS]:
                out.append(ELLIPSIS)
            skipping = True
            continue
        if skipping:
            found = _next(new, i, line)
            if found is None:
                continue
            i = found
        if i >= len(new):
            break
        out.append(_shown(new[i], line))
        i, skipping = i + 1, False
    if i < len(new) and out[-1:] != [ELLIPSIS] and not out[-1].endswith(ELLIPSIS):
        out.append(ELLIPSIS)
    return out


def _table_key(line: str) -> str | None:
    """The first cell of a table row ('objects'); '' for a wrapped row's next line; None for
    any line that is not a row."""
    if not line.startswith("\u2502"):
        return None
    return line.split("\u2502")[1].strip()


def trim_table(new: list[str], old: list[str]) -> list[str]:
    """A build table keeps the rows the page shows (by their first cell) and one '... | ...' row
    for each run of rows it left out; the other lines (the bar, the title, the rules) are new."""
    shown = {_table_key(line) for line in old} - {None, "", ELLIPSIS}
    out: list[str] = []
    keep = True
    for line in new:
        key = _table_key(line)
        if key is None:
            out.append(line)
            continue
        if key:
            keep = key in shown
            if not keep and _table_key(out[-1]) != ELLIPSIS:
                cells = line.split("\u2502")
                out.append("\u2502".join([cells[0]] + [f" {ELLIPSIS}".ljust(len(c)) for c in cells[1:-1]] + [cells[-1]]))
        if keep:
            out.append(line)
    return out


def refreshed(ex: Example, output: str) -> str | None:
    """The example's new lines, or None when the page still holds."""
    if matches(ex.expected, output):
        return None
    old = ex.expected.splitlines()
    new = wrapped(output)
    if any(_table_key(line) for line in new):
        tries = ["\n".join(trim_table(new, old))]
    else:    # the page wrapped a long answer, or cut a long line: whichever reads more like it
        raw = [line.rstrip() for line in output.rstrip("\n").splitlines()]
        tries = ["\n".join(trim_lines(new, old)),
                 "\n".join(w for line in trim_lines(raw, old) for w in (wrapped(line) if ELLIPSIS not in line else [line]))]
    tries = [t for t in tries if matches(t, output)] or ["\n".join(new)]   # else the whole output
    return max(tries, key=lambda t: difflib.SequenceMatcher(None, t, ex.expected).ratio())


# ---------------------------------------------------------------------------------- the pages

def rewrite(path: Path, changes: dict[Example, str]) -> None:
    lines = path.read_text(encoding="utf-8").splitlines()
    for ex, text in sorted(changes.items(), key=lambda kv: -kv[0].span[0]):   # bottom up: spans stay right
        lines[ex.span[0]:ex.span[1]] = text.splitlines()
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def run_examples(home: Path, build_output: str, scratch: Path) -> dict[Path, dict[Example, str]]:
    cwd = scratch / "cwd"
    cwd.mkdir()
    every = [(path, ex) for path in CHECKED for ex in examples(path)]
    for _, ex in every:
        if ex.argv[:2] == ("mkdir", "-p") and len(ex.argv) == 3:
            (cwd / ex.argv[2]).mkdir(parents=True, exist_ok=True)
    changes: dict[Path, dict[Example, str]] = {}
    seen: dict[tuple[str, ...], str] = {}
    for path, ex in every:
        if list(ex.argv) == KITCHEN_BUILD:
            output = build_output
        elif ex.argv[:1] == ("sg3d",) and ex.argv[1:2] and ex.argv[1] in RERUN:
            if ex.argv not in seen:
                out = sg3d(home, cwd, *ex.argv[1:])
                if out.returncode != 0:
                    raise SystemExit(f"{ex}: `{' '.join(ex.argv)}` failed:\n{printed(out)}")
                seen[ex.argv] = printed(out)
            output = seen[ex.argv]
        else:
            continue
        text = refreshed(ex, output)
        if text is not None:
            changes.setdefault(path, {})[ex] = text
    return changes


def run_record_page(home: Path, scratch: Path) -> dict[Path, dict[Example, str]]:
    """docs/record.md's own-recording example: its living-room stand-in script (the page's python
    block) writes `myroom` from ../shared's living room, which is built and asked about."""
    page = REPO / "docs" / "record.md"
    living = SHARED / "data" / "open3d-livingroom1-micro"
    if not living.is_dir():
        print(f"skipped {page.name}: {living} is not there", file=sys.stderr)
        return {}
    blocks = re.findall(r"^```python\n(.*?)^```", page.read_text(encoding="utf-8"), re.S | re.M)
    cwd = scratch / "record"
    cwd.mkdir()
    changes: dict[Example, str] = {}
    for ex in examples(page):
        if ex.argv[:1] == ("python",) and len(ex.argv) > 1 and ex.argv[1].endswith(".py"):
            script = cwd / ex.argv[1]
            script.write_text(next(b for b in blocks if "camera_primesense.json" in b), encoding="utf-8")
            args = [str(living) if a.endswith("open3d-livingroom1-micro") else a for a in ex.argv[2:]]
            out = subprocess.run([sys.executable, str(script), *args], cwd=cwd, capture_output=True, text=True)
            output = printed(out)
        elif ex.argv[:1] == ("cat",):
            output = (cwd / ex.argv[1]).read_text(encoding="utf-8")
        elif ex.argv[:2] == ("sg3d", "build"):
            out = sg3d(home, cwd, *ex.argv[1:])
            output = "\n".join([line for line in out.stderr.splitlines() if "\u2501" in line][-1:] + [out.stdout])
        elif ex.argv[:2] == ("sg3d", "ask"):
            output = printed(sg3d(home, cwd, *ex.argv[1:]))
        else:
            continue
        text = refreshed(ex, output)
        if text is not None:
            changes[ex] = text
    return {page: changes} if changes else {}


# ---------------------------------------------------------------------------------- figures

def kitchen_figures(home: Path, cwd: Path) -> dict:
    """The built kitchen's counts and its quality against the ground truth."""
    out = sg3d(home, cwd, "export", "--room", "kitchen", "--format", "json", "--out", "-")
    graph = json.loads(out.stdout)
    labels = Counter(n["label"] for n in graph["nodes"])
    edges = Counter(e["type"] for e in graph["edges"])
    figures = {"nodes": len(graph["nodes"]), "edges": len(graph["edges"]),
               "unnamed": labels.get("object", 0), "walls": labels.get("wall", 0),
               "shelves": labels.get("shelf", 0), "counters": labels.get("counter", 0),
               "floors": labels.get("floor", 0), "chairs": labels.get("chair", 0),
               "edges_by_type": dict(sorted(edges.items()))}
    if KITCHEN_GT.is_file():
        report = json.loads(sg3d(home, cwd, "eval", "--gt", str(KITCHEN_GT), "--room", "kitchen", "--no-vqa",
                                 "--json").stdout)
        figures["eval"] = {
            "named_nodes": report["nodes"]["graph_nodes"], "objects": report["objects"]["nodes"],
            "node_precision": report["nodes"]["precision"], "node_recall": report["nodes"]["recall"],
            "node_spurious": len(report["nodes"]["spurious"]), "node_duplicates": len(report["nodes"]["duplicates"]),
            "node_missing": report["nodes"]["gt_detectable"] - report["nodes"]["matched"],
            "object_matched": report["objects"]["matched"], "object_duplicates": report["objects"]["duplicates"],
            "object_spurious": report["objects"]["spurious"], "gt_located": report["objects"]["gt_located"],
            "edge_precision": report["edges"]["precision"], "edge_recall": report["edges"]["recall"],
            "object_precision": report["objects"]["precision"], "object_recall": report["objects"]["recall"],
            "colour_agreement": report["nodes"]["colour"]["agreement"]}
    return figures


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="rewrite nothing; exit 1 when something would change")
    args = ap.parse_args(argv)
    kitchen = SHARED / "data" / "7scenes-redkitchen"
    if not (kitchen / "camera-intrinsics.txt").is_file():
        raise SystemExit(f"the kitchen is not at {kitchen} (set SG3D_SHARED)")
    with tempfile.TemporaryDirectory(prefix="sg3d-docs-") as tmp:
        scratch = Path(tmp)
        home = scratch / "home"
        try:
            print("building the kitchen into a fresh store ...", file=sys.stderr)
            build = sg3d(home, REPO, *KITCHEN_BUILD[1:2], str(kitchen), *KITCHEN_BUILD[3:])
            if build.returncode != 0:
                raise SystemExit(f"the kitchen build failed:\n{build.stderr[-3000:]}")
            bar = [line for line in build.stderr.splitlines() if "\u2501" in line][-1:]
            changes = run_examples(home, "\n".join(bar + [build.stdout.rstrip()]), scratch)
            changes |= run_record_page(home, scratch)
            figures = kitchen_figures(home, scratch)
            if not args.check:
                drawn = sg3d(home, scratch, "show", "--room", "kitchen", "--out", str(PICTURE))
                if drawn.returncode != 0:
                    raise SystemExit(f"sg3d show failed: {drawn.stderr}")
        finally:
            sg3d(home, scratch, "db", "stop")
    stale = load().get("kitchen") != figures
    for path, found in changes.items():
        for ex in found:
            print(f"{ex}: {'would change' if args.check else 'rewritten'}", file=sys.stderr)
        if not args.check:
            rewrite(path, found)
    if stale:
        print(f"{FIGURES.relative_to(REPO)} kitchen: {'would change' if args.check else 'rewritten'}", file=sys.stderr)
        if not args.check:
            update("kitchen", figures)
    return 1 if args.check and (changes or stale) else 0


if __name__ == "__main__":
    raise SystemExit(main())
