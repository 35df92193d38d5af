"""Where each Modbus address of the simulated PLC points: the maps of maps.toml cut to a
target, and which devices a client may write (docs/commissioning.md, "Maps", "Writes").

A map has four tables (coils, discrete inputs, holding registers, input registers); each is a
sorted list of entries, an entry a run of devices of one letter from one protocol address
on. Resolving an address range gives the (device, number, half) of every address in it, or
None when one of them is outside every entry (exception 02). Nothing here touches a Machine:
resolving runs on the network thread, the reads and writes on the scan thread
(commission/modbus_slave.py).
"""

from __future__ import annotations

import bisect
import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from mlctool.targetapi.model import Target
from mlctool.targetapi.signals import device_signal

TABLES = ("coils", "discrete_inputs", "holding", "input_registers")
BIT_TABLES = ("coils", "discrete_inputs")
WRITABLE_TABLES = ("coils", "holding")
# devices an HMI writes unless the allow list says otherwise: not the inputs X (the terminals:
# the stimulus's and the models'), nor A (NC5's NC -> MLC inputs)
DEFAULT_READ_ONLY = frozenset("XA")


@dataclass(frozen=True, slots=True)
class Entry:
    first: int  # protocol address of device `lo`
    device: str
    lo: int
    hi: int
    words: int = 1  # 2: a 32-bit device over two addresses, low word first

    @property
    def last(self) -> int:
        return self.first + (self.hi - self.lo + 1) * self.words - 1


@dataclass(frozen=True)
class Map:
    name: str
    title: str
    tables: dict[str, tuple[Entry, ...]]

    def resolve(self, table: str, addr: int, count: int) -> list[tuple[str, int, int]] | None:
        """[(device, number, half)] of `count` addresses from `addr` (half: 0 the low or only
        word, 1 the high word of a pair); None if any address is not mapped."""
        entries = self.tables[table]
        starts = [e.first for e in entries]
        out = []
        a, end = addr, addr + count
        while a < end:
            i = bisect.bisect_right(starts, a) - 1
            if i < 0 or a > entries[i].last:
                return None
            e = entries[i]
            stop = min(end, e.last + 1)
            for x in range(a, stop):
                offset = x - e.first
                out.append((e.device, e.lo + offset // e.words, offset % e.words))
            a = stop
        return out

    def rows(self) -> list[tuple[str, Entry]]:
        """(table, entry) of every entry, for the documentation and `mlc run --map-table`."""
        return [(t, e) for t in TABLES for e in self.tables[t]]


@cache
def _raw_maps() -> dict:
    with open(Path(__file__).with_name("maps.toml"), "rb") as f:
        return tomllib.load(f)


def map_names() -> list[str]:
    return sorted(_raw_maps())


def default_map(target: Target) -> str:
    """The map named as the target, else vs (the FX-family layout)."""
    return target.name if target.name in _raw_maps() else "vs"


def load_map(name: str, target: Target) -> Map:
    """Map `name` cut to `target`'s devices (KeyError: no such map)."""
    raw = _raw_maps()[name]
    tables: dict[str, tuple[Entry, ...]] = {}
    for table in TABLES:
        spec = raw[table]
        if isinstance(spec, str):  # the same addresses as another table
            tables[table] = tables[spec]
            continue
        entries = []
        for item in spec:
            entry = _cut(Entry(item["first"], item["device"], item["lo"], item["hi"], item.get("words", 1)),
                         target, table in BIT_TABLES)
            if entry is not None:
                entries.append(entry)
        tables[table] = tuple(sorted(entries, key=lambda e: e.first))
    return Map(name, raw["title"], tables)


def _cut(e: Entry, target: Target, bits: bool) -> Entry | None:
    """The entry's devices that `target` has; for counter values, only counters of the
    entry's width (a 32-bit counter is no 16-bit register)."""
    dev = target.devices.get(e.device)
    if dev is None or (bits and dev.kind not in ("bit", "timer", "counter")) \
            or (not bits and dev.kind not in ("word", "timer", "counter")):
        return None
    lo, hi = max(e.lo, dev.lo), min(e.hi, dev.hi)
    if e.device == "C" and not bits:
        c_lo, c_hi = target.settings["counters32" if e.words == 2 else "counters16"]
        lo, hi = max(lo, c_lo), min(hi, c_hi)
    if lo > hi:
        return None
    return Entry(e.first + (lo - e.lo) * e.words, e.device, lo, hi, e.words)


class Permissions:
    """Which devices a client may write: none (`--read-only`), the allow list (`--allow`),
    or by default every device but the inputs (DEFAULT_READ_ONLY). Never the target's system
    areas (read-only special devices, numbers that do not exist): the PLC refuses them too."""

    def __init__(self, target: Target, read_only: bool = False,
                 allow: list[tuple[str, int, int]] | None = None):
        self.target = target
        self.read_only = read_only
        self.allow = allow

    def writable(self, device: str, number: int) -> bool:
        if self.read_only:
            return False
        if self.allow is not None:
            if not any(d == device and lo <= number <= hi for d, lo, hi in self.allow):
                return False
        elif device in DEFAULT_READ_ONLY:
            return False
        dev = self.target.devices.get(device)
        area = dev.area(number) if dev is not None else None
        if area is not None and area.write == "signals":  # the NC5's table says who writes it
            found = device_signal(self.target, device, number)
            return found is None or not found.signal.read_only or found.signal.direction == "HMI->MLC"
        return area is None or area.write not in ("system", "absent", "reserved")
