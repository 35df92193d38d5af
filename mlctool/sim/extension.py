"""Target simulation extensions: a target that has instructions of its own names a module in
target.toml (`sim_extension = "mlctool.fbs.sim"`). The module may define

- `ACTIONS`: {op: routine(m, s)} for its instructions, merged over semantics.ACTIONS;
- `before_scan(m)`: run before each scan's inputs are applied (hardware that runs on the
  virtual clock between scans, e.g. pulse axes), at m.now_us;
- `views(target, prog)`: device views a run always reports and traces (axis registers).
- `pulse_pins(target)`: the pins it drives as pulse trains; with `mlc sim --pulse-window`
  it records their level changes in `Machine.pin_window` (sim/pin_window.py).

State of the extension lives in `Machine.ext` (cleared by a power cycle). Targets without
the key behave as before.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from mlctool.sim import semantics


def extension(target) -> ModuleType | None:
    name = target.settings.get("sim_extension")
    return importlib.import_module(name) if name else None


def actions(target) -> dict:
    """The op -> routine table of `target`: the generic routines and the target's own."""
    ext = extension(target) if target is not None else None
    extra = getattr(ext, "ACTIONS", None)
    return {**semantics.ACTIONS, **extra} if extra else semantics.ACTIONS
