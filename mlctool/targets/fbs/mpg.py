"""FUN148 MPG: an axis following a manual pulse generator (handwheel) on virtual time.

Manual 001 ch. 11, FUN148 (OS >= V4.60) and R4020 (OS >= V4.63). Every sampling interval
the instruction reads the handwheel's high-speed counter, computes
`pulses = (handwheel pulses in the interval x Fa) / Fb` and outputs them at Fo with the
FUN141 ramp (P5 start, P4/P8 slope). Decisions (docs/fbs.md, "FUN148 MPG"):

- the interval is 50 ms of virtual time from the scan EN went On (the manual runs FUN148
  from the 50 ms interrupt; the simulator has none): a sample is taken by the first
  execution at or after each 50 ms mark;
- the handwheel count of HSC Sc is DR(4096 + 4 Sc) (HSC4's current value is DR4112 in the
  chapter's homing example 1), signed 32-bit;
- the remainder of the division is carried to the next sample (no drift at Fa/Fb < 1);
- pulses not output by the next sample are lost (the manual's 失步), counted in WR+3;
- the axis is held (M1992+Ps Off) while pulses are output, so FUN140/147 wait; a sample
  taken while FUN140/147 hold the axis outputs nothing (and is consumed);
- R4020 high byte 55H: bit 2Ps inhibits forward, bit 2Ps+1 reverse output of Ps.
"""

from __future__ import annotations

from dataclasses import dataclass

from mlctool.targets.fbs.axis import TICK_US, Axis

SAMPLE_US = 50_000
HSC_BASE, HSC_STRIDE = 4096, 4  # DR4096 + 4 Sc: current value of HSC Sc
INHIBIT, INHIBIT_KEY = 4020, 0x55  # R4020: high byte 55H enables the low byte's bits


@dataclass
class Follower:
    """FUN148 state of one axis (WR+0/1 last count, WR+2 carry, WR+3 pulses lost)."""

    owner: int = -1  # step index of the FUN148 that samples for this axis
    last_count: int = 0
    next_us: int = 0  # virtual time of the next sample
    carry: int = 0  # remainder of (count x Fa) / Fb
    lost: int = 0
    pending: int = 0  # pulses of the current interval still to output
    fo: float = 0.0
    acc: float = 0.0
    enabled: bool = False

    @property
    def active(self) -> bool:
        return self.pending > 0


def inhibited(r4020: int, ps: int, forward: bool) -> bool:
    """R4020 travel-limit inhibit of FUN148 (OS >= V4.63)."""
    if r4020 >> 8 != INHIBIT_KEY:
        return False
    return bool(r4020 >> (2 * ps + (0 if forward else 1)) & 1)


def sample(f: Follower, count: int, fa: int, fb: int) -> int:
    """Signed output pulses for a new handwheel count; the remainder is carried."""
    total = (count - f.last_count) * fa + f.carry
    f.last_count = count
    if fb <= 0:  # no ratio: nothing to output (DECISION; the manual gives no error code)
        f.carry = 0
        return 0
    out = abs(total) // fb * (1 if total >= 0 else -1)
    f.carry = total - out * fb
    return out


def start(f: Follower, a: Axis, pulses: int, fo: float) -> None:
    """Output `pulses` (signed) on axis `a` at up to `fo`; pulses still pending are lost."""
    f.lost = min(0xFFFF, f.lost + f.pending)
    f.pending, f.fo = abs(pulses), fo
    if not pulses:
        release(f, a)
        return
    if a.dir != (1 if pulses > 0 else -1):
        a.freq = 0.0  # reversing: restart from P5
    a.dir = 1 if pulses > 0 else -1
    a.ready, a.remaining = False, f.pending


def release(f: Follower, a: Axis) -> None:
    f.pending, f.acc = 0, 0.0
    a.freq, a.remaining, a.ready = 0.0, 0, True


def run(f: Follower, a: Axis, dt_us: int) -> None:
    """Output pending pulses for dt: ramp at the FUN141 slope from P5 up to Fo, brake
    to P5 before the end; exact counts (never more than the sample asked for)."""
    p = a.params
    t = 0
    while t < dt_us and f.pending:
        tick = min(TICK_US, dt_us - t)
        t += tick
        dt = tick / 1e6
        top = min(f.fo, p.p4_max, 921600)
        start_f = min(p.p5_start, top)
        fr = a.freq or start_f
        braking = (fr * fr - start_f ** 2) / (2 * p.decel) if p.decel != float("inf") else 0
        if f.pending <= braking:
            fr = max(start_f, fr - p.decel * dt)
        elif fr < top:
            fr = min(top, fr + p.accel * dt)
        else:
            fr = top
        a.freq = fr
        f.acc += fr * dt
        n = min(int(f.acc), f.pending)
        f.acc -= n
        f.pending -= n
        sign = -a.dir if p.p9_count_down else a.dir
        a.position += sign * n
        a.pulses_out += n
        a.last_dir = a.dir
        a.remaining = f.pending
    if not f.pending:
        release(f, a)
