"""The one door between the servers (network thread) and the machine (scan thread).

The scan loop owns the machine: no server touches it. A server hands a job (a function of
the machine: a Modbus request, an OPC UA write) to `submit`; the scan loop runs the queued
jobs in the gaps between scans (`serve_until`), never during a scan, and each job's `done`
gets its result. So a write lands between two scans, after scan k's END and before scan k+1
reads its inputs, as the VS's communication is served at the scan's END (003, CPUL: "Easy
Link, MODBUS ... follow the PLC's scan"); a read sees the machine as scan k left it.

Bounds: at most `capacity` jobs wait in all, at most `per_client` of one client; past
either, `submit` refuses at once (a Modbus server answers exception 06, busy). A job is
small (one request: at most 2000 bits or 125 words), and the scan loop stops taking jobs at
the next scan's deadline, so a flood delays a scan by at most one job, never by the queue.
"""

from __future__ import annotations

import threading
import time
from collections import Counter, deque
from collections.abc import Callable

from mlctool.sim.state import Machine

DEFAULT_CAPACITY = 1024
DEFAULT_PER_CLIENT = 16


class Exchange:
    def __init__(self, capacity: int = DEFAULT_CAPACITY, per_client: int = DEFAULT_PER_CLIENT,
                 clock: Callable[[], float] = time.perf_counter):
        self.capacity = capacity
        self.per_client = per_client
        self.clock = clock
        self._cv = threading.Condition(threading.Lock())
        self._jobs: deque = deque()
        self._pending: Counter = Counter()

    def submit(self, client: object, job: Callable[[Machine], object],
               done: Callable[[object, BaseException | None], None]) -> bool:
        """Queue `job` for the scan thread; False (nothing queued) when full."""
        with self._cv:
            if len(self._jobs) >= self.capacity or self._pending[client] >= self.per_client:
                return False
            self._jobs.append((client, job, done))
            self._pending[client] += 1
            self._cv.notify()
        return True

    def serve_until(self, m: Machine, deadline: float, stop: threading.Event | None = None) -> None:
        """Run queued jobs on `m` until `deadline` (the clock's time); wait for jobs while
        there is time. Returns at the deadline (or when `stop` is set, within 50 ms)."""
        clock = self.clock
        while True:
            with self._cv:
                while not self._jobs:
                    left = deadline - clock()
                    if left <= 0 or (stop is not None and stop.is_set()):
                        return
                    self._cv.wait(min(left, 0.05))
                if clock() >= deadline:
                    return
                client, job, done = self._jobs.popleft()
                self._pending[client] -= 1
                if not self._pending[client]:
                    del self._pending[client]
            try:
                result, error = job(m), None
            except Exception as e:  # a bug in a job: its client gets an error, the scan goes on
                result, error = None, e
            done(result, error)

    def wake(self) -> None:
        """Let a waiting serve_until look at its stop event now."""
        with self._cv:
            self._cv.notify_all()
