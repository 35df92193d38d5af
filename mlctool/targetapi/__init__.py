"""The interface between the toolchain and its targets (controllers).

Belongs here: what a target is to the rest of the code: its manual tables as data
(model.py: Target, InstrSpec, DeviceKind ...), how targets are found (registry.py: the
`mlctool.targets` entry points, TargetPackage) and what a target may give the simulator
(simulation.py: Simulation, SpecialDevice). Generic code (check, asm, sim, cli) imports this
package, never a target's own package.

Does not belong here: anything about one controller (that is mlctool/targets/<name>/), the
engine (mlctool/sim/).
"""

from mlctool.targetapi.model import Target, UnknownModel, available_targets, load_target
from mlctool.targetapi.registry import TargetPackage, simulation_of

__all__ = ["ModelKind", "Simulation", "SpecialDevice", "Target", "TargetPackage", "UnknownModel",
           "available_targets", "load_target", "simulation_of"]


def __getattr__(name: str):
    """Simulation, SpecialDevice and ModelKind are imported when first asked for: `mlc check` never
    needs them, and their dataclasses cost every start a few milliseconds (issue 19)."""
    if name in ("ModelKind", "Simulation", "SpecialDevice"):
        from mlctool.targetapi import simulation

        return getattr(simulation, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
