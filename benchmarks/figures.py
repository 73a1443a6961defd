"""docs/figures.json: the figures the README and docs quote, written by what measures them.

Each writer owns its keys: `python -m benchmarks.bench_rooms` the rooms' quality
(`rooms.<room>`), `python -m benchmarks.bench_build` the build speed (`build.<method>`), and
`python scripts/refresh_docs_examples.py` the built kitchen's graph and its `sg3d eval` figures
(`kitchen`). tests/repo/test_figures_quoted.py fails when a page quotes a figure that differs from
this file, so a figure is changed here (by rerunning its writer), then in the pages."""
from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any

FIGURES = Path(__file__).resolve().parent.parent / "docs" / "figures.json"


def load(path: Path = FIGURES) -> dict:
    return json.loads(path.read_text(encoding="utf-8")) if path.is_file() else {}


def lookup(figures: dict, key: str) -> Any:
    """figures['rooms']['kitchen']['any_recall'] for 'rooms.kitchen.any_recall'; KeyError naming the key."""
    value: Any = figures
    for part in key.split("."):
        if not isinstance(value, dict) or part not in value:
            raise KeyError(f"{key} is not in {FIGURES.name} (rerun what writes it: see benchmarks/figures.py)")
        value = value[part]
    return value


def update(key: str, values: Any, path: Path = FIGURES) -> None:
    """Set `key` ('rooms.kitchen') to `values`, keeping every other key; written whole, sorted, by
    a rename, so a killed benchmark leaves the old file."""
    figures = load(path)
    *parents, last = key.split(".")
    node = figures
    for part in parents:
        node = node.setdefault(part, {})
    node[last] = values
    text = json.dumps(figures, indent=2, sort_keys=True) + "\n"
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".figures-", suffix=".json")
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)
