"""The debugger's core: a Simulation stopped, stepped, run to conditions and run backwards.

Positions. The machine is either at a scan boundary `(k, -1)` (k scans done, scan k not
begun: its stimulus lines not applied yet) or inside scan k at `(k, n)`: the scan's inputs
applied and n instructions executed (`n = 0`: about to execute the first). Positions are
ordered as tuples. `step` executes one instruction (from a boundary it begins the scan first);
the instruction that ends the scan (END/FEND) takes the machine to the next boundary.

Time travel. Everything here is a function of the program, the stimulus and the user's own
actions (force, release, write), which are logged with the position they were taken at. A
checkpoint (a deep copy of the machine, the forces and the device models) is kept at every
`checkpoint_every` scan boundary; going back restores the nearest checkpoint at or before the
wanted position and replays forward. At most `max_checkpoints` are kept: past that, every
other one is dropped and the interval doubles, so memory stays bounded by max_checkpoints
machine copies plus the action log, however long the run (docs/debug.md).

Speed. Whole scans run on the simulator's engine (compiled by default); a scan is executed
instruction by instruction with the reference interpreter (scan.py's steps, one at a time)
only when something needs it: stepping, a source-line breakpoint, or a logged action inside
the scan. Scan-level conditions (`break if`, `watch`) are checked at scan ends.
"""

from __future__ import annotations

import copy
import math
import os
import re
import time
from array import array
from collections.abc import Callable
from dataclasses import dataclass, field

from mlctool.debug.expr import Expr, ExprError, resolve_device
from mlctool.devices.base import ModelIO
from mlctool.limits import clip, is_decimal
from mlctool.program import Image
from mlctool.sim.run.run import Simulation, plan_scans
from mlctool.sim.scan import DEFAULT_WATCHDOG, END_SCAN, Fault, begin_scan, end_of_scan
from mlctool.sim.state import DeviceView, Machine, SimFault
from mlctool.sim.stimulus.quantities import MAX_SCANS
from mlctool.sim.stimulus.stimulus import StimError, Stimulus, parse_value

BOUNDARY = -1
POLL_STEPS = 4096  # instructions executed one by one between two looks at the poll hook
Position = tuple[int, int]  # (scan, instructions executed in it; -1: at the scan's start)


class DebugError(ValueError):
    """A request the session cannot do: the message is for the user."""


class Interrupted(Exception):
    """Raised by a `poll` hook to end a long move where it is (a Pause, a Ctrl-C)."""


@dataclass
class Breakpoint:
    id: int
    kind: str  # "line" (before an instruction), "cond" (scan end), "watch" (value changed)
    where: str  # as the user wrote it
    steps: frozenset[int] = frozenset()  # line: the step indexes it stops before
    condition: Expr | None = None
    hit_condition: str = ""  # "5" or "==5": the 5th hit; ">=5", ">5"; "%5": every 5th
    log: str = ""  # a logpoint's message ("D0={D0}"): printed, never stops
    view: DeviceView | None = None  # watch: the device
    hits: int = 0
    enabled: bool = True
    last: object = None  # watch: the value last seen

    def describe(self) -> str:
        text = {"line": f"break {self.where}", "cond": f"break if {self.where}",
                "watch": f"watch {self.where}"}[self.kind]
        if self.kind == "line" and self.condition is not None:
            text += f" if {self.condition.text}"
        if self.hit_condition:
            text += f" hits {self.hit_condition}"
        if self.log:
            text = f"log {self.where} {self.log!r}"
        return f"#{self.id} {text} ({self.hits} hits)"


@dataclass
class Stop:
    """Why the machine stopped: reason is step | breakpoint | watch | condition | end | fault
    | goto | pause | entry; `breakpoints` the ids that fired; `text` a sentence for people."""
    reason: str
    text: str
    breakpoints: list[int] = field(default_factory=list)


def _hit_ok(cond: str, hits: int) -> bool:
    c = cond.replace(" ", "")
    mt = re.fullmatch(r"(==|>=|>|%)?(\d+)", c)
    if not mt:
        return True
    op, n = mt[1] or "==", int(mt[2])
    return {"==": hits == n, ">=": hits >= n, ">": hits > n, "%": n > 0 and hits % n == 0}[op]


def check_hit_condition(cond: str) -> str:
    if cond and not re.fullmatch(r"\s*(==|>=|>|%)?\s*\d+\s*", cond):
        raise DebugError(f"hit count {cond!r}: give N, ==N, >=N, >N or %N")
    return cond.strip()


class DebugSession:
    def __init__(self, image: Image, target, stimulus: Stimulus, models: list, period_us: int,
                 engine: str | None = None, watchdog: int = DEFAULT_WATCHDOG,
                 checkpoint_every: int = 100, max_checkpoints: int = 64, preload: list = ()):
        self.sim = Simulation(image, target, stimulus, models, period_us, [], False, watchdog, engine=engine,
                              preload=preload)
        self.image, self.target, self.period = image, target, period_us
        self.prog = self.sim.prog
        self.steps = self.prog.steps
        self.symbols = dict(image.symbols)
        self.watchdog = watchdog
        self.checkpoint_every = max(1, checkpoint_every)
        self.max_checkpoints = max(2, max_checkpoints)
        self.breakpoints: dict[int, Breakpoint] = {}
        self._next_bp = 1
        self.actions: dict[Position, list[tuple]] = {}  # position -> user actions taken there
        self.scan = 0
        self.n = BOUNDARY
        self.pc = 0  # next step index inside a scan
        self._wd = 0  # watchdog steps executed in this scan
        self.fault: Fault | None = None
        self.fault_pos: Position | None = None
        self.output: Callable[[str], None] = lambda text: None  # logpoints, expectation failures
        # the expectations that failed on this timeline: (scan, stimulus line) -> what failed
        # (`save` drops them from the stimulus it writes; an action taken before the scan
        # forgets them: the new timeline checks them again)
        self.failed_expects: dict[tuple[int, int], str] = {}
        # run-time warnings (W330 ...): each said once per instruction and message, as mlc sim
        # reports them; `_warnings_seen` counts the machine's list (shorter after going back)
        self._warned: set[tuple[object, str, str]] = set()
        self._warnings_seen = 0
        self.stops: list[tuple[Position, dict[str, int | float]]] = []  # watched values at stops
        # called between the scans of every long move (run, goto's replay, reverse-continue's
        # search, a console count's moves) and every POLL_STEPS instructions inside a scan,
        # where the machine is consistent: a front end lets other requests in there, or raises
        # Interrupted to end the move (the web page's Pause, DAP's pause, Ctrl-C on the terminal)
        self.poll: Callable[[], None] | None = None
        self._unpolled = 0  # instructions executed since the last poll
        self.replaying = False  # going back (or scanning for a hit): no action may be taken now
        self._memo_seed = {id(x): x for x in (target, image, self.prog, *self.steps)}
        self._layouts = 1 << 30
        self.checkpoints: dict[int, dict] = {}
        self._checkpointed_at = time.perf_counter()
        self._checkpoint()
        # `continue` with nothing firing stops where the stimulus ends (its `run`, else its last line)
        self.end_scan = plan_scans(stimulus, period_us, None, None)
        # `save`: relative paths from `cwd`; written only inside `folder`, never onto `inputs`
        # (load_session sets them: the project's folder, the files the session read)
        self.cwd = self.folder = os.getcwd()
        self.folder_is = "the session's current folder"

    # -- positions and state ------------------------------------------------------------
    @property
    def m(self) -> Machine:
        return self.sim.m

    @property
    def position(self) -> Position:
        return (self.scan, self.n)

    @property
    def time_us(self) -> int:
        return self.scan * self.period

    def current_step(self):
        """The step about to execute (None at a boundary)."""
        return self.steps[self.pc] if self.n != BOUNDARY and self.pc < len(self.steps) else None

    def where(self) -> str:
        s = self.current_step()
        if s is None:
            return f"scan {self.scan} (t={_time(self.time_us)}), before the scan"
        ins = s.ins
        return (f"scan {self.scan} (t={_time(self.time_us)}), {ins.file}:{ins.line}: step {ins.addr} "
                f"{' '.join((ins.mnemonic, *ins.texts))}")

    def _snapshot(self) -> dict:
        m = self.m
        w = m.writer
        if hasattr(w, "resolve"):
            w.resolve()
        state = dict(m.__dict__)
        state["writer"] = dict(dict.items(w))
        flat = {k: state.pop(k) for k in _FLAT if k in state}
        # unit words (VS UnG) are views of m.bfm: copied with it, so they stay its views
        # (the native engine's machine keeps its own words in arrays: copied flat as the lists)
        state["_unit_words"] = {k: v for k, v in flat["words"].items() if not isinstance(v, (list, array))}
        flat["words"] = {k: v for k, v in flat["words"].items() if isinstance(v, (list, array))}
        keep = {"machine": state, "forces": self.sim.forces, "models": self.sim.models}
        snap = copy.deepcopy(keep, dict(self._memo_seed))
        snap["flat"] = _copy_flat(flat)
        return snap

    def _restore(self, snap: dict) -> None:
        fresh = copy.deepcopy({k: v for k, v in snap.items() if k != "flat"}, dict(self._memo_seed))
        m = self.m
        m.__dict__.clear()
        units = fresh["machine"].pop("_unit_words")
        m.__dict__.update(fresh["machine"])
        m.__dict__.update(_copy_flat(snap["flat"]))
        m.words.update(units)
        self._layouts += 1
        m.layout = self._layouts  # the compiled scanner rebinds to the restored containers
        self.sim.forces = fresh["forces"]
        self.sim.models[:] = fresh["models"]
        self.sim.io = ModelIO(m)
        self.sim.irq = m.interrupts
        self._warnings_seen = len(m.warnings)

    def _checkpoint(self) -> None:
        k = self.scan
        if k % self.checkpoint_every or k in self.checkpoints:
            return
        started = time.perf_counter()
        self.checkpoints[k] = self._snapshot()
        now = time.perf_counter()
        # a checkpoint costing more than 5 % of the run since the last one: take them half as
        # often (going back then replays at most ~20 checkpoint costs; results never depend on it)
        if now - started > 0.05 * (started - self._checkpointed_at) and k:
            self.checkpoint_every *= 2
        self._checkpointed_at = now
        if len(self.checkpoints) > self.max_checkpoints:  # thin out: keep scan 0 and every other
            self.checkpoint_every *= 2
            for s in [s for s in self.checkpoints if s % self.checkpoint_every]:
                del self.checkpoints[s]

    # -- user actions (logged for replay) -----------------------------------------------
    def view(self, text: str) -> DeviceView:
        try:
            return resolve_device(text, self.target, self.symbols)
        except ExprError as e:
            raise DebugError(str(e)) from None

    def value_for(self, view: DeviceView, text: str) -> int | float:
        try:
            return parse_value(text, view)
        except StimError as e:
            raise DebugError(e.message) from None

    def force(self, view: DeviceView, value) -> None:
        self._act(("force", view, value))

    def release(self, view: DeviceView) -> None:
        if view not in self.sim.forces:
            raise DebugError(f"{view.name} is not forced")
        self._act(("release", view, None))

    def write(self, view: DeviceView, value) -> None:
        self._act(("write", view, value))

    def _act(self, action: tuple) -> None:
        if self.replaying:  # a front end that serves requests during a move (the web monitor)
            raise DebugError("the debugger is replaying to another point: Pause it first")
        pos = self.position
        # a new action starts a new timeline: what was logged after this point is dropped
        for p in [p for p in self.actions if p > pos]:
            del self.actions[p]
        for k in [k for k in self.checkpoints if k > pos[0]]:
            del self.checkpoints[k]
        self.stops = [(p, v) for p, v in self.stops if p <= pos]
        for key in [key for key in self.failed_expects if key[0] >= pos[0]]:  # not checked yet
            del self.failed_expects[key]
        if self.fault_pos is not None and self.fault_pos > pos:
            self.fault_pos = None
        self.actions.setdefault(pos, []).append(action)
        self._apply(action)

    def _apply(self, action: tuple) -> None:
        kind, view, value = action
        if kind == "force":
            self.sim.forces[view] = value
            view.write(self.m, value)
        elif kind == "release":
            self.sim.forces.pop(view, None)
        else:
            view.write(self.m, value)

    # -- execution ----------------------------------------------------------------------
    def _begin_scan(self) -> None:
        """What Simulation.run does before a scan, then the scan's own prelude (run_scan)."""
        self.sim.catch_up(self.scan)
        self.sim.apply_inputs(self.scan)

    def _scan_prelude(self) -> None:
        begin_scan(self.m)
        self.pc = 0
        self._wd = 0
        self.n = 0

    def _end_scan(self) -> None:
        sim, k = self.sim, self.scan
        sim.apply_forces()
        for e in sim.by_scan.get(k, ()):
            if e.kind in ("expect", "alarm"):
                outcome = sim.check(e, k)
                first_time = (k, e.line) not in self.failed_expects  # said once, not at each replay
                for f in outcome.failures:
                    what = f"{f.device} is {f.actual}, expected {f.expected}"
                    if first_time:
                        self.output(f"expect failed: {sim.st.path}:{f.line}: {what}"
                                    + (f" (last written by {f.writer})" if f.writer else ""))
                    self.failed_expects.setdefault((k, e.line), what)
        self._say_warnings()
        self.scan = k + 1
        self.n = BOUNDARY
        self._checkpoint()
        for action in self.actions.get((self.scan, BOUNDARY), ()):
            self._apply(action)

    def _say_warnings(self) -> None:
        warnings = self.m.warnings
        for _, pc, code, message in warnings[self._warnings_seen:]:
            if (pc, code, message) not in self._warned:
                self._warned.add((pc, code, message))
                _, path, line = self.sim.warned_at(pc)
                self.output(f"warning: {path}:{line}: {code} {message}")
        self._warnings_seen = len(warnings)

    def _faulted(self, f: Fault) -> None:
        self.fault = f
        self.fault_pos = self.position

    def _need_running(self) -> None:
        if self.fault is not None:
            raise DebugError(f"the program faulted: {self.fault.message}; go back (back, goto) to continue")

    def _enter_scan(self) -> None:
        """From a boundary: the scan's inputs and prelude: position (k, 0)."""
        try:
            self._begin_scan()
        except Fault as f:
            self._scan_prelude()
            self._faulted(f)
            raise
        self._scan_prelude()
        for action in self.actions.get((self.scan, 0), ()):
            self._apply(action)

    def _exec_one(self) -> None:
        """Execute the instruction at pc (inside a scan); the scan's END ends the scan."""
        s = self.steps[self.pc]
        m = self.m
        m.pc = self.pc
        self._wd += s.steps
        try:
            if self._wd > self.watchdog:
                raise SimFault(f"scan watchdog: more than {self.watchdog} steps executed in one scan "
                               "(runaway loop?)")
            r = s.run(m, s)
        except SimFault as e:
            f = Fault(e.message, s)
            self._faulted(f)
            raise f from None
        self.n += 1
        if r is None:
            self.pc += 1
        elif r == END_SCAN:
            end_of_scan(m)
            self._end_scan()
            return
        else:
            self.pc = r
        if self.pc >= len(self.steps):
            f = Fault("execution ran past the last instruction without END", s)
            self._faulted(f)
            raise f
        for action in self.actions.get(self.position, ()):
            self._apply(action)

    def _whole_scan(self) -> None:
        """Scan k from its boundary on the engine (no stop inside)."""
        self._enter_scan()
        if any(p[0] == self.scan and p[1] > 0 for p in self.actions):
            while self.n != BOUNDARY:
                self._exec_one()
            return
        try:
            self.sim.scan(self.watchdog)
        except Fault as f:
            self._faulted(f)
            raise
        self._end_scan()

    def _instr_mode(self) -> bool:
        return any(b.enabled and b.kind == "line" for b in self.breakpoints.values())

    # -- going to a position (replay) ----------------------------------------------------
    def goto(self, pos: Position) -> None:
        """Put the machine at `pos` by restoring a checkpoint and replaying. Interrupted (from
        the poll hook) leaves it where the replay got to, between two scans or instructions."""
        if pos[0] < 0:
            raise DebugError("there is no scan before scan 0")
        if pos[0] > MAX_SCANS:
            raise DebugError(f"scan {pos[0]}: a run has at most {MAX_SCANS} scans (docs/simulator.md, Bounds)")
        if self.fault_pos is not None and pos > self.fault_pos:
            raise DebugError(f"the program faulted at scan {self.fault_pos[0]}: nothing after it")
        start = max(k for k in self.checkpoints if k <= pos[0])
        was, self.replaying = self.replaying, True
        try:
            if not (start <= self.scan and self.position <= pos and self.fault is None):
                self._restore(self.checkpoints[start])
                self.scan, self.n, self.pc, self.fault = start, BOUNDARY, 0, None
                for action in self.actions.get((start, BOUNDARY), ()):
                    self._apply(action)
            if self.n != BOUNDARY and self.scan < pos[0]:
                while self.n != BOUNDARY:
                    self._exec_one()
                    self._instruction_done()
            while self.scan < pos[0]:
                self._between_scans()
                self._whole_scan()
            if pos[1] >= 0:
                if self.n == BOUNDARY:
                    self._enter_scan()
                while self.n < pos[1]:
                    self._exec_one()
                    if self.n == BOUNDARY:
                        raise DebugError(f"scan {pos[0]} ends after {pos[1]} instructions")
                    self._instruction_done()
        except Fault:
            pass
        finally:
            self.replaying = was
            self._reset_watches()

    def scan_length(self, k: int) -> int:
        """Instructions scan k executes (its END included); leaves the machine inside scan k."""
        self.goto((k, 0))
        n = 0
        while self.scan == k and self.n != BOUNDARY:
            self._exec_one()
            n += 1
            self._instruction_done()
        return n

    # -- interrupting a long move ----------------------------------------------------------
    def _between_scans(self) -> None:
        if self.poll is not None:
            self.poll()

    def _instruction_done(self) -> None:
        """Inside a scan: the poll hook every POLL_STEPS instructions (a scan may run up to
        the watchdog's million steps one by one)."""
        self._unpolled += 1
        if self._unpolled >= POLL_STEPS and self.poll is not None:
            self._unpolled = 0
            self.poll()

    def _undone_if_interrupted(self, what: str, move: Callable[[], Stop]) -> Stop:
        """`move()`; interrupted, the machine is put back where it was (from a copy taken
        first, ~0.5 ms: a replay back could be as long as the move) and the stop says so."""
        here = (self._snapshot(), self.scan, self.n, self.pc, self._wd, self.fault, self.fault_pos)
        try:
            return move()
        except Interrupted:
            snap, self.scan, self.n, self.pc, self._wd, self.fault, self.fault_pos = here
            self._restore(snap)
            self._reset_watches()
            return Stop("pause", f"interrupted: {what} did not finish; still at {self.where()}")

    def _reset_watches(self) -> None:
        for b in self.breakpoints.values():
            if b.kind == "watch":
                b.last = b.view.read(self.m)

    # -- commands ------------------------------------------------------------------------
    def step(self) -> Stop:
        """One instruction."""
        self._need_running()
        try:
            if self.n == BOUNDARY:
                self._enter_scan()
            self._exec_one()
        except Fault as f:
            return self._fault_stop(f)
        return self._stopped(Stop("step", f"stepped to {self.where()}"))

    def step_scan(self) -> Stop:
        """To the next scan boundary (a breakpoint or watch on the way stops it, logpoints print)."""
        stop = self.run(scans=1)
        if stop.reason == "step":
            return Stop("step", f"scan done: {self.where()}")
        return stop

    def run(self, scans: int | None = None, until: Expr | None = None, limit: int = 100_000) -> Stop:
        """Run until a breakpoint or watch fires, `until` holds at a scan end, `scans` scans
        are done (from here), or `limit` scans have run."""
        self._need_running()
        end = None
        if scans is None and until is None:
            end = self.end_scan if self.scan < self.end_scan else None
            scans = (self.end_scan - self.scan) if end is not None else None
        goal = self.scan + (scans if scans is not None else limit)
        if self.n != BOUNDARY and self.scan + 1 > goal:
            goal = self.scan + 1
        instr = self._instr_mode()
        first = True
        try:
            while True:
                if instr or self.n != BOUNDARY:
                    stop = self._run_instructions(first)
                    if stop is not None:
                        return self._stopped(stop)
                else:
                    self._whole_scan()
                first = False
                stop = self._scan_end_checks(until)
                if stop is not None:
                    return self._stopped(stop)
                if self.scan >= goal and end is not None:
                    return self._stopped(Stop("end", f"the stimulus ends here: {self.where()}"))
                if self.scan >= goal and scans is None:  # the bound of a run with no end
                    return self._stopped(Stop("pause", f"ran {limit} scans, the most one run goes at a time "
                                                       f"(again to go on): at {self.where()}"))
                if self.scan >= goal:
                    return self._stopped(Stop("step", f"ran to {self.where()}"))
                self._between_scans()
        except Fault as f:
            return self._fault_stop(f)
        except Interrupted:
            return self._stopped(self.interrupted())

    def interrupted(self) -> Stop:
        return Stop("pause", f"interrupted at {self.where()}")

    def scan_number(self, text: str) -> int:
        """A scan number as typed (`40`, `#40`): ASCII digits, at most MAX_SCANS."""
        text = text.strip().removeprefix("#")
        if not is_decimal(text) or int(text) > MAX_SCANS:
            raise DebugError(f"{clip(text, 24)!r}: give a scan number from 0 to {MAX_SCANS}")
        return int(text)

    def _run_instructions(self, first: bool) -> Stop | None:
        """The rest of this scan (or the next one) instruction by instruction, stopping before
        an instruction with a line breakpoint (not the one we are at when starting)."""
        if self.n == BOUNDARY:
            self._enter_scan()
            first = False
        at_start = first
        while self.n != BOUNDARY:
            if not at_start:
                stop = self._line_checks()
                if stop is not None:
                    return stop
            at_start = False
            self._exec_one()
            if self.n != BOUNDARY:
                stop = self._watch_checks()
                if stop is not None:
                    return stop
                self._instruction_done()
        return None

    def _counted_hit_stops(self, b) -> bool:
        """Count a hit of breakpoint b; True when it stops the run: its hit condition holds and
        it is no logpoint (a logpoint prints its message instead)."""
        b.hits += 1
        if b.hit_condition and not _hit_ok(b.hit_condition, b.hits):
            return False
        if b.log:
            self.output(self.format_log(b.log))
            return False
        return True

    def _line_checks(self) -> Stop | None:
        fired = []
        for b in self.breakpoints.values():
            if not (b.enabled and b.kind == "line" and self.pc in b.steps):
                continue
            if b.condition is not None and not b.condition.truth(self.m):
                continue
            if self._counted_hit_stops(b):
                fired.append(b)
        if fired:
            return Stop("breakpoint", f"breakpoint {', '.join(f'#{b.id} {b.where}' for b in fired)} "
                        f"at {self.where()}", [b.id for b in fired])
        return None

    def _watch_checks(self) -> Stop | None:
        fired, texts = [], []
        for b in self.breakpoints.values():
            if not (b.enabled and b.kind == "watch"):
                continue
            v = b.view.read(self.m)
            if v != b.last and not (_nan(v) and _nan(b.last)):
                old, b.last = b.last, v
                b.hits += 1
                if b.hit_condition and not _hit_ok(b.hit_condition, b.hits):
                    continue
                fired.append(b)
                texts.append(f"{b.view.name} changed {_fmt(old)} -> {_fmt(v)}")
        if fired:
            return Stop("watch", f"watch #{fired[0].id}: {'; '.join(texts)} at {self.where()}",
                        [b.id for b in fired])
        return None

    def _scan_end_checks(self, until: Expr | None) -> Stop | None:
        stop = self._watch_checks()
        if stop is not None:
            return stop
        fired = []
        for b in self.breakpoints.values():
            if b.enabled and b.kind == "cond" and b.condition.truth(self.m) and self._counted_hit_stops(b):
                fired.append(b)
        if fired:
            return Stop("condition", f"condition #{fired[0].id} ({fired[0].where}) holds at {self.where()}",
                        [b.id for b in fired])
        if until is not None and until.truth(self.m):
            return Stop("condition", f"{until.text} holds at {self.where()}")
        return None

    def _fault_stop(self, f: Fault) -> Stop:
        where = ""
        if f.step is not None:
            ins = f.step.ins
            where = f" at {ins.file}:{ins.line}: {' '.join((ins.mnemonic, *ins.texts))}"
        return self._stopped(Stop("fault", f"fault in scan {self.scan}{where}: {f.message}"))

    def _stopped(self, stop: Stop) -> Stop:
        watched = {b.view.name: b.view.read(self.m) for b in self.breakpoints.values() if b.kind == "watch"}
        if watched and self.n == BOUNDARY and self.fault is None:
            self.stops.append((self.position, watched))
        return stop

    # -- going back ----------------------------------------------------------------------
    def previous_position(self) -> Position:
        k, n = self.position
        if n > 0:
            return (k, n - 1)
        if n == 0:
            return (k, BOUNDARY)
        if k == 0:
            raise DebugError("at the start: nothing to go back to")
        length = self.scan_length(k - 1)
        return (k - 1, length - 1)

    def back(self) -> Stop:
        """One instruction back."""
        return self._undone_if_interrupted("back", self._back)

    def _back(self) -> Stop:
        here = self.position
        try:
            target = self.previous_position()
        except DebugError:
            self.goto(here)
            raise
        self.goto(target)
        return Stop("step", f"back to {self.where()}")

    def back_scan(self) -> Stop:
        k, n = self.position
        if n == BOUNDARY:
            if k == 0:
                raise DebugError("at the start: nothing to go back to")
            k -= 1

        def move() -> Stop:
            self.goto((k, BOUNDARY))
            return Stop("step", f"back to {self.where()}")
        return self._undone_if_interrupted("back scan", move)

    def goto_scan(self, k: int) -> Stop:
        """To the start of scan k; interrupted, it stays where the replay got to (as a run)."""
        try:
            self.goto((k, BOUNDARY))
        except Interrupted:
            return self._stopped(self.interrupted())
        if self.fault is not None:
            return Stop("fault", f"the program faulted before scan {k}: {self.fault.message}")
        return Stop("goto", f"at {self.where()}")

    def reverse_continue(self) -> Stop:
        """Back to the last position before here where a breakpoint or watch fired (the
        start if none did). Hit counts are not changed by the search."""
        return self._undone_if_interrupted("reverse-continue", self._reverse_continue)

    def _reverse_continue(self) -> Stop:
        here = self.position
        counts = {b.id: b.hits for b in self.breakpoints.values()}
        for b in self.breakpoints.values():  # hit counts count from the start of the run
            b.hits = 0
        found: tuple[Position, Stop] | None = None
        saved_out, self.output = self.output, (lambda text: None)
        was, self.replaying = self.replaying, True
        try:
            self.goto((0, BOUNDARY))
            instr = self._instr_mode()
            first = True
            while self.position < here and self.fault is None:
                self._between_scans()
                try:
                    if instr or self.n != BOUNDARY:
                        stop = self._run_instructions(first)
                        if stop is None:
                            stop = self._scan_end_checks(None)
                    else:
                        self._whole_scan()
                        stop = self._scan_end_checks(None)
                except Fault:
                    break
                first = stop is not None  # stopped before an instruction: go on past it
                if stop is not None and self.position < here:
                    found = (self.position, stop)
        finally:
            self.replaying = was
            self.output = saved_out
            for b in self.breakpoints.values():
                b.hits = counts.get(b.id, b.hits)
        if found is None:
            self.goto((0, BOUNDARY))
            return Stop("entry", "no breakpoint fired before: at the start")
        self.goto(found[0])
        stop = found[1]
        return Stop(stop.reason, stop.text, stop.breakpoints)

    # -- breakpoints ---------------------------------------------------------------------
    def _add(self, b: Breakpoint) -> Breakpoint:
        self.breakpoints[b.id] = b
        self._next_bp = b.id + 1
        return b

    def _new_id(self) -> int:
        return self._next_bp

    def steps_at(self, spec: str) -> tuple[str, frozenset[int]]:
        """`FILE:LINE`, `LINE` (the main file), a step address (`#120` or a number with no
        such line...), or a label `P3` / a symbol naming one -> step indexes to stop before."""
        spec = spec.strip()
        files = sorted({s.ins.file for s in self.steps})
        mt = re.fullmatch(r"(?:(.+):)?(\d+)", spec)
        if spec.startswith("#") and spec[1:].isdigit():
            addr = int(spec[1:])
            hit = [s.index for s in self.steps if s.ins.addr == addr]
            if not hit:
                raise DebugError(f"no instruction at step {addr}")
            return spec, frozenset(hit)
        if mt:
            path, line = mt[1], int(mt[2])
            cands = [f for f in files if path is None or f == path or f.endswith("/" + path)
                     or _base(f) == _base(path)]
            if not cands:
                raise DebugError(f"{path}: not a source file of the program ({', '.join(files)})")
            f = cands[0]
            # the first instruction on the line, or the next line with one
            later = [s for s in self.steps if s.ins.file == f and s.ins.line >= line]
            if not later:
                raise DebugError(f"{f}: no instruction at or after line {line}")
            first_line = min(s.ins.line for s in later)
            hit = [s.index for s in later if s.ins.line == first_line]
            return f"{f}:{first_line}", frozenset(hit[:1])
        up = spec.upper()
        sym = self.symbols.get(spec, "").upper()
        for name in (up, sym):
            mp = re.fullmatch(r"P(\d+)", name or "")
            if mp and int(mp[1]) in self.prog.labels:
                return spec, frozenset({self.prog.labels[int(mp[1])]})
        raise DebugError(f"{spec!r}: give FILE:LINE, LINE, #STEP or a label (P3)")

    def add_line(self, spec: str, condition: str = "", hit: str = "", log: str = "") -> Breakpoint:
        where, steps = self.steps_at(spec)
        cond = self.expr(condition) if condition.strip() else None
        if log:
            self._check_log(log)
        return self._add(Breakpoint(self._new_id(), "line", where, steps, cond,
                                    check_hit_condition(hit), log))

    def add_condition(self, text: str, hit: str = "") -> Breakpoint:
        e = self.expr(text)
        return self._add(Breakpoint(self._new_id(), "cond", text.strip(), condition=e,
                                    hit_condition=check_hit_condition(hit)))

    def add_watch(self, name: str, hit: str = "") -> Breakpoint:
        view = self.view(name)
        b = Breakpoint(self._new_id(), "watch", view.name, view=view, hit_condition=check_hit_condition(hit))
        b.last = view.read(self.m)
        return self._add(b)

    def delete(self, bp_id: int) -> None:
        if self.breakpoints.pop(bp_id, None) is None:
            raise DebugError(f"no breakpoint #{bp_id}")

    def clear_lines(self, path: str | None = None) -> None:
        for b in [b for b in self.breakpoints.values() if b.kind == "line"]:
            if path is None or b.where.rsplit(":", 1)[0] == path or _base(b.where.rsplit(":", 1)[0]) == _base(path):
                del self.breakpoints[b.id]

    def expr(self, text: str) -> Expr:
        try:
            return Expr(text, self.target, self.symbols)
        except ExprError as e:
            raise DebugError(str(e)) from None

    def _check_log(self, template: str) -> None:
        for inner in re.findall(r"\{([^{}]*)\}", template):
            self.expr(inner)

    def format_log(self, template: str) -> str:
        def sub(mt):
            try:
                return _fmt(self.expr(mt[1]).value(self.m))
            except DebugError as e:
                return f"<{e}>"
        return re.sub(r"\{([^{}]*)\}", sub, template)

    # -- looking at things ---------------------------------------------------------------
    def describe(self, view: DeviceView) -> str:
        """`X0 = 1`, `D0:d = 70000`, timers and counters with value, preset and elapsed."""
        m = self.m
        forced = " (forced)" if view in self.sim.forces else ""
        if view.kind in ("T", "C") and view.view in ("bit", "w", "d") and view.kind in self.m.bits:
            n = view.number
            contact = m.bits[view.kind][n]
            preset = self.preset_of(view.kind, n)
            if view.kind == "T":
                value = m.words["T"][n]
                base = m.timer_base_us(n)
                text = (f"T{n}: contact {'On' if contact else 'Off'}, value {value}"
                        f" ({_time(value * base)} elapsed)")
                if preset is not None:
                    text += f", preset {preset} ({_time(preset * base)})"
                text += ", running" if m.t_running[n] else ""
            else:
                value = m.cval[n] if not m.is_c32(n) else view.read(m) if view.view == "d" else m.cval[n]
                text = f"C{n}: contact {'On' if contact else 'Off'}, value {value}"
                if preset is not None:
                    text += f", preset {preset}"
            return text + forced
        return f"{view.name} = {_fmt(view.read(m))}{forced}"

    def preset_of(self, kind: str, n: int) -> int | None:
        for s in self.steps:
            ops = s.ins.operands
            if len(s.ops) >= 2 and ops and getattr(ops[0], "device", None) == kind and ops[0].number == n \
                    and s.ins.mnemonic in ("OUT", "TMR", "CNT", "DCNT", "TMRH"):
                try:
                    return s.ops[1].get(self.m)
                except (SimFault, AttributeError, IndexError):
                    return None
        return None

    def changed_between(self, a: int, b: int) -> list[tuple[str, object, object]]:
        """Devices whose values differ between the boundaries of scans a and b. Interrupted,
        the machine is put back where it was and Interrupted is raised."""
        values: list[dict] = []

        def move() -> Stop:
            here = self.position
            for k in (a, b):
                self.goto((k, BOUNDARY))
                values.append(self.device_values())
            self.goto(here)
            return Stop("step", "")
        stop = self._undone_if_interrupted(f"diff {a} {b}", move)
        if stop.reason == "pause":
            raise Interrupted(stop.text)
        before, after = values
        return [(k, before.get(k), after.get(k)) for k in sorted(set(before) | set(after), key=_dev_key)
                if before.get(k) != after.get(k)]

    def device_values(self) -> dict[str, int | float]:
        m = self.m
        out: dict[str, int | float] = {}
        for kind, arr in m.bits.items():
            for i, v in enumerate(arr):
                if v:
                    out[f"{kind}{i}"] = v
        for kind, arr in m.words.items():
            for i, v in enumerate(arr):
                if v:
                    out[f"{kind}{i}" + (":w" if kind == "T" else "")] = v
        for i, v in enumerate(m.cval):
            if v:
                out[f"C{i}:w"] = v
        return out

    def program_views(self) -> list[DeviceView]:
        """The devices the program, the stimulus and the models use (sorted)."""
        return list(self.sim.views)


# Machine containers of plain numbers (device memory, timer and edge state): copied flat, as
# deepcopy walks every element (a checkpoint of the NC5's memory took ~10 ms that way)
_FLAT = ("bits", "words", "cval", "t_running", "t_last", "t_frac", "t_seen", "t_preset", "edge")


def _copy_flat(flat: dict) -> dict:
    out = {}
    for k, v in flat.items():
        out[k] = {kk: vv[:] for kk, vv in v.items()} if isinstance(v, dict) else v[:]
    return out


def machine_state(m: Machine) -> dict:
    """A machine's state as plain comparable values (for replay-equivalence tests)."""
    # not compared: shared program data, the engine's bookkeeping, and the scan-local
    # registers every scan starts by clearing (the engines leave them differently)
    skip = {"target", "image", "layout", "writer", "interrupts", "pc", "pin_window",
            "acc", "blocks", "stack", "calls", "fors"}
    out = {}
    for k, v in m.__dict__.items():
        if k in skip:
            continue
        if isinstance(v, dict):
            v = {kk: (bytes(vv) if isinstance(vv, bytearray) else list(vv) if isinstance(vv, list) else vv)
                 for kk, vv in v.items()}
        elif isinstance(v, bytearray):
            v = bytes(v)
        out[k] = v
    return out


def _base(path: str | None) -> str:
    return (path or "").replace("\\", "/").rsplit("/", 1)[-1]


def _nan(v) -> bool:
    return isinstance(v, float) and math.isnan(v)


def _fmt(v) -> str:
    if isinstance(v, float):
        return repr(v)
    return str(v)


def _time(us: int) -> str:
    if us % 1_000_000 == 0 and us:
        return f"{us // 1_000_000}s"
    if us % 1000 == 0:
        return f"{us // 1000}ms"
    return f"{us}us"


def _dev_key(name: str):
    mt = re.match(r"([A-Z]+)(\d+)", name)
    return (mt[1], int(mt[2]), name) if mt else (name, 0, name)
