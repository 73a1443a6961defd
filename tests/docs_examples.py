"""The docs' console examples, shared by tests/e2e/test_docs_examples.py (which checks that they hold)
and scripts/refresh_docs_examples.py (which rewrites them from real output): where they are, how
a page's `$ command` lines and the output under them are read, and how an output is compared."""
from __future__ import annotations

import os
import re
import shlex
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHARED = Path(os.environ.get("SG3D_SHARED", ROOT.parent / "shared"))       # as tests/conftest.py
DOCS = ROOT / "docs"
CHECKED = [DOCS / "asking.md", DOCS / "commands.md", DOCS / "formats.md", ROOT / "README.md"]
COUNTED = [DOCS / "commands.md", DOCS / "formats.md"]
RERUN = ("ask", "export", "show")                      # the subcommands whose examples are run again
KITCHEN_BUILD = ["sg3d", "build", "../shared/data/7scenes-redkitchen", "--room", "kitchen"]
OBJECT_ID = re.compile(r"\bo-[0-9a-f]{16}\b")
BOX_DRAWING = re.compile(r"[\u2500-\u257f]")
CONSOLE = re.compile(r"^```console\n(.*?)^```", re.S | re.M)
COUNT = re.compile(r"\b(\d+) (nodes|edges)\b")
UNNAMED = re.compile(r"\b(?:[a-z]+(?:-[a-z]+)? )?object \d+\b")     # 'grey object 6', 'grey-white object 7'
LIST_ANSWER = re.compile(r"(\d+ [^:]+): (.+)")


@dataclass(frozen=True)
class Example:
    doc: str            # path relative to the repository
    line: int           # of the `$ ` line
    argv: tuple[str, ...]
    expected: str       # the lines under it, up to the next `$ ` line or the block's end
    span: tuple[int, int] = (0, 0)   # those lines in the file: 0-based first, and one past the last

    def __str__(self) -> str:
        return f"{self.doc}:{self.line}"


def examples(path: Path) -> list[Example]:
    """Every `$ command` of the file's console blocks with the output shown under it."""
    text = path.read_text(encoding="utf-8")
    out = []
    for block in CONSOLE.finditer(text):
        first = text.count("\n", 0, block.start(1)) + 1
        lines = block.group(1).splitlines()
        starts = [i for i, ln in enumerate(lines) if ln.startswith("$ ")] + [len(lines)]
        for i, j in zip(starts, starts[1:]):
            command = lines[i][2:].rstrip()
            k = i + 1
            while command.endswith("\\") and k < j:          # a command continued on the next line
                command = command[:-1] + " " + lines[k].strip()
                k += 1
            try:
                argv = tuple(shlex.split(command))
            except ValueError:
                argv = (command,)
            out.append(Example(path.relative_to(ROOT).as_posix(), first + i, argv, "\n".join(lines[k:j]),
                               (first - 1 + k, first - 1 + j)))
    return out


def normalise(text: str) -> str:
    lines = [ln for ln in text.splitlines() if "━" not in ln]       # progress bars
    text = " ".join(BOX_DRAWING.sub(" ", "\n".join(lines)).split())     # a name wrapped at a line end too
    text = UNNAMED.sub("object #", OBJECT_ID.sub("o-ID", text))
    return " ".join(text.split())


def list_answer(text: str) -> tuple[str, list[str]] | None:
    """'N things on the floor ...: a, b (x, y) and c' -> (the head, its items), split outside
    parentheses; None for any other text."""
    m = LIST_ANSWER.fullmatch(text)
    if m is None:
        return None
    items, depth, start, body = [], 0, 0, m.group(2)
    for i, ch in enumerate(body):
        depth += (ch == "(") - (ch == ")")
        if depth == 0 and body.startswith(", ", i):
            items.append(body[start:i])
            start = i + 2
    items.append(body[start:])
    last = items.pop()
    items += [part for part in re.split(r" and (?![^(]*\))", last) if part]
    return m.group(1), items


def matches(expected: str, actual: str) -> bool:
    """Whether `actual` reads as `expected`, `...` in it standing for any text. What depends on
    numbering only is not compared: an unnamed object's colour word and number ('grey object 6'),
    and the order of a list answer's items (sorted by those names): its head ('10 things on the
    floor in the kitchen') must be the same and its items the same (those shown, when trimmed)."""
    want, got = normalise(expected), normalise(actual)
    pieces = re.split(r"\s*\.\.\.\s*", want)
    if re.fullmatch(".*?".join(re.escape(p) for p in pieces), got, re.S) is not None:
        return True
    w, g = list_answer(want), list_answer(got)
    if w is None or g is None or w[0] != g[0]:
        return False
    shown = [item for item in w[1] if item != "..."]
    trimmed = len(shown) < len(w[1])
    return not Counter(shown) - Counter(g[1]) and (trimmed or Counter(shown) == Counter(g[1]))
