"""No test module imports another test module, and the benchmarks import nothing from tests/:
what they share lives in conftest.py, tests/scenes.py, tests/sequences.py, tests/factories.py or
sg3d.testing."""
from __future__ import annotations

import ast
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def imported_modules(path: Path) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
    return names


def test_no_test_module_imports_another():
    offenders = [f"{p.relative_to(REPO)} -> {m}" for p in sorted((REPO / "tests").rglob("*.py"))
                 for m in imported_modules(p) if m.split(".")[-1].startswith("test_")]
    assert offenders == []


def test_benchmarks_import_nothing_from_tests():
    offenders = [f"{p.relative_to(REPO)} -> {m}" for p in sorted((REPO / "benchmarks").rglob("*.py"))
                 for m in imported_modules(p) if m == "tests" or m.startswith("tests.")]
    assert offenders == []
