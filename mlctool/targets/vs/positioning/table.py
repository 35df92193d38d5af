"""DTBL (8-3 FNC 312): positioning tables of steps, on the axis moves of targets/vs/positioning/moves.py."""

from __future__ import annotations

from mlctool.sim.hardware import motion
from mlctool.sim.state import Machine, s16
from mlctool.targets.vs.common import op_error, set_relay, state
from mlctool.targets.vs.positioning.moves import (
    _advance,
    _cfg,
    _claim,
    _cruise_to,
    _direction_pin,
    _pair,
    _params,
    _register,
    _speed,
)
from mlctool.targets.vs.pulse_out import ABNORMAL, DONE, _relay, _release, _set
from mlctool.targets.vs.serial import mbus

# ------------------------------------------------------------ DTBL (FNC 312)

# operation commands of a table row (8-3 DTBL "運轉資料")
END, SINGLE_REL, SINGLE_ABS, CHAIN_REL, CHAIN_ABS, JMP = range(6)
MOVES = (SINGLE_REL, SINGLE_ABS, CHAIN_REL, CHAIN_ABS)
NO_MCODE = -1
WITH_MCODE = 10_000  # m codes 10000-32767 come with the step's start, 0-9999 after its end


def _field(m: Machine, row, name: str) -> int:
    """A row's field now: a constant, or the register(s) it names (32-bit: the pair), as the
    field's width in target.toml [tables.DTBL] says."""
    op = row.fields[name]
    if op.is_const:
        return int(op.value)
    width = next(f.get("width", 16) for f in m.target.settings["tables"][row.kind]["fields"]
                 if f["name"] == name)
    words = m.words[op.kind]
    v = words[op.number] | ((words[op.number + 1] << 16) if width == 32 else 0)
    return v - (1 << width) if v >> (width - 1) & 1 else v


def _mcode(m: Machine, axis: int, code: int) -> None:
    """D9349 = the m code; M9348 On while there is one (-1: none)."""
    m.words["D"][_register(m, axis, "mcode")] = code & 0xFFFF
    _set(m, axis, _cfg(m)["mcode_on"], code != NO_MCODE)


def _table_step(m: Machine, s, memo: dict, step: int) -> None:
    memo["step"] = step
    kind, n = s.ins.operands[1].kind, s.ops[1].addr(m)
    m.words[kind][n] = step & 0xFFFF  # S2: the step in progress


def _table_flow(m: Machine, s, memo: dict) -> None:
    """Run the rows that need no start signal from the present step: END turns M9029 On for
    one scan and the table is finished, JMP goes to the row its position names. DECISION
    (the page draws END right after the last move): END and JMP run when reached."""
    rows = memo["rows"]
    for _ in range(len(rows) + 1):
        step = memo["step"]
        if not 0 <= step < len(rows):
            memo["phase"] = "stopped"
            return op_error(m, s, f"table step {step} does not exist (rows 0-{len(rows) - 1})")
        cmd = _field(m, rows[step], "command")
        if cmd == END:
            memo["phase"], memo["m9029"] = "end", True
            set_relay(m, "done", True)
            return
        if cmd != JMP:
            memo["phase"] = "wait"
            return
        _table_step(m, s, memo, _field(m, rows[step], "position"))
    memo["phase"] = "stopped"
    op_error(m, s, "the table's JMP rows loop without a move or END")


def _table_parts(m: Machine, memo: dict, axis: int) -> list[tuple[int, int]]:
    """(row, signed travel) of the move that starts at the present step: one row for the
    single commands; for the continuous ones the following continuous rows too, while they
    run the same way (DECISION: a continuous row that turns back ends the run there; the
    page: the run "stops first, then goes on with the next step" when it must break off)."""
    rows, step = memo["rows"], memo["step"]
    at, parts, way = _pair(m, axis, "position"), [], 0
    while step < len(rows):
        cmd = _field(m, rows[step], "command")
        if cmd not in MOVES or (parts and (cmd in (SINGLE_REL, SINGLE_ABS)
                                           or _field(m, rows[parts[0][0]], "command") < CHAIN_REL)):
            break
        pos = _field(m, rows[step], "position")
        travel = pos - at if cmd in (SINGLE_ABS, CHAIN_ABS) else pos
        if parts and travel * way < 0:
            break
        way = way or (1 if travel > 0 else -1 if travel < 0 else 0)
        parts.append((step, travel))
        at += travel
        step += 1
    return parts


def _table_speed(m: Machine, memo: dict, axis: int) -> float:
    row = memo["rows"][memo["parts"][memo["part"]][0]]
    return _speed(m, axis, _field(m, row, "speed"), memo["p"])


def _table_move(m: Machine, s, memo: dict, axis: int) -> None:
    """A start signal M9347 OFF -> ON with no m code pending: the move of the present step."""
    parts = _table_parts(m, memo, axis)
    way = next((1 if d > 0 else -1 for _, d in parts if d), 1)
    p = _params(m, axis)
    for offset in (DONE, ABNORMAL):
        _set(m, axis, offset, False)
    memo.update(t0=m.now_us, dir=way, pos0=_pair(m, axis, "position"), p=p, ended=False,
                stopping=False, moved=0, parts=parts, part=0, phase="move",
                bounds=[sum(abs(d) for _, d in parts[:k + 1]) for k in range(len(parts))])
    _direction_pin(m, s, way)
    _table_part(m, s, memo, axis, 0.0, 0.0, 0.0)


def _table_part(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    """Plan the present part from (t, x, v): the last part ends on the total travel, the
    others run on at their speed to their boundary; a WITH m code shows at the part's start."""
    row = memo["parts"][memo["part"]][0]
    _table_step(m, s, memo, row)
    code = _field(m, memo["rows"][row], "mcode")
    if code >= WITH_MCODE:
        _mcode(m, axis, code)
    p, memo["cruise"] = memo["p"], _table_speed(m, memo, axis)
    if memo["part"] == len(memo["parts"]) - 1:
        memo["prof"] = motion.move_to(t, x, v, memo["bounds"][-1], memo["cruise"], p["bias"],
                                      p["up"], p["down"])
    else:
        memo["prof"] = motion.run_on(t, x, v, memo["cruise"], p["bias"], p["up"], p["down"])


def _table_replan(m: Machine, s, memo: dict, axis: int, t: float, x: float, v: float) -> None:
    """Parts whose boundary was passed since the last execution hand over at that instant;
    then the speed data and the override may change the present part's speed."""
    while memo["part"] < len(memo["parts"]) - 1 and x >= memo["bounds"][memo["part"]] - motion.EPS:
        at = motion.time_at(memo["prof"], memo["bounds"][memo["part"]])
        _, speed = motion.at(memo["prof"], at)
        memo["part"] += 1
        _table_part(m, s, memo, axis, at, memo["bounds"][memo["part"] - 1], speed)
        x, v = motion.at(memo["prof"], t)
    _cruise_to(memo, _table_speed(m, memo, axis), t, x, v)


def _table_moved(m: Machine, s, memo: dict, axis: int) -> None:
    """A move has ended: done (M9342 On): an AFTER m code, then the next step; a stop relay
    (M9343 On): the table stays stopped until the condition goes Off (8-3: restart)."""
    if not _relay(m, axis, DONE):
        memo["phase"] = "stopped"
        return
    row = memo["parts"][-1][0]
    code = _field(m, memo["rows"][row], "mcode")
    if 0 <= code < WITH_MCODE:
        _mcode(m, axis, code)
    _table_step(m, s, memo, row + 1)
    _table_flow(m, s, memo)


def _table_begin(m: Machine, s, memo: dict, axis: int) -> bool:
    q = s.ins.operands[0].number + s.ops[0].index_value(m)
    rows = mbus.tables(m, "DTBL").get(q)
    if not rows:
        op_error(m, s, f"table Q{q} has no DTBL rows (.table Q{q} DTBL ...)")
        return False
    if not _claim(m, s, axis):
        return False
    _mcode(m, axis, NO_MCODE)  # the page: DTBL's start sets the m code to -1
    memo.update(rows=rows, ended=True, start_level=_relay(m, axis, _cfg(m)["table_start"]),
                off_level=_relay(m, axis, _cfg(m)["mcode_off"]), m9029=False)
    kind, n = s.ins.operands[1].kind, s.ops[1].addr(m)
    _table_step(m, s, memo, s16(m.words[kind][n + 1]))  # S2+1: the start step
    _table_flow(m, s, memo)
    return True


def _table_signals(m: Machine, s, memo: dict, axis: int) -> None:
    """M9349 OFF -> ON clears the m code; M9347 OFF -> ON turns M9342 Off and starts the step
    waiting for it, unless an m code is pending (DECISION: that edge is then ignored)."""
    off = _relay(m, axis, _cfg(m)["mcode_off"])
    if off and not memo["off_level"]:
        _mcode(m, axis, NO_MCODE)
    start = _relay(m, axis, _cfg(m)["table_start"])
    rise = start and not memo["start_level"]
    memo["off_level"], memo["start_level"] = off, start
    if not rise:
        return
    _set(m, axis, DONE, False)
    pending = s16(m.words["D"][_register(m, axis, "mcode")]) != NO_MCODE
    if memo["phase"] == "wait" and not pending and m.acc:
        _table_move(m, s, memo, axis)


def dtbl(m: Machine, s) -> None:
    """DTBL S1 S2 D1 D2 (FNC 312): runs positioning table S1 (`.table Qn DTBL position speed
    mcode command` rows, docs/vs.md) on axis D1 from step S2+1; S2 shows the step. Each move
    starts on M9347 OFF -> ON; m codes in D9349/M9348, cleared by M9349; M9029 at END."""
    y = s.ops[-2]
    axis = y.addr(m)
    memo = state(m, s, {})
    if memo.get("m9029"):  # On for one scan: the next execution turns it Off
        memo["m9029"] = False
        set_relay(m, "done", False)
    if not memo:
        if not m.acc:
            return
        started: dict = {}  # kept only once the table has started (as moves._drive)
        if not _table_begin(m, s, started, axis):
            memo["refused"] = True  # not executed until the condition goes Off and On again
            return
        memo.update(started)
    if memo.get("refused"):
        if not m.acc:
            memo.clear()
        return
    _table_signals(m, s, memo, axis)
    if memo["phase"] == "move":
        _advance(m, s, memo, axis, lambda t, x, v: _table_replan(m, s, memo, axis, t, x, v))
        if memo["ended"]:
            if m.acc:
                _table_moved(m, s, memo, axis)
            else:
                memo["phase"] = "stopped"
    if not m.acc and memo["phase"] != "move":
        _release(m, s, axis, y)
        memo.clear()


POS_TABLE_ACTIONS = {"tbl": dtbl}
