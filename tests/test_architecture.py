"""The package's layout rules (docs/architecture.md), checked on the import graph that
tools/import_graph.py reads from the source.

Imports count wherever they are written, inside functions too: a lazy import hides a cycle
from Python, not from a reader. The CLI (mlctool.cli.*) sits on top of everything and nothing
imports it, so its lazy command imports cannot close a cycle.
"""

from __future__ import annotations

import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))

import import_graph  # noqa: E402

from mlctool.targetapi.registry import BUILTIN  # noqa: E402

GRAPH = import_graph.graph()


def test_no_import_cycles():
    assert import_graph.cycles(GRAPH) == []


def test_the_cycle_finder_finds_a_cycle():
    g = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert import_graph.cycles(g) == [["a", "b", "c"]]


def test_the_engine_imports_no_target():
    """mlctool/sim/ is the engine alone: targets plug in through mlctool.targetapi."""
    bad = {m: sorted(t for t in deps if t.startswith("mlctool.targets"))
           for m, deps in GRAPH.items() if m.startswith("mlctool.sim")}
    assert {m: t for m, t in bad.items() if t} == {}


# mlctool/sim/'s parts, each importing only the machine (the modules at mlctool/sim/ itself)
# and the parts before it (docs/architecture.md)
SIM_PARTS = ("hardware", "engines", "stimulus", "run", "campaign")


def sim_part(module: str) -> int | None:
    """The rank of a module of mlctool/sim/: 0 the machine, then SIM_PARTS in order."""
    parts = module.split(".")
    if parts[:2] != ["mlctool", "sim"]:
        return None
    return SIM_PARTS.index(parts[2]) + 1 if len(parts) > 2 and parts[2] in SIM_PARTS else 0


def test_the_engine_parts_import_only_the_parts_before_them():
    assert set(SIM_PARTS) == {p.name for p in (ROOT / "mlctool" / "sim").iterdir()
                              if (p / "__init__.py").exists()}
    bad = sorted((m, t) for m, deps in GRAPH.items() if sim_part(m) is not None for t in deps
                 if sim_part(t) is not None and sim_part(t) > sim_part(m))
    assert bad == []


def test_the_parts_rule_finds_a_part_importing_a_later_one():
    assert sim_part("mlctool.sim.engines.engine") > sim_part("mlctool.sim.state")
    assert sim_part("mlctool.sim.campaign.batch") > sim_part("mlctool.sim.run.run") > sim_part("mlctool.sim.engines.engine")
    assert sim_part("mlctool.sim.hardware") == sim_part("mlctool.sim.hardware.pulses") and sim_part("mlctool.check") is None


def test_lazy_imports_are_seen():
    """The graph reads imports inside functions (a lazy import still names a dependency)."""
    assert "mlctool.syntax.lark_parser" in GRAPH["mlctool.syntax.parser"]


def test_generic_code_imports_no_target():
    """Only a target's own package and the CLI may name a target package (the CLI's FBs
    positioning-file commands)."""
    allowed = ("mlctool.targets", "mlctool.cli")
    bad = {m: sorted(t for t in deps if t.startswith("mlctool.targets."))
           for m, deps in GRAPH.items() if not m.startswith(allowed)}
    assert {m: t for m, t in bad.items() if t} == {}


def test_targets_do_not_import_each_other():
    def target_of(module: str) -> str | None:
        parts = module.split(".")
        return parts[2] if len(parts) > 2 and parts[:2] == ["mlctool", "targets"] else None

    bad = [(m, t) for m, deps in GRAPH.items() for t in deps
           if target_of(m) and target_of(t) and target_of(m) != target_of(t)]
    assert bad == []


def test_builtin_targets_are_registered_as_entry_points():
    """pyproject.toml registers every folder of mlctool/targets/ as a third-party target is
    registered, and registry.BUILTIN (the fallback of an uninstalled checkout) agrees."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text("utf-8"))
    points = project["project"]["entry-points"]["mlctool.targets"]
    folders = {p.parent.name: f"mlctool.targets.{p.parent.name}:TARGET"
               for p in (ROOT / "mlctool" / "targets").glob("*/target.toml")}
    assert points == folders == BUILTIN


# -- docs/architecture.md matches the tree

DOC = (ROOT / "docs" / "architecture.md").read_text("utf-8")
PACKAGES = sorted(p.parent.relative_to(ROOT).as_posix() for p in (ROOT / "mlctool").rglob("__init__.py")
                  if "toy" not in p.parts)


def test_the_picture_is_the_import_graph():
    import architecture_svg

    drawn = (ROOT / "docs" / "architecture.svg").read_text("utf-8")
    assert drawn == architecture_svg.svg(architecture_svg.group_graph()), \
        "docs/architecture.svg is stale: run python tools/architecture_svg.py"


def test_every_package_has_a_row():
    missing = [p for p in PACKAGES if p != "mlctool" and f"| `{p}/` |" not in DOC]
    assert missing == []


def test_every_path_named_exists():
    import re

    named = set(re.findall(r"`((?:mlctool|tests|tools|docs)/[^`\s]*)`", DOC))
    assert named and [p for p in sorted(named) if not (ROOT / p).exists()] == []


def test_every_package_says_what_belongs_there():
    """Each package's docstring says what belongs there and what does not."""
    import ast

    vague = []
    for p in PACKAGES:
        doc = ast.get_docstring(ast.parse((ROOT / p / "__init__.py").read_text("utf-8"))) or ""
        if "Belongs here" not in doc or "Does not belong here" not in doc:
            vague.append(p)
    assert vague == []
