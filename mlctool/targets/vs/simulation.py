"""The Vigor VS target's Simulation (mlctool/targetapi/simulation.py): its routines, one
module per manual chapter or peripheral, merged with routines.py; the hooks its hardware
needs; the special devices its stimulus names (BFM, data bank, peer stations).

A new chapter module is added to FAMILIES.
"""

from __future__ import annotations

import importlib

from mlctool.targetapi.simulation import Simulation
from mlctool.targets.vs import clock, hsc
from mlctool.targets.vs.interrupts import Interrupts
from mlctool.targets.vs.routines import BASIC_ACTIONS, device_clear, step_monitor
from mlctool.targets.vs.special_devices import SPECIAL_DEVICES

# module -> its table of op -> routine
FAMILIES = {
    "mlctool.targets.vs.shift": "SHIFT_ACTIONS",
    "mlctool.targets.vs.data": "DATA_ACTIONS",
    "mlctool.targets.vs.floats": "FLOAT_ACTIONS",
    "mlctool.targets.vs.strings": "STRING_ACTIONS",
    "mlctool.targets.vs.clock": "CLOCK_ACTIONS",
    "mlctool.targets.vs.pid": "PID_ACTIONS",
    "mlctool.targets.vs.hsc": "HSC_ACTIONS",
    "mlctool.targets.vs.convert": "CONVERT_ACTIONS",
    "mlctool.targets.vs.tables": "TABLE_ACTIONS",
    "mlctool.targets.vs.ascii_codes": "ASCII_ACTIONS",
    "mlctool.targets.vs.scale": "SCALE_ACTIONS",
    "mlctool.targets.vs.timing": "TIMING_ACTIONS",
    "mlctool.targets.vs.io_refresh": "IO_REFRESH_ACTIONS",
    "mlctool.targets.vs.serial.mbus": "MBUS_ACTIONS",  # Modbus master MBUS (FNC 149)
    "mlctool.targets.vs.interrupts": "INTERRUPT_ACTIONS",  # IRET/EI/DI, pointers (2-12)
    "mlctool.targets.vs.bfm": "BFM_ACTIONS",  # FROM/TO on a simulated buffer memory (6-9)
    "mlctool.targets.vs.databank": "DATABANK_ACTIONS",  # DBRD/DBWR memory card data bank (6-11)
    "mlctool.targets.vs.datatable": "DATA_TABLE_ACTIONS",  # DTRD data tables (6-11)
    "mlctool.targets.vs.pulse_out": "PULSE_OUTPUT_ACTIONS",  # PLSY, PWM, PLSR (6-7)
    "mlctool.targets.vs.scan_io": "SCAN_IO_ACTIONS",  # MTR, DSW (6-7, 6-9)
    "mlctool.targets.vs.io_devices": "IO_DEVICE_ACTIONS",  # SEGD, PRUN (6-9, 6-10)
    "mlctool.targets.vs.keypad_display": "KEYPAD_DISPLAY_ACTIONS",  # TKY, HKY, SEGL, PR (6-9)
    "mlctool.targets.vs.serial.rs": "SERIAL_RS_ACTIONS",  # RS non-protocol send/receive (6-10)
    "mlctool.targets.vs.serial.link": "PLC_LINK_ACTIONS",  # LINK, CPUL with peer PLCs (6-10)
    "mlctool.targets.vs.positioning.moves": "POSITIONING_ACTIONS",  # JOGF ... PLSV, FNC 301-311 (8-3)
    "mlctool.targets.vs.positioning.table": "POS_TABLE_ACTIONS",  # DTBL, FNC 312 (8-3)
    "mlctool.targets.vs.positioning.absolute": "POS_ABS_ACTIONS",  # DABS, FNC 313 (8-3)
    "mlctool.targets.vs.positioning.mpg": "POS_MPG_ACTIONS",  # MPG, FNC 314 (8-3)
    "mlctool.targets.vs.positioning.lines": "POS_LINES_ACTIONS",  # LIR, LIA, FNC 315/316 (8-3)
    "mlctool.targets.vs.positioning.homing": "HOMING_ACTIONS",  # ZRN, FNC 300, DOG search (8-1-2)
}


def family_actions() -> dict:
    """routines.py's table, and over it the chapter modules' (none of which may share an op)."""
    out: dict = {}
    for module, table in FAMILIES.items():
        actions = getattr(importlib.import_module(module), table)
        clash = set(out) & set(actions)
        if clash:
            raise RuntimeError(f"{module}: ops already defined by another family: {sorted(clash)}")
        out.update(actions)
    return {**BASIC_ACTIONS, **out}


SIMULATION = Simulation(
    actions=family_actions(),
    # before every scan, on the targets whose target.toml has one of the settings: the
    # virtual calendar's registers, the high-speed counters counted up to the scan's start
    scan_hooks=((clock.refresh, ("rtc",)),
                (hsc.catch_up, ("high_speed_counters", "hardware_counters")),
                (step_monitor, ("step_monitor",)), (device_clear, ("device_clear",))),
    interrupts=Interrupts,
    special_devices=SPECIAL_DEVICES,
)
