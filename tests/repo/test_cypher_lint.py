"""Every cypher/*.cypher passes Neo4j's own Cypher linter (.ci/cypher-lint/lint.mjs).

Needs node on PATH and the linter installed: `npm ci --prefix .ci/cypher-lint`; skips otherwise.
"""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
LINT_DIR = REPO / ".ci" / "cypher-lint"
LINT = LINT_DIR / "lint.mjs"
PACKAGE = LINT_DIR / "node_modules" / "@neo4j-cypher" / "language-support"


def _node() -> str:
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not on PATH (the Cypher linter runs on Node.js >= 18.18)")
    if not PACKAGE.is_dir():
        pytest.skip("Cypher linter not installed: run `npm ci --prefix .ci/cypher-lint` to enable")
    return node


def _lint(*files: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [_node(), str(LINT), *map(str, files)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_cypher_files_lint_clean():
    res = _lint()
    out = res.stdout + res.stderr
    assert res.returncode == 0, f"Cypher lint failed:\n{out}"
    assert "cypher lint: " in out and ", 0 errors," in out, out


def test_linter_reports_a_broken_statement(tmp_path):
    broken = tmp_path / "broken.cypher"
    broken.write_text("// a comment line, then a missing ')'\nMATCH (n RETURN n\n")
    res = _lint(broken)
    out = res.stdout + res.stderr
    assert res.returncode == 1, out
    # file:line:col of the offending token (line 2: comment lines keep their numbers);
    # the path is shown relative to the repo when inside it, else absolute.
    assert f"{broken.name}:2:10: error: Invalid input 'RETURN'" in out, out
    assert "1 error" in out, out


def test_linter_accepts_parameters_and_multi_statement_files(tmp_path):
    ok = tmp_path / "schema_like.cypher"
    ok.write_text(
        "// constraints\n"
        "CREATE CONSTRAINT t_id IF NOT EXISTS FOR (b:Building) REQUIRE b.id IS UNIQUE;\n"
        "UNWIND $rows AS r MATCH (o:Object {id: r.id}) SET o += r.props;\n"
        "// trailing comment\n"
    )
    res = _lint(ok)
    out = res.stdout + res.stderr
    assert res.returncode == 0, out
    assert "cypher lint: 1 file, 0 errors, 0 warnings" in out, out
