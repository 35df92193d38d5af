"""The FBs pulse pins as pulse trains inside `mlc sim --pulse-window` (docs/fbs.md).

The axes run in 1 ms ticks and know how many pulses each tick output, not when: the n
pulses of a tick are spread evenly over it (period P = 1 ms / n, 50 % duty), which keeps the
count exact and the frequency that of the tick. Pins of Ps: Y(2Ps) and Y(2Ps+1) by the
axis' output mode:

- U/D: a forward pulse on the even pin, a reverse pulse on the odd one;
- P/R: pulses on the even pin, the odd pin is the direction (1 = up-count);
- A/B: one pulse = one cycle of A (even pin) with B (odd) a quarter period behind when
  forward, ahead when reverse.
"""

from __future__ import annotations

from mlctool.sim.hardware.pin_window import PinWindow

Levels = dict  # Y number -> level last written in the window


def _set(trace: PinWindow, levels: Levels, n: int, t_ns: int, level: int) -> None:
    if levels.get(n) != level:
        levels[n] = level
        trace.add(t_ns, "Y", n, level)


def open_window(trace: PinWindow, levels: Levels, p: int, mode: str, up: bool) -> None:
    """At the window's start the pins are at rest (direction shown in P/R)."""
    _set(trace, levels, 2 * p, trace.from_ns, 0)
    _set(trace, levels, 2 * p + 1, trace.from_ns, int(up) if mode == "PR" else 0)


def emit(trace: PinWindow, levels: Levels, p: int, mode: str, t0_us: int, dt_us: int,
         n: int, up: bool) -> None:
    """The n pulses axis Ps output in [t0, t0 + dt), inside the window only."""
    if n <= 0 or not mode or not trace.overlaps(t0_us, t0_us + dt_us):
        return
    even, odd = 2 * p, 2 * p + 1
    t0, period = t0_us * 1000, dt_us * 1000 / n
    if mode == "PR" and trace.inside(t0):
        _set(trace, levels, odd, t0, int(up))
    for j in range(n):
        t = t0 + int(j * period)
        if t < trace.from_ns:
            continue
        if t >= trace.to_ns or trace.overflow:
            return
        half, quarter = int(period / 2), int(period / 4)
        if mode == "UD":
            pin = even if up else odd
            _set(trace, levels, pin, t, 1)
            _set(trace, levels, pin, t + half, 0)
        elif mode == "PR":
            _set(trace, levels, even, t, 1)
            _set(trace, levels, even, t + half, 0)
        else:  # AB quadrature
            lead, lag = (even, odd) if up else (odd, even)
            _set(trace, levels, lead, t, 1)
            _set(trace, levels, lag, t + quarter, 1)
            _set(trace, levels, lead, t + half, 0)
            _set(trace, levels, lag, t + half + quarter, 0)
