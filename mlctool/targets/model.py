"""A target's manual tables as plain data, loaded from mlctool/targets/<name>/*.toml.

Generic code asks the Target; nothing outside a target folder names a target's devices.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

TARGETS_DIR = Path(__file__).resolve().parent

BIT_KINDS = frozenset("XYMA")
GROUP_KINDS = frozenset({"KnX", "KnY", "KnM", "KnA"})
CONST_KINDS = frozenset({"K", "F"})


@dataclass(frozen=True, slots=True)
class Area:
    lo: int
    hi: int
    name: str
    write: str = "ok"  # ok | nc | reserved
    latched: bool = False


@dataclass(frozen=True, slots=True)
class DeviceKind:
    name: str
    kind: str  # bit | word | timer | counter | pointer
    lo: int
    hi: int
    areas: tuple[Area, ...]
    section: str
    input: bool = False
    width16_only: bool = False

    def area(self, number: int) -> Area | None:
        for a in self.areas:
            if a.lo <= number <= a.hi:
                return a
        return None


@dataclass(frozen=True, slots=True)
class OperandSpec:
    role: str
    kinds: frozenset[str]
    access: str = "r"  # r | w | rw
    range16: tuple[int, int] | None = None  # constant range, overrides the width's K range
    range32: tuple[int, int] | None = None
    words: tuple[int, int] = (1, 2)  # 16-bit words occupied in the 16-bit / 32-bit form
    bits: int = 1  # consecutive bits occupied by a bit destination
    devices16: tuple[int, int] | None = None  # narrower device-number range per form
    devices32: tuple[int, int] | None = None
    forbid16: tuple[tuple[int, int], ...] = ()  # device numbers not allowed in the 16-bit form
    word_range: tuple[int, int] | None = None  # constant range when operand `word_range_of`
    word_range_of: str | None = None  # ... is a word device (DECO/ENCO n)
    ranges: tuple[tuple[str, tuple[tuple[int, int], ...]], ...] = ()  # per kind: allowed numbers

    def allowed(self, kind: str) -> tuple[tuple[int, int], ...] | None:
        """Device-number ranges this operand allows for `kind` (None: the device's range)."""
        return next((r for k, r in self.ranges if k == kind), None)

    @property
    def writes(self) -> bool:
        return "w" in self.access


@dataclass(frozen=True, slots=True)
class InstrSpec:
    """One mnemonic: a form (16-bit, 32-bit or float) of a manual instruction."""

    mnemonic: str
    api: int | None
    width: int  # 16 or 32
    is_float: bool
    steps: int
    cls: str  # load | and | or | anb | orb | mps | mrd | mpp | inv | nop | output | free | label
    op: str
    operands: tuple[OperandSpec, ...]
    index: bool
    short_steps: bool  # "1~2" steps: 1 in the short ranges, else 2
    table: int  # trailing table entries (VRT), 0 if none
    constraints: tuple[str, ...]  # named cross-operand rules (ZRST), checked generically
    section: str
    notes: tuple[str, ...]
    inputs: tuple[str, ...] = ()  # a multi-input instruction: its inputs, one block each


@dataclass(frozen=True, slots=True)
class Target:
    name: str
    title: str
    manual: str
    capacity: int
    devices: dict[str, DeviceKind]
    instructions: dict[str, InstrSpec]
    settings: dict  # the rest of target.toml (timer bases, limits, decisions)

    def instruction(self, mnemonic: str) -> InstrSpec | None:
        return self.instructions.get(mnemonic.upper())

    def timer_base_ms(self, number: int) -> int:
        for b in self.settings["timer_bases"]:
            if b["lo"] <= number <= b["hi"]:
                return b["ms"]
        raise KeyError(number)

    def is_counter32(self, number: int) -> bool:
        lo, hi = self.settings["counters32"]
        return lo <= number <= hi

    def short_operand(self, kind: str, number: int) -> bool:
        rng = self.settings.get("short_operand", {}).get(kind)
        return rng is not None and rng[0] <= number <= rng[1]

    @property
    def indexable(self) -> frozenset[str]:
        return frozenset(self.settings.get("indexable", ()))

    def krange(self, width: int) -> tuple[int, int]:
        lo, hi = self.settings["k32" if width == 32 else "k16"]
        return lo, hi


def _pair(v) -> tuple[int, int] | None:
    return (int(v[0]), int(v[1])) if v is not None else None


def _operand(o: dict) -> OperandSpec:
    return OperandSpec(
        role=o["role"],
        kinds=frozenset(o["kinds"].split()),
        access=o.get("access", "r"),
        range16=_pair(o.get("range")),
        range32=_pair(o.get("range32", o.get("range"))),
        words=tuple(o.get("words", (1, 2))),
        bits=o.get("bits", 1),
        devices16=_pair(o.get("devices16")),
        devices32=_pair(o.get("devices32")),
        forbid16=tuple(tuple(r) for r in o.get("forbid16", ())),
        word_range=_pair(o.get("word_range")),
        word_range_of=o.get("word_range_of"),
        ranges=tuple((k, tuple(tuple(r) for r in v)) for k, v in sorted(o.get("ranges", {}).items())),
    )


def _instructions(entries: list[dict]) -> dict[str, InstrSpec]:
    out: dict[str, InstrSpec] = {}
    for e in entries:
        operands = tuple(_operand(o) for o in e.get("operands", ()))
        notes = tuple(x for x in (e.get("note"), e.get("decision")) if x)
        is_float = bool(e.get("float", False))
        for width, name, steps in zip((16, 32), e["names"], e["steps"], strict=True):
            if not name:
                continue
            spec = InstrSpec(
                mnemonic=name, api=e.get("api"), width=width, is_float=is_float, steps=steps,
                cls=e["class"], op=e["op"], operands=operands,
                index=bool(e.get("index", e.get("api") is not None and e["class"] != "free")),
                short_steps=e.get("steps_rule") == "short", table=e.get("table", 0),
                constraints=tuple(e.get("constraints", ())),
                section=e["section"], notes=notes, inputs=tuple(e.get("inputs", ())),
            )
            # aliases name the 16-bit form too (FBs: HSPSO is also written FUN140)
            for alias in [name] + (e.get("aliases", []) if width == 16 else []):
                out[alias] = spec
    return out


@cache
def load_target(name: str) -> Target:
    folder = TARGETS_DIR / name
    if not (folder / "target.toml").is_file():
        raise KeyError(name)
    settings = tomllib.loads((folder / "target.toml").read_text("utf-8"))
    devices_raw = tomllib.loads((folder / "devices.toml").read_text("utf-8"))
    devices = {
        k: DeviceKind(
            name=k, kind=v["kind"], lo=v["range"][0], hi=v["range"][1],
            areas=tuple(Area(**a) for a in v.get("areas", ())), section=v["section"],
            input=v.get("input", False), width16_only=v.get("width16_only", False),
        )
        for k, v in devices_raw.items()
    }
    instrs = _instructions(tomllib.loads((folder / "instructions.toml").read_text("utf-8"))["instr"])
    return Target(settings["name"], settings["title"], settings["manual"], settings["capacity"],
                  devices, instrs, settings)


def available_targets() -> list[str]:
    return sorted(p.parent.name for p in TARGETS_DIR.glob("*/target.toml"))
