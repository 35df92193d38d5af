"""Another family's special relays and registers on a target (specials.toml in the target's
tables folder, e.g. mlctool/targets/vs/specials.toml):
FX M8000 or Delta DVP M1000 (RUN on) is M9000 on the VS. `mlc import` rewrites them by
function; `mlc check` warns when a program uses them as specials (W217).

The target's own special devices whose function the simulator does not model
(unmodelled_specials.toml beside it): `mlc sim` warns when a program writes one (W608)."""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from mlctool.targetapi.registry import UnknownTarget, target_package

_DEVICE = re.compile(r"([A-Z]+)([0-9]+)")


@dataclass(frozen=True)
class Special:
    function: str
    device: str  # the target's device (M9000)
    section: str  # the target manual's row


@dataclass(frozen=True)
class Family:
    name: str  # fx | dvp
    title: str
    special: dict[str, tuple[int, int]]  # device kind -> the family's special range
    mapping: dict[tuple[str, int], Special]  # (kind, number) -> the target's device
    mnemonics: dict[str, str]  # the family's spelling -> the target's (TMR -> OUT)

    def is_special(self, kind: str, number: int) -> bool:
        rng = self.special.get(kind)
        return rng is not None and rng[0] <= number <= rng[1]


def _span(text: str) -> tuple[str, int, int]:
    first, _, last = text.partition("-")
    m = _DEVICE.fullmatch(first)
    n = _DEVICE.fullmatch(last) if last else m
    if m is None or n is None or m[1] != n[1]:
        raise ValueError(f"specials.toml: bad device or range {text!r}")
    return m[1], int(m[2]), int(n[2])


@cache
def families(target_name: str) -> dict[str, Family]:
    """The families mapped onto the target ({} when it has no specials.toml)."""
    try:
        path = Path(target_package(target_name).tables) / "specials.toml"
    except UnknownTarget:
        return {}
    if not path.is_file():
        return {}
    data = tomllib.loads(path.read_text("utf-8"))
    out = {}
    for name, fam in data.get("families", {}).items():
        mapping: dict[tuple[str, int], Special] = {}
        for row in data.get("map", ()):
            if name not in row:
                continue
            kind, lo, hi = _span(row[name])
            vkind, vlo, vhi = _span(row["vs"] if "vs" in row else row["target"])
            if hi - lo != vhi - vlo:
                raise ValueError(f"specials.toml: {row[name]} and {row['vs']} differ in length")
            for k in range(hi - lo + 1):
                mapping[(kind, lo + k)] = Special(row["function"], f"{vkind}{vlo + k}", row["section"])
        out[name] = Family(name, fam["title"], {k: (int(v[0]), int(v[1])) for k, v in fam["special"].items()},
                           mapping, dict(fam.get("mnemonics", {})))
    return out


@dataclass(frozen=True)
class Unmodelled:
    """Special devices of the target whose written value has a function the simulator does not
    model (unmodelled_specials.toml in the target's tables folder; `mlc sim` warns, W608)."""

    kind: str
    lo: int
    hi: int
    function: str
    section: str  # the target manual's row
    why: str  # why the simulator does not model it


@cache
def unmodelled_specials(target_name: str) -> tuple[Unmodelled, ...]:
    """The target's unmodelled specials, one entry per device or range (() without the file)."""
    try:
        path = Path(target_package(target_name).tables) / "unmodelled_specials.toml"
    except UnknownTarget:
        return ()
    if not path.is_file():
        return ()
    rows = tomllib.loads(path.read_text("utf-8")).get("device", ())
    return tuple(Unmodelled(*_span(devices), row["function"], row["section"], " ".join(row["why"].split()))
                 for row in rows for devices in row["devices"])
