"""Value conversions (manual 6-15 FNC 170 GRY / 171 GBIN, 6-21 FNC 256 LIMIT / 257 BAND /
258 ZONE)."""

from __future__ import annotations

from mlctool.sim import semantics as base
from mlctool.sim.state import Machine, s16, s32
from mlctool.targets.vs.common import op_error


def _wrap(s, v: int) -> int:
    return s32(v) if s.width == 32 else s16(v)


def _limit_of(s) -> int:
    return (1 << 31) - 1 if s.width == 32 else 32767


@base._on
def gry(m: Machine, s) -> None:
    """GRY S D: binary -> Gray code (FNC 170); S outside 0-32767 (0-2147483647): operation error."""
    v = s.ops[0].get(m)
    if not 0 <= v <= _limit_of(s):
        op_error(m, s, f"{v} is outside 0-{_limit_of(s)}")
        return
    s.ops[1].set(m, v ^ (v >> 1))


@base._on
def gbin(m: Machine, s) -> None:
    """GBIN S D: Gray code -> binary (FNC 171)."""
    v = s.ops[0].get(m)
    if not 0 <= v <= _limit_of(s):
        op_error(m, s, f"{v} is outside 0-{_limit_of(s)}")
        return
    out, shift = v, v >> 1
    while shift:
        out ^= shift
        shift >>= 1
    s.ops[1].set(m, out)


def _bounds(m: Machine, s) -> tuple[int, int] | None:
    lo, hi = s.ops[0].get(m), s.ops[1].get(m)
    if lo > hi:  # DECISION: the page's curves need S1 <= S2
        op_error(m, s, f"S1 = {lo} is above S2 = {hi}")
        return None
    return lo, hi


@base._on
def limit(m: Machine, s) -> None:
    """LIMIT S1 S2 S3 D: S3 kept within S1..S2 (FNC 256)."""
    b = _bounds(m, s)
    if b:
        s.ops[3].set(m, max(b[0], min(b[1], s.ops[2].get(m))))


@base._on
def band(m: Machine, s) -> None:
    """BAND S1 S2 S3 D: dead band: S3 - S1 below S1, 0 inside, S3 - S2 above (FNC 257);
    DECISION: a result past the width wraps (no flags)."""
    b = _bounds(m, s)
    if b:
        v = s.ops[2].get(m)
        s.ops[3].set(m, _wrap(s, v - b[0] if v < b[0] else v - b[1] if v > b[1] else 0))


@base._on
def zone(m: Machine, s) -> None:
    """ZONE S1 S2 S3 D: S3 + S1 when S3 < 0, 0 at 0, S3 + S2 when S3 > 0 (FNC 258; the
    page's curve, its flattened text prints "<-5000"); a result past the width wraps."""
    neg, pos, v = s.ops[0].get(m), s.ops[1].get(m), s.ops[2].get(m)
    s.ops[3].set(m, _wrap(s, v + neg if v < 0 else v + pos if v > 0 else 0))


CONVERT_ACTIONS = {"gry": gry, "gbin": gbin, "limit": limit, "band": band, "zone": zone}
