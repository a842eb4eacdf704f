"""The layers point one way: app, env and lab -> game -> engine, and no module cycle anywhere;
Gymnasium (an optional extra) is imported by the environment alone.

Every import counts, wherever it stands: at the top, inside a function, or under
`if TYPE_CHECKING:`. The checker is tested on a made-up package first, so a pass means
something.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# What each layer may import of the package besides itself. `base` is the package's root
# modules (the version, atomic writes), which import nothing of the package.
ALLOWED = {
    "base": set(),
    "engine": {"base"},
    "game": {"base", "engine"},
    "lab": {"base", "engine", "game"},
    "app": {"base", "engine", "game", "lab", "env"},  # (the bench times the environment)
    "env": {"base", "engine", "game", "lab"},  # never the window's app
    "entry": {"base", "app"},
}


def module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def layer_of(module: str, package: str) -> str:
    parts = module.split(".")
    if len(parts) == 1:
        return "base"
    if parts[1] == "__main__":
        return "entry"
    return parts[1] if parts[1] in ALLOWED else "base"


def imports_of(path: Path, module: str, known: set[str]) -> set[str]:
    """Modules of the package this file imports, anywhere in it, resolved to known modules."""
    tree = ast.parse(path.read_text(), str(path))
    is_package = path.name == "__init__.py"
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = module.split(".")
                anchor = anchor if is_package else anchor[:-1]
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            targets = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base
                       for alias in node.names]
        else:
            continue
        for target in targets:
            while target and target not in known:
                target = target.rpartition(".")[0]
            if target and target != module:
                found.add(target)
    return found


def import_graph(root: Path, package: str) -> dict[str, set[str]]:
    files = {module_name(p, root): p for p in (root / package).rglob("*.py")}
    known = set(files)
    return {name: imports_of(path, name, known) for name, path in files.items()}


def violations(graph: dict[str, set[str]], package: str) -> list[str]:
    """Arrows against the layers, then import cycles (each once, as a path)."""
    found = []
    for module, targets in sorted(graph.items()):
        layer = layer_of(module, package)
        for target in sorted(targets):
            other = layer_of(target, package)
            if other != layer and other not in ALLOWED[layer]:
                found.append(f"{module} ({layer}) imports {target} ({other})")
    found += [" -> ".join(cycle) for cycle in cycles(graph)]
    return found


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One cycle through each strongly connected group of modules (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in sorted(graph.get(node, ())):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            group = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                group.append(member)
                if member == node:
                    break
            if len(group) > 1:
                groups.append(_loop(graph, set(group)))
    for node in sorted(graph):
        if node not in index:
            visit(node)
    return groups


def _loop(graph: dict[str, set[str]], group: set[str]) -> list[str]:
    """A path around a strongly connected group, from its first member back to it."""
    start = min(group)
    paths = {start: [start]}
    frontier = [start]
    while frontier:
        node = frontier.pop(0)
        for nxt in sorted(graph[node] & group):
            if nxt == start:
                return [*paths[node], start]
            if nxt not in paths:
                paths[nxt] = [*paths[node], nxt]
                frontier.append(nxt)
    raise AssertionError("not a cycle")


def test_the_package_layers_point_one_way_with_no_cycles():
    graph = import_graph(ROOT, "invaders")
    assert {"invaders.engine.detector", "invaders.game.world", "invaders.lab.oracle",
            "invaders.app.cli"} <= set(graph)
    assert violations(graph, "invaders") == []


def test_the_engine_imports_nothing_else_of_the_package():
    graph = import_graph(ROOT, "invaders")
    for module, targets in graph.items():
        if module.startswith("invaders.engine"):
            assert all(t.startswith("invaders.engine") for t in targets), (module, targets)


def _package(tmp_path: Path, files: dict[str, str]) -> dict[str, set[str]]:
    for name, text in files.items():
        path = tmp_path / "pkg" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    for folder in ("", "engine", "game", "app", "lab"):
        init = tmp_path / "pkg" / folder / "__init__.py"
        if not init.exists():
            init.parent.mkdir(parents=True, exist_ok=True)
            init.write_text("")
    return import_graph(tmp_path, "pkg")


def test_the_checker_finds_arrows_up_hidden_in_functions_and_type_checking(tmp_path):
    graph = _package(tmp_path, {
        "engine/core.py": "from typing import TYPE_CHECKING\n"
                          "if TYPE_CHECKING:\n    from pkg.game.world import World\n",
        "game/world.py": "def f():\n    from pkg.app import cli\n",
        "app/cli.py": "from pkg.game import world\n",
        "lab/study.py": "from ..app.cli import main\n",
    })
    assert violations(graph, "pkg") == [
        "pkg.engine.core (engine) imports pkg.game.world (game)",
        "pkg.game.world (game) imports pkg.app.cli (app)",
        "pkg.lab.study (lab) imports pkg.app.cli (app)",
        "pkg.app.cli -> pkg.game.world -> pkg.app.cli",
    ]


def test_the_checker_finds_a_cycle_inside_one_layer(tmp_path):
    graph = _package(tmp_path, {
        "game/a.py": "import pkg.game.b\n",
        "game/b.py": "def later():\n    from pkg.game import c\n",
        "game/c.py": "from . import a\n",
        "game/d.py": "from pkg.game.a import thing\n",
    })
    assert violations(graph, "pkg") == ["pkg.game.a -> pkg.game.b -> pkg.game.c -> pkg.game.a"]


def test_only_the_environment_imports_gymnasium():
    outside = []
    for path in sorted((ROOT / "invaders").rglob("*.py")):
        if path.parent.name == "env":
            continue
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            outside += [f"{path.name}: {n}" for n in names if n.split(".")[0] == "gymnasium"]
    assert outside == []
    assert "gymnasium" in (ROOT / "invaders" / "env" / "space_invaders.py").read_text()
