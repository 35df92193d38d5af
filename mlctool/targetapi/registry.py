"""Where targets come from: the entry-point group `mlctool.targets`.

Every target, built-in or from another package, is a `TargetPackage` named by an entry point
of the group (pyproject.toml of the package that holds it):

    [project.entry-points."mlctool.targets"]
    vs = "mlctool.targets.vs:TARGET"

Loading the entry point imports only the target package's `__init__` (it must stay light: `mlc
check` loads it); the simulator imports the package's `simulation` module when a program of
the target is simulated.

A checkout run without installing (or an install older than the entry points) still finds the
built-in targets: BUILTIN lists them as pyproject.toml does (tests/test_architecture.py holds
the two lists equal).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

GROUP = "mlctool.targets"
BUILTIN = {
    "fbs": "mlctool.targets.fbs:TARGET",
    "nc5": "mlctool.targets.nc5:TARGET",
    "vs": "mlctool.targets.vs:TARGET",
}


@dataclass(frozen=True)
class TargetPackage:
    """A target as a package declares it.

    name: what `--target` and mlc.toml call it.
    tables: the folder of its manual tables (target.toml, devices.toml, instructions.toml;
      docs/architecture.md "A new target").
    simulation: "module:attribute" of its `Simulation` (targetapi/simulation.py), imported when
      a program of the target is simulated; "" when the engine's generic routines are all it
      needs.
    """

    name: str
    tables: Path
    simulation: str = ""


class UnknownTarget(KeyError):
    """No installed package declares a target of that name."""


def _load(ref: str) -> TargetPackage:
    module, _, attr = ref.partition(":")
    return getattr(importlib.import_module(module), attr)


@cache
def _references() -> dict[str, str]:
    # imported here: importlib.metadata (with the email package) is ~15 ms of every start,
    # and `mlc check` of a built-in target never reads the entry points
    from importlib.metadata import entry_points

    refs = {ep.name: ep.value for ep in entry_points(group=GROUP)}
    return {**refs, **BUILTIN}  # a package cannot take a built-in target's name


@cache
def target_package(name: str) -> TargetPackage:
    # a built-in target is found without reading every installed package's metadata (a few
    # ms of `mlc check`'s start-up); its entry point says the same (tests/test_architecture.py)
    ref = BUILTIN.get(name) or _references().get(name)
    if ref is None:
        raise UnknownTarget(name)
    package = _load(ref)
    if not isinstance(package, TargetPackage) or package.name != name:
        raise TypeError(f"entry point {name} = {ref!r} is not TargetPackage({name!r}, ...)")
    return package


def target_names() -> list[str]:
    return sorted(_references())


@cache
def _simulation(name: str):
    from mlctool.targetapi.simulation import NO_SIMULATION

    ref = target_package(name).simulation
    return _load(ref) if ref else NO_SIMULATION


def simulation_of(target):
    """The `Simulation` of a loaded Target (its routines, hooks and special devices)."""
    return _simulation(target.name)
