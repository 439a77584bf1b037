"""The package keeps the shape a newcomer can find their way in: no import cycle, small
functions, classes and modules, and a docstring on everything public."""

import ast
import re
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "inmoov_dsl"
MOST_LINES = {"function": 60, "class": 200, "module": 300}


def modules() -> dict[str, Path]:
    """Dotted module name -> file, for every module of the package."""
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        found[".".join(parts)] = path
    return found


def imports(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """The package's modules that ``name`` imports, anywhere in it (inside functions too)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")
            base = base[:len(base) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            for alias in node.names:
                found.add(f"{module}.{alias.name}" if f"{module}.{alias.name}" in known
                          else module)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
    return {m for m in found if m in known and m != name}


def cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """An import cycle in ``graph``, as the modules along it, or None."""
    state: dict[str, str] = {}

    def visit(node: str, trail: list[str]) -> list[str] | None:
        state[node] = "open"
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                return [*trail[trail.index(nxt):], nxt] if nxt in trail else [node, nxt]
            if nxt not in state and (found := visit(nxt, [*trail, nxt])):
                return found
        state[node] = "done"
        return None

    for start in sorted(graph):
        if start not in state and (found := visit(start, [start])):
            return found
    return None


def test_the_cycle_finder_finds_one():
    assert cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert cycle({"a": {"b"}, "b": set()}) is None


def test_no_module_of_the_package_imports_itself_back():
    known = modules()
    graph = {name: imports(name, path, known) for name, path in known.items()}
    assert graph["inmoov_dsl.cli.gestplay"]  # the finder sees the imports
    assert cycle(graph) is None


def sizes():
    """(kind, where, lines) for every module, class and function of the package."""
    for name, path in modules().items():
        text = path.read_text(encoding="utf-8")
        yield "module", name, len(text.splitlines())
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                kind = "class" if isinstance(node, ast.ClassDef) else "function"
                yield kind, f"{name}:{node.lineno} {node.name}", \
                    node.end_lineno - node.lineno + 1


@pytest.mark.parametrize("kind", sorted(MOST_LINES))
def test_nothing_is_too_long_to_read(kind):
    longer = [f"{where} ({lines} lines)" for k, where, lines in sizes()
              if k == kind and lines > MOST_LINES[kind]]
    assert not longer, f"over {MOST_LINES[kind]} lines: {longer}"


def test_everything_public_says_what_it_is_for():
    missing = []
    for name, path in modules().items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        if ast.get_docstring(tree) is None:
            missing.append(name)
        todo = [(tree.body, name)]
        while todo:
            body, owner = todo.pop()
            for node in body:
                if node.name.startswith("_") if hasattr(node, "name") else True:
                    continue
                if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef) \
                        and ast.get_docstring(node) is None:
                    missing.append(f"{owner}.{node.name}")
                if isinstance(node, ast.ClassDef):
                    todo.append((node.body, f"{owner}.{node.name}"))
    assert not missing, f"no docstring: {missing}"


def folder_order() -> list[str]:
    """The folders of docs/code.md's table, top (imported by the others) first."""
    text = (PACKAGE.parent / "docs" / "code.md").read_text(encoding="utf-8")
    found = []
    for row in re.findall(r"^\| (`[^|]+`) \|", text, re.M):
        found += re.findall(r"`(\w+)/`", row)
    return found


def test_a_folder_imports_only_the_folders_above_it_in_the_map():
    """docs/code.md's rule, kept: a folder imports only from the folders above it in
    its table (and the root), never from one below."""
    order = folder_order()
    assert order[:4] == ["voice", "language", "boards", "profiles"]
    assert sorted(order) == sorted(p.name for p in PACKAGE.iterdir()
                                   if (p / "__init__.py").exists())
    known = modules()
    rank = {f: k for k, f in enumerate(order)}

    def folder(module: str) -> str | None:
        parts = module.split(".")
        return parts[1] if len(parts) > 2 or (len(parts) == 2 and parts[1] in rank) \
            else None

    below = sorted(f"{name} imports {other}" for name, path in known.items()
                   for other in imports(name, path, known)
                   if folder(name) and folder(other) and folder(name) != folder(other)
                   and rank[folder(other)] > rank[folder(name)])
    assert not below
