"""The scan: address 0 to END (2.2 END), program flow (4.1), end-of-scan bookkeeping.

A scan is a pure function of the machine state and its start time: nothing here reads a
clock. Fatal faults carry the step index so the caller can name the address and source line.
"""

from __future__ import annotations

from collections.abc import Callable

from mlctool.program import Image
from mlctool.sim.decode import Program, Step, decode
from mlctool.sim.semantics import advance_timer, alarm
from mlctool.sim.state import Machine, SimFault
from mlctool.targetapi.registry import simulation_of

END_SCAN = -1
CALL_ALARM = "CALL_NESTING"  # 4.1 API-01: a 6th level "該副程式不執行"
# a 6th FOR level: a fault, or on a target that names a code for it (VS 6-2 FOR, error 6704)
# an operation error: that FOR is not executed, its body runs once
FOR_ALARM = "FOR_NESTING"
DEFAULT_WATCHDOG = 1_000_000  # steps per scan


class Fault(Exception):
    """A fatal fault at a step: stops the run (E604)."""

    def __init__(self, message: str, step: Step | None):
        super().__init__(message)
        self.message = message
        self.step = step


def _jump_to(m: Machine, prog: Program, s: Step, target: int) -> int:
    # leaving FOR loops by CJ is allowed (4.1 API-08 item 3): drop loops the target is outside of
    while m.fors and not (m.fors[-1][0] < target <= m.fors[-1][1]):
        m.fors.pop()
    return target


def _label(m: Machine, prog: Program, s: Step) -> int:
    if s.target >= 0:
        return s.target
    p = s.ins.operands[0].number + s.ops[0].index_value(m)  # P may be V/Z-modified (API-00/01)
    if p not in prog.labels:
        raise SimFault(f"{s.ins.mnemonic} {s.ins.texts[0]}: P{p} is not defined")
    return prog.labels[p]


def flow_routines(prog_ref: list[Program]) -> dict:
    """Program-flow routines; they return the next step index, END_SCAN, or None."""

    def cj(m: Machine, s: Step):
        if m.acc:
            return _jump_to(m, prog_ref[0], s, _label(m, prog_ref[0], s))
        return None

    def call(m: Machine, s: Step):
        if not m.acc:
            return None
        limit = prog_ref[0].target.settings["call_depth"]
        if len(m.calls) >= limit:
            alarm(m, CALL_ALARM, f"CALL {s.ins.texts[0]}: level {len(m.calls) + 1} exceeds "
                  f"{limit}; subroutine not executed")
            return None
        m.calls.append(s.index + 1)
        return _label(m, prog_ref[0], s)

    def sret(m: Machine, s: Step):
        if not m.calls:
            raise SimFault("SRET executed without a CALL")
        return m.calls.pop()

    def fend(m: Machine, s: Step):
        if m.calls:
            raise SimFault(f"{s.ins.mnemonic} executed inside a subroutine, before SRET (4.1 API-06)")
        if m.fors:
            raise SimFault(f"{s.ins.mnemonic} executed inside FOR-NEXT (4.1 API-06)")
        return END_SCAN

    def for_(m: Machine, s: Step):
        n = max(1, s.ops[0].get(m))  # N <= K1 is taken as K1 (4.1 API-08)
        limit = prog_ref[0].target.settings["for_depth"]
        if len(m.fors) >= limit:
            if FOR_ALARM in (m.target.settings.get("operation_error") or {}).get("codes", {}):
                alarm(m, FOR_ALARM, f"FOR {s.ins.texts[0]}: level {len(m.fors) + 1} exceeds {limit}; "
                      "not executed, the body runs once")
                return None
            raise SimFault(f"FOR nested deeper than {limit} levels (4.1 API-08)")
        m.fors.append([s.index, s.target, n])
        return None

    def next_(m: Machine, s: Step):
        if m.fors and m.fors[-1][1] == s.index:
            loop = m.fors[-1]
            loop[2] -= 1
            if loop[2] > 0:
                return loop[0] + 1
            m.fors.pop()
        return None  # a NEXT reached without its FOR running (CJ into the body) passes

    return {"cj": cj, "call": call, "sret": sret, "fend": fend, "end": fend,
            "for": for_, "next": next_}




def load_program(image: Image, target, probe=None) -> Program:
    ref: list[Program] = []
    prog = decode(image, target, flow_routines(ref), probe)
    ref.append(prog)
    return prog


def begin_scan(m: Machine) -> None:
    """A scan's prelude: the per-scan evaluation state cleared, the system relays set (also
    what the debugger does before it steps into a scan)."""
    m.t_seen[:] = bytes(len(m.t_seen))  # in place: only power_cycle replaces containers
    m.acc = False
    m.blocks.clear()
    m.stack.clear()
    m.calls = []
    m.fors = []
    system_relays(m)


def run_scan(prog: Program, m: Machine, watchdog: int = DEFAULT_WATCHDOG) -> None:
    """Execute one scan starting at virtual time m.now_us. Raises Fault on fatal faults."""
    begin_scan(m)
    run_steps(prog, m, 0, 0, watchdog)
    end_of_scan(m)


def system_relays(m: Machine) -> None:
    """Special relays the system drives before each scan, and the target's scan hooks (see
    before_scan_routine)."""
    routine = before_scan_routine(m.target)
    if routine is not None:
        routine(m)


_BEFORE_SCAN: dict[int, tuple] = {}  # id(target) -> (target, its routine or None)


def before_scan_routine(target) -> Callable[[Machine], None] | None:
    """What the system does before each scan on this target, worked out once (None: nothing):
    the target's scan hooks whose settings it has (its Simulation.scan_hooks: VS's virtual
    calendar registers, high-speed counters), then the special relays of target.toml [system_relays]: always
    On/Off, On/Off in the first scan only, clocks with a period in ms (half On)."""
    known = _BEFORE_SCAN.get(id(target))
    if known is not None and known[0] is target:
        return known[1]
    hooks = tuple(hook for hook, needs in simulation_of(target).scan_hooks if any(k in target.settings for k in needs))
    table = target.settings.get("system_relays") or {}
    on, off = tuple(table.get("always_on", ())), tuple(table.get("always_off", ()))
    first_on, first_off = tuple(table.get("first_scan_on", ())), tuple(table.get("first_scan_off", ()))
    clocks = tuple((int(n), int(ms) * 1000) for n, ms in table.get("clocks", {}).items())

    def routine(m: Machine) -> None:
        for hook in hooks:
            hook(m)
        bits = m.bits["M"]
        first = m.scans_done == 0
        for n in on:
            bits[n] = 1
        for n in off:
            bits[n] = 0
        for n in first_on:
            bits[n] = 1 if first else 0
        for n in first_off:
            bits[n] = 0 if first else 1
        for n, period in clocks:
            bits[n] = 1 if m.now_us % period < period // 2 else 0
    known = _BEFORE_SCAN[id(target)] = (target, routine if hooks or table else None)
    return known[1]


def run_steps(prog: Program, m: Machine, pc: int, executed: int, watchdog: int) -> None:
    """Execute steps from `pc` to END with `executed` steps already counted in this scan.
    Raises Fault (with the step) on fatal faults and on the step watchdog."""
    steps = prog.steps
    n = len(steps)
    s = None
    try:
        while pc < n:
            s = steps[pc]
            m.pc = pc
            executed += s.steps
            if executed > watchdog:
                raise SimFault(f"scan watchdog: more than {watchdog} steps executed in one scan "
                               "(runaway loop?)")
            r = s.run(m, s)
            if r is None:
                pc += 1
            elif r == END_SCAN:
                break
            else:
                pc = r
        else:
            raise SimFault("execution ran past the last instruction without END")
    except SimFault as e:
        raise Fault(e.message, s) from None


def _running_unseen(running: bytearray, seen: bytearray) -> list[int]:
    """The timers running whose TMR did not run this scan, in order: the bytes (0/1) as
    little-endian ints, byte n of running AND NOT seen (not a Python loop over every timer:
    a program with running timers would pay for all of them each scan)."""
    x = int.from_bytes(running, "little") & ~int.from_bytes(seen, "little")
    out = []
    while x:
        low = x & -x
        out.append((low.bit_length() - 1) >> 3)
        x ^= low
    return out


def end_of_scan(m: Machine) -> None:
    # counter contacts act at the end of the scan (1.7 table)
    if m.c_pending:
        for n in sorted(m.c_pending):
            m.bits["C"][n] = 1
        m.c_pending.clear()
    # running timers whose TMR was not executed (CJ-skipped, subroutine not called): by the
    # target's `skipped` rule of their base; default (NC5) they keep timing and turn On at
    # the preset (4.1 API-00 item 3, example 2). VS (6-2 CJ): 10/100 ms timers pause, 1 ms
    # timers keep timing with their contact frozen until their OUT runs again.
    target = m.target
    for n in _running_unseen(m.t_running, m.t_seen) if 1 in m.t_running else ():  # memchr first
        rule = target.timer_base(n).get("skipped", "run")
        if rule == "pause":
            m.t_running[n] = 0  # its next OUT restarts timing from the value it holds
        elif rule == "run_frozen":
            contact = m.bits["T"][n]
            advance_timer(m, n, m.t_preset[n])
            m.bits["T"][n] = contact
        else:
            advance_timer(m, n, m.t_preset[n])
    # step ladder: steps that transferred go Off now (4-1-3); the rail is whole again
    if m.stl_leaving:
        for n in m.stl_leaving:
            m.bits["S"][n] = 0
        m.stl_leaving.clear()
    m.scans_done += 1
    m.stl_steps = ()
    m.stl_joining = False
    m.bus = True
    m.mc_stack.clear()
