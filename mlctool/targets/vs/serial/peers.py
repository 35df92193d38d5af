"""Peer PLC stations on the serial ports (Vigor VS LINK 6-10 FNC 89, CPUL FNC 87).

A peer is a `model vsplc link=CPn station=k` line of the stimulus (mlctool/devices/vsplc.py).
Its devices are simulated as memory only (no program runs in it) that LINK/CPUL read and
write and the stimulus sets and checks by name: `CP1#2.D10` (register D10 of station 2 on
CP1), `CP1#2.D10:h` / `:d`, `CP1#2.M5`, `CP1#2.Y10` (octal X/Y, as the target numbers them).
Registers are 0 until written; the memory lives in Machine.peers and outlives a power cycle
of the simulated PLC (the peers are other PLCs).
"""

from __future__ import annotations

import re

from mlctool.sim.state import (
    DeviceView,
    Machine,
    NameError_,
    bits_f32,
    f32_bits,
    put_words,
    s16,
    s32,
)
from mlctool.syntax.operands import device_number
from mlctool.targetapi.model import Target

PEER = "CP"  # DeviceView kinds "CP1#2.D": a register of peer station 2 on port CP1

WORD_KINDS = "DR"
BIT_KINDS = "XYMS"
_NAME = re.compile(r"CP(?P<port>[0-9]+)#(?P<station>[0-9]+)\.(?P<dev>[A-Z])(?P<num>[0-9]+)"
                   r"(?::(?P<view>[A-Z]+))?")


def parse_name(text: str, target: Target, special=None) -> DeviceView:
    """`special`: the SpecialDevice the view carries (special_devices.py)."""
    m = _NAME.fullmatch(text.strip().upper())
    if not m:
        raise NameError_(f"{text!r} is not a peer station device (e.g. CP1#2.D10, CP1#2.M5)")
    port, station, kind = int(m["port"]), int(m["station"]), m["dev"]
    ports = target.settings.get("serial_ports", {})
    count = ports.get("count", {})
    top = count.get(target.model or "", 5) if isinstance(count, dict) else int(count or 0)
    if not 1 <= port <= top:
        raise NameError_(f"{text!r}: ports are CP1-CP{top} on this model" if top else
                         f"{text!r}: target {target.name} has no serial ports")
    if not 0 <= station <= 254:
        raise NameError_(f"{text!r}: stations are 0-254 (6-10 LINK/CPUL)")
    dev = target.devices.get(kind)
    if dev is None or kind not in WORD_KINDS + BIT_KINDS:
        raise NameError_(f"{text!r}: peer stations show {', '.join(WORD_KINDS + BIT_KINDS)} devices")
    digits = m["num"]
    if dev.radix == 8 and ("8" in digits or "9" in digits):
        raise NameError_(f"{text!r}: {kind} is numbered in octal")
    number = int(digits, dev.radix)
    view = (m["view"] or ("w" if kind in WORD_KINDS else "bit")).lower()
    allowed = ("w", "h", "d", "f") if kind in WORD_KINDS else ("bit",)
    if view not in allowed:
        raise NameError_(f"{text!r}: {kind} of a peer takes the views {', '.join(':' + v for v in allowed)}"
                         if kind in WORD_KINDS else f"{text!r}: bit devices take no view")
    if not dev.lo <= number <= dev.hi - (1 if view in ("d", "f") else 0):
        raise NameError_(f"{text!r}: no such device ({kind}{dev.lo}-{kind}{dev.hi})")
    return DeviceView(f"{PEER}{port}#{station}.{kind}", number, view, radix=dev.radix, special=special)


def view_name(view: DeviceView) -> str:  # CP1#2.D10, CP1#2.M5
    return f"{view.kind}{device_number(view.number, view.radix)}" + \
        ("" if view.view in ("w", "bit") else f":{view.view}")


def _where(view: DeviceView) -> tuple[tuple[int, int], str]:
    port, rest = view.kind[len(PEER):].split("#")
    station, kind = rest.split(".")
    return (int(port), int(station)), kind


def memory(m: Machine, port: int, station: int) -> dict[tuple[str, int], int]:
    return m.peers.setdefault((port, station), {})


def read_view(m: Machine, view: DeviceView) -> int | float:
    key, kind = _where(view)
    mem = memory(m, *key)
    raw = mem.get((kind, view.number), 0)
    if view.view == "bit":
        return raw
    if view.view in ("d", "f"):
        raw |= mem.get((kind, view.number + 1), 0) << 16
        return s32(raw) if view.view == "d" else bits_f32(raw)
    return raw if view.view == "h" else s16(raw)


def write_view(m: Machine, view: DeviceView, value: int | float) -> None:
    key, kind = _where(view)
    mem = memory(m, *key)
    if view.view == "bit":
        mem[(kind, view.number)] = 1 if value else 0
        return
    raw = f32_bits(float(value)) if view.view == "f" else int(value) & 0xFFFFFFFF
    mem[(kind, view.number)] = raw & 0xFFFF
    if view.view in ("d", "f"):
        mem[(kind, view.number + 1)] = raw >> 16


# -- block transfers (LINK/CPUL): `length` points of kind from number, as raw values

def own_block(m: Machine, kind: str, number: int, length: int) -> list[int]:
    return list((m.bits if kind in BIT_KINDS else m.words)[kind][number:number + length])


def set_own_block(m: Machine, kind: str, number: int, values: list[int]) -> None:
    # (the table's range is checked at build)
    put_words((m.bits if kind in BIT_KINDS else m.words)[kind], number, values)
    for k in range(len(values)):
        m.writer[(kind, number + k)] = m.pc


def peer_block(m: Machine, port: int, station: int, kind: str, number: int, length: int) -> list[int]:
    mem = memory(m, port, station)
    return [mem.get((kind, number + k), 0) for k in range(length)]


def set_peer_block(m: Machine, port: int, station: int, kind: str, number: int, values: list[int]) -> None:
    mem = memory(m, port, station)
    for k, v in enumerate(values):
        mem[(kind, number + k)] = v
