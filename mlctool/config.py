"""Project configuration: `mlc.toml` or `[tool.mlc]` in pyproject.toml, found upward from cwd.

    target = "nc5"
    capacity = 65536          # program capacity override (steps)
    [severity]                # per-code severity: "error" | "warning" | "off"
    W401 = "off"
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from mlctool.diagnostics import MlcError, Span, diag


@dataclass
class Config:
    target: str | None = None
    capacity: int | None = None
    severity: dict[str, str] = field(default_factory=dict)
    data: dict = field(default_factory=dict)  # the whole table, for other commands (build, test)
    root: Path | None = None


def _table(path: Path) -> dict | None:
    try:
        data = tomllib.loads(path.read_text("utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise MlcError(diag(str(path), Span.at(1), "E100", f"cannot read configuration: {e}")) from e
    if path.name == "pyproject.toml":
        return data.get("tool", {}).get("mlc")
    return data


def load_config(start: Path | None = None, explicit: str | None = None) -> Config:
    if explicit:
        candidates = [Path(explicit)]
    else:
        here = (start or Path.cwd()).resolve()
        candidates = []
        for d in (here, *here.parents):
            candidates += [d / "mlc.toml", d / "pyproject.toml"]
    for path in candidates:
        if path.is_file():
            table = _table(path)
            if table is None:
                continue
            sev = {k.upper(): str(v).lower() for k, v in table.get("severity", {}).items()}
            for code, value in sev.items():
                if value not in ("error", "warning", "off"):
                    raise MlcError(diag(str(path), Span.at(1), "E105",
                                        f"severity of {code} must be error, warning or off, not {value!r}"))
            return Config(table.get("target"), table.get("capacity"), sev, table, path.parent)
    return Config()
