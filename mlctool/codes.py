"""The registry of diagnostic codes, read from codes.toml."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True, slots=True)
class Code:
    code: str
    severity: str
    summary: str
    doc: str


def _load() -> dict[str, Code]:
    # beside this module, as grammars/il.lark is read (importlib.resources costs ~5 ms of imports)
    data = tomllib.loads(Path(__file__).with_name("codes.toml").read_text("utf-8"))
    return {k: Code(k, v["severity"], v["summary"], v["doc"]) for k, v in sorted(data.items())}


CODES: dict[str, Code] = _load()
