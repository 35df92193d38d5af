"""FX-family routines (Vigor VS) beyond semantics_fx.py, one small module per manual chapter;
semantics_fx merges `ACTIONS` into its table (keyed by `op`, like semantics.py)."""

from __future__ import annotations

from mlctool.sim.fx.data import DATA_ACTIONS
from mlctool.sim.fx.floats import FLOAT_ACTIONS
from mlctool.sim.fx.shift import SHIFT_ACTIONS
from mlctool.sim.fx.strings import STRING_ACTIONS

ACTIONS = {**SHIFT_ACTIONS, **DATA_ACTIONS, **FLOAT_ACTIONS, **STRING_ACTIONS}
