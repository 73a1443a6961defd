"""The code's shape, read with `ast` (no import, no store): functions short enough to read whole,
parameter lists short enough to call without a keyword map (the pipeline's and the application's:
what grows goes into a stage's config or a frozen dataclass), and no import cycle among the project's modules (a lazy import inside a function counts too:
moving an import into a function hides a cycle, it does not break it)."""
from __future__ import annotations

import ast
from pathlib import Path

import networkx as nx

REPO = Path(__file__).resolve().parents[2]
PACKAGES = ("sg3d",)   # the one top-level package; its layers are subpackages
MAX_FUNCTION_LINES = 80
# (file, function) pairs allowed past the limit while they are being cut along their sections
KNOWN_LONG: set[tuple[str, str]] = set()
MAX_PARAMETERS = 6                              # self and cls aside; *args and **kwargs one each
SHORT_PARAMETER_LISTS = ("sg3d/ingest/", "sg3d/app/")
# (file, function) pairs allowed past it while they are being regrouped
KNOWN_LONG_LISTS: set[tuple[str, str]] = set()


def _modules() -> dict[str, Path]:
    out = {}
    for package in PACKAGES:
        for path in sorted((REPO / package).rglob("*.py")):
            parts = list(path.relative_to(REPO).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join(parts)] = path
    return out


def _trees() -> dict[str, tuple[Path, ast.Module]]:
    return {name: (path, ast.parse(path.read_text(), str(path))) for name, path in _modules().items()}


def long_functions(trees) -> list[str]:
    found = []
    for path, tree in trees.values():
        rel = path.relative_to(REPO).as_posix()
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = node.end_lineno - node.lineno + 1      # decorators (a command's options) aside
                if n > MAX_FUNCTION_LINES and (rel, node.name) not in KNOWN_LONG:
                    found.append(f"{rel}:{node.lineno} {node.name} ({n} lines)")
    return found


def parameter_count(node: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    a = node.args
    names = [p.arg for p in a.posonlyargs + a.args + a.kwonlyargs]
    if names and names[0] in ("self", "cls"):
        names = names[1:]
    return len(names) + (a.vararg is not None) + (a.kwarg is not None)


def long_parameter_lists(trees) -> list[str]:
    found = []
    for path, tree in trees.values():
        rel = path.relative_to(REPO).as_posix()
        if not rel.startswith(SHORT_PARAMETER_LISTS):
            continue
        for node in ast.walk(tree):
            if (isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and parameter_count(node) > MAX_PARAMETERS
                    and (rel, node.name) not in KNOWN_LONG_LISTS):
                found.append(f"{rel}:{node.lineno} {node.name} ({parameter_count(node)} parameters)")
    return found


def _imported(name: str, path: Path, node: ast.AST, known: set[str]) -> list[str]:
    """The project modules an import statement names (`from a import b` names a.b when b is a
    module, else a)."""
    if isinstance(node, ast.Import):
        return [a.name for a in node.names if a.name in known]
    if not isinstance(node, ast.ImportFrom):
        return []
    base = node.module or ""
    if node.level:
        package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        package = package[:len(package) - node.level + 1]
        base = ".".join(package + ([node.module] if node.module else []))
    out = []
    for alias in node.names:
        sub = f"{base}.{alias.name}"
        if sub in known:
            out.append(sub)
        elif base in known:
            out.append(base)
    return out


def import_graph(trees) -> nx.DiGraph:
    known = set(trees)
    graph = nx.DiGraph()
    graph.add_nodes_from(known)
    for name, (path, tree) in trees.items():
        for node in ast.walk(tree):
            for target in _imported(name, path, node, known):
                if target != name:
                    graph.add_edge(name, target)
    return graph


def cycles(graph: nx.DiGraph) -> list[list[str]]:
    return [sorted(c) for c in nx.strongly_connected_components(graph) if len(c) > 1]


def test_no_function_outside_the_tests_is_longer_than_80_lines():
    assert long_functions(_trees()) == []


def test_no_function_of_the_pipeline_or_the_application_takes_more_than_6_parameters():
    assert long_parameter_lists(_trees()) == []


def test_the_parameter_check_sees_a_long_list():
    path = REPO / "sg3d" / "app" / "shape_probe.py"      # a path inside the package, never written
    tree = ast.parse("class C:\n    def m(self, a, b, c, d, e, f, *rest):\n        pass\n"
                     "def g(a, b, c, d, e, f):\n    pass\n")
    assert long_parameter_lists({"probe": (path, tree)}) == ["sg3d/app/shape_probe.py:2 m (7 parameters)"]


def test_the_project_modules_import_each_other_without_a_cycle():
    assert cycles(import_graph(_trees())) == []


def test_the_cycle_check_sees_a_lazy_import(tmp_path):
    """The checks themselves can fail: a two-module cycle through an import inside a function."""
    a = ast.parse("from pkg.b import f\n")
    b = ast.parse("def g():\n    from pkg.a import h\n    return h\n")
    trees = {"pkg.a": (tmp_path / "a.py", a), "pkg.b": (tmp_path / "b.py", b)}
    assert cycles(import_graph(trees)) == [["pkg.a", "pkg.b"]]


def test_the_length_check_sees_a_long_function(tmp_path):
    body = "\n".join(f"    x{i} = {i}" for i in range(MAX_FUNCTION_LINES))
    path = REPO / "pkg_shape_probe.py"      # a path inside the repository, never written
    tree = ast.parse(f"def long_one():\n{body}\n")
    assert long_functions({"probe": (path, tree)}) == [f"pkg_shape_probe.py:1 long_one ({MAX_FUNCTION_LINES + 1} lines)"]
