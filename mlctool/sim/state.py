"""Machine state of the simulated MLC, and the one device-name scheme of stimulus files,
`--watch` and JSON output (X0, T0:w, C64:d, D0:f, K4M0 ...).

Words are stored as raw unsigned 16-bit patterns; signed views are computed on access.
The 32-bit counters C64-C79 hold a signed 32-bit value each (1.7).
"""

from __future__ import annotations

import re
import struct
from array import array
from collections.abc import Callable
from dataclasses import dataclass, field

from mlctool.limits import clip, long_number, too_long_message
from mlctool.sim import signals
from mlctool.sim.signals import SIGNAL
from mlctool.sim.unit_words import UnitWords, unit_word_arrays
from mlctool.syntax.operands import device_number
from mlctool.targetapi.model import Target
from mlctool.targetapi.registry import simulation_of


class SimFault(Exception):
    """A run-time fault of the program (E604). `fatal` faults stop the run."""

    def __init__(self, message: str, fatal: bool = True, alarm: str | None = None):
        super().__init__(message)
        self.message = message
        self.fatal = fatal
        self.alarm = alarm


def s16(v: int) -> int:
    v &= 0xFFFF
    return v - 0x10000 if v & 0x8000 else v


def s32(v: int) -> int:
    v &= 0xFFFFFFFF
    return v - 0x100000000 if v & 0x80000000 else v


def f32_bits(x: float) -> int:
    """IEEE-754 single-precision bit pattern of x (rounded to nearest, overflow -> inf)."""
    try:
        return struct.unpack("<I", struct.pack("<f", x))[0]
    except OverflowError:
        return 0x7F800000 if x > 0 else 0xFF800000


# DECISION: a float operation whose result is NaN stores this quiet NaN (7FC00000H): the
# manuals define no NaN results, and CPython keeps no one payload when both operands are NaN
# (the product of two NaNs can take either one's, depending on how the multiply was compiled)
F32_QUIET_NAN = 0x7FC00000


def bits_f32(v: int) -> float:
    return struct.unpack("<f", struct.pack("<I", v & 0xFFFFFFFF))[0]


def to_f32(x: float) -> float:
    """x rounded to single precision (what the MLC stores)."""
    return bits_f32(f32_bits(x))


def put_words(store, first: int, values) -> None:
    """values into store[first:first + len(values)], item by item: a device container is a
    list, the native engine's array('q') (Machine.use_arrays), whose slice takes no other
    sequence, or unit words (UnG). The values are read first (source and store may overlap)."""
    for k, v in enumerate(list(values)):
        store[first + k] = v


class Machine:
    """All device memory, timer/counter bookkeeping and the rung-evaluation registers."""

    def __init__(self, target: Target, n_instrs: int):
        self.target = target
        d = target.devices
        # every bit and word kind of the target (NC5: X Y M A / D V Z; VS: X Y M S / D R V Z)
        self.bits = {k: bytearray(v.hi + 1) for k, v in d.items() if v.kind == "bit"}
        self.bits["T"] = bytearray(d["T"].hi + 1)  # timer contacts
        self.bits["C"] = bytearray(d["C"].hi + 1)  # counter contacts
        self.words = {k: [0] * (v.hi + 1) for k, v in d.items() if v.kind == "word" and not v.unit_prefix}
        self.words["T"] = [0] * (d["T"].hi + 1)  # timer present values (unsigned)
        self.cval = [0] * (d["C"].hi + 1)  # C0-C63 unsigned 16-bit, C64-C79 signed 32-bit
        self.c32_lo, _ = target.settings["counters32"]
        self.n_instrs = n_instrs
        self.layout = 0  # bumped when power_cycle replaces device containers (compiled code holds them)
        # timer bookkeeping (1.6): running flag, virtual time (us) of the last update, remainder
        nt = len(self.words["T"])
        self.t_running = bytearray(nt)
        self.t_last = [0] * nt
        self.t_frac = [0] * nt
        self.t_seen = bytearray(nt)  # its TMR executed in this scan
        self.t_preset = [0] * nt  # preset seen by its last TMR execution
        self.c_pending: dict[int, int] = {}  # counter contacts applied at end of scan (1.7)
        self.edge = bytearray(n_instrs)  # per-instruction edge memory (LDP..., PLS/PLF, CNT)
        self.writer: dict[tuple[str, int], int] = {}  # device -> index of last writing instr
        self.now_us = 0
        self.pc = 0
        self.acc = False
        self.blocks: list[bool] = []
        self.stack: list[bool] = []
        self.calls: list[int] = []  # return step indexes (CALL/SRET)
        self.fors: list[list[int]] = []  # [FOR index, NEXT index, iterations left]
        self.alarms: list[tuple[int, int, str, str]] = []  # (time us, instr index, alarm, message)
        # run-time warnings (sim/semantics.py warn): (time us, instr index, code, message)
        self.warnings: list[tuple[int, int | tuple[str, int], str, str]] = []
        self.servo_limit: dict[int, int] = {}  # WRTL: station -> torque limit
        self.servo_at_limit: dict[int, int] = {}  # RDTL input, driven by stimulus/models
        # power rail of the rung being evaluated: Off inside an MC block whose condition is
        # Off or an STL step that is not active (loads are ANDed with it)
        self.bus = True
        self.mc_stack: list[bool] = []  # MC: the rail inside each open level, innermost last
        # the step relays of the STL block being executed (several in a parallel merge, 4-3-3;
        # empty outside step ladder) and whether the next STL joins them
        self.stl_steps: tuple[int, ...] = ()
        self.stl_joining = False
        self.stl_leaving: set[int] = set()  # steps that transferred: reset at the end of the scan
        self.fx_state: dict[int, object] = {}  # step index -> memory of an FX routine (SORT, PID)
        # input pulse trains of the stimulus (sim/hardware/pulses.py): (kind, number) -> trains; the
        # hardware's, so a power cycle keeps them
        self.pulse_trains: dict[tuple[str, int], list] = {}
        self.quadrature: dict[tuple, list] = {}  # A/B pairs (pulses.Quadrature), likewise kept
        self.hsc: dict = {}  # high-speed counters and their compare points (targets/vs/hsc.py)
        self.ext: dict = {}  # state of the target's simulation extension (its Simulation, mlctool/targetapi/simulation.py)
        self.interrupts = None  # the target's interrupt controller (targets/vs/interrupts.py) of a program with interrupt pointers
        # special-module buffer memory (targets/vs/bfm.py): (slot, register) -> raw 16-bit word; the
        # modules' own memory, so a power cycle of the PLC keeps it (as inputs X keep theirs)
        self.bfm: dict[tuple[int, int], int] = {}
        self.words.update(unit_word_arrays(d, self.bfm))  # U1G3 operands: the same registers
        # memory card data bank (targets/vs/databank.py, VS DBRD/DBWR): address -> raw 16-bit word;
        # flash memory that keeps its data without power (2-8), so a power cycle keeps it
        self.databank: dict[int, int] = {}
        # peer stations on the serial ports (targets/vs/serial/peers.py, VS LINK/CPUL): (port, station) ->
        # (kind, number) -> raw value; other PLCs, so a power cycle of this one keeps them
        self.peers: dict[tuple[int, int], dict[tuple[str, int], int]] = {}
        # model-owned signals (sim/signals.py, `XC1.pos`): (kind "@XC1", signal index) -> value,
        # published by the models each step
        self.signals: dict[tuple[str, int], int] = {}
        # model kind "@NC1" -> what brings its signals up to date before one is read (ModelIO.on_read)
        self.signal_refresh: dict[str, Callable[[], None]] = {}
        self.pin_window = None  # sim/hardware/pin_window.py PinWindow: pulse pins inside a window (kept over power)
        self.image = None  # the linked program (Image): data kept beside the code (.table rows)
        # the relay that turns every external output Off while On (target.toml `outputs_off`,
        # VS M9034): the program keeps its Y image, what is read from outside (DeviceView.read:
        # the stimulus, the trace, models) is the terminals; None: the target has none
        self.outputs_off: int | None = (target.settings.get("outputs_off") or {}).get("relay")
        self.scans_done = 0  # scans completed since power-on (first-scan relays)
        self.arrays = False  # word containers are 64-bit arrays (use_arrays), not lists
        self.power_on_values()

    def outputs_disabled(self) -> bool:
        """The outputs-off relay is On: every Y terminal is Off whatever the image holds."""
        return self.outputs_off is not None and bool(self.bits["M"][self.outputs_off])

    def power_on_values(self) -> None:
        """Registers the PLC sets at power-on (target.toml `[power_on] words`, e.g. the VS RND
        seed D9160 = K1, 6-16); none on a target without the table."""
        for name, value in self.target.settings.get("power_on", {}).get("words", {}).items():
            kind, number = name[0], int(name[1:])
            self.words[kind][number] = value & 0xFFFF

    def zeros(self, n: int) -> list[int] | array:
        """A new word container of n zeros, of the kind this machine keeps (use_arrays)."""
        return array("q", bytes(8 * n)) if self.arrays else [0] * n

    def use_arrays(self) -> bool:
        """Keep the word registers, timer values, counter values and timer bookkeeping in
        signed 64-bit arrays instead of lists (from now on, power cycles included): the native
        engine (sim/engines/native.py) reads and writes them as C memory. They index and compare as
        the lists do (every value here is an int well inside 64 bits: raw 16-bit words, 32-bit
        counters, microseconds). True when a container was replaced (Machine.layout moved)."""
        changed = False
        for k, words in self.words.items():
            if type(words) is list:
                self.words[k] = array("q", words)
                changed = True
        for name in ("cval", "t_last", "t_frac", "t_preset"):
            if type(getattr(self, name)) is list:
                setattr(self, name, array("q", getattr(self, name)))
                changed = True
        self.arrays = True
        if changed:
            self.layout += 1
        return changed

    # -- timers and counters
    def is_c32(self, n: int) -> bool:
        return n >= self.c32_lo

    def timer_base_us(self, n: int) -> int:
        return self.target.timer_base_ms(n) * 1000

    def reset_timer(self, n: int) -> None:
        self.words["T"][n] = 0
        self.bits["T"][n] = 0
        self.t_running[n] = 0
        self.t_frac[n] = 0

    def reset_counter(self, n: int) -> None:
        self.cval[n] = 0
        self.bits["C"][n] = 0
        self.c_pending.pop(n, None)

    # -- power
    def power_cycle(self) -> None:
        """Power off and on (1.4, 1.8.1): latched areas keep their values, the rest clear.

        Inputs X are the hardware's and stay as the stimulus set them.
        """
        devs = self.target.devices
        latched = {k: [a for a in devs[k].areas if a.latched] for k in devs}
        keep_bits = [(k, a.lo, bytes(self.bits[k][a.lo:a.hi + 1])) for k in self.bits if k not in "TC"
                     for a in latched.get(k, ())]
        keep_words = [(k, a.lo, self.words[k][a.lo:a.hi + 1]) for k in self.words if k != "T"
                      for a in latched.get(k, ())]
        # latched timers and counters (VS T246-T255, C100-C199 ...): value and contact kept
        keep_t = [(a.lo, self.words["T"][a.lo:a.hi + 1], bytes(self.bits["T"][a.lo:a.hi + 1]))
                  for a in latched.get("T", ())]
        keep_c = [(a.lo, self.cval[a.lo:a.hi + 1], bytes(self.bits["C"][a.lo:a.hi + 1]))
                  for a in latched.get("C", ())]
        for k in self.bits:
            if not devs.get(k) or not devs[k].input:
                self.bits[k][:] = bytes(len(self.bits[k]))
        for k in self.words:
            if not isinstance(self.words[k], UnitWords):  # module memory, kept like self.bfm
                self.words[k] = self.zeros(len(self.words[k]))
        self.cval = self.zeros(len(self.cval))
        for k, lo, data in keep_bits:
            self.bits[k][lo:lo + len(data)] = data
        for k, lo, data in keep_words:
            self.words[k][lo:lo + len(data)] = data
        for lo, values, contacts in keep_t:
            self.words["T"][lo:lo + len(values)] = values
            self.bits["T"][lo:lo + len(contacts)] = contacts
        for lo, values, contacts in keep_c:
            self.cval[lo:lo + len(values)] = values
            self.bits["C"][lo:lo + len(contacts)] = contacts
        self.power_on_values()  # after the latched areas: the PLC sets these whatever they held
        self.stl_leaving.clear()
        self.fx_state.clear()
        self.hsc.clear()
        self.ext.clear()  # target hardware (pulse axes ...) restarts from power-on
        if self.interrupts is not None:  # enabled, nothing pending
            self.interrupts.reset()
        self.scans_done = 0
        self.layout += 1
        n = len(self.t_running)
        self.t_running = bytearray(n)
        self.t_frac = self.zeros(n)
        self.c_pending.clear()
        self.edge = bytearray(self.n_instrs)
        self.servo_limit.clear()


# ---------------------------------------------------------------- device names

_NAME = re.compile(r"(?:K(?P<n>[0-9]+)(?P<gdev>[A-Z])(?P<gnum>[0-9]+)|(?P<dev>[A-Z])(?P<num>[0-9]+))"
                   r"(?::(?P<view>[A-Za-z]+))?")
_KIND_ORDER = "XYMSATCDRVZK"


class NameError_(ValueError):
    """A device name that is malformed or not a device of the target (E602)."""


@dataclass(frozen=True, slots=True)
class DeviceView:
    """One named view of device memory: `X0`, `T0:w`, `C64:d`, `D0:f`, `K4M0`."""

    kind: str  # X Y M A T C D V Z, or "K" for a bit group
    number: int
    view: str  # bit | w | d | f | h | group
    digits: int = 0  # bit group size n (K1-K8)
    gdev: str = ""  # bit group device
    radix: int = 10  # how the number is written (8: octal X/Y of FX-family targets)
    # a target's special device (targetapi SpecialDevice: VS BFM2#5, CP1#2.D10) that names,
    # reads and writes this view; None for the devices of the target's device table
    special: object = field(default=None, compare=False, repr=False)

    @property
    def name(self) -> str:
        if self.kind.startswith(SIGNAL):  # XC1.pos
            return signals.name_of(self.kind, self.number)
        if self.special is not None:
            return self.special.name(self)
        num = device_number(self.number, self.radix)
        if self.view == "group":
            return f"K{self.digits}{self.gdev}{num}"
        if self.view in ("bit",) or (self.view == "w" and self.kind in "DRVZ"):
            return f"{self.kind}{num}"
        return f"{self.kind}{num}:{self.view}"

    @property
    def width(self) -> int:
        """Bits of the value (for waveforms)."""
        if self.view == "bit":
            return 1
        if self.view == "group":
            return 4 * self.digits
        return 32 if self.view in ("d", "f") else 16

    @property
    def is_float(self) -> bool:
        return self.view == "f"

    def sort_key(self):
        kind = self.gdev if self.view == "group" else self.kind
        # the kind last: two models' signals of one number (XC1.pos, XC2.pos) in a fixed order
        return (_KIND_ORDER.find(kind) % (len(_KIND_ORDER) + 1), self.number, self.view != "bit", self.view,
                self.digits, kind)

    # -- access
    def read(self, m: Machine) -> int | float:
        """The value as seen from outside the program (stimulus, trace, models, debugger): a Y
        is its terminal, Off while the outputs-off relay is On (Machine.outputs_off)."""
        k, n, v = self.kind, self.number, self.view
        if k.startswith(SIGNAL):
            refresh = m.signal_refresh.get(k)
            if refresh is not None:
                refresh()
            return m.signals.get((k, n), 0)
        if self.special is not None:
            return self.special.read(m, self)
        if v == "bit":
            if k == "Y" and m.outputs_off is not None and m.bits["M"][m.outputs_off]:
                return 0  # the terminal, not the image (Machine.outputs_off)
            return m.bits[k][n]
        if v == "group":
            if self.gdev == "Y" and m.outputs_disabled():
                return 0
            bits = m.bits[self.gdev]
            return sum(bits[n + i] << i for i in range(4 * self.digits))
        if k == "T":
            return m.words["T"][n]
        if k == "C":
            return m.cval[n] if v == "w" else s32(m.cval[n])
        if v == "h":
            return m.words[k][n]
        if v == "w":
            return s16(m.words[k][n])
        raw = _pair_raw(m, k, n)
        return s32(raw) if v == "d" else bits_f32(raw)

    def write(self, m: Machine, value: int | float) -> None:
        k, n, v = self.kind, self.number, self.view
        if k.startswith(SIGNAL):  # only models publish (the stimulus refuses to set them)
            m.signals[(k, n)] = int(value)
            return
        if self.special is not None:
            self.special.write(m, self, value)
            return
        if v == "bit":
            m.bits[k][n] = 1 if value else 0
        elif v == "group":
            bits = m.bits[self.gdev]
            for i in range(4 * self.digits):
                bits[n + i] = (int(value) >> i) & 1
        elif k == "T":
            m.words["T"][n] = int(value) & 0xFFFF
        elif k == "C":
            m.cval[n] = int(value) & 0xFFFF if v == "w" else s32(int(value))
        elif v in ("w", "h"):
            m.words[k][n] = int(value) & 0xFFFF
        else:
            raw = f32_bits(float(value)) if v == "f" else int(value) & 0xFFFFFFFF
            _set_pair_raw(m, k, n, raw)


def _pair_raw(m: Machine, kind: str, n: int) -> int:
    if kind == "V":  # 32-bit V: V n low, Z n high (target.toml decision, 1.8.2)
        return m.words["V"][n] | (m.words["Z"][n] << 16)
    w = m.words[kind]
    return w[n] | (w[n + 1] << 16)


def _set_pair_raw(m: Machine, kind: str, n: int, raw: int) -> None:
    if kind == "V":
        m.words["V"][n] = raw & 0xFFFF
        m.words["Z"][n] = (raw >> 16) & 0xFFFF
        return
    w = m.words[kind]
    w[n] = raw & 0xFFFF
    w[n + 1] = (raw >> 16) & 0xFFFF


def _number(digits: str, dev, text: str) -> int:
    if dev.radix == 8 and ("8" in digits or "9" in digits):
        raise NameError_(f"{text!r}: {dev.name} is numbered in octal")
    return int(digits, dev.radix)


def parse_signal_name(text: str) -> DeviceView:
    """`XC1.pos` -> DeviceView (raises NameError_ for an unknown signal)."""
    m = signals.SIGNAL_NAME.fullmatch(text.strip().upper())
    signal = signals.canonical(m["signal"])
    if signal is None:
        from mlctool.suggest import did_you_mean  # only once a name is wrong

        wrong = text.strip().split(".", 1)[1]
        raise NameError_(f"{text!r}: no model signal {wrong!r}"
                         + (did_you_mean(wrong, signals.NAMES, "'") or f"; signals: {', '.join(signals.NAMES)}"))
    return DeviceView(signals.SIGNAL + m["model"], signals.index(signal), signals.VIEWS[signal])


def add_target_models(target: Target) -> None:
    """The target's own device models' signals (targetapi ModelKind) become names."""
    for kind in simulation_of(target).models:
        signals.add_kind(kind.kind, kind.signals)


def parse_device_name(text: str, target: Target) -> DeviceView:
    """`D0:f` -> DeviceView. Raises NameError_ with a message for E602."""
    long = long_number(text)
    if long:  # --watch, stimulus and report names: bounded before int() (mlctool/limits.py)
        raise NameError_(too_long_message(repr(clip(text)), len(long[0])))
    for special in simulation_of(target).special_devices:  # the target's own (VS BFM2#5)
        view = special.parse(text, target)
        if view is not None:
            return view
    if signals.looks_like(text):
        add_target_models(target)
        return parse_signal_name(text)
    m = _NAME.fullmatch(text.strip().upper())
    if not m:
        raise NameError_(f"{text!r} is not a device name (e.g. X0, T0:w, D0:d, K4M0)")
    view = (m["view"] or "").lower()
    devs = target.devices
    if m["n"]:
        digits, gdev = int(m["n"]), m["gdev"]
        dev = devs.get(gdev)
        if dev is None or dev.kind != "bit":
            raise NameError_(f"{text!r}: no bit device {gdev} on target {target.name}")
        num = _number(m["gnum"], dev, text)
        if view:
            raise NameError_(f"{text!r}: a bit group takes no view suffix")
        if not 1 <= digits <= 8:
            raise NameError_(f"{text!r}: bit groups are K1-K8")
        if num + 4 * digits - 1 > dev.hi:
            raise NameError_(f"{text!r} runs past {gdev}{dev.hi}")
        return DeviceView("K", num, "group", digits, gdev, dev.radix)
    kind = m["dev"]
    dev = devs.get(kind)
    if dev is None or dev.kind == "pointer":
        raise NameError_(f"{text!r}: no device {kind} on target {target.name}")
    num = _number(m["num"], dev, text)
    if not dev.lo <= num <= dev.hi:
        raise NameError_(f"{text!r}: {kind} ranges {kind}{dev.lo}-{kind}{dev.hi}")
    if dev.kind == "bit":
        if view:
            raise NameError_(f"{text!r}: bit devices take no view suffix")
        return DeviceView(kind, num, "bit", radix=dev.radix)
    if kind == "T":
        if view not in ("", "w"):
            raise NameError_(f"{text!r}: timers are T{num} (contact) or T{num}:w (present value)")
        return DeviceView(kind, num, "w" if view else "bit")
    if kind == "C":
        want = "d" if target.is_counter32(num) else "w"
        if view not in ("", want):
            raise NameError_(f"{text!r}: counter C{num} is C{num} (contact) or C{num}:{want} (value)")
        return DeviceView(kind, num, want if view else "bit")
    view = view or "w"
    if view not in ("w", "d", "f", "h"):
        raise NameError_(f"{text!r}: word views are :w :d :f :h")
    if view in ("d", "f") and kind != "V" and num + 1 > dev.hi:
        raise NameError_(f"{text!r}: the pair needs {kind}{num + 1}")
    return DeviceView(kind, num, view)
