"""FATEK FBs with NC positioning: everything about this controller.

Belongs here: its manual tables (target.toml, devices.toml, instructions.toml,
positioning.toml), the positioning language (lang.py: .pos/.mpos sources, model.py, table.py
register tables, image.py, files.py), the pulse axes (axis.py, interp.py group interpolation,
mpg.py hand wheel, pulses.py pin edges) and simulation.py, which hands the NC instructions
(FUN140-148) to the engine. Does not belong here: the engine (mlctool/sim/), plant models.

Only this file is imported when the target is named; the simulator imports simulation.py.
"""

from pathlib import Path

from mlctool.targetapi.registry import TargetPackage

TARGET = TargetPackage("fbs", Path(__file__).parent, "mlctool.targets.fbs.simulation:SIMULATION")
