"""Every figure the pages quote below is docs/figures.json's, which the code that measures it
writes (`python -m benchmarks.bench_rooms`: `rooms`; `python -m benchmarks.bench_build`: `build`;
`python scripts/refresh_docs_examples.py`: `kitchen`, the built kitchen's graph and its
`sg3d eval`). A page that quotes another figure fails here, naming the page, the figure's key and
both texts: rerun the writer, then copy its figure into the page. No store, no data."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from benchmarks.figures import FIGURES, load, lookup

ROOT = Path(__file__).resolve().parents[2]
FIELD = re.compile(r"\{([a-z_][\w.]*)(?::([^}]*))?\}")

E = "kitchen.eval"
QUOTED = [
    ("README.md", "On the kitchen: {kitchen.unnamed} unnamed objects, the floor, {kitchen.walls} walls, a counter, "
                  "{kitchen.shelves} shelves"),
    ("README.md", "kitchen any-label R/P {rooms.kitchen.any_recall:.2f}/{rooms.kitchen.any_precision:.2f}, named "
                  "{rooms.kitchen.named_recall:.2f}/{rooms.kitchen.named_precision:.2f}"),
    ("README.md", "study room (never tuned on) {rooms.study.any_recall:.2f}/{rooms.study.any_precision:.2f}, named "
                  "{rooms.study.named_recall:.2f}/{rooms.study.named_precision:.2f}"),
    ("README.md", "living room {rooms.living.any_recall:.2f}/{rooms.living.any_precision:.2f}, named "
                  "{rooms.living.named_recall:.2f}/{rooms.living.named_precision:.2f}"),
    ("README.md", f"| 3d-full, default | {{{E}.named_nodes}} | {{{E}.node_precision:.2f}} | {{{E}.node_recall:.2f}} | "
                  f"{{{E}.edge_precision:.2f}} | {{{E}.edge_recall:.2f}} | {{{E}.object_precision:.2f}} / "
                  f"{{{E}.object_recall:.2f}} |"),
    ("docs/figures.md", f"| **3d-full** (default) | {{{E}.named_nodes}} | {{{E}.node_spurious}} | "
                        f"{{{E}.node_duplicates}} | {{{E}.node_missing}} | {{{E}.node_precision:.2f}} | "
                        f"{{{E}.node_recall:.2f}} | {{{E}.edge_precision:.2f}} | {{{E}.edge_recall:.2f}} | "
                        f"{{{E}.objects}} | {{{E}.object_precision:.2f}} | {{{E}.object_recall:.2f}} |"),
    ("docs/figures.md", f"object nodes match {{{E}.object_matched}} of the {{{E}.gt_located}} located GT objects. "
                        f"Its {{{E}.objects}} object nodes include {{kitchen.unnamed}} unnamed ones"),
    ("docs/figures.md", "the floor, {kitchen.walls} walls, a counter and {kitchen.shelves} shelves"),
    ("docs/formats.md", "3DSSG has no predicate for UNDER, so its {kitchen.edges_by_type.UNDER} relations are left out"),
] + [
    ("docs/figures.md", f"{room} | {{rooms.{room}.any_recall:.2f}} | {{rooms.{room}.any_precision:.2f}} | "
                        f"{{rooms.{room}.named_recall:.2f}} | {{rooms.{room}.named_precision:.2f}} | "
                        f"{{rooms.{room}.duplicates}} | {{rooms.{room}.colour:.2f}} |")
    for room in ("kitchen", "study", "living")
]


def render(template: str, figures: dict) -> str:
    """The template with each {key} or {key:spec} replaced by figures.json's value."""
    return FIELD.sub(lambda m: format(lookup(figures, m.group(1)), m.group(2) or ""), template)


def flat(text: str) -> str:
    return " ".join(text.split())


def test_rendering_reads_nested_keys_and_formats():
    figures = {"rooms": {"kitchen": {"any_recall": 0.7801}}, "kitchen": {"walls": 6}}
    assert render("R {rooms.kitchen.any_recall:.2f}, {kitchen.walls} walls", figures) == "R 0.78, 6 walls"
    with pytest.raises(KeyError, match="rooms.study"):
        render("{rooms.study.any_recall}", figures)


@pytest.mark.parametrize("page, template", QUOTED, ids=[f"{p}:{t[:40]}" for p, t in QUOTED])
def test_a_quoted_figure_is_the_generated_one(page, template):
    figures = load()
    assert figures, f"{FIGURES} is missing: run the benchmarks and scripts/refresh_docs_examples.py"
    quoted = render(template, figures)
    text = flat((ROOT / page).read_text(encoding="utf-8"))
    if flat(quoted) in text:
        return
    pattern = re.escape(flat(FIELD.sub("\ue000", template))).replace("\ue000", "[^ |/,;]+")
    found = re.search(pattern, text)
    pytest.fail(f"{page} quotes {found.group(0) if found else 'nothing like it'!r}; {FIGURES.name} says {quoted!r}")
