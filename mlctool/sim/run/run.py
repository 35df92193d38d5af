"""One simulation run: program + stimulus + models -> a plain RunResult.

Timing rule (docs/stimulus.md): scan k starts at k x period. Events at time t apply before
the first scan that starts at or after t (models step first, then the stimulus, then forces);
expectations at time t are checked after that same scan completes.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from mlctool.devices.base import DeviceModel, ModelInputError, ModelIO, ParamError
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Image
from mlctool.sim import signals
from mlctool.sim.decode import Program, program_devices
from mlctool.sim.engines.engine import scanner
from mlctool.sim.hardware import seriallink
from mlctool.sim.hardware.pin_window import PinWindow
from mlctool.sim.hardware.pulses import Quadrature, Train, add_quadrature, add_train, drive_inputs
from mlctool.sim.scan import DEFAULT_WATCHDOG, Fault, load_program
from mlctool.sim.signals import SIGNAL
from mlctool.sim.state import DeviceView, Machine
from mlctool.sim.stimulus.stimulus import MAX_SCANS, Check, Event, Stimulus
from mlctool.targetapi.model import Target
from mlctool.targetapi.registry import simulation_of

DEFAULT_SCAN_US = 10_000


@dataclass
class Failure:
    line: int
    col: int
    time_us: int
    scan: int
    device: str
    expected: str
    actual: int | float | str
    writer: str  # "file:line: INSTR ..." of the last write, or "stimulus line N", or ""
    text: str
    note: str = ""  # why the value is not what the writer left (an output Off: VS M9034 On)


@dataclass
class Checked:
    """One `DEV=V` (or alarm) of an expect line as checked, held or not: the report page
    lists every one."""

    device: str
    expected: str
    actual: int | float | str
    held: bool


@dataclass
class ExpectOutcome:
    line: int
    text: str
    time_us: int
    scan: int
    failures: list[Failure] = field(default_factory=list)
    # every check of the line (a run on the reference or compiled engine; the batch lanes keep
    # only the failures); not compared, as `seconds`
    checks: list[Checked] = field(default_factory=list, compare=False)
    # wall time simulated since the previous check (JUnit test case `time`); not compared
    seconds: float = field(default=0.0, compare=False)

    @property
    def passed(self) -> bool:
        return not self.failures


@dataclass
class AlarmReport:
    time_us: int
    scan: int
    name: str
    message: str
    addr: int
    file: str
    line: int
    expected: bool = False


@dataclass
class WarningReport:
    """A run-time warning at its instruction (sim/semantics.py warn), or a device model's at
    its stimulus line (ModelIO.warn: addr None)."""

    time_us: int
    scan: int
    code: str
    message: str
    addr: int | None
    file: str
    line: int


@dataclass
class FaultReport:
    time_us: int
    scan: int
    message: str
    addr: int | None
    file: str
    line: int
    source: str


@dataclass
class RunResult:
    period_us: int
    scans: int
    devices: dict[str, int | float]  # final values, sorted by device
    views: list[DeviceView]
    expectations: list[ExpectOutcome]
    alarms: list[AlarmReport]
    fault: FaultReport | None
    trace: list[tuple[int, list[tuple[int, int | float]]]]  # (time us, [(view index, value)])
    pin_window: object = None  # sim/hardware/pin_window.py PinWindow of --pulse-window (None: per-scan levels only)
    warnings: list[WarningReport] = field(default_factory=list)  # run-time warnings, first of each

    @classmethod
    def lazy(cls, period_us: int, scans: int, expectations: list[ExpectOutcome],
             final: Callable[[], tuple[dict[str, int | float], list[DeviceView]]]) -> RunResult:
        """A result without alarms, fault or trace whose `devices` and `views` are made by
        `final()` when first read, then kept. The batch lanes give one per scenario: a campaign
        that only needs pass/fail and counts builds no dict of final values. It equals, prints
        and pickles as the result made eagerly (`final` must pickle; pickled before the first
        read, it is called on the other side)."""
        r = cls.__new__(cls)
        r.__dict__.update(period_us=period_us, scans=scans, expectations=expectations, alarms=[],
                          fault=None, trace=[], pin_window=None, warnings=[], _final=final)
        return r

    def __getattr__(self, name: str):
        # only for attributes not set: the devices and views of a lazy result, on first read
        if name in ("devices", "views"):
            final = self.__dict__.pop("_final", None)
            if final is not None:
                self.devices, self.views = final()
                return self.__dict__[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    @property
    def time_us(self) -> int:
        return self.scans * self.period_us

    @property
    def failed(self) -> list[Failure]:
        return [f for e in self.expectations for f in e.failures]

    @property
    def ok(self) -> bool:
        return (self.fault is None and not self.failed
                and all(a.expected for a in self.alarms))


def model_inputs(models: Sequence[DeviceModel]) -> list[str]:
    """The files the models read (an NC part program): inputs of the run, which no output of
    the command may overwrite (fileio.note_input: worker processes read them for mlc test and batches)."""
    return [path for model in models for path in model.inputs()]


def build_models(st: Stimulus, target: Target, watch: Sequence[DeviceView] = ()
                 ) -> tuple[list[DeviceModel], list[Diagnostic]]:
    models, diags, built = [], [], []
    if st.models:  # (the models' modules: only when a stimulus names one, ~0.1 s of imports)
        from mlctool.devices.registry import models_of

        kinds = models_of(target)
        folder = os.path.dirname(st.path)
    for spec in st.models:
        cls = kinds.get(spec.kind)
        if cls is None:
            from mlctool.suggest import did_you_mean

            diags.append(diag(st.path, Span.at(spec.line, spec.col, len(spec.kind)), "E601",
                              f"unknown device model {spec.kind!r}" + (did_you_mean(spec.kind, kinds, "'")
                                                                        or f"; models: {', '.join(sorted(kinds))}")))
            continue
        try:
            model = cls.build({k: v for k, (v, _) in spec.params.items()}, target, folder)
            model.at = (st.path, spec.line)
            models.append(model)
            built.append(spec)
        except ParamError as e:
            col = spec.params.get(e.key, ("", spec.col))[1]
            diags.append(diag(st.path, Span.at(spec.line, col, len(e.key)), e.code, e.message))
        except ModelInputError as e:
            diags += e.diags
    return models, diags + _signal_diags(st, list(zip(built, models)), watch)


def _signal_diags(st: Stimulus, models: list[tuple[object, DeviceModel]],
                  watch: Sequence[DeviceView]) -> list[Diagnostic]:
    """Every model signal named (`XC1.pos`) belongs to a model of that name that has it; two
    models never share a name."""
    diags, owners = [], {}
    counts: dict[str, int] = {}
    for _spec, model in models:
        if model.kind in signals.DEFAULT_PREFIX:
            counts[model.kind] = counts.get(model.kind, 0) + 1
            if not model.name:
                model.name = f"{signals.DEFAULT_PREFIX[model.kind]}{counts[model.kind]}"
    for spec, model in models:
        if not model.name:
            continue
        if model.name in owners:
            col = spec.params.get("name", ("", spec.col))[1]
            diags.append(diag(st.path, Span.at(spec.line, col), "E601",
                              f"two models are named {model.name}: give each its own name=..."))
        owners[model.name] = model
    places = [(v, st.path, e.line, e.col) for e in st.events
              for v in [c.view for c in e.checks] + [v for v, _ in e.assigns]]
    places += [(v, "<--watch>", 1, 1) for v in watch]
    seen = set()
    for view, path, line, col in places:
        if not view.kind.startswith(SIGNAL) or view in seen:
            continue
        seen.add(view)
        model = owners.get(signals.model_of(view.kind))
        name = signals.signal_of(view.number)
        if model is None:
            known = ", ".join(sorted(owners)) or "none"
            diags.append(diag(path, Span.at(line, col), "E602",
                              f"{view.name}: no model named {signals.model_of(view.kind)} "
                              f"(models with signals: {known})"))
        elif name not in signals.KINDS.get(model.kind, {}):
            from mlctool.suggest import did_you_mean

            own = signals.KINDS.get(model.kind, {})
            diags.append(diag(path, Span.at(line, col), "E602",
                              f"{view.name}: model {model.kind} has no signal {name!r}"
                              + (did_you_mean(name, own, "'") or f"; signals: {', '.join(own)}")))
    return diags


class RunTooLong(ValueError):
    """The scans a run asks for pass MAX_SCANS (a short scan period over a long time)."""


def plan_scans(st: Stimulus, period_us: int, until_us: int | None, scans: int | None) -> int:
    """Number of scans: --scans/--until, else the stimulus `run`, else through the last event.
    RunTooLong past MAX_SCANS (each time is bounded by MAX_TIME_US already)."""
    if scans is not None:
        n, why = scans, "--scans"
    elif until_us is not None:
        n, why = -(-until_us // period_us), "--until"
    elif st.run_scans is not None:
        n, why = st.run_scans, "`run`"
    elif st.run_time_us is not None:
        n, why = -(-st.run_time_us // period_us), "`run`"
    else:
        n, why = max((e.scan_index(period_us) + 1 for e in st.events), default=1), "the last stimulus line"
    if n > MAX_SCANS:
        raise RunTooLong(f"{why} asks for {n:,} scans of {period_us} us; a run is at most {MAX_SCANS:,} "
                         "scans (docs/simulator.md, Bounds)")
    return n


class Simulation:
    def __init__(self, image: Image, target: Target, st: Stimulus, models: list[DeviceModel],
                 period_us: int, watch: list[DeviceView], trace: bool,
                 watchdog: int = DEFAULT_WATCHDOG, probe=None, engine: str | None = None,
                 preload: list[tuple[str, int, list[int]]] = (), pulse_window: tuple[int, int] | None = None):
        self.image = image
        self.target = target
        self.prog: Program = load_program(image, target, probe)
        self.m = Machine(target, len(self.prog.steps))
        self.m.image = image
        if pulse_window is not None:  # the target's extension records its pulse pins' edges
            self.m.pin_window = PinWindow(*pulse_window)
        for kind, first, words in preload:  # register tables loaded with the program (--table)
            self.m.words[kind][first:first + len(words)] = [w & 0xFFFF for w in words]
        self.st = st
        self.models = models
        self.io = ModelIO(self.m)
        self.period = period_us
        self.watchdog = watchdog
        # the compiled engine (compile.py, engine.py) unless asked otherwise; coverage probes need the
        # reference interpreter
        self.scan = scanner(self.prog, self.m, "interp" if probe is not None else engine)
        names = program_devices(self.prog) | st.devices() | set(watch)
        # the target's own hardware (its Simulation): runs between scans, adds its registers
        own = simulation_of(target)
        self.before_scan = own.before_scan
        if own.views is not None:
            names.update(own.views(target, self.prog))
        for model in models:
            names.update(model.devices())
        self.views = sorted(names, key=DeviceView.sort_key)
        self.tracing = trace
        # where each time's value changes go as soon as they are complete (the streamed VCD);
        # None: they are kept in RunResult.trace
        self.trace_sink: Callable[[int, list[tuple[int, int | float]]], None] | None = None
        # called with the machine and the scan number at the end of every scan, forces applied
        # (the report samples the lit ladder elements here: ladder/report.py)
        self.scan_end: Callable[[Machine, int], None] | None = None
        self.forces: dict[DeviceView, int | float] = {}
        self.by_scan: dict[int, list[Event]] = {}
        for e in st.events:
            self.by_scan.setdefault(e.scan_index(period_us), []).append(e)
        self.alarm_names = {e.alarm for e in st.events if e.kind == "alarm"}
        # interrupt routines (VS 2-12): served between scans, interleaved with the stimulus
        has_pointers = any(s.ins.spec.cls == "interrupt" for s in self.prog.steps)
        self.irq = self.m.interrupts = own.interrupts(self.prog, target) \
            if has_pointers and own.interrupts is not None else None
        self.configure_ports()

    def configure_ports(self) -> None:
        """The stimulus's `port` lines: the PLC's port settings (again after a power cycle)."""
        for spec in self.st.ports:
            spec.apply(seriallink.port(self.m, spec.name))

    def writer_of(self, view: DeviceView) -> str:
        keys = ([(view.gdev, view.number + i) for i in range(4 * view.digits)] if view.view == "group"
                else [(view.kind, view.number)] + ([(view.kind, view.number + 1)]
                                                   if view.view in ("d", "f") and view.kind in "DT" else []))
        who = [self.m.writer[k] for k in keys if k in self.m.writer]
        if not who:
            return ""
        w = who[0]
        if w < 0:
            return f"stimulus line {-w}"
        ins = self.prog.steps[w].ins
        return f"{ins.file}:{ins.line}: {' '.join((ins.mnemonic, *ins.texts))}"

    def apply(self, e: Event) -> None:
        if e.kind == "power":
            self.m.power_cycle()
            self.configure_ports()
            for model in self.models:
                model.power_cycle()
        elif e.kind == "receive":  # bytes to the PLC's port (sim/stimulus/serial_stim.py)
            seriallink.port(self.m, e.port).deliver(e.time_us, e.data)
        elif e.kind == "set":
            for view, value in e.assigns:
                view.write(self.m, value)
                self._mark(view, e.line)
        elif e.kind == "force":
            for view, value in e.assigns:
                self.forces[view] = value
                self._mark(view, e.line)
        elif e.kind == "release":
            for view, _ in e.assigns:
                self.forces.pop(view, None)
        elif e.kind == "pulses":
            view, (start, period, end, *pair) = e.assigns[0]
            if pair:  # an A/B phase pair: both trains and the pair's counting record
                b, sign = pair
                add_quadrature(self.m, Quadrature((view.kind, view.number), (b.kind, b.number),
                                                  start, period, end, sign))
                self._mark(b, e.line)
            else:
                add_train(self.m, view.kind, view.number, Train(start, period, end))
            self._mark(view, e.line)

    def _mark(self, view: DeviceView, line: int) -> None:
        kind = view.gdev if view.view == "group" else view.kind
        self.m.writer[(kind, view.number)] = -line

    def apply_forces(self) -> None:
        for view, value in self.forces.items():
            view.write(self.m, value)

    def check(self, e: Event, k: int) -> ExpectOutcome:
        out = ExpectOutcome(e.line, e.text, k * self.period, k)
        if e.kind == "alarm":
            raised = any(a[2] == e.alarm for a in self.m.alarms)
            out.checks.append(Checked(f"alarm {e.alarm}", "raised", "raised" if raised else "not raised", raised))
            if not raised:
                out.failures.append(Failure(e.line, e.col, k * self.period, k, f"alarm {e.alarm}",
                                            "raised", "not raised", "", e.text))
            return out
        for c in e.checks:
            actual = c.view.read(self.m)
            held = c.holds(actual)
            out.checks.append(Checked(c.view.name, c.expected_text(), actual, held))
            if not held:
                out.failures.append(self._failure(e, c, k, actual))
        return out

    def _failure(self, e: Event, c: Check, k: int, actual) -> Failure:
        return Failure(e.line, c.col, k * self.period, k, c.view.name, c.expected_text(),
                       actual, self.writer_of(c.view), c.text, self._outputs_off_note(c.view))

    def _outputs_off_note(self, view: DeviceView) -> str:
        """A Y read while the outputs-off relay is On: say so (the writer left the image On)."""
        if "Y" not in (view.kind, view.gdev) or not self.m.outputs_disabled():
            return ""
        off = self.target.settings["outputs_off"]
        return (f"every output is Off while {self.target.device_name('M', off['relay'])} is On "
                f"(manual {off['section']}); the program's image is kept")

    def warned_at(self, where: int | tuple[str, int]) -> tuple[int | None, str, int]:
        """(step address, file, line) of a run-time warning's place: an instruction's index
        (sim/semantics.py warn), or a device model's stimulus line (ModelIO.warn; no step)."""
        if isinstance(where, tuple):
            return (None, *where)
        ins = self.prog.steps[where].ins
        return ins.addr, ins.file, ins.line

    def catch_up(self, k: int) -> None:
        """Virtual time moves to scan k: the target's hardware and the device models catch up
        to it, before the new inputs."""
        m = self.m
        m.now_us = k * self.period
        if self.before_scan:
            self.before_scan(m)
        for model in self.models:
            model.step(self.io, m.now_us, self.period)

    def apply_inputs(self, k: int) -> None:
        """Scan k's stimulus lines (in time order with the interrupt routines they request),
        pulse trains and forces, as the scan will read them."""
        events = self.by_scan.get(k, ())
        if self.irq is not None:
            self.irq.before_scan(self, k, events)
        else:
            for e in events:
                if e.kind not in ("expect", "alarm"):
                    self.apply(e)
        if self.m.pulse_trains:
            drive_inputs(self.m)
        self.apply_forces()

    def run(self, n_scans: int, progress: Callable[[int], None] | None = None) -> RunResult:
        m = self.m
        outcomes: list[ExpectOutcome] = []
        trace = TraceLog(self.trace_sink)
        last: list[int | float | None] = [None] * len(self.views)
        # Y bits a routine's REF put out between scans (targets/vs/interrupts.py): trace entries at
        # their own time; the scan after records each such view again
        y_views = {v.number: i for i, v in enumerate(self.views) if v.kind == "Y" and v.view == "bit"}
        moved: set[int] = set()
        fault = None
        reports = ScanReports(self)
        scans_done = 0
        checked_at = time.perf_counter()
        for k in range(n_scans):
            self.catch_up(k)
            try:
                self.apply_inputs(k)
                self.scan(self.watchdog)
            except Fault as f:
                fault = self.fault_report(f, k)
            self.apply_forces()
            scans_done = k + 1
            reports.collect(k)
            outputs = self.irq.outputs if self.irq is not None else []
            if self.tracing and outputs:
                for t, n, level in outputs:
                    i = y_views.get(n)
                    if i is None or t >= m.now_us or level == last[i]:
                        continue  # at the scan's own time the scan's entry shows it
                    trace.add(t, [(i, level)])
                    last[i] = level
                    moved.add(i)
            outputs.clear()
            if self.tracing:
                changes = []
                for i, v in enumerate(self.views):
                    val = v.read(m)
                    if i in moved or val != last[i] or (isinstance(val, float) and math.isnan(val)
                                                        and not (isinstance(last[i], float) and math.isnan(last[i]))):
                        changes.append((i, val))
                        last[i] = val
                moved.clear()
                if changes:
                    trace.add(m.now_us, changes)
            if self.scan_end is not None:
                self.scan_end(m, k)
            if fault:
                break
            for e in self.by_scan.get(k, ()):
                if e.kind in ("expect", "alarm"):
                    outcomes.append(self.check(e, k))
                    now = time.perf_counter()
                    outcomes[-1].seconds, checked_at = now - checked_at, now
            if progress:
                progress(k + 1)
        for k in sorted(s for s in self.by_scan if s >= scans_done):
            for e in self.by_scan[k]:
                if e.kind in ("expect", "alarm"):
                    o = ExpectOutcome(e.line, e.text, k * self.period, k)
                    o.failures.append(Failure(e.line, e.col, k * self.period, k, "(run)",
                                              f"scan {k} to run", f"run ended after {scans_done} scans",
                                              "", e.text))
                    outcomes.append(o)
        outcomes.sort(key=lambda o: (o.scan, o.line))
        devices = {v.name: v.read(m) for v in self.views}
        return RunResult(self.period, scans_done, devices, self.views, outcomes, reports.alarms(), fault,
                         trace.close(), m.pin_window, reports.warnings())

    def fault_report(self, f: Fault, k: int) -> FaultReport:
        if f.step is None:
            return FaultReport(k * self.period, k, f.message, None, self.image.modules[0][0]
                               if self.image.modules else "<program>", 1, "")
        ins = f.step.ins
        return FaultReport(k * self.period, k, f.message, ins.addr, ins.file, ins.line,
                           " ".join((ins.mnemonic, *ins.texts)))


class TraceLog:
    """The value changes of a traced run in time order, one entry per time. Changes at the
    time of the last entry join it; with a sink, every earlier entry is handed to the sink
    and dropped, so memory stays bounded by the number of devices, not of changes."""

    def __init__(self, sink: Callable[[int, list[tuple[int, int | float]]], None] | None = None):
        self.entries: list[tuple[int, list[tuple[int, int | float]]]] = []
        self.sink = sink

    def add(self, t: int, changes: list[tuple[int, int | float]]) -> None:
        if self.entries and self.entries[-1][0] == t:
            self.entries[-1][1].extend(changes)
            return
        if self.sink is not None and self.entries:
            self.sink(*self.entries.pop())
        self.entries.append((t, changes))

    def close(self) -> list[tuple[int, list[tuple[int, int | float]]]]:
        """The kept entries (none with a sink: they all went to it)."""
        if self.sink is not None:
            for t, changes in self.entries:
                self.sink(t, changes)
            self.entries = []
        return self.entries


class ScanReports:
    """The alarms and run-time warnings a run raised, gathered after each scan (`collect`): the
    first of each alarm per instruction (a continuous instruction repeats it every scan) and
    the first of each warning, as batch runs (Simulation.run) and live ones (mlc run) report
    them."""

    def __init__(self, sim: Simulation):
        self.sim = sim
        self.seen_alarms = self.seen_warnings = 0
        self._alarms: dict[tuple[str, int], AlarmReport] = {}
        self._warnings: dict[tuple[int, str, str], WarningReport] = {}

    def collect(self, k: int, trim: bool = False) -> None:
        """Scan k's new alarms and warnings. `trim` (a live run, which has no end): the machine
        then keeps one entry per alarm name, all `expect alarm` reads, and no warnings, so a
        continuous instruction's alarm every scan does not grow them for hours."""
        sim, m = self.sim, self.sim.m
        for t, pc, name, message in m.alarms[self.seen_alarms:]:
            ins = sim.prog.steps[pc].ins
            if (name, ins.addr) not in self._alarms:
                self._alarms[(name, ins.addr)] = AlarmReport(t, k, name, message, ins.addr, ins.file, ins.line,
                                                             name in sim.alarm_names)
        self.seen_alarms = len(m.alarms)
        for t, pc, code, message in m.warnings[self.seen_warnings:]:
            self._warnings.setdefault((pc, code, message), WarningReport(t, k, code, message, *sim.warned_at(pc)))
        self.seen_warnings = len(m.warnings)
        if trim and (len(m.alarms) > len(self._alarms) or m.warnings):
            firsts: dict[str, tuple] = {}
            for a in m.alarms:
                firsts.setdefault(a[2], a)
            m.alarms[:] = firsts.values()
            m.warnings.clear()
            self.seen_alarms, self.seen_warnings = len(m.alarms), 0

    def alarms(self) -> list[AlarmReport]:
        return list(self._alarms.values())

    def warnings(self) -> list[WarningReport]:
        return list(self._warnings.values())
