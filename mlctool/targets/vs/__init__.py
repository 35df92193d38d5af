"""Vigor VS series (FX-compatible): everything about this controller.

Belongs here: its manual tables (target.toml, devices.toml, instructions.toml), the routines
of its instructions (routines.py and one module per manual chapter), its peripherals
(positioning/ ch. 8, serial/ MBUS RS LINK CPUL and peer stations, hsc.py hhsc.py high-speed
counters, bfm.py special modules, interrupts.py) and simulation.py, which hands all that to
the engine. Does not belong here: the engine (mlctool/sim/), plant models (mlctool/devices/),
anything another target could use unchanged (the engine's generic routines).

Only this file is imported when the target is named (`mlc check --target vs`); the
simulator imports simulation.py.
"""

from pathlib import Path

from mlctool.targetapi.registry import TargetPackage

TARGET = TargetPackage("vs", Path(__file__).parent, "mlctool.targets.vs.simulation:SIMULATION")
