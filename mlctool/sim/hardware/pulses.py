"""Pulse trains on inputs, described by the stimulus (`0ms X0 pulses 1kHz until 500ms`), on
virtual time and counted analytically: a train is never stepped pulse by pulse.

A train of frequency f starting at t0 has its rising edges at t0 + k/f (k = 0, 1, ...)
before its end, and is On for the first half of each period (50 % duty). A later train on
the same input ends the earlier one where it starts. Scans see the input's level at their
start time; high-speed counters (targets/vs/hsc.py) and SPD count the edges between two times.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction


@dataclass(slots=True)
class Train:
    start_us: int
    period_us: Fraction | None  # None: 0 Hz (the input stays Off)
    end_us: int | None  # exclusive; None: until the next train on the input or the run's end

    def edges_upto(self, t: int) -> int:
        """Rising edges at times <= t."""
        if self.period_us is None or t < self.start_us:
            return 0
        n = math.floor((t - self.start_us) / self.period_us) + 1
        if self.end_us is not None:  # the edges before the end (exclusive)
            n = min(n, math.ceil((self.end_us - self.start_us) / self.period_us))
        return n

    def level(self, t: int) -> int:
        if self.period_us is None or t < self.start_us or (self.end_us is not None and t >= self.end_us):
            return 0
        return 1 if (t - self.start_us) % self.period_us < self.period_us / 2 else 0

    def edge_time(self, k: int) -> Fraction:
        """Time of edge number k (0 = the first)."""
        return self.start_us + k * self.period_us


def add_train(m, kind: str, number: int, train: Train) -> None:
    trains = m.pulse_trains.setdefault((kind, number), [])
    for old in trains:  # the new train ends the ones still running
        if old.end_us is None or old.end_us > train.start_us:
            old.end_us = max(old.start_us, train.start_us)
    trains.append(train)


def edges(m, kind: str, number: int, after: int, upto: int) -> list[tuple[Train, int, int]]:
    """The rising edges in (after, upto] as (train, first k, count) runs, in time order."""
    out = []
    for tr in m.pulse_trains.get((kind, number), ()):
        first = tr.edges_upto(after)
        last = tr.edges_upto(upto)
        if last > first:
            out.append((tr, first, last - first))
    return out


def count(m, kind: str, number: int, after: int, upto: int) -> int:
    return sum(n for _, _, n in edges(m, kind, number, after, upto))


@dataclass(slots=True)
class Quadrature:
    """An A/B pair (`X0/X1 pulses 1kHz`; a negative frequency turns the other way): A is a
    50 % train from start_us, B the same train a quarter period later (sign +1: A leads,
    the forward/up direction of 2-7-3) or three quarters later (sign -1: B leads).

    A/B counters count the pair's counting events, never its single edges: x1 one per cycle
    (B rising while A is On, or B falling while A is On when turning back), x2 both B edges,
    x4 every edge of A and B; the events of a cycle are evenly spaced from a quarter period
    (x1, x2) or from the start (x4), so they are counted with a Train of period T/x."""
    a: tuple[str, int]
    b: tuple[str, int]
    start_us: int
    period_us: Fraction | None
    end_us: int | None
    sign: int

    def counts(self, per_cycle: int, after: int, upto: int) -> int:
        if self.period_us is None:
            return 0
        first = self.start_us + (0 if per_cycle == 4 else self.period_us / 4)
        tr = Train(first, self.period_us / per_cycle, self.end_us)
        return self.sign * max(0, tr.edges_upto(upto) - tr.edges_upto(after))


def add_quadrature(m, pair: Quadrature) -> None:
    """The pair's A and B level trains (what scans, interrupts and 1-phase counters see) and
    its counting record; a later pair on the same inputs ends the earlier one."""
    for old in m.quadrature.setdefault((pair.a, pair.b), []):
        if old.end_us is None or old.end_us > pair.start_us:
            old.end_us = max(old.start_us, pair.start_us)
    m.quadrature[(pair.a, pair.b)].append(pair)
    t = pair.period_us
    add_train(m, *pair.a, Train(pair.start_us, t, pair.end_us))
    lag = None if t is None else (t / 4 if pair.sign > 0 else 3 * t / 4)
    add_train(m, *pair.b, Train(pair.start_us + (lag or 0), t, pair.end_us))


def quadrature_count(m, a: tuple[str, int], b: tuple[str, int], per_cycle: int,
                     after: int, upto: int) -> int:
    """Signed A/B counts in (after, upto]; inputs not driven as a pair count nothing."""
    return sum(q.counts(per_cycle, after, upto) for q in m.quadrature.get((a, b), ()))


def time_of_count(net, after: int, upto: int, k: int) -> int:
    """The first whole microsecond in (after, upto] by which `net(t)` (the signed counts of
    (after, t]) has reached k counts: when the k-th count of the interval happened. DECISION:
    for 2-phase and A/B counting, whose net count can go back, the first time it is reached."""
    lo, hi = after + 1, upto
    while lo < hi:
        mid = (lo + hi) // 2
        if abs(net(mid)) >= k:
            hi = mid
        else:
            lo = mid + 1
    return lo


def drive_inputs(m) -> None:
    """Before a scan: every input with a train takes the train's level at the scan's start."""
    for (kind, number), trains in m.pulse_trains.items():
        live = [tr for tr in trains if tr.start_us <= m.now_us]
        if live:
            m.bits[kind][number] = live[-1].level(m.now_us)
