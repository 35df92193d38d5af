"""LIR, LIA (8-3 FNC 315, 316): straight lines of two axes, on the axis moves of targets/vs/positioning/moves.py."""

from __future__ import annotations

import math
from types import SimpleNamespace

from mlctool.sim import semantics as base
from mlctool.sim.hardware import motion
from mlctool.sim.state import Machine
from mlctool.targets.vs.common import op_error, read_block, state, write_block
from mlctool.targets.vs.positioning.moves import _advance, _at_limit, _now, _pair, _start
from mlctool.targets.vs.pulse_out import DECEL_STOP, STOP, _max_hz, _owners, _relay, _release

# ------------------------------------------------------------ LIR, LIA (FNC 315, 316)

class _Pin:
    """An output pin of a two-axis instruction, in the shape _advance and _finish drive."""

    def __init__(self, kind: str, number: int):
        self.kind, self.number = kind, number

    def addr(self, m: Machine) -> int:
        return self.number

    def setbit(self, m: Machine, v: int) -> None:
        m.bits[self.kind][self.number] = 1 if v else 0


def _lin_axes(s, d: int) -> list:
    """D = 0: Y0/Y1 with the direction pins Y4/Y5; D = 1: Y2/Y3 with Y6/Y7 (the page's
    table), each as a stand-in step for the one-axis helpers (same owner index)."""
    first = 2 * d
    return [SimpleNamespace(ops=[_Pin("Y", first + k), _Pin("Y", first + k + 4)], index=s.index,
                            ins=s.ins, axis=first + k) for k in (0, 1)]


def _lin_begin(m: Machine, s, memos: list, absolute: bool) -> bool:
    """The vector speeds split by each axis's share of the path (written to S+5 ... S+8);
    both axes ramp in the same time, so they arrive together. The page: the axis parameters
    and the override do not apply; both travels 0: not executed."""
    d = base.count_in(m, s, 1)  # an index-modified D may name no pair of axes: an operation error
    if d is None:
        return False
    width = s.ops[0].width
    block = read_block(m, s.ops[0], 9, width)
    axes = _lin_axes(s, d)
    travel = [block[3 + k] - (_pair(m, a.axis, "position") if absolute else 0)
              for k, a in enumerate(axes)]
    bias = min(max(block[0], 0), 20_000)
    run = min(max(block[1], 10), _max_hz(m))
    if bias > run:
        op_error(m, s, f"the bias vector speed {bias} passes the run vector speed {run}")
        return False
    if not any(travel) or any(_owners(m).get(a.axis, s.index) != s.index for a in axes):
        return False
    ms = min(max(block[2], 0), 32_000)
    length = math.hypot(*travel)
    for k, (a, memo) in enumerate(zip(axes, memos, strict=True)):
        share = abs(travel[k]) / length
        b, r = bias * share, run * share
        block[5 + 2 * k], block[6 + 2 * k] = int(b), int(r)
        _start(m, a, memo, a.axis, 1 if travel[k] >= 0 else -1)
        rate = (r - b) * 1000 / ms if ms and r > b else math.inf
        memo.update(p={"max": r, "bias": b, "up": rate, "down": rate}, shim=a, cruise=r)
        # the page: an axis below 1 Hz puts out no pulses (DECISION: it stays; done with the other)
        memo["prof"] = motion.move_to(0.0, 0.0, 0.0, abs(travel[k]) if r >= 1 else 0, r, b, rate, rate)
    write_block(m, s.ops[0], block, width)
    return True


def _lin_stops(m: Machine, memos: list) -> None:
    """A stop relay of either axis stops both (M9346 at once, M9345 ramped), abnormal end; so
    does (ramped) a travel limit ahead of either (8-1-2 LSF/LSR)."""
    limit = any(not memo["ended"] and _at_limit(m, memo, memo["shim"].axis) for memo in memos)
    for relay, ramped in ((STOP, False), (DECEL_STOP, True)):
        if not any(_relay(m, memo["shim"].axis, relay) for memo in memos) and not (ramped and limit):
            continue
        for memo in memos:
            if memo["ended"]:
                continue
            t = _now(m, memo)
            if memo["stopping"] and (ramped or motion.ended(memo["prof"], t)):
                continue  # M9346 also cuts a ramp under way (as _advance), M9343 as it was
            x, v = motion.at(memo["prof"], t)
            memo["prof"] = (motion.stop(t, x, v, memo["p"]["bias"], memo["p"]["down"]) if ramped
                            else motion.halt(t, x))
            if not memo["stopping"]:
                memo["stopping"], memo["abnormal"] = True, True


def _linear(m: Machine, s, absolute: bool) -> None:
    memos = state(m, s, [])
    if not memos:
        if not m.acc:
            return
        started: list[dict] = [{}, {}]  # kept only once the move has started (as moves._drive)
        if not _lin_begin(m, s, started, absolute):
            memos[:] = [{"refused": True}]
            return
        memos.extend(started)
    if memos[0].get("refused"):
        if not m.acc:
            memos.clear()
        return
    _lin_stops(m, memos)
    for memo in memos:
        if not memo["ended"]:
            _advance(m, memo["shim"], memo, memo["shim"].axis)
    if not m.acc and all(memo["ended"] for memo in memos):
        for memo in memos:
            _release(m, memo["shim"], memo["shim"].axis, memo["shim"].ops[0])
        memos.clear()


def lir(m: Machine, s) -> None:
    """LIR S D (FNC 315): two axes (D = 0: Y0/Y1, 1: Y2/Y3) move S+3 / S+4 pulses on a straight
    line: bias and run vector speeds S, S+1, ramp time S+2 ms (the 32-bit form: pairs)."""
    _linear(m, s, False)


def lia(m: Machine, s) -> None:
    """LIA S D (FNC 316): as LIR to the absolute position (S+3, S+4)."""
    _linear(m, s, True)


POS_LINES_ACTIONS = {"lir": lir, "lia": lia}
