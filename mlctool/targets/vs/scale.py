"""Scaling by a table of points (manual 6-21 FNC 259 SCL, 269 SCL2)."""

from __future__ import annotations

from decimal import ROUND_HALF_UP, Decimal

from mlctool.sim import semantics as base
from mlctool.targets.vs.common import op_error, read_block


def _scale(interleaved: bool):
    """SCL S1 S2 D: S2 = the number of points, then X1, Y1, X2, Y2 ... (SCL) or X1..Xn,
    Y1..Yn (SCL2), words (32-bit: pairs); D = the Y of S1 on the line between the two points
    around it, rounded half-up (FNC 259/269). Operation errors (6706): X not ascending, two
    neighbouring values more than 65535 apart, S1 outside X1..Xn. An X given twice takes the
    second point's Y (the page). DECISION: fewer than 2 points is an operation error."""
    @base._on
    def run(m, s) -> None:
        src, table, dst = s.ops
        n = read_block(m, table, 1, s.width)[0]
        if n < 2:
            op_error(m, s, f"{n} points: a table needs at least 2")
            return
        values = read_block(m, table, 1 + 2 * n, s.width)[1:]
        if interleaved:
            xs, ys = values[0::2], values[1::2]
        else:
            xs, ys = values[:n], values[n:]
        if any(b < a for a, b in zip(xs, xs[1:])):
            op_error(m, s, "the X values are not in ascending order")
            return
        if any(abs(b - a) > 65535 for seq in (xs, ys) for a, b in zip(seq, seq[1:])):
            op_error(m, s, "two neighbouring points are more than 65535 apart")
            return
        x = src.get(m)
        if not xs[0] <= x <= xs[-1]:
            op_error(m, s, f"S1 = {x} is outside the table's {xs[0]}..{xs[-1]}")
            return
        for k in range(n - 1):  # the last segment holding x: an X given twice takes point 2
            if xs[k] <= x <= xs[k + 1]:
                seg = k
        x0, x1, y0, y1 = xs[seg], xs[seg + 1], ys[seg], ys[seg + 1]
        if x1 == x0:
            y = Decimal(y1)
        else:
            y = Decimal(y0) + Decimal(y1 - y0) * Decimal(x - x0) / Decimal(x1 - x0)
        # half-up on the magnitude ("4捨5入")
        dst.set(m, int(y.quantize(Decimal(1), rounding=ROUND_HALF_UP)))
    return run


SCALE_ACTIONS = {"scl": _scale(True), "scl2": _scale(False)}
