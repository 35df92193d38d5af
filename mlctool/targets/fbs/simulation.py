"""FBs NC instructions in `mlc sim`: the target's Simulation (mlctool/targetapi/simulation.py).

FUN140 HSPSO drives one `Axis` (axis.py) per Ps on the simulator's virtual clock: the axes
run between scans (`before_scan` advances them to the scan's start time with the inputs
their instruction last saw, so a stimulus input changed at t is seen from the scan at or
after t), and each HSPSO execution applies its EN/PAU/ABT at once. Axis registers and flags
are mirrored into PLC memory after every advance (manual 001 ch. 11, "介面處理信號"):

  DR4072+2Ps remaining pulses, DR4080+2Ps frequency, DR4088+2Ps position,
  R4060+Ps error (kept until the program writes 0), R4064+Ps step at the end of a step,
  M1992+Ps ready, M1996+Ps last step done, WR+0 step, WR+1 flags (DN b14 and ERR b13 stay
  until the program clears WR+1), pulse pins Y(2Ps), Y(2Ps+1) by the axis' output mode.

Decisions (docs/fbs.md): a table is read from SR when its HSPSO starts (EN rising edge or
taking over a free axis); pins show one level per scan, not the pulse train.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from mlctool.sim.semantics import OPERATION_ALARM, alarm, warn
from mlctool.sim.state import DeviceView, Machine, s16, s32
from mlctool.targetapi.simulation import Simulation
from mlctool.targets.fbs import mpg as follow
from mlctool.targets.fbs import pulses
from mlctool.targets.fbs.axis import TICK_US, Axis, Params
from mlctool.targets.fbs.files import table_preload
from mlctool.targets.fbs.interp import Group
from mlctool.targets.fbs.model import PosProgram, mhspo_mode_conflicts, tables
from mlctool.targets.fbs.table import TableError, decode, execution_error

AXES = 4
GROUPS = 2
# FUN147 per group: D4060+Gp error, D4062+Gp end step, DR4068+2Gp line speed, M1934+Gp done
G_ERROR, G_END_STEP, G_SPEED, G_DONE = 4060, 4062, 4068, 1934
REMAINING, FREQ, POSITION = 4072, 4080, 4088  # DR registers, + 2 Ps
ERROR, END_STEP = 4060, 4064  # R registers, + Ps
READY, LAST_DONE, DECEL_STOP = 1992, 1996, 1991  # M relays
DYNAMIC = 4056  # R4056 low byte 5AH: SPD changes take effect at once
# WR+1 flag bits (FUN140 WR table)
PAUSED, WAITING, CONTINUOUS, ACT, ERR, DN = 1 << 8, 1 << 9, 1 << 10, 1 << 12, 1 << 13, 1 << 14
LIVE = ((REMAINING, lambda a: a.remaining), (FREQ, lambda a: int(a.freq)),
        (POSITION, lambda a: a.position))
PIN_MODES = ("UD", "PR", "AB", "")  # "" = no pulse mode: Y pins stay ordinary outputs


@dataclass
class Slot:
    """One pulse output Ps: its axis, the HSPSO owning it and the inputs it last gave."""

    axis: Axis
    owner: int = -1  # step index of the owning HSPSO
    wr: tuple[str, int] | None = None  # owner's WR register
    inputs: tuple[bool, bool, bool] = (False, False, False)  # EN, PAU, ABT
    t_us: int = 0  # virtual time the axis has run to
    pin_mode: str = "UD"
    err_latched: bool = False
    used: bool = False  # driven by a FUN140/147/148 once: its registers and pins are mirrored
    follow: follow.Follower = field(default_factory=follow.Follower)  # FUN148 on this axis


@dataclass
class GroupSlot:
    """One FUN147 group Gp: the interpolation state, its owner's WR and inputs."""

    group: Group
    owner: int = -1
    wr: tuple[str, int] | None = None
    inputs: tuple[bool, bool, bool] = (False, False, False)
    t_us: int = 0
    err_latched: bool = False


@dataclass
class State:
    slots: list[Slot] = field(default_factory=list)
    groups: list[GroupSlot] = field(default_factory=list)
    pin_levels: dict = field(default_factory=dict)  # --pulse-window: Y levels written
    window_open: bool = False


def _state(m: Machine) -> State:
    st = m.ext.get("fbs")
    if st is None:
        modes = list(m.target.settings.get("pulse_modes", ["UD"] * AXES))
        st = State([Slot(Axis(PosProgram("hspso", ())), pin_mode=modes[p] if p < len(modes) else "UD")
                    for p in range(AXES)])
        axes = [slot.axis for slot in st.slots]
        st.groups = [GroupSlot(Group(PosProgram("mhspo", ()), axes)) for _ in range(GROUPS)]
        m.ext["fbs"] = st
    return st


class MemEnv:
    """What a running axis reads: PLC memory, and its own live registers (a step of the
    chapter's example reads DR4072 as the pulses the previous step left)."""

    def __init__(self, m: Machine, st: State):
        self.m, self.st = m, st

    def word(self, kind: str, n: int) -> int:
        return self.m.words[kind][n]

    def dword(self, kind: str, n: int) -> int:
        if kind == "R":
            for base, live in LIVE:
                if base <= n < base + 2 * AXES and (n - base) % 2 == 0:
                    return live(self.st.slots[(n - base) // 2].axis)
        w = self.m.words[kind]
        return s32(w[n] | w[n + 1] << 16)

    def bit(self, kind: str, n: int) -> bool:
        return bool(self.m.bits[kind][n])


# ------------------------------------------------------------------ time and memory

def _pieces(m: Machine, t0: int, traced: bool) -> list[tuple[int, int]]:
    """(start, length) of the advance from t0 to now: one piece, or 1 ms ticks when the
    pulse pins are traced (each tick's pulses are placed in it: fbs/pulses.py)."""
    dt = m.now_us - t0
    if dt <= 0:
        return []
    trace = m.pin_window
    if not traced or trace is None or not trace.overlaps(t0, m.now_us):
        return [(t0, dt)]
    return [(t, min(TICK_US, m.now_us - t)) for t in range(t0, m.now_us, TICK_US)]


def _advance(m: Machine, st: State, slot: Slot) -> None:
    t0, slot.t_us = slot.t_us, m.now_us
    a = slot.axis
    a.soft_stop = bool(m.bits["M"][DECEL_STOP])
    p = st.slots.index(slot)
    for start, dt in _pieces(m, t0, bool(slot.pin_mode)):
        before = a.pulses_out
        if slot.follow.active:
            follow.run(slot.follow, a, dt)
        elif a.state != "idle" or a.clr:
            en, pau, abt = slot.inputs
            a.run(MemEnv(m, st), en, pau, abt, dt)
        else:
            break
        if m.pin_window is not None:
            pulses.emit(m.pin_window, st.pin_levels, p, slot.pin_mode, start, dt,
                        a.pulses_out - before, a.dir > 0)


def _put32(m: Machine, n: int, v: int) -> None:
    w = m.words["R"]
    w[n], w[n + 1] = v & 0xFFFF, (v >> 16) & 0xFFFF


def _mirror(m: Machine, p: int, slot: Slot) -> None:
    a = slot.axis
    _put32(m, REMAINING + 2 * p, a.remaining)
    _put32(m, FREQ + 2 * p, int(a.freq))
    _put32(m, POSITION + 2 * p, a.position)
    if a.error:  # an event: R4060 keeps it until the program writes 0
        m.words["R"][ERROR + p] = a.error
        slot.err_latched = True
        a.error = 0
    m.words["R"][END_STEP + p] = a.end_step
    busy = a.state != "idle" or a.braking or not a.ready  # not ready: a FUN147 group has it
    m.bits["M"][READY + p] = 0 if busy else 1
    m.bits["M"][LAST_DONE + p] = 1 if a.done_last else 0
    if slot.wr is not None:
        kind, n = slot.wr
        w = m.words[kind]
        kept = w[n + 1] & (ERR | DN)
        if a.dn:
            kept |= DN
            a.dn = False
        if slot.err_latched:
            kept |= ERR
            slot.err_latched = False
        en, pau, _ = slot.inputs
        flags = len(a.program.steps) & 0xFF | kept
        flags |= PAUSED if pau and en and a.state != "idle" else 0
        flags |= WAITING if a.state == "wait" else 0
        flags |= CONTINUOUS if a.to_go == float("inf") and a.state == "run" and not a.home else 0
        flags |= ACT if a.act and a.state == "run" else 0
        w[n], w[n + 1] = a.wr0 & 0xFFFF, flags
    _pins(m, p, slot)


def _pins(m: Machine, p: int, slot: Slot) -> None:
    """Y(2Ps), Y(2Ps+1): one level per scan (the pulse train is not traced; docs/fbs.md).
    U/D: the even pin is On while forward pulses are output, the odd one for reverse;
    P/R: even On while pulsing, odd = direction (On = up-count); A/B: both On while pulsing."""
    if not slot.pin_mode:
        return
    a = slot.axis
    # FUN147/148 hold an idle axis (not ready) while they drive it
    pulsing = a.freq > 0 and (a.state == "run" or not a.ready) or a.braking
    up = a.dir > 0
    y = m.bits["Y"]
    if slot.pin_mode == "UD":
        y[2 * p], y[2 * p + 1] = int(pulsing and up), int(pulsing and not up)
    elif slot.pin_mode == "PR":
        y[2 * p], y[2 * p + 1] = int(pulsing), int(up)
    else:
        y[2 * p] = y[2 * p + 1] = int(pulsing)
    clr = a.params.clr
    if clr is not None and 0 <= clr < len(y):
        y[clr] = int(a.clr)


def _mode_overrides(m: Machine, st: State) -> None:
    """A stimulus `model stepper mode=` over the project's pulse output mode (the models step
    after before_scan, so scan 0's instructions apply it themselves)."""
    for p, mode in m.ext.get("pulse_modes", {}).items():
        st.slots[p].pin_mode = mode


def before_scan(m: Machine) -> None:
    """Every axis runs to the scan's start time (hardware keeps going between scans)."""
    st = _state(m)
    _mode_overrides(m, st)
    trace = m.pin_window
    if trace is not None and not st.window_open and m.now_us >= trace.from_us:
        st.window_open = True  # the pins of the axes in use go to rest at the window's start
        for p, slot in enumerate(st.slots):
            if slot.used and slot.pin_mode:
                pulses.open_window(trace, st.pin_levels, p, slot.pin_mode, slot.axis.dir > 0)
    for slot in st.slots:
        _advance(m, st, slot)
    for g, gs in enumerate(st.groups):
        _advance_group(m, st, gs)
        if gs.owner >= 0:
            _mirror_group(m, g, gs)
    for p, slot in enumerate(st.slots):
        if slot.used:
            _mirror(m, p, slot)


# ------------------------------------------------------------------ instructions

def _inputs(m: Machine, count: int) -> list[bool]:
    """A multi-input instruction's inputs: the blocks before it and the current result
    (docs/fbs.md: one load block per input, in order)."""
    got = [m.acc]
    for _ in range(count - 1):
        got.insert(0, m.blocks.pop() if m.blocks else False)
    return got


def _load_table(m: Machine, kind: str, n: int) -> PosProgram | None:
    """The program in the registers from SR (header, step count, steps), or None."""
    w = m.words[kind]
    d = tables().by_header(w[n])
    size = d.table_words(w[n + 1]) if d else 0
    if not d or n + size > len(w):
        return None
    try:
        return decode(list(w[n:n + size]))
    except TableError:
        return None


EMPTY_TABLE = "W330"  # codes.toml: a positioning instruction started on an empty or invalid table


def _not_started(m: Machine, s, dialect: str, kind: str, n: int, program: PosProgram | None, code: int,
                 register: str) -> None:
    """W330: FUN140/FUN147 started (EN rising) on a table that is no program of its own, with
    the error code the PLC puts in `register` (R4060+Ps, D4060+Gp)."""
    own, other = ("FUN140", "FUN147") if dialect == "hspso" else ("FUN147", "FUN140")
    if program is None:
        first = m.words[kind][n] if 0 <= n < len(m.words[kind]) else 0
        why = (f"an empty table at {kind}{n} (nothing loaded there: mlc.toml `tables` or --table)" if first == 0
               else f"{kind}{n}, which holds no positioning table (header {first:04X}H)")
    elif program.dialect != dialect:
        why = f"{kind}{n}, which holds a {other} table"
    else:
        why = f"the table at {kind}{n}, which breaks a rule of its program (the build's F{code:03d})"
    written = s.ins.mnemonic if s.ins.mnemonic.upper().startswith("FUN") else f"{own} {s.ins.mnemonic}"
    warn(m, EMPTY_TABLE, f"{written} {' '.join(s.ins.texts)} started on {why}: not started, "
         f"error {code} in {register}")


def hspso(m: Machine, s) -> None:
    """FUN140 HSPSO Ps SR WR with inputs EN, PAU, ABT (manual 001 ch. 11 FUN140 1-9)."""
    en, pau, abt = _inputs(m, 3)
    st = _state(m)
    p = s.ops[0].get(m) % AXES
    slot = st.slots[p]
    a = slot.axis
    rising = en and not m.edge[s.index]
    m.edge[s.index] = en
    if slot.owner != s.index:
        # several FUN140 may share an axis; one runs at a time, the next takes a free axis
        if not (en and not abt) or a.state != "idle" or a.braking or not a.ready:
            m.acc = False
            return
        slot.owner, a.last_en, slot.used = s.index, False, True
        rising = True
    slot.wr = (s.ops[2].kind, s.ops[2].addr(m, 7))
    _advance(m, st, slot)
    if a.state == "idle" and not a.ready:  # a FUN147 group or FUN148 holds the axis: wait
        if rising or not en:  # an EN edge seen while held starts the run when it is free
            a.last_en = False
        slot.inputs = (False, pau, abt)
        m.acc = False
        return
    if rising and not abt and a.state == "idle":
        sr_kind, sr = s.ops[1].kind, s.ops[1].addr(m, 2)
        program = _load_table(m, sr_kind, sr)
        code = execution_error(program) if program is not None and program.dialect == "hspso" else 0
        if program is None or program.dialect != "hspso":
            a.error = 34  # not a FUN140 table: "不合法定位程式"
            a.last_en = True
            _not_started(m, s, "hspso", sr_kind, sr, program, 34, f"R{ERROR + p}")
        elif code:
            a.error = code  # a table written at run time breaks a build rule (41, 42, 43, 34)
            a.last_en = True
            _not_started(m, s, "hspso", sr_kind, sr, program, code, f"R{ERROR + p}")
        else:
            a.program = program
            wr0 = m.words[slot.wr[0]][slot.wr[1]]  # the user may preset WR+0 (next step - 1)
            a.wr0 = wr0 if 0 <= wr0 <= len(program.steps) else 0
    slot.inputs = (en, pau, abt)
    a.soft_stop = bool(m.bits["M"][DECEL_STOP])
    a.run(MemEnv(m, st), en, pau, abt, 0)
    _mirror(m, p, slot)
    m.acc = a.act and a.state == "run"  # the result after FUN140 is its ACT output


def _param_table(w: list[int], n: int) -> tuple[Params | None, int]:
    """24 registers of FUN141 -> (Params, 0) or (None, error code = parameter number + 1)."""
    r = w[n:n + 24]
    d = lambda k: s32(r[k] | r[k + 1] << 16)  # noqa: E731
    p0, p1, p2, p3, p4, p5 = r[0], r[1], d(2), r[4], d(5), d(7)
    p14 = d(17)
    checks = [(1, 0 <= p0 <= 2), (2, 1 <= p1 or p14), (3, 1 <= p2 <= 999999), (4, 0 <= p3 <= 3),
              (5, 1 <= p4 <= 921600), (6, 0 <= p5 <= 921600), (7, r[9] >= 1), (8, r[10] <= 32767),
              (9, r[11] <= 30000), (10, r[12] >> 8 <= 1 and r[12] & 0xFF <= 1), (13, r[15] <= 30000),
              (14, r[16] <= 30000), (15, 0 <= p14 <= 1999999)]
    bad = next((code for code, ok in checks if not ok), 0)
    if bad:
        return None, bad
    per_rev = p14 or p1
    unit = 10 ** (3 - p3)
    ut = unit if p0 == 1 else unit * per_rev / p2  # motor unit: Ps; machine/compound: via P1/P2
    speed = 1000 * per_rev / (6 * p2) if p0 == 0 else 1.0  # machine unit speeds (A5, P4 formula)
    dog, pg0, limit = r[19] & 0xFF, r[20] & 0xFF, r[19] >> 8  # P15-0, P15-2, P15-1
    clr = r[20] >> 8
    return Params(p4_max=round(p4 * speed), p5_start=round(p5 * speed), p6_creep=round(r[9] * speed),
                  p7_backlash=r[10], p8_accel_ms=r[11], p9_count_down=bool(r[12] & 1),
                  p9_home_left=bool(r[12] >> 8), p10_fwd=s16(r[13]), p11_rev=s16(r[14]),
                  p12_decel_ms=r[15], p13_ms=r[16], ut_pulses=ut, speed_scale=speed,
                  dog=None if dog == 0xFF else dog & 0x7F, dog_nc=bool(dog & 0x80) and dog != 0xFF,
                  limit=None if limit == 0xFF else limit & 0x7F, limit_nc=bool(limit & 0x80) and limit != 0xFF,
                  pg0=None if pg0 == 0xFF else pg0 & 0x7F, pg0_trailing=bool(pg0 & 0x80) and pg0 != 0xFF,
                  clr=None if clr == 0xFF else clr, p16_origin=d(21), p17_count=r[23]), 0


def mpara(m: Machine, s) -> None:
    """FUN141 MPARA Ps SR: executed whether EN is 0 or 1; an invalid parameter -> R4060+Ps.
    The result after it is its ERR output: 11.6 FUN141 note 4, "當參數值有錯誤時，輸出指示
    〝ERR〞ON" (On while the table holds a wrong value, whatever EN is; docs/fbs.md)."""
    st = _state(m)
    p = s.ops[0].get(m) % AXES
    kind, n = s.ops[1].kind, s.ops[1].addr(m, 24)
    params, code = _param_table(m.words[kind], n)
    slot = st.slots[p]
    m.acc = params is None
    if params is None:
        if m.words["R"][ERROR + p] != code:
            slot.axis.error = code
            _mirror(m, p, slot)
        return
    if params != slot.axis.params:
        slot.axis.params = params


def psoff(m: Machine, s) -> None:
    """FUN142 PSOFF Ps: EN = 1 stops the axis' pulse output at once."""
    if m.acc:
        st = _state(m)
        p = s.ops[0].get(m) % AXES
        st.slots[p].axis.stop()
        _mirror(m, p, st.slots[p])


def pscnv(m: Machine, s) -> None:
    """FUN143 PSCNV Ps D: D (pair) = the current position in display units (Ut), the
    inverse of the travel conversion, truncated toward 0 (DECISION)."""
    if m.acc:
        st = _state(m)
        a = st.slots[s.ops[0].get(m) % AXES].axis
        ut = a.params.ut_pulses
        v = int(a.position / ut) if ut else a.position
        ref = s.ops[1]
        kind, n = ref.kind, ref.addr(m, 2)
        w = m.words[kind]
        w[n], w[n + 1] = v & 0xFFFF, (v >> 16) & 0xFFFF
        m.writer[(kind, n)] = m.writer[(kind, n + 1)] = m.pc


def _advance_group(m: Machine, st: State, gs: GroupSlot) -> None:
    t0, gs.t_us = gs.t_us, m.now_us
    grp = gs.group
    for start, dt in _pieces(m, t0, True):
        if grp.state == "idle":
            break
        before = [a.pulses_out for a in grp.axes]
        en, pau, abt = gs.inputs
        grp.run(MemEnv(m, st), en, pau, abt, dt)
        if m.pin_window is not None:
            for p, slot in enumerate(st.slots):
                pulses.emit(m.pin_window, st.pin_levels, p, slot.pin_mode, start, dt,
                            slot.axis.pulses_out - before[p], slot.axis.dir > 0)


def _mirror_group(m: Machine, g: int, gs: GroupSlot) -> None:
    grp = gs.group
    if grp.error:
        m.words["D"][G_ERROR + g] = grp.error
        gs.err_latched, grp.error = True, 0
    m.words["D"][G_END_STEP + g] = grp.end_step
    _put32(m, G_SPEED + 2 * g, int(grp.vector))
    m.bits["M"][G_DONE + g] = 1 if grp.done_last else 0
    if gs.wr is not None:
        kind, n = gs.wr
        w = m.words[kind]
        kept = w[n + 1] & (ERR | DN)
        if grp.dn:
            kept, grp.dn = kept | DN, False
        if gs.err_latched:
            kept, gs.err_latched = kept | ERR, False
        en, pau, _ = gs.inputs
        flags = len(grp.program.steps) & 0xFF | kept
        flags |= PAUSED if pau and en and grp.state != "idle" else 0
        flags |= WAITING if grp.state == "wait" else 0
        flags |= CONTINUOUS if grp.state == "run" and grp.lead == float("inf") else 0
        flags |= ACT if grp.state == "run" and grp.used else 0
        w[n], w[n + 1] = grp.wr0 & 0xFFFF, flags


def mhspo(m: Machine, s) -> None:
    """FUN147 MHSPO Gp SR WR with inputs EN, PAU, ABT: linear interpolation (interp.py).
    It starts only when every axis its step names is free (M1992+Ps On)."""
    en, pau, abt = _inputs(m, 3)
    st = _state(m)
    g = s.ops[0].get(m) % GROUPS
    gs = st.groups[g]
    grp = gs.group
    rising = en and not m.edge[s.index]
    m.edge[s.index] = en
    if gs.owner != s.index:
        if not (en and not abt) or grp.state != "idle":
            m.acc = False
            return
        gs.owner, grp.last_en, rising = s.index, False, True
    gs.wr = (s.ops[2].kind, s.ops[2].addr(m, 9))
    _advance_group(m, st, gs)
    if (rising or not grp.last_en) and en and not abt and grp.state == "idle":
        sr_kind, sr = s.ops[1].kind, s.ops[1].addr(m, 2)
        program = _load_table(m, sr_kind, sr)
        code = execution_error(program) if program is not None and program.dialect == "mhspo" else 0
        _mode_overrides(m, st)
        if program is None or program.dialect != "mhspo":
            grp.error, grp.last_en = 34, True
            _not_started(m, s, "mhspo", sr_kind, sr, program, 34, f"D{G_ERROR + g}")
        elif code:
            grp.error, grp.last_en = code, True  # a table written at run time breaks a build rule
            _not_started(m, s, "mhspo", sr_kind, sr, program, code, f"D{G_ERROR + g}")
        elif conflicts := mhspo_mode_conflicts(program, [slot.pin_mode for slot in st.slots]):
            k, i = conflicts[0]  # 11.6: U/D or A/B only; the manual names no error code for it
            alarm(m, OPERATION_ALARM, f"FUN147 step {k + 1:03d} drives Ps{i}, whose pulse output mode is "
                  "P/R: FUN147 takes U/D or A/B only (11.6); not started")
            grp.last_en = True  # not retried until EN rises again
        else:
            grp.program = program
            wr0 = m.words[gs.wr[0]][gs.wr[1]]
            grp.wr0 = wr0 if 0 <= wr0 <= len(program.steps) else 0
            k = grp.wr0 + 1 if grp.wr0 < len(program.steps) else 1
            named = [i for i, v in enumerate(program.steps[k - 1].motion.travel) if v.kind]
            if any(st.slots[i].axis.state != "idle" or not st.slots[i].axis.ready for i in named):
                en = False  # an axis is busy: wait (retried every scan while EN is On)
            grp.p13_ms = st.slots[named[0]].axis.params.p13_ms if named else 500
            for i in named:
                st.slots[i].used = True
    gs.inputs = (en, pau, abt)
    grp.run(MemEnv(m, st), en, pau, abt, 0)
    _mirror_group(m, g, gs)
    for i in grp.used:
        _mirror(m, i, st.slots[i])
    m.acc = grp.state == "run" and bool(grp.used)


def _dword(m: Machine, kind: str, n: int) -> int:
    w = m.words[kind]
    return s32(w[n] | w[n + 1] << 16)


def mpg(m: Machine, s) -> None:
    """FUN148 MPG Sc Ps Fo Mr WR with input EN: the axis follows the handwheel counted by
    HSC Sc (mpg.py; decisions in docs/fbs.md). The result after it is its ACT output."""
    en = m.acc
    st = _state(m)
    sc, p = s.ops[0].get(m), s.ops[1].get(m)
    wr_kind, wr = s.ops[4].kind, s.ops[4].addr(m, 4)
    if not (0 <= sc <= 7 and 0 <= p < AXES):  # out of the operand range: no output
        m.acc = False
        return
    slot = st.slots[p]
    f, a = slot.follow, slot.axis
    _advance(m, st, slot)
    count = _dword(m, "R", follow.HSC_BASE + follow.HSC_STRIDE * sc)
    if not en:
        if f.owner == s.index and f.enabled:
            if f.active:  # EN Off: output stops at once (as FUN140 without M1991)
                follow.release(f, a)
            f.enabled = False
        m.acc = f.active and f.owner == s.index
        if slot.used:
            _mirror(m, p, slot)
        return
    if f.owner != s.index and (f.active or (f.enabled and f.owner >= 0)):
        m.acc = False  # another FUN148 follows on this axis
        return
    if not f.enabled or f.owner != s.index:  # EN rising: the reference count, 50 ms clock
        f.owner, f.enabled, f.last_count, f.carry, f.lost = s.index, True, count, 0, 0
        f.next_us = m.now_us + follow.SAMPLE_US
    elif m.now_us >= f.next_us:
        while f.next_us <= m.now_us:
            f.next_us += follow.SAMPLE_US
        fa, fb = m.words[s.ops[3].kind][s.ops[3].addr(m, 2)], m.words[s.ops[3].kind][s.ops[3].addr(m, 2) + 1]
        pulses = follow.sample(f, count, fa, fb)
        fo = _dword(m, s.ops[2].kind, s.ops[2].addr(m, 2))
        free = a.state == "idle" and not a.braking and (a.ready or f.active)
        r4020 = m.words["R"][follow.INHIBIT]
        if not free or fo <= 0 or (pulses and follow.inhibited(r4020, p, pulses > 0)):
            pulses = 0  # held by FUN140/147, no frequency, or inhibited: nothing is output
        follow.start(f, a, pulses, fo)
        slot.used = True
    w = m.words[wr_kind]
    w[wr], w[wr + 1] = f.last_count & 0xFFFF, (f.last_count >> 16) & 0xFFFF
    w[wr + 2], w[wr + 3] = f.carry & 0xFFFF, f.lost & 0xFFFF
    for k in range(4):
        m.writer[(wr_kind, wr + k)] = m.pc
    if slot.used:
        _mirror(m, p, slot)
    m.acc = f.active  # ACT: pulses being output


ACTIONS = {"mpg": mpg, "mhspo": mhspo, "hspso": hspso, "mpara": mpara, "psoff": psoff, "pscnv": pscnv}


def pulse_pins(target) -> list[tuple[str, int]]:
    """The pins `mlc sim --pulse-window` traces as pulse trains: Y0-Y7 of Ps0-Ps3."""
    return [("Y", n) for n in range(2 * AXES)]


PS_OPS = ("hspso", "mpara", "psoff", "pscnv")  # first operand Ps (FUN147's is a group)


def views(target, prog) -> list[DeviceView]:
    """The registers and flags of every axis a FUN140/141/143/148 names with a constant Ps."""
    axes = {s.ins.operands[0].value % AXES for s in prog.steps
            if s.ins.spec.op in PS_OPS and s.ins.operands and s.ins.operands[0].is_const}
    axes |= {s.ins.operands[1].value for s in prog.steps  # FUN148: Sc Ps ...
             if s.ins.spec.op == "mpg" and len(s.ins.operands) > 1 and s.ins.operands[1].is_const
             and 0 <= s.ins.operands[1].value < AXES}
    axes = sorted(axes)
    out = []
    for p in axes:
        out += [DeviceView("R", REMAINING + 2 * p, "d"), DeviceView("R", FREQ + 2 * p, "d"),
                DeviceView("R", POSITION + 2 * p, "d"), DeviceView("R", ERROR + p, "w"),
                DeviceView("R", END_STEP + p, "w"), DeviceView("M", READY + p, "bit"),
                DeviceView("M", LAST_DONE + p, "bit"), DeviceView("Y", 2 * p, "bit"),
                DeviceView("Y", 2 * p + 1, "bit")]
    return out


SIMULATION = Simulation(actions=ACTIONS, before_scan=before_scan, views=views, pulse_pins=pulse_pins,
                        load_table=table_preload)
