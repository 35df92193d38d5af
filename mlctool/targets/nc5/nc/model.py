"""The virtual NC: one channel of the NC5's CNC side as an `mlc sim` device model.

    model nc5 [channel=1] [axes=X,Y,Z] [program=part.nc] [name=NC1] [start=0,0,0]
              [feedback=4ms] [rapid=10000] [feed_max=10000] [jog_max=2000] [home_speed=3000]
              [spindle_max=6000] [spindle_ramp=1s] [at_speed=100] [zero_speed=100]
              [orient_at=0] [orient_time=300ms] [tools=16] [first_tool=1] [standby_pot=1]
              [magazine=1] [reset_spindle=1] [mpg=D100] [soft1_x=LO:HI] [soft2_x=LO:HI]
              [hard_x=LO:HI] [macro_9001=O9001.nc] [sync_b=Y] [clock=2022-06-01T00:00:00] ...

Each step (before every scan, on the simulator's clock) it reads the MLC -> NC relays and
registers the previous scan left (addresses.py: M2c..., D2c...) and writes the NC -> MLC ones
(M3c..., D3c..., D49c..) for the coming scan: modes (5.3.1, 6.1), the part program (5.3.2, 6.2)
and its handwheel run, the M/S/T handshake (5.3.10, 6.8), axes (5.3.3-5.3.6, 6.3-6.7, 6.9), the
one-key macro (5.3.8, 6.12), MLC axes (5.3.9, 6.14), synchronous, transferred and gantry axes
(5.3.11, 5.3.12, 6.15, 6.16), the first spindle (5.3.13, 6.10, 6.11), tool magazine 1 (5.3.14,
6.13), part counters, machining and system times (5.3.15). A step in which only time passes is
skipped and caught up in closed form (step()). What
the manual does not give (speeds, ramps, travel) is a parameter; docs/nc5.md has the table and
every decision. Its own state is published as signals (published.py): NC1.mode, NC1.X.pos ...
"""

from __future__ import annotations

import datetime
import math
import os
import struct

from mlctool.devices.base import DeviceModel, ModelInputError, ModelIO, ParamError
from mlctool.diagnostics import Span, diag
from mlctool.fileio import read_input
from mlctool.sim.state import DeviceView, parse_signal_name
from mlctool.sim.stimulus.stimulus import StimError, parse_time
from mlctool.targetapi.model import Target
from mlctool.targets.nc5.nc import addresses as A
from mlctool.targets.nc5.nc.program import MAX_BYTES, NOT_HANDSHAKEN_M, Block, PartProgram, parse

AUTO, EDIT, MDI, MPG, JOG, RAPID, INC, HOME = range(8)  # D2x000 values (5.2.2, 6.1)
IDLE, RUNNING, HOLD, BLOCK_STOP, MST_WAIT, PROGRAM_STOP, END, ALARM = range(8)  # published.STATES
NO_PROGRAM = "W345"  # codes.toml: cycle start on a model nc5 line without program=
SOFT_LIMIT, HARD_LIMIT, NO_MAGAZINE = 1, 2, 3  # published.ALARMS

# (key, default, lo, hi, unit): numeric parameters; docs/nc5.md "Parameters" is this table
NUMBERS = (
    ("rapid", 10000, 1, 999999, "mm/min"),  # N1.030 / N2.020 at 100 %
    ("feed_max", 10000, 1, 999999, "mm/min"),  # N1.033
    ("jog_max", 2000, 1, 999999, "mm/min"),  # N2.030 at D2x006 = 100
    ("home_speed", 3000, 1, 999999, "mm/min"),  # N2.053
    ("spindle_max", 6000, 1, 999999, "rpm"),  # N0.1008
    ("at_speed", 100, 0, 999999, "rpm"),  # N0.1018 (6.10's example value)
    ("zero_speed", 100, 0, 999999, "rpm"),  # N0.1017 (6.10's example value)
    ("orient_at", 0, 0, 35999, "0.01 deg"),  # N0.1013
    ("tools", 16, 1, 999, "pots"),  # N0.1402
    ("first_tool", 1, 1, 9999, "tool"),  # N0.1403
    ("standby_pot", 1, 1, 999, "pot"),  # N0.1404
    ("magazine", 1, 0, 1, ""),  # N0.1400: magazine 1 on
    ("reset_spindle", 1, 0, 1, ""),  # N0.1400: spindle tool after a reset: 0, or the highest + 1
)
TIMES = (("feedback", "4ms"), ("spindle_ramp", "1s"), ("orient_time", "300ms"))  # (key, default)
MAX_TIME_US = 60_000_000
ANGLE_WORD = 4  # D3x028's place in the words _outputs writes (_output_addresses)


def _s16(v: int) -> int:
    return v - 0x10000 if v & 0x8000 else v


def _f32(dw, n: int) -> float:
    """The float in D n (low word) and D n+1 (6.14: 須為浮點數型態數值); 0 if not finite."""
    v = struct.unpack("<f", struct.pack("<HH", dw[n] & 0xFFFF, dw[n + 1] & 0xFFFF))[0]
    return v if math.isfinite(v) else 0.0


def _s32(lo: int, hi: int) -> int:
    v = lo | hi << 16
    return v - 0x100000000 if v & 0x80000000 else v


class Axis:
    __slots__ = ("letter", "offset", "pos", "speed", "vel", "rest", "homed", "home_done", "homing", "inc_target",
                 "soft1", "soft2", "hard", "mlc", "mlc_target", "mlc_done", "base", "held")

    def __init__(self, letter: str, pos: int):
        self.letter = letter
        self.offset = A.AXIS_ORDER.index(letter)  # per-axis rows: X +0 ... W +8 (5.2.1)
        self.pos = pos  # machine position, 0.001 mm
        self.speed = 0  # mm/min in force, signed (published X.speed)
        self.vel = 0  # manual move in force (jog, INC, homing), 0.001 mm/min, signed
        self.rest = 0  # what a manual move's steps left under 0.001 mm, x 60 000 000 (distance())
        self.homed = False  # M3x320: ever homed since power-up
        self.home_done = False  # M3x336: homed, not moved by hand or program since
        self.homing = False
        self.inc_target: int | None = None
        self.soft1: tuple[int, int] | None = None
        self.soft2: tuple[int, int] | None = None
        self.hard: tuple[int, int] | None = None
        self.mlc = False  # an MLC axis (M3x432+): the MLC moves it (5.3.9, 6.14)
        self.mlc_target: int | None = None  # position mode: where the trigger sent it
        self.mlc_done = False  # M3x448+: in position (position mode)
        self.base = 0  # position when its synchronous / transfer relation began (5.3.11, 5.3.12)
        self.held: int | None = None  # a transfer's master: where it stands while pos is its command


class NcModel(DeviceModel):
    kind = "nc5"
    SKIP = True  # skip the steps that only let time pass (step()); tests compare with False
    NO_MACROS = [False] * 16  # M3x048-M3x063 while no macro call is on

    @classmethod
    def build(cls, params: dict[str, str], target: Target, folder: str) -> NcModel:
        model = cls(params, target)
        if "program" in params:
            model.program = model.read_program(os.path.join(folder, params["program"]))
        for n, name in sorted(model.macro_files.items()):
            model.macros[n] = model.read_program(os.path.join(folder, name), macro=True)
        return model

    def __init__(self, params: dict[str, str], target: Target):
        super().__init__(params, target)
        self._warnings: list[tuple[str, str]] = []  # run-time warnings of a step (code, message)
        self.channel = self._int("channel", "1", 1, 8)
        axes = self._param("axes", "X,Y,Z").upper().replace(" ", "")
        letters = axes.split(",")
        if any(a not in A.AXIS_ORDER or len(a) != 1 for a in letters) or len(set(letters)) != len(letters):
            raise ParamError("axes", f"axes takes distinct letters of {','.join(A.AXIS_ORDER)} "
                                     f"(the 5.2.1 axis rows), not {axes!r}")
        self.letters = "".join(letters)
        self.num = {key: self._int(key, str(default), lo, hi) for key, default, lo, hi, _ in NUMBERS}
        self.times = {key: self._time(key, default) for key, default in TIMES}
        starts = self._param("start", ",".join("0" for _ in letters)).split(",")
        if len(starts) != len(letters):
            raise ParamError("start", f"start takes one position (mm) per axis ({axes}), not {len(starts)}")
        self.limits = {(kind, a): self._range(f"{kind}_{a.lower()}") for a in letters
                       for kind in ("soft1", "soft2", "hard") if f"{kind}_{a.lower()}" in params}
        self.axes = [self._axis(a, self._mm("start", v)) for a, v in zip(letters, starts)]
        self.mpg = self.device("mpg") if "mpg" in params else None
        if self.mpg is not None and self.mpg.view != "w":
            raise ParamError("mpg", "mpg takes a data register such as D100 (the handwheel's pulse count)")
        self.used.add("program")  # read by build, against the stimulus' folder
        self.macro_files = self._macro_files(params)
        self.macros: dict[int, PartProgram] = {}
        self.relations = self._relations(params, letters)
        self.clock0 = self._clock()
        text = self._param("name", f"NC{self.channel}")
        if not text[:1].isalpha() or not text.replace("_", "").isalnum():
            raise ParamError("name", f"name takes a letter then letters, digits or _ (e.g. NC1), not {text!r}")
        self.name = text.upper()
        if self.num["first_tool"] + self.num["tools"] > 32767:
            raise ParamError("tools", "first_tool + tools must stay below 32768 (the tool registers are 16-bit)")
        if self.num["standby_pot"] > self.num["tools"]:
            raise ParamError("standby_pot", f"standby_pot takes 1-{self.num['tools']} (the pots of tools=)")
        self.check_unused()
        self.program = PartProgram("", [])
        self.read: list[str] = []  # the files read (inputs())
        self._mb = None  # the memory of the last full step
        self.busy = False  # the step left something for the next one (_wake)
        self.tick_only = False  # the next event only counts a second (_wake)
        self._addresses()
        self._output_addresses()
        self._input_ranges()
        self._power_on()

    def _macro_files(self, params: dict[str, str]) -> dict[int, str]:
        """macro_N=FILE: the macro O<N> (N 1-9999) the one-key call runs (5.3.8, 6.12: the
        channel's O_MACRO folder; read by build, against the stimulus' folder)."""
        out = {}
        for key in params:
            if key.startswith("macro_"):
                number = key[6:]
                if not number.isdigit() or not 1 <= int(number) <= 9999:
                    raise ParamError(key, f"{key}: a macro's number is 1-9999 (macro_9001=probe.nc), not {number!r}")
                out[int(number)] = self._param(key, None)
        return out

    def _relations(self, params: dict[str, str], letters: list[str]) -> dict[int, tuple[int, int]]:
        """sync_B=Y (or =-Y): axis B's master is Y (N2.015), '-' the opposite direction
        (N2.016 = 1): follower index -> (master index, sign), for 5.3.11 and 5.3.12."""
        out = {}
        for key in params:
            if not key.startswith("sync_"):
                continue
            follower = key[5:].upper()
            text = self._param(key, None).strip().upper()
            master = text.lstrip("-")
            if follower not in letters or master not in letters or follower == master:
                raise ParamError(key, f"{key} takes another axis of axes= ({','.join(letters)}) as the master, "
                                      f"'-' first for the opposite direction (sync_b=-Y), not {text!r}")
            out[letters.index(follower)] = (letters.index(master), -1 if text.startswith("-") else 1)
        for f, (m, _) in out.items():
            if m in out:  # 6.15 note 4: an axis is not master and follower at once
                raise ParamError(f"sync_{letters[m].lower()}", f"axis {letters[m]} is the master of {letters[f]}: "
                                 "it cannot follow another axis (6.15: not master and follower at once)")
        return out

    def _clock(self) -> int:
        """clock=YYYY-MM-DDTHH:MM:SS: the system time at the run's start (D49000-D49002), s since 1970."""
        text = self._param("clock", "2022-06-01T00:00:00")
        try:
            when = datetime.datetime.strptime(text, "%Y-%m-%dT%H:%M:%S")
        except ValueError:
            raise ParamError("clock", f"clock takes YYYY-MM-DDTHH:MM:SS (2022-06-01T08:30:00), not {text!r}") from None
        if not 2000 <= when.year <= 2099:
            raise ParamError("clock", f"clock: the year is 2000-2099 (D49000 holds two digits), not {when.year}")
        return int((when - datetime.datetime(1970, 1, 1)).total_seconds())

    def _axis(self, letter: str, pos: int) -> Axis:
        """An axis at pos as at power-up (not homed), with its limits (soft1_x= ...)."""
        ax = Axis(letter, pos)
        ax.soft1, ax.soft2, ax.hard = (self.limits.get((kind, letter)) for kind in ("soft1", "soft2", "hard"))
        return ax

    # -- parameters
    def _int(self, key: str, default: str, lo: int, hi: int) -> int:
        text = self._param(key, default)
        if not text.isdigit() or not lo <= int(text) <= hi:
            raise ParamError(key, f"{key} takes {lo}-{hi}, not {text!r}")
        return int(text)

    def _time(self, key: str, default: str) -> int:
        text = self._param(key, default)
        try:
            us = parse_time(text)
        except StimError as e:
            raise ParamError(key, e.message) from None
        if not 0 <= us <= MAX_TIME_US:
            raise ParamError(key, f"{key} takes 0s-60s, not {text}")
        return us

    def _mm(self, key: str, text: str) -> int:
        try:
            v = float(text)
        except ValueError:
            raise ParamError(key, f"{key}: {text!r} is not a number of mm") from None
        if not math.isfinite(v) or abs(v) > 99999.999:
            raise ParamError(key, f"{key} takes -99999.999 to 99999.999 mm, not {text}")
        return round(v * 1000)

    def _range(self, key: str) -> tuple[int, int]:
        lo, sep, hi = self._param(key, None).partition(":")
        if not sep:
            raise ParamError(key, f"{key} takes LO:HI in mm (e.g. -500:70)")
        a, b = self._mm(key, lo), self._mm(key, hi)
        if a > b:
            raise ParamError(key, f"{key}: LO {lo} is above HI {hi}")
        return a, b

    def read_program(self, path: str, macro: bool = False) -> PartProgram:
        """A part program or macro (an input of the run: inputs()); its mistakes are diagnostics."""
        self.read.append(path)
        try:
            data = read_input(path, MAX_BYTES + 1)
        except OSError as e:
            raise ModelInputError([diag(path, Span.at(1), "E100", f"cannot read the part program: "
                                                                 f"{e.strerror or e}")]) from None
        if len(data) > MAX_BYTES:
            raise ModelInputError([diag(path, Span.at(1), "E264", f"a part program of the model is at most "
                                                                 f"{MAX_BYTES} bytes")])
        try:
            text = data.decode("utf-8-sig")
        except UnicodeDecodeError as e:
            raise ModelInputError([diag(path, Span.at(1), "E102", f"the part program is not UTF-8 "
                                                                 f"(byte {e.start})")]) from None
        program, diags = parse(path, text, self.letters, macro)
        if diags:
            raise ModelInputError(diags)
        return program

    def inputs(self) -> list[str]:
        return list(self.read)

    def _addresses(self) -> None:
        """The device numbers of this channel, once (addresses.number)."""
        for key, entry in A.entries().items():
            setattr(self, "a_" + key.lower(), A.number(entry, self.channel))

    def _power_on(self) -> None:
        self.last_t: int | None = None
        self.skipped_to = -1  # the latest step skipped (step()); the state is as of last_t
        self.wake = 0  # the first time something happens without an input changing (_wake)
        self.snap: tuple | None = None  # the inputs the last full step read (_inputs)
        self.counting = False  # the program runs: D49c04/D49c06 count
        self.orienting = False  # the orientation timer runs
        self.gear = 0
        self.time_shown: tuple[int, list[int]] = (-1, [])  # (second, D49000-D49002) of _system_time
        self.mode = AUTO  # D2x000 = 0 at power-up: AUTO
        self.mode_request = AUTO
        self.mode_due: int | None = None
        self.state = IDLE
        self.hold_by_mode = False
        self.alarm = 0
        self.ptr = 0
        self.phase = 0  # of the block at ptr: 0 start, 1 moving or dwelling, 2 M/S/T, 3 done
        self.block_line = 0
        self.absolute = True
        self.motion = 0
        self.feed = 0  # 0.001 mm/min, modal F
        self.move: tuple | None = None  # (start, end, length, rapid) of the block's motion
        # the block's motion in closed form: travelled(t) = seg_from + seg_speed x (t - seg_t0), in
        # 0.001 mm, t in us, seg_speed in 0.001 mm/min; seg_end the time it ends at that speed
        self.seg_t0, self.seg_from, self.seg_speed, self.seg_end = 0, 0.0, 0, 0
        self.seg_axes: list[tuple[Axis, int, int]] = []  # (axis, start, end): movers not locked
        self.seg_risky = False  # an end past a hardware limit: no step is skipped on the way
        self.dwell_left = 0
        self.strobes_up = False
        self.ends = (0, 0, 0)  # M3x021, M3x022, M3x023
        self.s_code = 0
        self.path_speed = 0
        self.spindle_rpm = 0.0
        self.spindle_target = 0
        self.angle_udeg = 0  # 10^-6 deg
        self.oriented = False
        self.orient_left = -1
        self.last = {}  # previous levels of the edge-triggered relays
        self.mpg_count: int | None = None
        self.cycle_us = self.total_us = 0
        self.estop = False
        self.reset_seen = False
        self.parts_done_add = False
        self.was_running = False
        self.command = 0
        self.magazine_relays = b""
        self.out_bits: list[int] = []
        self.out_words: list[int] = []
        self.published: list[int] = []
        self.publisher = None
        self.macro_ready = [0] * 16  # M3x048+k: the macro number prepared, 0 none (5.3.8)
        self.macro_call = False  # M3x027: from a prepare until the macro has run
        self.macro_needs_auto = False  # M3x028
        self.macro_error = False  # M3x029
        self.macro_pending = -1  # the prepare of this step: complete in the next one
        self.macro_running = 0  # which of the 16 runs
        self.macro_pending_name = 0
        self.macro_relays = bytes(23)  # M2x025-M2x047 as the last step saw them
        self.mlc_axes = False  # an axis is the MLC's (_inputs reads the MLC axes' speeds)
        self.extra = self.mpg is not None
        self.macro_blocks: list[Block] | None = None  # the macro in execution (else the part program)
        self.active: dict[int, tuple[int, int, bool]] = {}  # follower -> (master, sign, transfer)
        self.pulses = 0  # handwheel pulses read in this step
        self.hand_run = False  # M2x006 in this step: the program's moves take the pulses
        self._magazine_reset()

    # -- the magazine (5.3.14, 6.13)
    def _magazine_reset(self) -> None:
        n, first = self.num["tools"], self.num["first_tool"]
        self.pots = [first + i for i in range(n)]  # pot k+1 holds first + k (6.13 reset)
        # DECISION (notes #28): N0.1400 is two parameters here: magazine= (on/off) and
        # reset_spindle= (spindle tool after a reset: 0, or the highest tool + 1, 6.13's example)
        self.spindle_tool = first + n if self.num["reset_spindle"] else 0
        # DECISION (notes #29): the standby pot after a reset is N0.1404 (standby_pot=), its
        # tool whatever the pot holds; no T code has been read since (D3x037 = 0)
        self.standby = self.num["standby_pot"]
        self.standby_t = 0
        self.command_t = 0

    def _pot_steps(self) -> int:
        """D3x039: command pot - standby pot the short way round, in (-n/2, n/2] (6.13: "最高差值
        為±8" of 16 pots). DECISION (notes #30): the sign of 5.2.1 (forward: D3x039 - 1)."""
        if self.command_t not in self.pots:
            return 0
        n = len(self.pots)
        d = (self.pots.index(self.command_t) + 1 - self.standby) % n
        return d - n if d > n // 2 else d

    # -- simulation
    def power_cycle(self) -> None:
        """DECISION: the MLC and the NC are one controller (5.1), so a power cycle restarts the
        NC as at the run's start: AUTO, the program at its first block, nothing homed, the
        spindle stopped, magazine 1 reset, the counters from 0 (D49c00-D49c07 are not latched),
        every NC -> MLC signal written again from the next step. The axes stay where they are:
        the machine does not move while the power is off."""
        if self.last_t is not None and self.skipped_to > self.last_t:
            self._catch_up(self.skipped_to)
        self.axes = [self._axis(ax.letter, ax.pos if ax.held is None else ax.held) for ax in self.axes]
        self._power_on()

    def devices(self) -> list[DeviceView]:
        return [parse_signal_name(f"{self.name}.{s}") for s in self.signal_names] + \
            ([self.mpg] if self.mpg is not None else [])

    def _input_ranges(self) -> None:
        """What _inputs reads: the channel's M2c000-M2c727 and D2c000-D2c033 (the MLC -> NC
        relays and registers read as they change; the macro names D2x064+ and the MLC axes'
        targets D2x256+ are read at an edge of a relay), the handwheel's register, and the MLC
        axes' speeds D2x288+ while an axis is the MLC's (6.14: they act at once)."""
        self.m_lo, self.d_lo = A.number(A.CYCLE_START, self.channel), A.number(A.MODE, self.channel)
        self.m_hi, self.d_hi = self.m_lo + 728, self.d_lo + 34
        self.speeds_lo = A.number(A.MLC_SPEED, self.channel)

    def _inputs(self, mb, dw) -> tuple:
        snap = (mb[self.m_lo:self.m_hi], dw[self.d_lo:self.d_hi])
        if self.mpg is not None:
            snap += (dw[self.mpg.number],)
        if self.mlc_axes:
            snap += (dw[self.speeds_lo:self.speeds_lo + 18],)
        return snap

    def step(self, io: ModelIO, t_us: int, period_us: int) -> None:
        """One step before the scan at t_us. A step whose inputs are those of the last full step
        and that comes before the model's next event (_wake) is skipped: its only MLC-visible
        change, the spindle angle, is written; the rest catches up (_catch_up) at the next full
        step or when a signal is read (_refresh). Everything skipped moves in closed form, so
        the outcome does not depend on which steps were skipped."""
        mb, dw = io.memory("M"), io.memory("D")
        snap = self._inputs(mb, dw) if self.extra else (mb[self.m_lo:self.m_hi], dw[self.d_lo:self.d_hi])
        if snap == self.snap:
            if t_us < self.wake:
                self.skipped_to = t_us
                if self.spindle_rpm:
                    self._write_angle(dw, t_us)
                return
            if self.tick_only:  # only a counted second passes: D49c04 / D49c06
                self._catch_up(t_us)
                self._write_times(dw)
                if self.spindle_rpm:
                    self._write_angle(dw, t_us)
                self._publish()
                self.wake = self._wake(t_us)
                return
        if self.publisher is None:
            io.on_read(self.name, self._refresh)
            self.publisher = io.publisher(self.name, self.signal_names)
        self._mb = mb
        if self.skipped_to > (self.last_t or 0):
            self._catch_up(self.skipped_to)
        self._step(mb, dw, t_us)
        for code, message in self._warnings:  # said through io here: the model keeps no ModelIO
            io.warn(self, code, message)
        self._warnings.clear()
        self.wake = self._wake(t_us) if self.SKIP else t_us + 1
        self.snap = snap

    def _step(self, mb, dw, t_us: int) -> None:
        dt = 0 if self.last_t is None else t_us - self.last_t
        changed_at = t_us if self.last_t is None else self.last_t  # when the last scan wrote
        self.last_t = t_us
        self.busy = dt == 0  # the first step: the next one moves
        self.jumped: list[Axis] = []  # moved by the handwheel in this step
        self._mode(dw, t_us, changed_at)
        self._emergency_and_reset(mb)
        before = [a.pos for a in self.axes]
        for ax in self.axes:
            ax.vel = 0
        servo = bool(mb[self.a_servo_on]) and not self.estop
        moving_ok = [servo and not mb[self.a_axis_servo_off + a.offset] for a in self.axes]
        self.was_running = self.state in (RUNNING, MST_WAIT)
        self.pulses = self._mpg_pulses(dw) if self.mpg is not None else 0
        self.hand_run = bool(mb[self.a_handwheel_run])
        if not self.estop and not mb[self.a_nc_reset]:
            self._macro(mb, dw)
            if self.mode in (JOG, RAPID, INC, MPG):  # 6.15 note 3: checked at any time
                self._relate(mb)
            self._program(mb, dw, t_us, dt, moving_ok)
            if self.mode >= MPG:  # the manual modes (a mode change ends their moves)
                self._manual(mb, dw, dt, moving_ok)
            self._mlc_switch(mb)
            self._mlc_move(mb, dw, dt, moving_ok)
        self._follow()
        if self.active and self._hit_hard_limit(mb) and self.state in (RUNNING, MST_WAIT):
            self.state = ALARM  # a follower past its hardware limit (its soft limits: its master's)
        self.mlc_axes = any(ax.mlc for ax in self.axes)
        self.extra = self.mpg is not None or self.mlc_axes
        self._spindle(mb, dw, dt)
        self._magazine(mb)
        self.gear = _s16(dw[self.a_spindle_gear])
        self._outputs(mb, dw, dt, before, moving_ok)
        self._publish()

    # -- skipped steps (step())
    def _catch_up(self, t: int) -> None:
        """The state at t from that of last_t, when nothing but time passed in between (no
        input changed, t before the next event): the moves in force go on, the times count."""
        dt = t - self.last_t
        self.last_t = t
        if self.counting:
            self.cycle_us += dt
            self.total_us += dt
        if self.phase == 1 and self.state in (RUNNING, MST_WAIT):
            if self.dwell_left > 0:
                self.dwell_left -= dt
            elif self.seg_speed:
                self._place(t)
        for ax in self.axes:
            if ax.vel:
                d = self._distance(ax, abs(ax.vel), dt)
                ax.pos += d if ax.vel > 0 else -d
        self._follow()
        if self.spindle_rpm:
            self.angle_udeg = (self.angle_udeg + int(self.spindle_rpm) * 6 * dt) % 360_000_000
        if self.orienting:
            self.orient_left -= dt

    def _refresh(self) -> None:
        """Before one of the model's signals is read: the signals as of the latest step."""
        if self.last_t is not None and self.skipped_to > self.last_t:
            self._catch_up(self.skipped_to)
            self._publish()

    def _write_angle(self, dw, t: int) -> None:
        """D3x028 at t while the spindle turns at a steady speed (a skipped step; 0.01 deg <
        36000: the high word D3x029 stays 0)."""
        v = (self.angle_udeg + int(self.spindle_rpm) * 6 * (t - self.last_t)) % 360_000_000 // 10_000
        if v != self.out_words[ANGLE_WORD]:
            dw[self.a_spindle_angle] = self.out_words[ANGLE_WORD] = v

    def _write_times(self, dw) -> None:
        """D49c04 / D49c06 (s) and the system time D49000-D49002 at last_t (a step that only
        counts)."""
        words = self.out_words
        for k, v in enumerate(self._time_words(), self.times_word):
            if words[k] != v:
                dw[self.word_addresses[k]] = words[k] = v

    def _time_words(self) -> list[int]:
        """D49c04-D49c07 (s, 32-bit) and D49000-D49002 at last_t."""
        words = []
        for v in (self.total_us // 1_000_000, self.cycle_us // 1_000_000):
            words += [v & 0xFFFF, (v >> 16) & 0xFFFF]
        return words + self._system_time()

    def _wake(self, now: int) -> int:
        """The first time after `now` at which a step with the same inputs does more than
        _catch_up does: a mode's feedback, a block's motion or dwell ends, a manual move reaches
        a target or a limit, the orientation is done, a counted second passes. now + 1 (the
        next step) when this step left something to settle."""
        self.tick_only = False
        if self.busy or self.spindle_rpm != self.spindle_target:
            return now + 1  # (a ramp changes D3x026 every step)
        if any(self.axes[f].hard for f in self.active):
            return now + 1  # (a follower's hardware limit is checked every step: _step)
        wake = 1 << 62
        if self.mode_due is not None:
            wake = self.mode_due
        if self.phase == 1 and self.state in (RUNNING, MST_WAIT):
            if self.dwell_left > 0:
                wake = min(wake, now + self.dwell_left)
            elif self.seg_speed:
                if self.seg_risky:
                    return now + 1
                wake = min(wake, self.seg_end)
        for ax in self.axes:
            if ax.vel:
                if ax.home_done or ax.pos == 0:  # M3x336 / M3x352 change once it moves
                    return now + 1
                ahead = [b - ax.pos for b in self._bounds(ax)]
                ahead = [abs(d) for d in ahead if (d > 0) == (ax.vel > 0) or not d]  # (at one: stops next)
                if ahead:
                    need = min(ahead) * 60_000_000 - ax.rest
                    wake = min(wake, now + max(1, -(-need // abs(ax.vel))))
        if self.orienting:
            wake = min(wake, now + max(1, self.orient_left))
        tick = now + 1_000_000 - now % 1_000_000  # the system time's next second
        if self.counting:
            tick = min(tick, now + 1_000_000 - max(self.total_us % 1_000_000, self.cycle_us % 1_000_000))
        self.tick_only = tick < wake
        return min(wake, tick)

    @staticmethod
    def _bounds(ax: Axis) -> list[int]:
        """Where a manual move may have to stop or raise an alarm (a step is taken there)."""
        out = [0] if ax.homing else []
        for target in (ax.inc_target, ax.mlc_target):
            if target is not None:
                out.append(target)
        for limit in (ax.soft1, ax.soft2):
            if limit is not None:
                out += limit
        if ax.hard is not None:
            out += [ax.hard[0] - 1, ax.hard[1] + 1]
        return out

    def _mode(self, dw, t_us: int, changed_at: int) -> None:
        """5.3.1 / 6.1: D2x000 selects the mode; the feedback M3x000-M3x007 follows "約 4 ms"
        after the value changed (feedback=). A value outside 0-7 selects nothing."""
        want = _s16(dw[self.a_mode])
        if want != self.mode_request:
            self.mode_request = want
            self.mode_due = changed_at + self.times["feedback"] if 0 <= want <= 7 and want != self.mode else None
        if self.mode_due is not None and t_us >= self.mode_due:
            self.mode, self.mode_due = self.mode_request, None
            if self.state in (RUNNING, MST_WAIT) and self.mode not in (AUTO, MDI):
                # 6.2 (e): a mode change ends "程序執行中"; the program waits at its block
                self.state, self.hold_by_mode = HOLD, True
                self._halt_segment(changed_at)
            for ax in self.axes:  # a manual move stops with its mode
                ax.homing, ax.inc_target = False, None

    def _emergency_and_reset(self, mb) -> None:
        """M2x013 emergency stop (M3x018) and M2x004 NC reset (M3x019 On while it is held, from
        the step after; DECISION: the completion is level, back Off with M2x004)."""
        self.estop = bool(mb[self.a_emergency_stop])
        resetting = self.estop or mb[self.a_nc_reset]
        if resetting:
            self._reset()
        mb[self.a_reset_done] = 1 if mb[self.a_nc_reset] and self.reset_seen else 0
        if self.reset_seen != bool(mb[self.a_nc_reset]):
            self.busy = True  # M3x019 follows in the next step
        self.reset_seen = bool(mb[self.a_nc_reset])

    def _reset(self) -> None:
        self.state, self.hold_by_mode, self.alarm = IDLE, False, 0
        self.ptr, self.phase, self.move, self.dwell_left, self.seg_speed = 0, 0, None, 0, 0
        if self.strobes_up:
            self._mb[self.a_m_strobe] = self._mb[self.a_s_strobe] = self._mb[self.a_t_strobe] = 0
        self.strobes_up = False
        self.ends = (0, 0, 0)
        self.path_speed = 0
        for ax in self.axes:
            ax.homing, ax.inc_target = False, None
        # 6.12: a reset clears the macro call's flags (初始完成, 需切換自動模式) and ends a macro
        self.macro_ready, self.macro_call, self.macro_needs_auto, self.macro_error = [0] * 16, False, False, False
        self.macro_pending, self.macro_blocks = -1, None

    # -- the one-key macro call (5.3.8, 6.12)
    def _macro(self, mb, dw) -> None:
        """A rising edge of M2x032+k prepares the macro D2x064+k names: M3x027 On at once, then
        (the next step) M3x048+k and M3x028 On. A rising edge of M2x025 in AUTO, the program
        not running, runs the lowest prepared one; M3x028 drops. When it has run (M99, M02,
        M30 or its last block) M3x027 and M3x048+k drop and the part program is back at its
        first block. DECISIONS: a prepare works in any mode (notes #25: the example prepares,
        then switches to AUTO, as M3x028 asks); M3x029 for a name of 0, of 10000 or more
        (notes #26: "當設定為 10000 以上時 ... 錯誤") or of no macro_N= file; M3x027 is On from
        the prepare until the macro has run (notes #24: 6.12's own flow, step 4)."""
        if self.macro_pending >= 0:
            k, self.macro_pending = self.macro_pending, -1
            self.macro_ready[k] = self.macro_pending_name
            self.macro_needs_auto = True
        relays = mb[self.a_macro_start:self.a_macro_prepare + 16]  # M2x025 ... M2x047
        if relays == self.macro_relays:
            return
        was, self.macro_relays = self.macro_relays, relays
        first = self.a_macro_prepare - self.a_macro_start
        edges = [k for k in range(16) if relays[first + k] and not was[first + k]]
        for k in edges:
            name = dw[self.a_macro_name + k]
            if not 1 <= name <= 9999 or name not in self.macros:
                self.macro_error = True
                continue
            self.macro_error, self.macro_call, self.macro_pending = False, True, k
            self.macro_pending_name = name
            self.busy = True  # complete in the next step
        start = relays[0] and not was[0]
        ready = [k for k in range(16) if self.macro_ready[k]]
        if start and ready and self.mode == AUTO and self.state in (IDLE, END) and self.macro_blocks is None:
            self.macro_running = ready[0]
            self.macro_blocks = self.macros[self.macro_ready[ready[0]]].blocks
            self.macro_needs_auto = False
            self.ptr, self.phase, self.state = 0, 0, RUNNING

    def _macro_done(self) -> None:
        self.macro_ready[self.macro_running] = 0
        self.macro_call, self.macro_blocks = False, None
        self.state, self.ptr, self.phase = IDLE, 0, 0

    # -- the part program (5.3.2, 6.2, 5.3.10, 6.8)
    def _edge(self, mb, address: int) -> bool:
        now = mb[address]
        was = self.last.get(address, 0)
        self.last[address] = now
        return bool(now and not was)

    def _program(self, mb, dw, now: int, dt: int, moving_ok: list[bool]) -> None:
        start = self._edge(mb, self.a_cycle_start)
        if mb[self.a_feed_hold] and self.state in (RUNNING, MST_WAIT) and self.phase == 1:
            self.state, self.hold_by_mode = HOLD, False  # 6.2: stops at once, keeps the coordinates
            self._halt_segment(now - dt)
        elif start and self.mode in (AUTO, MDI) and not mb[self.a_feed_hold] and self.state != ALARM:
            if self.state in (IDLE, END):
                self.ptr, self.phase, self.ends, self.cycle_us = 0, 0, (0, 0, 0), 0
                self.state = RUNNING
                if not self.program.path:  # DECISION (docs/nc5.md): a run-time warning, not an error
                    self._warnings.append((NO_PROGRAM, f"{self.name}: cycle start with no part program (this "
                                           "model line has no program=...): an empty program ran, the cycle ended at once"))
            elif self.state in (HOLD, BLOCK_STOP, PROGRAM_STOP):
                self.state, self.hold_by_mode = (MST_WAIT if self.phase == 2 else RUNNING), False
        if self.state in (RUNNING, MST_WAIT):
            self._run(mb, dw, now, dt, moving_ok)
        else:
            self.path_speed = 0

    def _run(self, mb, dw, now: int, budget: int, moving_ok: list[bool]) -> None:
        blocks = self.program.blocks if self.macro_blocks is None else self.macro_blocks
        for _ in range(len(blocks) + 2):  # zero-time blocks: at most the program once per step
            if self.ptr >= len(blocks):
                if self.macro_blocks is not None:
                    self._macro_done()
                    return
                self.state, self.ends = END, (1, self.ends[1], self.ends[2])  # 6.2 (d): no more program
                self.ptr, self.phase = 0, 0
                return
            block = blocks[self.ptr]
            if self.phase == 0:
                if block.skippable and mb[self.a_block_skip]:
                    self.ptr += 1
                    continue
                self.block_line = block.line
                if not self._begin(block):
                    return
                self.phase = 1
            if self.phase == 1:
                budget = self._advance(mb, dw, now, budget, moving_ok)
                if budget < 0:
                    return
                self.path_speed = 0  # the block's motion has ended: no speed while its codes wait
                self.phase = 2
            if self.phase == 2:
                waited = self.state == MST_WAIT
                if not self._handshake(mb, dw, block):
                    if self.state != ALARM:
                        self.state = MST_WAIT
                    return
                if waited:  # the finish is seen now: the time before went to waiting, not to the next block
                    budget = 0
                self.state = RUNNING
                self.phase = 3
            self.phase, self.ptr = 0, self.ptr + 1
            if self._control(mb, block):
                return
            if mb[self.a_single_block]:
                self.state = BLOCK_STOP  # 6.2: stops after the block, M3x024
                return
        self.path_speed = 0
        self.busy = True  # the program once in this step: it goes on in the next

    def _begin(self, block: Block) -> bool:
        """The block's modal words and its motion; False when a soft limit stops the program."""
        if block.absolute is not None:
            self.absolute = block.absolute
        if block.motion is not None:
            self.motion = block.motion
        if block.feed is not None:
            self.feed = block.feed
        self.move, self.dwell_left = None, block.dwell_us or 0
        self.seg_from, self.seg_speed = 0.0, 0
        if block.axes:
            start = [a.pos for a in self.axes]
            end = list(start)
            for i, ax in enumerate(self.axes):
                # the program leaves an MLC axis and a follower alone (6.14; 6.15 note 6: 自動忽略)
                if ax.letter in block.axes and not ax.mlc and i not in self.active:
                    v = block.axes[ax.letter]
                    end[i] = v if self.absolute else start[i] + v
            for i, ax in enumerate(self.axes):
                limit = self._soft_limit(ax)
                if limit is not None and end[i] != start[i] and not limit[0] <= end[i] <= limit[1]:
                    self.state, self.alarm = ALARM, SOFT_LIMIT  # checked before the move (6.9)
                    return False
            length = math.sqrt(sum((e - s) ** 2 for s, e in zip(start, end)))
            if length > 0:
                self.move = (start, end, length, self.motion == 0)
                self.seg_risky = any(ax.hard is not None and not ax.hard[0] <= e <= ax.hard[1]
                                     for ax, e in zip(self.axes, end))
        return True

    def _soft_limit(self, ax: Axis) -> tuple[int, int] | None:
        """6.9: the first soft limit, or the second while its release (M2x368+) is On; only once
        the axis is homed (incremental motors)."""
        if not ax.homed:
            return None
        return ax.soft2 if self._mb[self.a_soft_limit_release + ax.offset] else ax.soft1

    def _advance(self, mb, dw, now: int, budget: int, moving_ok: list[bool]) -> int:
        """Move or dwell for the last `budget` us up to `now`; the time left over when the
        block's motion ends, -1 while it goes on. The motion is in closed form (seg_*): a
        new speed (an override) starts a new segment where the interval starts."""
        if self.dwell_left > 0:
            self.path_speed = 0  # a dwell moves nothing
            used = min(budget, self.dwell_left)
            self.dwell_left -= used
            return budget - used if self.dwell_left == 0 else -1
        if self.move is None:
            return budget
        start, end, length, rapid = self.move
        speed = self._path_speed(mb, dw, rapid)  # 0.001 mm/min
        movers = [i for i, (s, e) in enumerate(zip(start, end)) if s != e]
        stopped = not all(moving_ok[i] for i in movers) or self._hard_stopped(mb)
        if speed <= 0 or stopped or self.hand_run:
            speed = 0
        if speed != self.seg_speed:
            begin = now - budget
            self.seg_from, self.seg_t0, self.seg_speed = self._travelled(begin), begin, speed
            if speed:
                self.seg_end = begin + math.ceil((length - self.seg_from) * 60e6 / speed)
        self.path_speed = speed // 1000
        # 5.3.2 M2x006 handwheel run: the moves stop at once; each pulse takes the path 0.001 mm x
        # D2x009 on (DECISION: the multiplier of 6.3's handwheel; a pulse back does not go back)
        stepped = self.hand_run and self.pulses > 0 and not stopped
        if stepped:
            self.seg_from = min(length, self.seg_from + self.pulses * min(dw[self.a_mpg_scale], 1000))
        elif not speed:
            return -1
        # a locked axis stays (6.4); machining moves the others (6.7 (b): not "homed" any more)
        self.seg_axes = [(self.axes[i], start[i], end[i]) for i in movers
                         if not mb[self.a_axis_lock + self.axes[i].offset]]
        for ax, _, _ in self.seg_axes:
            ax.home_done = False
        if stepped:
            self._place(now)
            if self.seg_from < length:
                self.busy = True  # the flags of the handwheel's move drop next
                return -1
            return 0
        done = now >= self.seg_end
        self._place(self.seg_end if done else now)
        if self._hit_hard_limit(mb):
            self.state = ALARM
            self.seg_speed = 0
            return -1
        if done:
            self.seg_speed = 0
            return now - self.seg_end
        return -1

    def _halt_segment(self, t: int) -> None:
        """The block's motion stops at t, where the last step placed the axes (a hold): the
        closed form would otherwise count the held time as travelled when it resumes."""
        self.seg_from, self.seg_speed = self._travelled(t), 0

    def _travelled(self, t: int) -> float:
        """0.001 mm of the block's motion done at t (seg_*)."""
        if not self.seg_speed:
            return self.seg_from
        return min(self.move[2], self.seg_from + self.seg_speed * (t - self.seg_t0) / 60e6)

    def _place(self, t: int) -> None:
        """The moving axes where the block's motion has them at t."""
        f = self._travelled(t) / self.move[2]
        for ax, s, e in self.seg_axes:
            ax.pos = round(s + (e - s) * f)

    def _path_speed(self, mb, dw, rapid: bool) -> int:
        """6.2 / 6.6: G01 at F x D2x002 (0-150 %, DECISION notes #8: the register read 0-65535
        and limited to 150) up to feed_max; dry run (M2x005) takes D2x006 as the F (DECISION
        notes #9: in mm/min, 5.2.2's example "F50"); G00 at rapid x D2x004 (0-100 %)."""
        if rapid:
            return self._rapid_speed(dw)
        feed = dw[self.a_jog_speed] * 1000 if mb[self.a_dry_run] else self.feed
        speed = feed * min(dw[self.a_feed_override], 150) // 100
        return min(speed, self.num["feed_max"] * 1000)

    def _rapid_speed(self, dw) -> int:
        """G00 and RAPID mode: rapid x D2x004 (0-100 %), 0.001 mm/min."""
        return self.num["rapid"] * 1000 * min(max(_s16(dw[self.a_rapid_override]), 0), 100) // 100

    def _handshake(self, mb, dw, block: Block) -> bool:
        """5.3.10 / 6.8: the block's M, S and T codes raise their flags together with their
        registers, once M2x016 is Off (DECISION: the finish signal must drop between two codes,
        else a held finish would pass the next code unseen); the NC waits for M2x016 On, then
        drops the flags and goes on."""
        m = block.m if block.m is not None and block.m not in NOT_HANDSHAKEN_M else None
        t = block.t
        if t is not None and self.strobes_up is False:
            if not self.num["magazine"]:
                self.state, self.alarm = ALARM, NO_MAGAZINE  # 6.8: an alarm, D3x052 not written
                return False
            first = self.num["first_tool"]
            if not first <= t < first + self.num["tools"]:
                t = None  # 6.8: outside N0.1402's tools the T code is not shown, no flag
        if m is None and block.s is None and t is None:
            return True
        if not self.strobes_up:
            if mb[self.a_mst_finish]:
                return False
            if m is not None:
                dw[self.a_m_code] = m
                mb[self.a_m_strobe] = 1
            if block.s is not None:
                self.s_code = block.s
                dw[self.a_s_code], dw[self.a_s_code + 1] = block.s & 0xFFFF, block.s >> 16
                mb[self.a_s_strobe] = 1
            if t is not None:
                dw[self.a_t_code] = t
                self.standby_t = self.command_t = t  # 6.13: D3x037 the latest T, D3x039 its way
                mb[self.a_t_strobe] = 1
            self.strobes_up = True
            return False
        if not mb[self.a_mst_finish]:
            return False
        mb[self.a_m_strobe] = mb[self.a_s_strobe] = mb[self.a_t_strobe] = 0
        self.strobes_up = False
        if m is not None and self.relations:
            self._relate(mb)  # 6.15 note 3 a: at the end of an M code's handshake (AUTO, MDI)
        return True

    def _control(self, mb, block: Block) -> bool:
        """M00, M01 (with M2x009), M02, M30 after the block; True when the program stops.
        DECISION (notes #33): an M00 or M01 stop drops M3x016 and leaves M3x017 Off (that is the
        feed hold's); M02 and M30 both go back to the first block (M30's 回頭; after M02 there
        is nothing else to run)."""
        m = block.m
        if m == 0 or (m == 1 and mb[self.a_optional_stop]):
            self.state = PROGRAM_STOP
            return True
        if self.macro_blocks is not None and m in (2, 30, 99):
            self._macro_done()
            return True
        if m in (2, 30):
            self.state, self.ptr = END, 0
            self.ends = (1, 1 if m == 2 else self.ends[1], 1 if m == 30 else self.ends[2])
            self.parts_done_add = True
            return True
        return False

    # -- limits (6.9)
    def _hard_stopped(self, mb) -> bool:
        return self.alarm == HARD_LIMIT and not mb[self.a_hard_limit_release]

    def _hit_hard_limit(self, mb) -> bool:
        """An axis past its hardware limit switch (hard_x=) stops everything with an alarm,
        unless M2x007 releases the limits (6.9: "將暫時無視硬體極限訊號")."""
        if mb[self.a_hard_limit_release]:
            return False
        for ax in self.axes:
            if ax.hard is not None and not ax.hard[0] <= ax.pos <= ax.hard[1]:
                ax.pos = min(max(ax.pos, ax.hard[0]), ax.hard[1])
                self.alarm = HARD_LIMIT
                return True
        return False

    # -- manual modes (5.3.4-5.3.6, 6.3-6.7)
    def _manual(self, mb, dw, dt: int, moving_ok: list[bool]) -> None:
        mode = self.mode
        for i, ax in enumerate(self.axes):
            o = ax.offset
            plus, minus = mb[self.a_jog_plus + o], mb[self.a_jog_minus + o]
            plus_edge, minus_edge = self._edge(mb, self.a_jog_plus + o), self._edge(mb, self.a_jog_minus + o)
            home_edge = self._edge(mb, self.a_home_start + o)
            ok = moving_ok[i]
            if mode == HOME and home_edge and self.relations:
                self._relate(mb, ax)  # 6.15 note 3 c
            if ax.mlc or i in self.active:  # the MLC's axis; a follower moves with its master
                continue
            if not ok or mb[self.a_axis_lock + o] or self._hard_stopped(mb) or dt == 0:
                if not ok:
                    ax.homing, ax.inc_target = False, None
                continue
            if mode in (JOG, RAPID) and plus != minus:
                speed = self._jog_speed(dw) if mode == JOG else self._rapid_speed(dw)
                self._drive(mb, ax, speed if plus else -speed, dt)
            elif mode == INC:
                if ax.inc_target is None and (plus_edge or minus_edge) and plus != minus:
                    amount = _s32(dw[self.a_inc_amount], dw[self.a_inc_amount + 1])  # x 0.001 mm (N1.001)
                    ax.inc_target = ax.pos + (amount if plus else -amount)
                if ax.inc_target is not None and (self._approach(mb, ax, ax.inc_target, self._jog_speed(dw), dt)
                                                  or self.alarm == HARD_LIMIT):
                    ax.inc_target, ax.vel = None, 0
            elif mode == HOME:
                if home_edge:
                    ax.homing = True
                if ax.homing:
                    speed = self.num["home_speed"] * 1000
                    step = self._distance(ax, speed, dt)
                    ax.pos += max(-step, min(step, -ax.pos))
                    if ax.pos == 0:  # the origin: machine coordinate 0 (6.7)
                        ax.homing, ax.homed, ax.home_done = False, True, True
                    else:
                        ax.vel = -speed if ax.pos > 0 else speed
        if mode == MPG and self.pulses:
            self._handwheel(mb, dw)

    @staticmethod
    def _distance(ax: Axis, speed: int, dt: int) -> int:
        """0.001 mm covered in `dt` us at `speed` 0.001 mm/min, what is under 0.001 mm carried
        to the next step (so a step's truncation does not slow the axis)."""
        total = speed * dt + ax.rest
        ax.rest = total % 60_000_000
        return total // 60_000_000

    def _drive(self, mb, ax: Axis, vel: int, dt: int) -> None:
        """A manual move at vel (0.001 mm/min, signed) for dt us: vel is in force after it
        unless a limit stopped the axis."""
        d = self._distance(ax, abs(vel), dt)
        if self._move_by(mb, ax, d if vel > 0 else -d):
            ax.vel = vel

    def _approach(self, mb, ax: Axis, target: int, speed: int, dt: int) -> bool:
        """A manual move toward target at speed (0.001 mm/min) for dt us: True when the axis
        is there or a limit stopped it, else its velocity is in force."""
        step = self._distance(ax, speed, dt)
        if not self._move_by(mb, ax, max(-step, min(step, target - ax.pos))) or ax.pos == target:
            return True
        ax.vel = speed if target > ax.pos else -speed
        return False

    def _jog_speed(self, dw) -> int:
        """6.4: jog at N2.030 (jog_max) x D2x006 %. DECISION (notes #9): in JOG/INC D2x006 is a
        percentage, limited to 100 ("系統內部僅支援 0 ~ 100")."""
        return self.num["jog_max"] * 1000 * min(dw[self.a_jog_speed], 100) // 100

    def _move_by(self, mb, ax: Axis, delta: int) -> bool:
        """A manual move by delta; False when it stopped at a limit (no further to go)."""
        target = ax.pos + delta
        limit = self._soft_limit(ax)
        if limit is not None:  # a manual move stops at the soft limit
            if (delta > 0 and ax.pos >= limit[1]) or (delta < 0 and ax.pos <= limit[0]):
                return False
            target = min(max(target, min(ax.pos, limit[0])), max(ax.pos, limit[1]))
        if delta == 0:
            return True
        free = target == ax.pos + delta
        ax.pos = target
        ax.home_done = False  # 6.7 (a): moved by hand
        if ax.hard is not None and not ax.hard[0] <= ax.pos <= ax.hard[1] and not mb[self.a_hard_limit_release]:
            ax.pos = min(max(ax.pos, ax.hard[0]), ax.hard[1])
            self.alarm = HARD_LIMIT
            ax.inc_target = None
            return False
        return free

    def _mpg_pulses(self, dw) -> int:
        """The handwheel's pulses since the last full step: the count in the mpg= register (the
        stimulus turns the wheel: `100ms D100=25`), 16-bit, wrapping. Pulses the NC has no use
        for in that step (not MPG mode, no handwheel run) are lost, as a wheel turned then."""
        count = dw[self.mpg.number]
        pulses = 0 if self.mpg_count is None else _s16((count - self.mpg_count) & 0xFFFF)
        self.mpg_count = count
        return pulses

    def _handwheel(self, mb, dw) -> None:
        """6.3: each pulse moves the axis D2x008 (0 = X, 1 = Y ... the 5.2.1 axis order) by
        0.001 mm x D2x009."""
        offset = dw[self.a_mpg_axis]
        for ax in self.axes:
            if ax.offset == offset and self.pulses and not ax.mlc:
                before = ax.pos
                self._move_by(mb, ax, self.pulses * min(dw[self.a_mpg_scale], 1000))
                self.jumped.append(ax) if ax.pos != before else None

    # -- MLC axes (5.3.9, 6.14)
    def _mlc_switch(self, mb) -> None:
        """M2x432+ asks that the axis be the MLC's, M3x432+ says it is. DECISION: the switch
        is made once the axis stands still (6.14: "切換時，該軸須為靜止狀態"): the program's
        pause-interpretation M code is the MLC's to hold (M2x016), not the model's."""
        moving = {id(ax) for ax, _, _ in self.seg_axes} if self.seg_speed and self.phase == 1 else set()
        for ax in self.axes:
            want = bool(mb[self.a_mlc_switch + ax.offset])
            if want != ax.mlc and not ax.vel and id(ax) not in moving and ax.mlc_target is None:
                ax.mlc, ax.mlc_target, ax.mlc_done = want, None, False
                ax.homing, ax.inc_target = False, None

    def _mlc_move(self, mb, dw, dt: int, moving_ok: list[bool]) -> None:
        """6.14: the trigger M2x448+ (its rising edge) starts a move, Off stops it. Position
        mode (M2x416+ Off): to D2x256+ (float, mm; with M2x464+ a distance from where the axis
        is), at |D2x288+| (float, mm/min), then M3x448+ On. Speed mode: at D2x288+, signed,
        while the trigger is On; M3x448+ (at speed) On at once (the model does not ramp).
        D2x288+ acts at once; the target only at the next rising edge. Speeds up to feed_max
        (N2.023). DECISION: the model's axes are linear: D2x288+ is mm/min for every axis."""
        for i, ax in enumerate(self.axes):
            if not ax.mlc:
                continue
            o = ax.offset
            trigger = mb[self.a_mlc_trigger + o]
            edge = self._edge(mb, self.a_mlc_trigger + o)
            speed_mode = mb[self.a_mlc_speed_mode + o]
            speed = _f32(dw, self.a_mlc_speed + 2 * o)
            speed = round(max(-self.num["feed_max"], min(self.num["feed_max"], speed)) * 1000)
            if not trigger:
                ax.mlc_target = None
                if speed_mode:
                    ax.mlc_done = False
                continue
            if edge:
                ax.mlc_done = False
                if not speed_mode:
                    target = _f32(dw, self.a_mlc_target + 2 * o)
                    amount = round(max(-99999.999, min(99999.999, target)) * 1000)
                    ax.mlc_target = ax.pos + amount if mb[self.a_mlc_incremental + o] else amount
            if not moving_ok[i] or mb[self.a_axis_lock + o] or self._hard_stopped(mb) or dt == 0:
                continue
            if speed_mode:
                ax.mlc_target = None
                self._drive(mb, ax, speed, dt)
                ax.mlc_done = ax.vel != 0
            elif ax.mlc_target is not None and self._approach(mb, ax, ax.mlc_target, abs(speed), dt):
                ax.mlc_target, ax.mlc_done = None, ax.pos == ax.mlc_target

    # -- synchronous and transferred axes (5.3.11, 5.3.12, 6.15, 6.16)
    def _relate(self, mb, only: Axis | None = None) -> None:
        """Which followers of the sync_ parameters follow now: M2x256 with M2x288+ (synchronous:
        the follower moves with its master), M2x257 with M2x304+ (transfer: the master's
        program moves move the follower instead). 6.15 note 3 says when the NC looks: at the
        end of an M code's handshake in AUTO/MDI, at any time in JOG/MPG (DECISION: and in
        RAPID and INC, the other manual moves), at an axis' home start in HOME (`only`)."""
        for f, (m, sign) in self.relations.items():
            follower = self.axes[f]
            if only is not None and only is not follower and only is not self.axes[m]:
                continue
            o = follower.offset
            transfer = bool(mb[self.a_transfer_on] and mb[self.a_transfer_receive + o])
            sync = bool(mb[self.a_sync_on] and mb[self.a_sync_follow + o])
            want = (m, sign, transfer and not sync) if sync or transfer else None
            if want != self.active.get(f):
                self._release(self.active.pop(f, None))
                if want is not None:
                    follower.base, self.axes[m].base = follower.pos, self.axes[m].pos
                    self.active[f] = want

    def _release(self, relation: tuple[int, int, bool] | None) -> None:
        """A transfer's master stands where it stood when the transfer ends."""
        if relation is not None and relation[2]:
            master = self.axes[relation[0]]
            if master.held is not None:
                master.pos, master.held = master.held, None

    def _follow(self) -> None:
        """The followers where their masters put them (closed form from the bases): synchronous,
        the master's travel (x -1 for a '-' master); transfer, the master's program travel goes
        to the follower and the master stays (DECISION notes #31: transfer acts on the program's
        moves only, 6.15 note 2 "僅規劃於自動模式下生效"; in a manual mode its master moves)."""
        for f, (m, sign, transfer) in self.active.items():
            follower, master = self.axes[f], self.axes[m]
            if transfer and self.mode not in (AUTO, MDI):
                self._release((m, sign, transfer))
                follower.base, master.base = follower.pos, master.pos
                continue
            follower.pos = follower.base + sign * (master.pos - master.base)
            if transfer:  # its pos is the program's command, it stands at its base
                master.held = master.base

    # -- the first spindle (5.3.13, 6.10, 6.11)
    def _spindle(self, mb, dw, dt: int) -> None:
        fwd, rev = mb[self.a_spindle_forward], mb[self.a_spindle_reverse]
        orient = mb[self.a_spindle_orient]
        command = _s32(dw[self.a_spindle_speed], dw[self.a_spindle_speed + 1]) if mb[self.a_spindle_source] \
            else self.s_code
        command = max(command, 0)
        self.command = command
        target = min(command * min(dw[self.a_spindle_override], 120) // 100, self.num["spindle_max"])
        direction = 0 if orient or fwd == rev or self.estop else (1 if fwd else -1)
        self.spindle_target = direction * target
        ramp = self.times["spindle_ramp"]
        before = self.spindle_rpm
        if ramp == 0:
            self.spindle_rpm = float(self.spindle_target)
        elif dt:
            step = self.num["spindle_max"] * dt / ramp
            gap = self.spindle_target - self.spindle_rpm
            self.spindle_rpm = float(self.spindle_target) if abs(gap) <= step else \
                self.spindle_rpm + (step if gap > 0 else -step)
        self.angle_udeg = (self.angle_udeg + round((before + self.spindle_rpm) * 3 * dt)) % 360_000_000
        if self.spindle_rpm != 0:
            self.oriented, self.orient_left = False, -1
        if orient and not self.oriented and abs(self.spindle_rpm) <= self.num["zero_speed"]:
            if self.orient_left < 0:
                self.orient_left = self.times["orient_time"]
                self.spindle_rpm = 0.0
            self.orient_left -= dt
            if self.orient_left <= 0:
                self.angle_udeg, self.oriented = self.num["orient_at"] * 10_000, True
        if not orient:
            self.oriented, self.orient_left = False, -1
        self.orienting = self.orient_left >= 0 and not self.oriented

    # -- tool magazine 1 (5.3.14, 6.13)
    def _magazine(self, mb) -> None:
        relays = mb[self.a_magazine_forward:self.a_magazine_forward + 4]  # M2x064-M2x067
        if relays == self.magazine_relays:
            return
        self.magazine_relays = relays
        n = len(self.pots)
        if self._edge(mb, self.a_magazine_reset):
            self._magazine_reset()
        if self._edge(mb, self.a_magazine_forward):
            self.standby = self.standby % n + 1  # 6.13: max -> 1
        if self._edge(mb, self.a_magazine_reverse):
            self.standby = (self.standby - 2) % n + 1  # DECISION (notes #27): reverse, 1 -> max
        if self._edge(mb, self.a_tool_exchange):
            k = self.standby - 1
            self.spindle_tool, self.pots[k] = self.pots[k], self.spindle_tool

    # -- outputs
    def _output_addresses(self) -> None:
        """The NC -> MLC relays and registers in the order _outputs computes them."""
        bits = [self.a_mode_feedback + k for k in range(8)]
        bits += [self.a_running, self.a_paused, self.a_block_stopped, self.a_estop_state,
                 self.a_last_line, self.a_m02_end, self.a_m30_end]
        bits += [self.a_macro_running, self.a_macro_needs_auto, self.a_macro_error]
        bits += [self.a_macro_ready + k for k in range(16)]
        for ax in self.axes:
            o = ax.offset
            bits += [self.a_servo_state + o, self.a_homed + o, self.a_home_done + o, self.a_at_origin + o,
                     self.a_moving + o, self.a_moving_plus + o, self.a_moving_minus + o,
                     self.a_mlc_axis_on + o, self.a_mlc_in_position + o]
        bits += [self.a_spindle_at_speed, self.a_spindle_zero_speed, self.a_spindle_oriented]
        self.bit_addresses = bits
        words = []
        for n in (self.a_spindle_command, self.a_spindle_actual, self.a_spindle_angle):
            words += [n, n + 1]
        words += [self.a_spindle_tool, self.a_standby_t, self.a_standby_pot, self.a_pot_steps]
        self.times_word = len(words)  # D49c04's place
        for n in (self.a_total_time, self.a_cycle_time):
            words += [n, n + 1]
        words += [A.SYSTEM_TIME + k for k in range(3)]
        self.word_addresses = words
        self.signal_names = ["mode", "state", "block", "alarm", "feed"]  # in the order _publish gives them
        self.signal_names += [f"{a.letter}.{s}" for a in self.axes for s in ("pos", "speed")]
        self.signal_names += ["spindle.rpm", "spindle.cmd", "spindle.angle", "spindle.gear"]

    def _outputs(self, mb, dw, dt: int, before: list[int], moving_ok: list[bool]) -> None:
        """Every NC -> MLC relay and register, written where its value changed (the MLC does
        not write them: the checker says so)."""
        state, mode = self.state, self.mode
        running = state in (RUNNING, MST_WAIT) or (state == HOLD and not self.hold_by_mode)
        bits = [0] * 8
        if 0 <= mode < 8:
            bits[mode] = 1
        bits += [running, state == HOLD, state == BLOCK_STOP, self.estop, *self.ends,
                 self.macro_call, self.macro_needs_auto, self.macro_error]
        bits += [ready != 0 for ready in self.macro_ready] if self.macro_call else self.NO_MACROS
        vel = [ax.vel for ax in self.axes]  # 0.001 mm/min of the moves in force
        if self.seg_speed and self.phase == 1 and state in (RUNNING, MST_WAIT):
            length = self.move[2]
            for ax, s, e in self.seg_axes:  # the block's motion
                vel[self.axes.index(ax)] = round(self.seg_speed * (e - s) / length)
        for f, (m, sign, transfer) in self.active.items():  # followers move as their masters
            if not transfer or mode in (AUTO, MDI):
                vel[f] = sign * vel[m]
                if transfer:
                    vel[m] = 0
        for i, ax in enumerate(self.axes):
            # moving: a move in force after the step, or moved by the handwheel in this step
            v = vel[i]
            if not v and ax in self.jumped:
                v = (ax.pos - before[i]) * 60_000_000 // dt if dt else 0
                self.busy = True  # the flags drop in the next step
            ax.speed = v // 1000 if v > 0 else -(-v // 1000)
            bits += [moving_ok[i], ax.homed, ax.home_done, ax.homed and ax.pos == 0, v != 0, v > 0, v < 0,
                     ax.mlc, ax.mlc_done]
        rpm = round(self.spindle_rpm)
        bits += [abs(rpm - self.spindle_target) <= self.num["at_speed"], abs(rpm) <= self.num["zero_speed"],
                 self.oriented]
        if bits != self.out_bits:
            for n, v, old in zip(self.bit_addresses, bits, self.out_bits or [None] * len(bits)):
                if v != old:
                    mb[n] = 1 if v else 0
            self.out_bits = bits
        if running or self.was_running:  # the interval this step ran the program for
            self.cycle_us += dt
            self.total_us += dt
        self.counting = running
        if self.parts_done_add:  # 5.3.15: one part at each M02 / M30
            self.parts_done_add = False
            self._put32(dw, self.a_parts_done, _s32(dw[self.a_parts_done], dw[self.a_parts_done + 1]) + 1)
        # DECISION (notes #32): D3x026 is the ramped speed the NC commands at this moment (the
        # "即時命令速度"), without its sign; D3x024 the command in force (S, or D2x024 with M2x710)
        words = []
        for v in (self.command, abs(rpm), self.angle_udeg // 10_000):  # angle: 0.01 deg (N0.1013's unit)
            words += [v & 0xFFFF, (v >> 16) & 0xFFFF]
        words += [self.spindle_tool, self.standby_t, self.standby, self._pot_steps() & 0xFFFF]
        words += self._time_words()
        if words != self.out_words:
            for n, v, old in zip(self.word_addresses, words, self.out_words or [None] * len(words)):
                if v != old:
                    dw[n] = v
            self.out_words = words

    def _system_time(self) -> list[int]:
        """D49000-D49002 at last_t: the clock= time plus the run's. DECISION (5.3.15 names only
        "年、月", "日、時", "分、秒"): two decimal digits each, year-month 2206 for June 2022,
        day-hour 1508 for the 15th at 8 h, minute-second 3045."""
        second = self.clock0 + self.last_t // 1_000_000
        if second != self.time_shown[0]:
            t = datetime.datetime(1970, 1, 1) + datetime.timedelta(seconds=second)
            self.time_shown = (second, [t.year % 100 * 100 + t.month, t.day * 100 + t.hour, t.minute * 100 + t.second])
        return self.time_shown[1]

    @staticmethod
    def _put32(dw, n: int, v: int) -> None:
        dw[n], dw[n + 1] = v & 0xFFFF, (v >> 16) & 0xFFFF

    def _publish(self) -> None:
        values = [self.mode, self.state, self.block_line, self.alarm,
                  self.path_speed if self.state in (RUNNING, MST_WAIT) else 0]
        for ax in self.axes:
            values += [ax.pos if ax.held is None else ax.held, ax.speed]
        values += [round(self.spindle_rpm), self.spindle_target, self.angle_udeg // 10_000, self.gear]
        if values != self.published:
            self.publisher(values, self.published)
            self.published = values

