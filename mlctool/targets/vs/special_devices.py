"""The VS devices a stimulus, `--watch` and the trace name beyond the device table
(targetapi SpecialDevice): a special module's buffer registers `BFM2#5` (6-9 FROM/TO), the
memory card data bank `DB#100` (6-11 DBRD/DBWR) and peer stations' devices `CP1#2.D10`
(6-10 LINK/CPUL, serial/peers.py). Their memory is the Machine's (m.bfm, m.databank,
m.peers): kept over a power cycle of the simulated PLC.
"""

from __future__ import annotations

import re

from mlctool.sim.state import DeviceView, Machine, NameError_, bits_f32, f32_bits, s16, s32
from mlctool.targetapi.model import Target
from mlctool.targetapi.simulation import SpecialDevice
from mlctool.targets.vs.bfm import last_register, slots
from mlctool.targets.vs.databank import size
from mlctool.targets.vs.serial import peers

BFM = "BFM"  # DeviceView kind of a special module's buffer register: number = slot x BFM_SLOT + register
BFM_SLOT = 1 << 16
_BFM_NAME = re.compile(r"BFM(?P<slot>[0-9]+)#(?P<reg>[0-9]+)(?::(?P<view>[A-Za-z]+))?")
DATABANK = "DB"  # DeviceView kind of a memory card data bank word: number = address
_DB_NAME = re.compile(r"DB#(?P<addr>[0-9]+)(?::(?P<view>[A-Za-z]+))?")


def _memory(m: Machine, kind: str, n: int) -> tuple[dict, object]:
    """The dict behind a buffer register ((slot, register) keys) or a data bank word."""
    return (m.bfm, divmod(n, BFM_SLOT)) if kind == BFM else (m.databank, n)


def _next(key):
    """The key of the word after `key` (the high word of a :d / :f view)."""
    return (key[0], key[1] + 1) if isinstance(key, tuple) else key + 1



def _read(m: Machine, view: DeviceView) -> int | float:
    memory, key = _memory(m, view.kind, view.number)
    raw = memory.get(key, 0)
    if view.view in ("d", "f"):
        raw |= memory.get(_next(key), 0) << 16
        return s32(raw) if view.view == "d" else bits_f32(raw)
    return raw if view.view == "h" else s16(raw)


def _write(m: Machine, view: DeviceView, value: int | float) -> None:
    memory, key = _memory(m, view.kind, view.number)
    raw = f32_bits(float(value)) if view.view == "f" else int(value) & 0xFFFFFFFF
    memory[key] = raw & 0xFFFF
    if view.view in ("d", "f"):
        memory[_next(key)] = raw >> 16


def _bfm_text(view: DeviceView) -> str:  # BFM2#5, BFM2#5:d
    slot, reg = divmod(view.number, BFM_SLOT)
    return f"BFM{slot}#{reg}" + ("" if view.view == "w" else f":{view.view}")


def _bank_text(view: DeviceView) -> str:  # DB#100, DB#100:d
    return f"DB#{view.number}" + ("" if view.view == "w" else f":{view.view}")


def _bfm_name(text: str, target: Target) -> DeviceView:
    """`BFM2#5` (register 5 of the module in slot 2), views :h, :d, :f (VS 6-9 FROM/TO)."""
    table = target.settings.get("buffer_memory")
    if not table:
        raise NameError_(f"{text!r}: target {target.name} has no special-module buffer memory")
    m = _BFM_NAME.fullmatch(text.strip().upper())
    if not m:
        raise NameError_(f"{text!r} is not a buffer register (e.g. BFM1#0, BFM2#10:d)")
    slot, reg, view = int(m["slot"]), int(m["reg"]), (m["view"] or "w").lower()
    top = slots(target)
    if not 1 <= slot <= top:
        raise NameError_(f"{text!r}: module slots are 1-{top} on model {target.model}" if top else
                         f"{text!r}: model {target.model} has no special modules")
    last = last_register(target) - (1 if view in ("d", "f") else 0)
    if not 0 <= reg <= last:
        raise NameError_(f"{text!r}: buffer registers are #0-#{last_register(target)}")
    if view not in ("w", "h", "d", "f"):
        raise NameError_(f"{text!r}: buffer registers take the views :h, :d, :f")
    return DeviceView(BFM, slot * BFM_SLOT + reg, view, special=BUFFER_MEMORY)


def _bank_name(text: str, target: Target) -> DeviceView:
    """`DB#100` (memory card data bank word 100), views :h, :d, :f (VS 6-11 DBRD/DBWR)."""
    words = size(target)
    if not words:
        raise NameError_(f"{text!r}: target {target.name} has no memory card data bank")
    m = _DB_NAME.fullmatch(text.strip().upper())
    if not m:
        raise NameError_(f"{text!r} is not a data bank word (e.g. DB#0, DB#100:d)")
    addr, view = int(m["addr"]), (m["view"] or "w").lower()
    if addr > words - 1:
        raise NameError_(f"{text!r}: data bank addresses are #0-#{words - 1}")
    if view in ("d", "f") and addr == words - 1:
        raise NameError_(f"{text!r}: the pair needs #{words}, past the last address #{words - 1}")
    if view not in ("w", "h", "d", "f"):
        raise NameError_(f"{text!r}: data bank words take the views :h, :d, :f")
    return DeviceView(DATABANK, addr, view, special=DATA_BANK)


def _parse_bfm(text: str, target: Target) -> DeviceView | None:
    return _bfm_name(text, target) if text.strip().upper().startswith(BFM) else None


def _parse_bank(text: str, target: Target) -> DeviceView | None:
    return _bank_name(text, target) if text.strip().upper().startswith(DATABANK + "#") else None


def _parse_peer(text: str, target: Target) -> DeviceView | None:
    return peers.parse_name(text, target, PEER_STATION) \
        if re.match(peers.PEER + r"[0-9]+#", text.strip().upper()) else None


BUFFER_MEMORY = SpecialDevice(_parse_bfm, _read, _write, _bfm_text)
DATA_BANK = SpecialDevice(_parse_bank, _read, _write, _bank_text)
PEER_STATION = SpecialDevice(_parse_peer, peers.read_view, peers.write_view, peers.view_name)
SPECIAL_DEVICES = (BUFFER_MEMORY, DATA_BANK, PEER_STATION)
