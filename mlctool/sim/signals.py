"""Model-owned signals: what a device model shows by name, `XC1.pos`, `XC1.alarm`, for
stimulus expectations, `--watch`, JSON and the VCD (docs/stimulus.md "Model signals").

A model line names its model (`model xc100 name=XC1 ...`, default XC1); every step the model
publishes its signals into Machine.signals, and a DeviceView of kind SIGNAL + NAME reads
them. They are the device's state as the device knows it (not PLC memory): the program
cannot see them, the stimulus cannot set them. The signal names of each model kind are
listed here, so the scan side never imports the device models; state.py's
parse_signal_name reads a signal's name. A target's own models (targetapi ModelKind, the
NC5's virtual NC) add their kinds with add_kind when the target's Simulation is first asked
for a name: their signals are numbered after the built-in ones, in the order of the target's
table, so the numbers are the same in every process that loads the same target.
"""

from __future__ import annotations

import re

SIGNAL = "@"  # DeviceView kind prefix: "@XC1" with number = index into NAMES

# model kind -> signal -> (view, meaning); views as DeviceView's: bit, w (16-bit), d (32-bit)
KINDS: dict[str, dict[str, tuple[str, str]]] = {
    "xc100": {
        "pos": ("d", "actual position (encoder), 0.01 mm from the origin (1008H/100AH in mm)"),
        "cmd": ("d", "command position, 0.01 mm"),
        "speed": ("d", "actual speed, 0.01 mm/s (signed)"),
        "action": ("w", "ActionStatus 1000H: 0 stopped, 1 moving, 2 abnormal stop"),
        "alarm": ("w", "AlarmStatus 1005H (10.2); 0 = none"),
        "error": ("w", "ErrorStatus 100DH (10.3); 0 = none"),
        "step": ("w", "StepNo 100EH: the running (or last) point, -1 none"),
        "torque": ("w", "motor torque (current) in 0.1 % of rated, as MonCurrent 1007H: "
                        "during a push the pushing torque"),
        "limit": ("w", "torque limit in force, 0.1 %: the point's (9014H), the homing one "
                       "(OrgTrqLimit 0907H) or the push torques (0400H/0401H); 0 at rest"),
        "servo": ("bit", "servo ON (100CH)"),
        "homed": ("bit", "origin return complete"),
        "inp": ("bit", "in position (1001H)"),
        "pushing": ("bit", "torque limit reached (1004H TrqLmtStatus, TRQ_LMT)"),
    },
    "stepper": {  # mlctool/devices/stepper.py, FBs manual 11.5.1
        "freq": ("d", "pulse frequency of the axis, Ps/s (DR4080+2Ps)"),
        "pulses": ("d", "position of the axis, pulses (DR4088+2Ps)"),
        "rpm": ("d", "shaft speed, 0.01 rpm: 60 x f / n (11.5.1), negative while the position falls"),
        "angle": ("d", "shaft angle, 0.01 deg, 0..35999"),
        "travel": ("d", "travel, um: pulses x um_per_rev / pulses_per_rev (MPARA parameters 1, 2)"),
    },
}
DEFAULT_PREFIX = {"xc100": "XC", "stepper": "MOT"}  # an unnamed model is XC1, XC2 ... in stimulus order
NAMES: list[str] = sorted({s for table in KINDS.values() for s in table})
VIEWS: dict[str, str] = {s: v for table in KINDS.values() for s, (v, _) in table.items()}
_INDEX: dict[str, int] = {s: i for i, s in enumerate(NAMES)}
_BY_UPPER: dict[str, str] = {s.upper(): s for s in NAMES}  # the names are read case-insensitively
# MODEL.signal, where a signal may have one inner dot (a part of the device: NC1.X.pos)
SIGNAL_NAME = re.compile(r"(?P<model>[A-Z][A-Z0-9_]*)\.(?P<signal>[A-Z_][A-Z0-9_]*(?:\.[A-Z_][A-Z0-9_]*)?)")
MODEL_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def add_kind(kind: str, table: dict[str, tuple[str, str]]) -> None:
    """A target's model kind and its signals (targetapi ModelKind); once per kind."""
    if kind in KINDS:
        return
    KINDS[kind] = dict(table)
    for signal, (view, _) in table.items():
        if signal.upper() in _BY_UPPER:
            continue  # a name the built-in models use too: one number, one view
        _INDEX[signal] = len(NAMES)
        NAMES.append(signal)
        VIEWS[signal] = view
        _BY_UPPER[signal.upper()] = signal


def canonical(signal: str) -> str | None:
    """The signal's name as its table spells it (`x.POS` -> `X.pos`), None if no model has it."""
    return _BY_UPPER.get(signal.upper())


def index(signal: str) -> int:
    return _INDEX[signal]


def looks_like(text: str) -> bool:
    return SIGNAL_NAME.fullmatch(text.strip().upper()) is not None


def name_of(kind: str, number: int) -> str:
    return f"{kind[len(SIGNAL):]}.{NAMES[number]}"


def model_of(kind: str) -> str:
    return kind[len(SIGNAL):]


def signal_of(number: int) -> str:
    return NAMES[number]
