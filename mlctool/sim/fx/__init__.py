"""FX-family routines (Vigor VS) beyond semantics_fx.py, one small module per manual chapter;
semantics_fx merges their tables into its own (keyed by `op`, like semantics.py).

Importing any of them loads semantics first: semantics -> semantics_fx -> these modules is
the one import order that has no cycle. A new family module is added to FAMILIES.
"""

from __future__ import annotations

import importlib

from mlctool.sim import semantics  # noqa: F401

# module -> its table of op -> routine
FAMILIES = {
    "mlctool.sim.fx.shift": "SHIFT_ACTIONS",
    "mlctool.sim.fx.data": "DATA_ACTIONS",
    "mlctool.sim.fx.floats": "FLOAT_ACTIONS",
    "mlctool.sim.fx.strings": "STRING_ACTIONS",
    "mlctool.sim.fx.clock": "CLOCK_ACTIONS",
    "mlctool.sim.fx.pid": "PID_ACTIONS",
    "mlctool.sim.fx.hsc": "HSC_ACTIONS",
    "mlctool.sim.fx.convert": "CONVERT_ACTIONS",
    "mlctool.sim.fx.tables": "TABLE_ACTIONS",
    "mlctool.sim.fx.ascii_codes": "ASCII_ACTIONS",
    "mlctool.sim.fx.scale": "SCALE_ACTIONS",
    "mlctool.sim.fx.timing": "TIMING_ACTIONS",
    "mlctool.sim.fx.io_refresh": "IO_REFRESH_ACTIONS",
    "mlctool.sim.fx_mbus": "MBUS_ACTIONS",  # Modbus master MBUS (FNC 149)
    "mlctool.sim.fx.interrupts": "INTERRUPT_ACTIONS",  # IRET/EI/DI, pointers (2-12)
    "mlctool.sim.fx.bfm": "BFM_ACTIONS",  # FROM/TO on a simulated buffer memory (6-9)
    "mlctool.sim.fx.databank": "DATABANK_ACTIONS",  # DBRD/DBWR memory card data bank (6-11)
    "mlctool.sim.fx.datatable": "DATA_TABLE_ACTIONS",  # DTRD data tables (6-11)
    "mlctool.sim.fx.pulse_out": "PULSE_OUTPUT_ACTIONS",  # PLSY, PWM, PLSR (6-7)
    "mlctool.sim.fx.scan_io": "SCAN_IO_ACTIONS",  # MTR, DSW (6-7, 6-9)
    "mlctool.sim.fx.io_devices": "IO_DEVICE_ACTIONS",  # SEGD, PRUN (6-9, 6-10)
    "mlctool.sim.fx.keypad_display": "KEYPAD_DISPLAY_ACTIONS",  # TKY, HKY, SEGL, PR (6-9)
    "mlctool.sim.fx.serial_rs": "SERIAL_RS_ACTIONS",  # RS non-protocol send/receive (6-10)
    "mlctool.sim.fx.plc_link": "PLC_LINK_ACTIONS",  # LINK, CPUL with peer PLCs (6-10)
    "mlctool.sim.fx.positioning": "POSITIONING_ACTIONS",  # JOGF ... PLSV, FNC 301-311 (8-3)
    "mlctool.sim.fx.pos_table": "POS_TABLE_ACTIONS",  # DTBL, FNC 312 (8-3)
    "mlctool.sim.fx.pos_abs": "POS_ABS_ACTIONS",  # DABS, FNC 313 (8-3)
    "mlctool.sim.fx.pos_mpg": "POS_MPG_ACTIONS",  # MPG, FNC 314 (8-3)
    "mlctool.sim.fx.pos_lines": "POS_LINES_ACTIONS",  # LIR, LIA, FNC 315/316 (8-3)
    "mlctool.sim.fx.homing": "HOMING_ACTIONS",  # ZRN, FNC 300, home modes, DOG search (8-1-2)
}

# routines run before every scan (module, name, the target.toml settings of which one is
# enough for the routine to have something to do: other targets skip it)
BEFORE_SCAN = (("mlctool.sim.fx.clock", "refresh", ("rtc",)),
               ("mlctool.sim.fx.hsc", "catch_up", ("high_speed_counters", "hardware_counters")))
# hardware that requests interrupts (IHC, IHHC) counts up to now before the interrupt queue of
# the interval is built (fx/interrupts.py); counting again at the scan's start adds nothing
INTERRUPT_SOURCES = (("mlctool.sim.fx.hsc", "catch_up"),)


def family_actions() -> dict:
    out: dict = {}
    for module, table in FAMILIES.items():
        actions = getattr(importlib.import_module(module), table)
        clash = set(out) & set(actions)
        if clash:
            raise RuntimeError(f"{module}: ops already defined by another family: {sorted(clash)}")
        out.update(actions)
    return out


def routines(named: tuple) -> tuple:
    """The routines of (module, name, ...) entries."""
    return tuple(getattr(importlib.import_module(m), name) for m, name, *_ in named)


def before_scan_hooks() -> tuple:
    """(routine, settings it needs) pairs of BEFORE_SCAN."""
    return tuple(zip(routines(BEFORE_SCAN), (needs for *_, needs in BEFORE_SCAN)))
