"""The README is the front door and docs/ the site behind it: the README stays short, every
docs link in it reaches a page, every page is in the site's nav and linked from the README, and
the site builds with `mkdocs build --strict` where mkdocs is installed (the `docs` extra)."""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
MKDOCS_YML = ROOT / "mkdocs.yml"
MAX_README_LINES = 200

# [text](target) and ![alt](target); the target ends at whitespace or the closing parenthesis
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")
# a nav entry of mkdocs.yml: "- Title: page.md" or "- page.md"
NAV_PAGE = re.compile(r"^\s*-\s*(?:[^:\n]+:\s*)?([\w./-]+\.md)\s*$")


def readme_links() -> list[str]:
    return LINK.findall(README.read_text(encoding="utf-8"))


def docs_targets() -> list[str]:
    """README link targets inside docs/, without their #anchor."""
    return [t.split("#", 1)[0] for t in readme_links() if t.startswith("docs/")]


def nav_pages() -> list[str]:
    text = MKDOCS_YML.read_text(encoding="utf-8")
    nav = text.split("\nnav:", 1)[1]
    # the nav block ends at the next top-level key
    nav = re.split(r"\n(?=\S)", nav, maxsplit=1)[0]
    return [m.group(1) for line in nav.splitlines() if (m := NAV_PAGE.match(line))]


def doc_pages() -> list[str]:
    return sorted(p.relative_to(DOCS).as_posix() for p in DOCS.rglob("*.md"))


def test_readme_is_at_most_200_lines():
    n = len(README.read_text(encoding="utf-8").splitlines())
    assert n <= MAX_README_LINES, f"README.md has {n} lines; the front door keeps to {MAX_README_LINES}"


def test_every_docs_link_in_the_readme_reaches_a_file():
    targets = docs_targets()
    assert targets, "README.md links to no page of docs/"
    missing = [t for t in targets if not (ROOT / t).is_file()]
    assert not missing, f"README.md links to missing docs files: {missing}"


def test_every_page_is_in_the_nav_and_every_nav_entry_exists():
    nav, pages = nav_pages(), doc_pages()
    assert nav, "mkdocs.yml has no nav pages"
    assert sorted(set(pages) - set(nav)) == [], "pages missing from mkdocs.yml nav"
    assert sorted(set(nav) - set(pages)) == [], "nav entries without a page in docs/"


def test_every_page_is_linked_from_the_readme():
    linked = {t.removeprefix("docs/") for t in docs_targets()}
    unlinked = [p for p in doc_pages() if p not in linked]
    assert not unlinked, f"docs pages the README does not link to: {unlinked}"


def test_the_site_builds_strictly(tmp_path):
    try:
        import material  # noqa: F401
        import mkdocs  # noqa: F401
    except ImportError:
        if os.environ.get("CI", "").lower() == "true":   # CI installs the docs extra
            pytest.fail("mkdocs / mkdocs-material not installed in CI (pip install -e '.[docs]')")
        pytest.skip("mkdocs and mkdocs-material not installed (pip install -e '.[docs]')")
    result = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
        cwd=ROOT, capture_output=True, text=True, timeout=300,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"})
    assert result.returncode == 0, result.stdout + result.stderr
    assert (tmp_path / "site" / "index.html").is_file()
