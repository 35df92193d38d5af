"""A pulse axis's speed profile on virtual time, solved analytically (never pulse by pulse).

A profile is a list of segments (start s, travel in pulses, speed Hz, acceleration Hz/s),
each valid until the next one starts, and an optional end time after which the axis stands
still. Travel is unsigned (pulses put out since the profile's start); the caller gives it a
direction. Speeds ramp linearly: `up`/`down` are the rates (Hz/s; math.inf for a ramp time
of 0), `bias` the start/stop speed: a start jumps to it, a stop ramps down to it and then
stops (the bias-speed figure of the positioning chapters).

Why not fbs/axis.py: that model runs a FATEK positioning program (steps, GOTO, DRVZ modes)
in 1 ms ticks; the VS instructions each need one move, replanned when the speed changes, and
the exact travel at any instant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

EPS = 1e-7  # float slack when turning travel into whole pulses
EPS_T = 1e-9  # s: an end time that is a sum of floats is reached at that instant


@dataclass
class Profile:
    segments: list[tuple[float, float, float, float]] = field(default_factory=list)
    end: float | None = None  # s; None: runs on
    stop_at: float | None = None  # travel of a move that ends at a position


def ended(p: Profile, t: float) -> bool:
    return p.end is not None and t >= p.end - EPS_T


def _ramp(v0: float, v1: float, rate: float) -> tuple[float, float]:
    """Duration and travel of a linear ramp v0 -> v1."""
    if rate == math.inf or v0 == v1:
        return 0.0, 0.0
    dt = abs(v1 - v0) / rate
    return dt, (v0 + v1) / 2 * dt


def at(p: Profile, t: float) -> tuple[float, float]:
    """Travel and speed at t s."""
    if ended(p, t):
        t = p.end
        stopped = True
    else:
        stopped = False
    t0, x0, v0, a = next((seg for seg in reversed(p.segments) if seg[0] <= t), p.segments[0])
    dt = max(0.0, t - t0)
    x, v = x0 + v0 * dt + a * dt * dt / 2, max(0.0, v0 + a * dt)
    if p.stop_at is not None:
        x = min(x, p.stop_at)
    return x, (0.0 if stopped else v)


def run_on(t: float, x: float, v: float, cruise: float, bias: float, up: float, down: float) -> Profile:
    """From (t, x, v): ramp to `cruise` and keep it (a speed without a target position)."""
    v = max(v, min(bias, cruise)) if v < bias else v
    rate = up if cruise >= v else down
    dt, dx = _ramp(v, cruise, rate)
    segs = [(t, x, v, 0.0 if dt == 0 else math.copysign(rate, cruise - v))]
    if dt > 0:
        segs.append((t + dt, x + dx, cruise, 0.0))
    elif segs[0][2] != cruise:
        segs[0] = (t, x, cruise, 0.0)
    return Profile(segs)


def stop(t: float, x: float, v: float, bias: float, down: float) -> Profile:
    """Decelerating stop from (t, x, v): ramp down to the bias speed, then stand still."""
    if v <= bias or down == math.inf:
        return Profile([(t, x, 0.0, 0.0)], end=t)
    dt, _ = _ramp(v, bias, down)
    return Profile([(t, x, v, -down)], end=t + dt)


def halt(t: float, x: float) -> Profile:
    """Immediate stop."""
    return Profile([(t, x, 0.0, 0.0)], end=t)


def move_to(t: float, x: float, v: float, target: float, cruise: float, bias: float,
            up: float, down: float) -> Profile:
    """From (t, x, v): reach travel `target` at the bias speed (then stop): ramp toward
    `cruise`, keep it, ramp down to arrive. A short move peaks lower (triangle); an axis
    already too fast to stop in time ramps down at once and stops on the target."""
    dist = target - x
    if dist <= EPS:
        return Profile([(t, x, 0.0, 0.0)], end=t, stop_at=target)
    v = max(v, bias)
    cruise = max(cruise, bias)

    def braking(u: float) -> float:
        return _ramp(u, bias, down)[1]

    if braking(v) >= dist:  # ramp down now; the stop comes on the target, whatever the speed
        a = 0.0 if down == math.inf else down
        if a == 0.0:
            return Profile([(t, x, v, 0.0)], end=t + dist / v, stop_at=target)
        disc = max(0.0, v * v - 2 * a * dist)
        return Profile([(t, x, v, -a)], end=t + (v - math.sqrt(disc)) / a, stop_at=target)
    peak = cruise
    if cruise > v:
        inv = (0 if up == math.inf else 1 / (2 * up)) + (0 if down == math.inf else 1 / (2 * down))
        if inv > 0:
            top = (dist + (0 if up == math.inf else v * v / (2 * up))
                   + (0 if down == math.inf else bias * bias / (2 * down))) / inv
            peak = min(cruise, math.sqrt(top))
    rate = up if peak >= v else down
    t1, x1 = _ramp(v, peak, rate)
    t3, x3 = _ramp(peak, bias, down)
    cruise_s = max(0.0, dist - x1 - x3) / peak if peak > 0 else 0.0
    segs = [(t, x, v, 0.0 if t1 == 0 else math.copysign(rate, peak - v))]
    if t1 > 0:
        segs.append((t + t1, x + x1, peak, 0.0))
    elif v != peak:
        segs[0] = (t, x, peak, 0.0)
    start_down = t + t1 + cruise_s
    if t3 > 0:
        segs.append((start_down, x + x1 + peak * cruise_s, peak, -down))
    return Profile(segs, end=start_down + t3, stop_at=target)


def time_at(p: Profile, target: float) -> float | None:
    """The time the travel reaches `target` (None: never)."""
    for i, (t0, x0, v0, a) in enumerate(p.segments):
        t_end = p.segments[i + 1][0] if i + 1 < len(p.segments) else p.end
        x_end = at(p, t_end)[0] if t_end is not None else math.inf
        if target <= x_end + EPS:
            dx = max(0.0, target - x0)
            if a == 0:
                return t0 + (dx / v0 if v0 > 0 else 0.0)
            disc = max(0.0, v0 * v0 + 2 * a * dx)
            return t0 + (math.sqrt(disc) - v0) / a
    return None
