"""The XC100's kinematic axis: one fixed time step of a commanded motion, no wall clock.

Positions are command pulses (10000 encoder pulses per motor revolution through the electronic
gear, 5.1). The command position moves on a trapezoidal profile (speed % x HighSpeed, times to
reach the set speed from the point table or 0804H/0805H); the actual position follows at a
steady lag of velocity / kp and cannot pass the mechanical ends or a workpiece.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass
class Motion:
    """What the axis is doing. `target` None = velocity mode (JOG, TSL, homing searches)."""

    kind: str  # point | cmd | jog | home
    target: float | None
    direction: int  # +1 / -1: velocity-mode direction
    speed: float  # set speed, pulses/s
    acc: float  # pulses/s^2
    dec: float
    end_speed: float = 0.0  # > 0: the next -R point follows without a stop (4.2)
    torque: int = 1000  # torque limit, x0.1 %
    torque_stop: bool = False  # TSL and -T: the move ends when the torque limit is reached
    point: int = -1
    phase: str = ""  # homing: seek zback zseek offset; jog: inch pause run
    stopping: bool = False  # decelerating to a stop (STOP, LOCK, JOG release)
    stop_status: int = 0  # ActionStatus after a stop: 0 normal, 2 abnormal
    soft_limited: bool = False  # the target was cut at a software limit
    arrived: bool = False  # command output finished
    timer_us: int = 0  # wait time, teach/jog timers, homing torque time
    near_target: float | None = None  # NEAR compares with this (ABS/INC targets only, 3.8)


def ramp_rate(speed: float, time_ms: int) -> float:
    """Acceleration that reaches `speed` in `time_ms` (4.1: time to the set speed)."""
    return max(speed, 1.0) / (max(time_ms, 1) / 1000.0)


def step_target(cmd: float, vel: float, m: Motion, h: float) -> tuple[float, float, bool]:
    """One step of `h` seconds toward m.target -> (cmd, vel, arrived)."""
    r = m.target - cmd
    if r == 0:
        return cmd, m.end_speed * (1 if vel >= 0 else -1), True
    d = 1 if r > 0 else -1
    s = vel * d  # speed along the way to the target (negative: still moving away)
    if m.stopping:
        s_new = max(0.0, s - m.dec * h)
    else:
        s_new = s + m.acc * h if s < m.speed else max(m.speed, s - m.dec * h)
        # never faster than what still stops (or slows to end_speed) at the target
        s_new = min(s_new, math.sqrt(m.end_speed ** 2 + 2.0 * m.dec * abs(r)))
    if s_new * h >= abs(r):
        return m.target, m.end_speed * d, True
    return cmd + s_new * h * d, s_new * d, m.stopping and s_new == 0.0


def step_velocity(vel: float, m: Motion, h: float) -> float:
    """One step of a velocity-mode motion -> new signed velocity."""
    s = vel * m.direction
    if m.stopping:
        s_new = max(0.0, s - m.dec * h)
    elif s < m.speed:
        s_new = min(m.speed, s + m.acc * h)
    else:
        s_new = max(m.speed, s - m.dec * h)
    return s_new * m.direction
