"""A target's signals: the special relays and registers through which its PLC talks to the
machine around it (the NC5's MLC <-> NC and MLC <-> HMI special M/D, manual ch. 5).

A target that has them says so in target.toml `[signals]` (the file of rows, the special
ranges it governs, the channels) and keeps the rows in a tab-separated file beside its tables
(one row per device pattern; `x` in a pattern is the channel digit). Generic code asks here:
the checker (check/signals.py: W250-W252), and every front end that shows what a device is
through `describe_device` (hover, ladder comments, VCD, --watch, the debugger).

Tab-separated rather than TOML: one row per line diffs well, and the 1134 rows of the NC5
read in about a millisecond where tomllib takes some 60 ms of every `mlc check`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from mlctool.targetapi.registry import UnknownTarget, target_package


@dataclass(frozen=True, slots=True)
class Signal:
    """One row of the manual's table."""

    device: str  # the pattern as printed: M2x000 (x: the channel), M30000
    name: str  # the manual's name as printed
    english: str
    direction: str  # MLC->NC | NC->MLC | MLC->HMI | HMI->MLC
    access: str  # R (the NC/system writes it) | R/W
    type: str  # bit | word | 32-bit | 32-bit float
    table: str  # the manual's summary table (5.2.1, 5.2.2)
    sections: tuple[str, ...]  # the function sections that list it (5.3.x)
    line: int  # the row's line in the manual text
    variable: str = ""  # the NC macro variable it maps to (#25000), if any
    decision: str = ""  # DECISION: where the manual contradicts itself about the row

    @property
    def kind(self) -> str:
        return self.device[0]

    @property
    def words(self) -> int:
        return 2 if self.type.startswith("32-bit") else 1

    @property
    def read_only(self) -> bool:
        return self.access == "R"

    @property
    def section(self) -> str:
        """Where the manual describes it: its 5.3 sections, else its summary table."""
        return ", ".join(self.sections) or self.table

    def number(self, channel: int) -> int:
        """The device number of the pattern on a channel (0: a row without x)."""
        return int(self.device[1:].replace("x", str(channel)))


@dataclass(frozen=True, slots=True)
class SignalAt:
    """A device that is (a word of) a signal, on its channel."""

    signal: Signal
    kind: str
    number: int
    channel: int  # 1-8, 0 for the system rows
    high: bool = False  # the upper word of a 32-bit signal

    @property
    def device(self) -> str:
        return f"{self.kind}{self.number}"

    def describe(self) -> str:
        """The one line every front end shows: `M21000 - 程式啟動 cycle start, MLC->NC,
        channel 1, 5.3.2`."""
        return f"{self.device} - {self.text}"

    @property
    def text(self) -> str:
        """describe() without the device: where the device is already shown (`--watch`)."""
        s = self.signal
        where = f"channel {self.channel}" if self.channel else "system"
        half = f", high word of {s.kind}{self.number - 1}" if self.high else ""
        width = f", {s.type}" if s.type not in ("bit", "word") else ""
        return f"{s.name} {s.english}, {s.direction}{width}{half}, {where}, {s.section}"

    @property
    def identifier(self) -> str:
        """The device and its English name as one identifier (M21000_cycle_start): a VCD alias."""
        return f"{self.device}_" + "_".join(re.findall(r"[A-Za-z0-9]+", self.signal.english))


    def rows(self) -> list[tuple[str, str]]:
        """The whole row, field by field (`mlc explain M21000`, the editor's hover)."""
        s = self.signal
        by = {"R": f"R: {_WRITER.get(s.direction, 'the system')} writes it, the MLC reads it", "R/W": "R/W: the MLC writes it"}
        out = [("manual name", s.name), ("English", s.english), ("direction", s.direction),
               ("access", by[s.access]), ("type", s.type + (f" (this is its high word: {s.kind}{self.number - 1})"
                                                             if self.high else "")),
               ("channel", f"{self.channel} (pattern {s.device})" if self.channel else f"the system ({s.device})"),
               ("section", f"{s.section} (row of {s.table}, manual line {s.line})")]
        if s.variable:
            out.append(("NC variable", s.variable))
        if s.decision:
            out.append(("decision", s.decision))
        return out


_WRITER = {"NC->MLC": "the NC", "HMI->MLC": "the HMI"}


@dataclass(frozen=True, slots=True)
class SignalRange:
    kind: str
    lo: int
    hi: int
    direction: str
    channel_digit: int  # which of the five digits is the channel, from the left


@dataclass(frozen=True)
class SignalTable:
    signals: tuple[Signal, ...]
    ranges: tuple[SignalRange, ...]
    channels: tuple[int, int]
    setting: str  # the mlc.toml key of the channels the machine has
    default_channels: int
    section: str
    _patterns: dict[str, tuple[Signal, bool]]  # pattern (M2x000, D2x015) -> (row, high word)

    def range_of(self, kind: str, number: int) -> SignalRange | None:
        for r in self.ranges:
            if r.kind == kind and r.lo <= number <= r.hi:
                return r
        return None

    def at(self, kind: str, number: int) -> SignalAt | None:
        """The signal a device is (a word of), or None."""
        r = self.range_of(kind, number)
        if r is None:
            return None
        digits = str(number)
        found = self._patterns.get(kind + digits)
        if found is not None:
            return SignalAt(found[0], kind, number, 0, found[1])
        k = r.channel_digit - 1
        if len(digits) <= k or not self.channels[0] <= int(digits[k]) <= self.channels[1]:
            return None
        found = self._patterns.get(f"{kind}{digits[:k]}x{digits[k + 1:]}")
        return SignalAt(found[0], kind, number, int(digits[k]), found[1]) if found else None

    def channel_count(self, config_data: dict | None) -> int:
        """The channels the project's machine has (mlc.toml `channels`, else the default)."""
        value = (config_data or {}).get(self.setting, self.default_channels)
        return value if isinstance(value, int) and not isinstance(value, bool) else self.default_channels


_COLUMNS = ("device", "name", "english", "direction", "access", "type", "table", "sections", "line", "variable",
            "decision")


def _read(path: Path, header: dict) -> SignalTable:
    lines = [line.split("\t") for line in path.read_text("utf-8").split("\n") if line and line[0] != "#"]
    at = [lines[0].index(c) for c in _COLUMNS]  # the header line names the columns
    rows = []
    for cells in lines[1:]:
        device, name, english, direction, access, type_, table, sections, line, variable, decision = \
            [cells[k] for k in at]
        rows.append(Signal(device, name, english, direction, access, type_, table,
                           tuple(sections.split(",")) if sections else (), int(line), variable, decision))
    patterns: dict[str, tuple[Signal, bool]] = {}
    for s in rows:
        patterns[s.device] = (s, False)
        if s.words == 2:  # the upper word: D2x014 -> D2x015 (the x stays where it is)
            low = s.device[1:]
            k = low.find("x")
            high = str(int(low.replace("x", "1")) + 1).zfill(len(low))
            patterns[s.kind + (high[:k] + "x" + high[k + 1:] if k >= 0 else high)] = (s, True)
    ranges = tuple(SignalRange(r["kind"], int(r["lo"]), int(r["hi"]), r["direction"], int(r["channel_digit"]))
                   for r in header["ranges"])
    lo, hi = header["channels"]
    return SignalTable(tuple(rows), ranges, (int(lo), int(hi)), header["setting"], int(header["default_channels"]),
                       header["section"], patterns)


@cache
def _table(name: str) -> SignalTable | None:
    from mlctool.targetapi.model import load_target

    header = load_target(name).settings.get("signals")
    if header is None:
        return None
    try:
        folder = Path(target_package(name).tables)
    except UnknownTarget:
        return None
    return _read(folder / header["file"], header)


def signals_of(target) -> SignalTable | None:
    """The signal table of a loaded Target (None: the target has none)."""
    if "signals" not in target.settings:
        return None
    return _table(target.name)


def device_signal(target, kind: str, number: int) -> SignalAt | None:
    """The hook every front end that shows devices asks (hover and completion, ladder, VCD,
    --watch, the debugger's print, variables and monitor): the signal row a device is (a word
    of), None for a device that is no signal or a target without signals."""
    table = signals_of(target) if target is not None else None
    return table.at(kind, number) if table is not None else None


def describe_device(target, kind: str, number: int) -> str | None:
    """device_signal's one line: `M21000 - 程式啟動 cycle start, MLC->NC, channel 1, 5.3.2`."""
    found = device_signal(target, kind, number)
    return found.describe() if found else None
