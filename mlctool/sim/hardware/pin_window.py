"""Pulse pins traced as real pulse trains for a time window (`mlc sim --pulse-window`).

A target's simulation extension that outputs pulse trains between scans (FBs FUN140/147/148)
records the pins' level changes here, in nanoseconds, but only inside the window; the VCD
writer (vcd.py) puts them in place of the pins' per-scan levels there. The number of edges is
bounded (EDGE_LIMIT): a recorder that would exceed it stops recording and says so, and
`mlc sim` refuses the window with a usage error instead of writing a huge file.
"""

from __future__ import annotations

from dataclasses import dataclass, field

EDGE_LIMIT = 1_000_000  # level changes written for one window (docs/fbs.md "Pulse pins")


@dataclass
class PinWindow:
    from_us: int
    to_us: int
    limit: int = EDGE_LIMIT
    edges: list[tuple[int, str, int, int]] = field(default_factory=list)  # (t ns, kind, n, level)
    pins: set[tuple[str, int]] = field(default_factory=set)  # pins whose levels the window shows
    overflow: bool = False

    @property
    def from_ns(self) -> int:
        return self.from_us * 1000

    @property
    def to_ns(self) -> int:
        return self.to_us * 1000

    def overlaps(self, t0_us: int, t1_us: int) -> bool:
        return t0_us < self.to_us and t1_us > self.from_us

    def inside(self, t_ns: int) -> bool:
        return self.from_ns <= t_ns < self.to_ns

    def add(self, t_ns: int, kind: str, n: int, level: int) -> None:
        """One level change of pin kind+n at t (ignored outside the window)."""
        self.pins.add((kind, n))
        if not self.inside(t_ns) or self.overflow:
            return
        if len(self.edges) >= self.limit:
            self.overflow = True
            return
        self.edges.append((t_ns, kind, n, level))


def parse_window(text: str, parse_time) -> tuple[int, int]:
    """`FROM..TO` (stimulus time syntax, e.g. `100ms..150ms`) -> (from us, to us)."""
    a, sep, b = text.partition("..")
    if not sep:
        raise ValueError("give FROM..TO, e.g. 100ms..150ms")
    lo, hi = parse_time(a.strip()), parse_time(b.strip())
    if hi <= lo:
        raise ValueError(f"the window {text!r} is empty: TO must be after FROM")
    return lo, hi
