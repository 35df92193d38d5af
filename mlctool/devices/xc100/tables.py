"""The XC100's data tables (params.toml, points.toml, alarms.toml) as plain dataclasses.

The TOML files cite the manual's sections and carry the decisions where it is silent.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache
from importlib import resources


@dataclass(frozen=True, slots=True)
class Param:
    addr: int
    words: int
    name: str
    section: str
    lo: int
    hi: int
    default: int
    reboot: bool
    signal: str  # "in" / "out" for IO assignment parameters, else ""
    note: str


@dataclass(frozen=True, slots=True)
class PointField:
    offset: int
    words: int
    name: str
    lo: int
    hi: int
    default: int
    values: tuple[int, ...]  # allowed values when not a range
    ui_lo: int  # the 4.1 point-table screen's range (positions in 0.01 mm); lo/hi are 8.2's
    ui_hi: int

    def ui_allows(self, v: int) -> bool:
        """4.1's range, or the field's initial value (which the screen shows unchanged)."""
        return self.ui_lo <= v <= self.ui_hi or v == self.default


@dataclass(frozen=True, slots=True)
class Tables:
    params: tuple[Param, ...]
    by_addr: dict[int, Param]
    by_name: dict[str, Param]
    fields: tuple[PointField, ...]
    modes: dict[int, str]
    alarms: dict[int, tuple[str, int]]  # code -> (name, blink count)
    errors: dict[int, str]

    def field(self, name: str) -> PointField:
        return next(f for f in self.fields if f.name == name)

    def inputs(self) -> list[Param]:
        return [p for p in self.params if p.signal == "in"]

    def outputs(self) -> list[Param]:
        return [p for p in self.params if p.signal == "out"]


def _load(name: str) -> dict:
    return tomllib.loads(resources.files(__package__).joinpath(name).read_text(encoding="utf-8"))


@cache
def tables() -> Tables:
    raw = _load("params.toml")["param"]
    params = tuple(Param(int(p["addr"], 16), p.get("words", 1), p["name"], p["section"], p["min"],
                         p["max"], p["default"], p.get("reboot", False), p.get("signal", ""),
                         p.get("note", "")) for p in raw)
    pts = _load("points.toml")
    fields = []
    for f in pts["field"]:
        values = tuple(f.get("values", ()))
        lo = f.get("min", min(values) if values else 0)
        hi = f.get("max", max(values) if values else 0)
        fields.append(PointField(f["offset"], f.get("words", 1), f["name"], lo, hi, f["default"], values,
                                 f.get("ui_min", lo), f.get("ui_max", hi)))
    al = _load("alarms.toml")
    return Tables(
        params=params,
        by_addr={p.addr: p for p in params},
        by_name={p.name: p for p in params},
        fields=tuple(fields),
        modes={int(k): v for k, v in pts["modes"].items()},
        alarms={int(k): (v["name"], v["blinks"]) for k, v in al["alarm"].items()},
        errors={int(k): v for k, v in al["error"].items()},
    )
