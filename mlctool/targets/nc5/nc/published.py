"""The signals the virtual NC publishes (`NC1.mode`, `NC1.X.pos` ...): its own state for
expectations, --watch, JSON, the VCD, the report and the debugger (sim/signals.py, through
targetapi ModelKind). They are not MLC memory: the MLC program sees the NC only through the
special M/D of addresses.py.
"""

from __future__ import annotations

from mlctool.targets.nc5.nc.addresses import AXIS_ORDER

STATES = ("idle", "running", "feed hold", "single-block stop", "M/S/T wait", "M00/M01 stop",
          "program end", "alarm")
ALARMS = {1: "soft limit", 2: "hardware limit", 3: "T code with the magazine off (N0.1400 = 0)"}

SIGNALS: dict[str, tuple[str, str]] = {
    "mode": ("w", "the mode in force (M3x000-M3x007 feedback): 0 AUTO, 1 EDIT, 2 MDI, 3 MPG, "
                  "4 JOG, 5 RAPID, 6 INC, 7 HOME"),
    "state": ("w", "program state: " + ", ".join(f"{i} {s}" for i, s in enumerate(STATES))),
    "block": ("w", "line of the part program's block in execution (or last executed); 0 none"),
    "alarm": ("w", "NC alarm: 0 none, " + ", ".join(f"{k} {v}" for k, v in ALARMS.items())),
    "feed": ("d", "path speed in force, mm/min (with the overrides)"),
    **{f"{a}.pos": ("d", f"{a} axis machine position, 0.001 mm") for a in AXIS_ORDER},
    **{f"{a}.speed": ("d", f"{a} axis speed, mm/min, negative while moving -") for a in AXIS_ORDER},
    "spindle.rpm": ("d", "first spindle actual speed, rpm, negative in reverse"),
    "spindle.cmd": ("d", "first spindle target speed, rpm (command x override, limited)"),
    "spindle.angle": ("d", "first spindle angle, 0.01 deg, 0..35999"),
    "spindle.gear": ("w", "first spindle gear as D2x027 selects it (1-4)"),
}
