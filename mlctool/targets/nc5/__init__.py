"""Delta NC5 MLC: everything about this controller.

Belongs here: its manual tables (target.toml, devices.toml, instructions.toml, and
signals.tsv: the MLC <-> NC special M/D of ch. 5, with signals.py to name them) and its NC
side, the virtual CNC a stimulus starts with `model nc5 ...` (nc/, given to the simulator by
simulation.py). Its instructions are all covered by the engine's generic routines
(mlctool/sim/semantics.py). Does not belong here: the engine, plant models (mlctool/devices/:
the XC100 axis controller it talks to).
"""

from pathlib import Path

from mlctool.targetapi.registry import TargetPackage

TARGET = TargetPackage("nc5", Path(__file__).parent, "mlctool.targets.nc5.simulation:SIMULATION")
