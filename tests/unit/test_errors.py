"""Every exception class of the product derives from the one base, `sg3d.core.errors.Sg3dError`."""
from __future__ import annotations

import ast
import builtins
from pathlib import Path

from sg3d.app.build import BuildError
from sg3d.app.errors import NotFound
from sg3d.core.errors import Sg3dError
from sg3d.queries.reader.grammar import GrammarError

REPO = Path(__file__).resolve().parents[2]
PACKAGES = ("sg3d",)   # the one top-level package; its layers are subpackages
BUILTIN_EXCEPTIONS = {n for n, v in vars(builtins).items() if isinstance(v, type) and issubclass(v, BaseException)}


def _base_name(node: ast.expr) -> str:
    return node.attr if isinstance(node, ast.Attribute) else getattr(node, "id", "")


def exception_classes_without_the_base() -> list[str]:
    """Classes that derive straight from a built-in exception (or click's) without naming Sg3dError
    among their bases; a class deriving from a project exception inherits the base through it."""
    missing = []
    for package in PACKAGES:
        for path in sorted((REPO / package).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(), str(path))):
                if not isinstance(node, ast.ClassDef):
                    continue
                bases = {_base_name(b) for b in node.bases}
                if bases & (BUILTIN_EXCEPTIONS | {"ClickException"}) and "Sg3dError" not in bases | {node.name}:
                    missing.append(f"{path.relative_to(REPO)}:{node.lineno} {node.name}")
    return missing


def test_every_product_exception_derives_from_sg3d_error():
    assert exception_classes_without_the_base() == []


def test_the_base_keeps_names_messages_and_builtin_bases():
    exc = BuildError("no frames found in /x")
    assert isinstance(exc, Sg3dError) and isinstance(exc, ValueError) and str(exc) == "no frames found in /x"
    assert issubclass(NotFound, Sg3dError) and issubclass(GrammarError, ValueError)
    assert type(exc).__name__ == "BuildError"
