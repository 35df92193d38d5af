"""What a target gives the simulator engine (mlctool/sim/), beyond its tables.

The engine runs every target with its generic routines (sim/semantics.py: contacts, coils,
timers, counters, moves, arithmetic, floats) and the scan's program flow; a target adds what
its manual has beyond them through one `Simulation` object, named by its TargetPackage
(registry.py). Every field is optional. Routines take the engine's Machine `m` and the decoded
step `s` (sim/decode.py Step) and follow the conventions of sim/semantics.py.

State a target's hardware keeps between scans lives in `Machine.ext` (cleared by a power
cycle), keyed by the target's own names.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType


@dataclass(frozen=True)
class SpecialDevice:
    """Devices a stimulus, `--watch` and the trace name that are not in the target's device
    table: a special module's buffer memory (VS `BFM2#5`), a peer station's registers
    (`CP1#2.D10`). The engine asks each in turn to parse a name it does not know.

    parse(text, target) -> DeviceView or None (not one of these; raise state.NameError_ for
      a name that is one of these but wrong);
    read(m, view) -> value; write(m, view, value);
    name(view) -> the text parse takes back.
    The views it returns carry it (`DeviceView.special`), so reads and writes come back here.
    """

    parse: Callable
    read: Callable
    write: Callable
    name: Callable


@dataclass(frozen=True)
class ModelKind:
    """A device model the target brings (a stimulus `model KIND ...` line), beside the generic
    ones of mlctool/devices/: the NC5's virtual NC.

    kind: the stimulus' KIND word.
    model: "module:Class" of its DeviceModel (mlctool/devices/base.py), imported when a
      stimulus names the kind.
    signals: signal -> (view, meaning), as sim/signals.py KINDS: the names it publishes
      (`NC1.X.pos`), known as soon as the target is.
    """

    kind: str
    model: str
    signals: Mapping[str, tuple[str, str]]


@dataclass(frozen=True)
class Simulation:
    """actions: op -> routine(m, s) for the target's own ops (instructions.toml `op`), taking
      precedence over the engine's generic routine of the same op. The compiled engine inlines
      only the generic routines; a target routine that is the generic one wherever the
      compiler inlines the op says so with `routine.generic = <the generic routine>`.
    scan_hooks: (routine(m), settings) pairs run at the start of every scan, before the
      system relays, on a loaded target whose target.toml has one of the settings (the
      virtual calendar, high-speed counters).
    before_scan: routine(m) run before each scan's inputs are applied (hardware that runs on
      the virtual clock between scans: pulse axes), at m.now_us.
    views(target, program) -> device views a run always reports and traces (axis registers).
    pulse_pins(target) -> pins driven as pulse trains; `mlc sim --pulse-window` records
      their level changes in Machine.pin_window (sim/hardware/pin_window.py).
    load_table(spec) -> (table, problems): a register table `mlc sim --table` loads.
    interrupts(program, target) -> the interrupt controller of a program that has interrupt
      pointers (class "interrupt"); the run asks it before every scan
      (`before_scan(simulation, k, events)`), reads its `outputs`, and `reset()`s it on a
      power cycle.
    special_devices: see SpecialDevice.
    models: see ModelKind.
    """

    actions: Mapping[str, Callable] = field(default_factory=lambda: MappingProxyType({}))
    scan_hooks: tuple[tuple[Callable, tuple[str, ...]], ...] = ()
    before_scan: Callable | None = None
    views: Callable | None = None
    pulse_pins: Callable | None = None
    load_table: Callable | None = None
    interrupts: Callable | None = None
    special_devices: tuple[SpecialDevice, ...] = ()
    models: tuple[ModelKind, ...] = ()


NO_SIMULATION = Simulation()
