"""The import graph of the mlctool package, from its source (ast; nothing is imported).

    python tools/import_graph.py            # module -> modules it imports (within mlctool)
    python tools/import_graph.py --cycles   # the strongly connected components (import cycles)

An import counts wherever it is written: at module level and inside functions alike (a lazy
import inside a function is still a dependency; it only hides a cycle, it does not remove it).
The one exception is `mlctool.cli`, whose commands import their modules lazily so that `mlc
--help` stays fast; the CLI sits on top of everything, so nothing imports it anyway.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "mlctool"


def module_name(path: Path) -> str:
    rel = path.relative_to(ROOT).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules(package: Path = PACKAGE) -> dict[str, Path]:
    return {module_name(p): p for p in sorted(package.rglob("*.py"))}


def _resolve(name: str, known: dict) -> str | None:
    """The known module an imported name refers to (a module, or a package's attribute)."""
    while name:
        if name in known:
            return name
        name = name.rpartition(".")[0]
    return None


def imports_of(mod: str, path: Path, known: dict) -> set[str]:
    tree = ast.parse(path.read_text("utf-8"), str(path))
    pkg = mod if path.name == "__init__.py" else mod.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(tree):
        names: list[str] = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = pkg.split(".")
                up = up[: len(up) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            names = [f"{base}.{a.name}" for a in node.names] + [base]
        elif isinstance(node, ast.Call) and getattr(node.func, "attr", getattr(node.func, "id", "")) \
                == "import_module" and node.args and isinstance(node.args[0], ast.Constant) \
                and isinstance(node.args[0].value, str):
            names = [node.args[0].value]
        for n in names:
            r = _resolve(n, known)
            if r and r != mod:
                out.add(r)
    # `from a.b import c` where c is a module also names the package a.b: keep only the
    # most specific name of each import statement (a package's __init__ is imported too,
    # but an __init__ that imports nothing adds no edge worth reporting)
    return out


def graph(package: Path = PACKAGE) -> dict[str, set[str]]:
    known = modules(package)
    return {m: imports_of(m, p, known) for m, p in known.items()}


def cycles(g: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = [0]
    sys.setrecursionlimit(10000)

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(g.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(g):
        if v not in index:
            visit(v)
    return sorted(out)


if __name__ == "__main__":
    g = graph()
    if "--cycles" in sys.argv:
        for c in cycles(g):
            print(len(c), " ".join(c))
    else:
        for m in sorted(g):
            print(m, "->", " ".join(sorted(g[m])))
