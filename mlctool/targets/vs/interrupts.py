"""Interrupts (VS 2-12, 2-15-1, 6-2 FNC 03-05 IRET/EI/DI) on virtual time.

Model (docs/vs.md "Interrupts"): a scan is instantaneous at its start time, so every request
that falls between two scans, (previous scan, this scan], is served before this scan, in time
order, interleaved with the stimulus lines of that interval:

- an input pointer (IX0P rising, IX0F falling) is requested by an edge of its input: a
  stimulus line that changes the input (at the line's time) or an edge of a pulse train on it;
- a timer pointer ITAnn/ITBnn/ITCnn every nn ms of virtual time from RUN (time 0);
- IHC0-IHC7 by a DHSCS compare met, IHHC1/IHHC2 by a hardware counter reaching its set
  value, at the time of that count (targets/vs/hsc.py, targets/vs/hhsc.py leave them in m.hsc["irq"]);
- the routine runs from its pointer to IRET at the request's time, with a fresh rung state;
  the interrupted scan state is kept (a routine served by EI runs inside the scan).

A request is dropped while its disable relay (M9050-M9063) is On; it is remembered while DI is
in force (DI executed, no EI since) and served when EI executes, in request order, once per
pointer. Routines do not nest. The fixed first line `LD M9163 / MOV Kxx D9163` delays the
routine xx ms (2-15-1).

Inputs and outputs in a routine (6-7 FNC 50 REF, 2-12: "中斷子程序中經常需要立即讀取外部狀態或
立即驅動外部負載。此時，應于中斷子程序中使用 I/O更新指令REF"): the X image is what the last scan
read (REF page: inputs are read before STEP0), so a routine sees a stimulus line that changed
an input since that scan only after `REF X0/X10 n`, which reads the level the stimulus gives
at the request's time (pulse trains included) into the image; `REF Y0 n` puts Y out at that
time (recorded in `outputs` for the trace and VCD). The pointer's own edge and the requests
are judged on those stimulus levels, as before.
"""

from __future__ import annotations

import heapq
import math
from fractions import Fraction

from mlctool.check.interrupts import Pointer, disable_relay, pointer_numbered
from mlctool.sim.hardware.pulses import edges
from mlctool.sim.scan import END_SCAN, Fault
from mlctool.sim.state import Machine, SimFault
from mlctool.targets.vs.hsc import catch_up

# hardware that requests interrupts (IHC, IHHC) counts up to now before the interrupt queue of
# the interval is built; counting again at the scan's start adds nothing
INTERRUPT_SOURCES = (catch_up,)

IRET_DONE = -2  # returned by IRET: the routine ends (the scan loop never sees it)
EDGE_LIMIT = 100_000  # pulse-train edges requesting routines in one scan interval


class Interrupts:
    """The interrupt routines of one program and their run-time state (on Machine.interrupts)."""

    def __init__(self, prog, target):
        self.prog = prog
        self.routines: dict[int, tuple[Pointer, int]] = {}  # I number -> (pointer, its step index)
        for s in prog.steps:
            if s.ins.spec.cls == "interrupt":
                p = pointer_numbered(s.ins.operands[0].number, target)
                if p is not None:
                    self.routines[p.number] = (p, s.index)
        self.inputs = [p for p, _ in self.routines.values() if p.source == "input"]
        self.timers = [p for p, _ in self.routines.values() if p.source == "timer"]
        self.delay = (target.settings.get("interrupts") or {}).get("delay")
        self.watchdog = 1_000_000
        self.reset()

    def reset(self) -> None:
        """Power-on: interrupts enabled, nothing pending."""
        self.di = False  # DI executed and no EI since
        self.active = False  # a routine is running
        self.pending: list[int] = []  # requests held by DI, served by EI
        self.delayed: list[tuple[Fraction, int]] = []  # (time, I number): delayed past the last scan
        self.seq = 0
        self.held: dict[int, int] = {}  # X number -> image level, for inputs the stimulus has moved
        self.phys: dict[int, int] = {}  # while a routine runs: X number -> stimulus level of `held`
        self.exact: Fraction | None = None  # request time of the routine running between scans
        self.outputs: list[tuple[int, int, int]] = []  # (us, Y number, level) put out by REF Y
        self.sim = None

    # -- between scans
    def before_scan(self, sim, k: int, events) -> None:
        """Stimulus lines of scan k and the requests of (previous scan, this scan], in time order."""
        m: Machine = sim.m
        now = m.now_us
        self.sim, self.held = sim, {}  # the image is the last scan's: nothing moved yet
        after = (k - 1) * sim.period if k > 0 else -1
        # (time, order, sequence, what, item): at one instant stimulus lines first, in file
        # order, then requests; the sequence keeps the heap from comparing items
        queue: list[tuple] = []
        for e in events:  # trains first: their edges in this interval are requests too
            if e.kind == "pulses":
                sim.apply(e)
        for n, e in enumerate(events):
            if e.kind not in ("expect", "alarm", "pulses"):
                queue.append((Fraction(e.time_us if e.time_us is not None else now), 0, n, "event", e))
        for p in self.timers:
            period = p.unit * 1000
            for j in range(max(1, after // period + 1), now // period + 1):
                queue.append((Fraction(j * period), 1, self._next(), "request", p.number))
        queue += [(t, 1, self._next(), "request", n) for t, n in self._train_edges(m, after, now)]
        # high-speed counter requests (IHC from DHSCS, IHHC at the set value: targets/vs/hsc.py, hhsc.py),
        # counted before the scan; a pointer without a routine requests nothing (DECISION)
        for count_up in INTERRUPT_SOURCES:
            count_up(m)
        queue += [(Fraction(t), 1, self._next(), "request", n) for t, n in m.hsc.pop("irq", ())
                  if n in self.routines]
        queue += [(t, 1, self._next(), "due", n) for t, n in self.delayed]
        self.delayed = []
        heapq.heapify(queue)
        while queue:
            t, _, _, what, item = heapq.heappop(queue)
            if t > now:  # a delayed request due after this scan
                self.delayed.append((t, item))
                continue
            m.now_us, self.exact = math.floor(t), t  # routines run at the request's time
            if what == "event":
                xs = m.bits["X"]
                before = xs[:]
                sim.apply(item)
                sim.apply_forces()
                if item.kind != "power":  # the image keeps what the last scan read
                    for n in range(len(xs)):
                        if xs[n] != before[n]:
                            self.held.setdefault(n, before[n])
                for p in self.inputs:
                    level = xs[p.unit]
                    if level != before[p.unit] and level == p.family["edge_level"][p.suffix]:
                        self._request(m, p.number, t, queue)
            elif what == "due":
                self._serve(m, item)
            else:
                self._request(m, item, t, queue)
        m.now_us = now
        self.held, self.exact = {}, None  # the scan reads every input now

    def _next(self) -> int:
        self.seq += 1
        return self.seq

    def _train_edges(self, m: Machine, after: int, upto: int) -> list[tuple[Fraction, int]]:
        """Pulse-train edges on interrupt inputs in (after, upto]: rising for P, falling for F."""
        out = []
        for p in self.inputs:
            level = p.family["edge_level"][p.suffix]
            dev = p.family.get("device", "X")
            for tr in m.pulse_trains.get((dev, p.unit), ()):
                half = tr.period_us / 2 if tr.period_us else 0
                shift = 0 if level else half  # a fall follows its rise by half a period
                for _tr, first, count in edges(m, dev, p.unit, after - shift, upto - shift):
                    if _tr is not tr:
                        continue
                    if len(out) + count > EDGE_LIMIT:
                        raise SimFault(f"more than {EDGE_LIMIT} pulse edges request interrupt {p.name} "
                                       "in one scan interval; lower the train's frequency")
                    for j in range(first, first + count):
                        t = tr.edge_time(j) + shift
                        if tr.end_us is not None and t > tr.end_us:
                            t = Fraction(tr.end_us)
                        if after < t <= upto:
                            out.append((t, p.number))
        return out

    def _request(self, m: Machine, number: int, t: Fraction, queue: list) -> None:
        p, step = self.routines[number]
        if m.bits["M"][disable_relay(p)]:
            return  # disabled by its special relay: the request is dropped (DECISION)
        delay = self._delay_ms(m, step)
        if delay:
            heapq.heappush(queue, (t + delay * 1000, 1, self._next(), "due", number))
            return
        self._serve(m, number)

    def _serve(self, m: Machine, number: int) -> None:
        if self.di or self.active:
            if number not in self.pending:
                self.pending.append(number)
            return
        self.run_routine(m, number)
        self.serve_pending(m)

    def serve_pending(self, m: Machine) -> None:
        while self.pending and not self.di and not self.active:
            self.run_routine(m, self.pending.pop(0))

    def _delay_ms(self, m: Machine, step: int) -> int:
        """The fixed form `LD M9163 / MOV Kxx D9163` right after the pointer: xx ms (2-15-1)."""
        if not self.delay:
            return 0
        steps = self.prog.steps
        if step + 2 >= len(steps):
            return 0
        ld, mov = steps[step + 1].ins, steps[step + 2].ins
        if (ld.spec.cls == "load" and ld.spec.api is None and ld.operands and ld.operands[0].kind == "M"
                and ld.operands[0].number == self.delay["relay"] and mov.spec.op == "mov"
                and mov.operands[1].kind == "D" and mov.operands[1].number == self.delay["register"]):
            return max(0, steps[step + 2].ops[0].get(m))
        return 0

    # -- one routine
    def run_routine(self, m: Machine, number: int) -> None:
        """Run the routine from its pointer to IRET; the interrupted state is put back."""
        _, start = self.routines[number]
        saved = (m.acc, m.blocks[:], m.stack[:], m.calls, m.fors, m.pc, m.bus, m.stl_steps, m.stl_joining,
                 m.mc_stack[:])
        m.acc, m.calls, m.fors, m.bus, m.stl_steps, m.stl_joining = False, [], [], True, (), False
        m.blocks.clear()
        m.stack.clear()
        m.mc_stack.clear()
        self.active = True
        xs = m.bits["X"]
        self.phys = {n: xs[n] for n in self.held}  # the routine sees the image
        for n, level in self.held.items():
            xs[n] = level
        relays = m.target.settings.get("system_relays") or {}
        for n in relays.get("always_on", ()):  # M9000 also in a routine before the first scan
            m.bits["M"][n] = 1
        steps = self.prog.steps
        pc, executed, s = start + 1, 0, None
        try:
            while True:
                if pc >= len(steps):
                    raise SimFault("interrupt routine ran past the last instruction without IRET")
                s = steps[pc]
                m.pc = pc
                executed += s.steps
                if executed > self.watchdog:
                    raise SimFault(f"interrupt watchdog: more than {self.watchdog} steps in one routine")
                r = s.run(m, s)
                if r is None:
                    pc += 1
                elif r == IRET_DONE:
                    break
                elif r == END_SCAN:
                    raise SimFault(f"interrupt routine reached {s.ins.mnemonic} without IRET")
                else:
                    pc = r
        except SimFault as e:
            raise Fault(e.message, s) from None
        finally:
            self.active = False
            for n in self.held:  # back to the stimulus levels; REF took its inputs out of held
                self.held[n], xs[n] = xs[n], self.phys[n]
            self.phys = {}
            (m.acc, m.blocks[:], m.stack[:], m.calls, m.fors, m.pc, m.bus, m.stl_steps, m.stl_joining,
             m.mc_stack[:]) = saved


    # -- REF (6-7 FNC 50) inside a routine
    def refresh_inputs(self, m: Machine, first: int, n: int) -> None:
        """X first .. first+n-1 take the level the stimulus gives at the request's time: a
        pulse train's level then, else the latest stimulus line's (forces win, as at a scan).
        DECISION: the page's ~10 ms input delay is not modelled (as REFF: levels are exact)."""
        if not self.active:
            return
        t = self.exact if self.exact is not None else Fraction(m.now_us)
        xs = m.bits["X"]
        for i in range(first, min(first + n, len(xs))):
            self.held.pop(i, None)
            level = self.phys.pop(i, xs[i])
            live = [tr for tr in m.pulse_trains.get(("X", i), ()) if tr.start_us <= t]
            if live:
                level = live[-1].level(t)
            xs[i] = level
        if self.sim is not None:
            self.sim.apply_forces()

    def refresh_outputs(self, m: Machine, first: int, n: int) -> None:
        """Y first .. first+n-1 go out at the request's time (a routine run between scans);
        the run's trace shows them then. DECISION: the page's ~10 ms relay delay is not
        modelled; a routine served by EI inside a scan puts them out at the scan's time, which
        the scan's own trace entry shows."""
        if not self.active or self.exact is None:
            return
        ys = m.bits["Y"]
        off = m.outputs_disabled()  # M9034 On: the terminals stay Off (target.toml outputs_off)
        for i in range(first, min(first + n, len(ys))):
            self.outputs.append((m.now_us, i, 0 if off else ys[i]))


# -- the instructions
def _ctl(m: Machine) -> Interrupts | None:
    return m.interrupts


def iret(m: Machine, s):
    ctl = _ctl(m)
    if ctl is None or not ctl.active:
        raise SimFault("IRET executed outside an interrupt routine")
    if m.calls:
        raise SimFault("IRET executed inside a subroutine, before SRET")
    return IRET_DONE


def ei(m: Machine, s) -> None:
    """Interrupts allowed again; requests remembered since DI are served now (6-2 FNC 04)."""
    ctl = _ctl(m)
    if ctl is not None:
        ctl.di = False
        ctl.serve_pending(m)


def di(m: Machine, s) -> None:
    """Requests from here on are remembered until EI (6-2 FNC 05)."""
    ctl = _ctl(m)
    if ctl is not None:
        ctl.di = True


def pointer(m: Machine, s) -> None:
    """The pointer line itself: nothing (reached only as the start of its routine)."""


INTERRUPT_ACTIONS = {"iret": iret, "ei": ei, "di": di, "interrupt": pointer}
