"""`mlc run`: a Simulation's scans paced to the wall clock (docs/commissioning.md).

Scan k is due at start + k x period / speed of wall time (virtual time stays k x period:
the stimulus, the timers and the device models see the same times as `mlc sim`). Between two
scans the loop serves the servers' jobs (commission/exchange.py) until the next scan is due,
then runs it: the models catch up, the stimulus lines and forces of the scan apply, the
program runs, the expectations of the scan are checked.

Figures (Stats): the jitter of a scan is how late it starts after it was due; an overrun is a
scan that ends after the next one was due (the scan plus what the loop served took longer
than the period). A loop that falls more than SLIP_PERIODS periods behind (the machine was
suspended, a debugger paused it) starts counting afresh from now rather than running the
missed scans back to back; each such restart is a `slip`.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from mlctool.commission.exchange import Exchange
from mlctool.sim.run.run import ExpectOutcome, FaultReport, ScanReports, Simulation
from mlctool.sim.scan import Fault

SLIP_PERIODS = 10
STATUS_EVERY_S = 0.5
# the interpreter hands the GIL to a waiting thread after this long (CPython's default is 5 ms):
# a scan due while the servers' thread runs Python waits at most this long for it
SWITCH_INTERVAL_S = 0.0005


@dataclass
class Stats:
    period_us: int
    speed: float
    scans: int = 0
    jitter_sum_s: float = 0.0
    jitter_worst_s: float = 0.0
    overruns: int = 0
    slips: int = 0
    scan_worst_s: float = 0.0  # the longest scan itself (program and models)
    wall_s: float = 0.0
    jitters: list[float] = field(default_factory=list, repr=False)  # kept only when asked (bench)

    @property
    def jitter_mean_s(self) -> float:
        return self.jitter_sum_s / self.scans if self.scans else 0.0

    def line(self) -> str:
        return (f"scan {self.scans}  {self.scans * self.period_us / 1e6:.2f} s PLC time  "
                f"jitter mean {self.jitter_mean_s * 1e3:.2f} ms worst {self.jitter_worst_s * 1e3:.2f} ms  "
                f"overruns {self.overruns}")

    def as_dict(self) -> dict:
        return {"scans": self.scans, "period_us": self.period_us, "speed": self.speed,
                "plc_time_s": self.scans * self.period_us / 1e6, "wall_s": round(self.wall_s, 6),
                "jitter_mean_ms": round(self.jitter_mean_s * 1e3, 4),
                "jitter_worst_ms": round(self.jitter_worst_s * 1e3, 4),
                "scan_worst_ms": round(self.scan_worst_s * 1e3, 4),
                "overruns": self.overruns, "slips": self.slips}


class LiveRun:
    """A Simulation run in real time. Call `run` on the thread that owns the machine."""

    def __init__(self, sim: Simulation, speed: float = 1.0, exchange: Exchange | None = None,
                 clock: Callable[[], float] = time.perf_counter, keep_jitters: bool = False):
        self.sim = sim
        self.speed = speed
        self.exchange = exchange or Exchange(clock=clock)
        self.clock = clock
        self.stats = Stats(sim.period, speed)
        self.keep_jitters = keep_jitters
        self.outcomes: list[ExpectOutcome] = []
        self.fault: FaultReport | None = None
        self.reports = ScanReports(sim)  # the alarms and warnings, as mlc sim reports them
        self.stop = threading.Event()
        # called after every scan on the scan thread (OPC UA publishes the values it watches)
        self.after_scan: list[Callable[[int], None]] = []

    def run(self, n_scans: int | None, status: Callable[[Stats], None] | None = None) -> Stats:
        """Scans until `n_scans` are done (None: until stop is set), a fault, or Ctrl-C
        (KeyboardInterrupt ends the run cleanly: the scan in progress completes first)."""
        sim, st, clock, ex = self.sim, self.stats, self.clock, self.exchange
        switch = sys.getswitchinterval()
        sys.setswitchinterval(min(switch, SWITCH_INTERVAL_S))
        wall_period = sim.period / 1e6 / self.speed
        started = start = clock()
        next_status = started + STATUS_EVERY_S
        k = 0
        try:
            while (n_scans is None or k < n_scans) and not self.stop.is_set():
                due = start + st.scans * wall_period
                ex.serve_until(sim.m, due, self.stop)
                if self.stop.is_set():
                    break
                now = clock()
                late = now - due
                if late > SLIP_PERIODS * wall_period:  # its lateness still counts as jitter
                    st.slips += 1
                    start = now - st.scans * wall_period
                self._scan(k)
                end = clock()
                for hook in self.after_scan:
                    hook(k + 1)
                st.scans = k = k + 1
                st.jitter_sum_s += late
                st.jitter_worst_s = max(st.jitter_worst_s, late)
                st.scan_worst_s = max(st.scan_worst_s, end - now)
                if self.keep_jitters:
                    st.jitters.append(late)
                if end > start + k * wall_period:
                    st.overruns += 1
                if self.fault is not None:
                    break
                if status is not None and end >= next_status:
                    status(st)
                    next_status = end + STATUS_EVERY_S
        except KeyboardInterrupt:
            pass  # Ctrl-C: a clean stop after the last whole scan
        finally:
            sys.setswitchinterval(switch)
        st.wall_s = clock() - started
        return st

    def _scan(self, k: int) -> None:
        sim = self.sim
        sim.catch_up(k)
        try:
            sim.apply_inputs(k)
            sim.scan(sim.watchdog)
        except Fault as f:
            self.fault = sim.fault_report(f, k)
        sim.apply_forces()
        self.reports.collect(k, trim=True)
        if self.fault is not None:
            return  # as in a batch run, a faulted scan's expectations are not checked
        for e in sim.by_scan.get(k, ()):
            if e.kind in ("expect", "alarm"):
                self.outcomes.append(sim.check(e, k))
