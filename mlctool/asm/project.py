"""The project build: what `mlc build` with no arguments reads from mlc.toml (docs/project.md).

    target = "nc5"
    sources = ["src/main.il", "src/lib/handling.il"]   # main module first, then libraries
    output = "build/program.mlx"
    listing = "build/program.lst"                       # optional
    map = "build/program.map"                           # optional
    [symbols]                                           # device symbols of every module
    START = "X0"

Paths are relative to the folder of mlc.toml and are handed to the checker relative to the
current directory, so diagnostics name files the way the user reaches them.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from mlctool.config import Config
from mlctool.diagnostics import MlcError, Span, diag

DEFAULT_OUTPUT = "build/program.mlx"


@dataclass
class ProjectBuild:
    sources: list[str]
    output: str | None
    listing: str | None
    map: str | None
    root: str | None


def _bad(where: str | tuple[str, Span], message: str) -> MlcError:
    file, span = where if isinstance(where, tuple) else (where, Span.at(1))
    return MlcError(diag(file, span, "E510", message), 2)


def project_build(config: Config) -> ProjectBuild:
    if config.root is None:
        raise _bad("<command line>", "no sources given and no mlc.toml found here or above")
    data = config.data
    sources = data.get("sources")
    if not isinstance(sources, list) or not sources or not all(isinstance(s, str) for s in sources):
        raise _bad(config.locate("sources"), "mlc.toml needs `sources = [\"main.il\", ...]` to build without arguments")
    for key in ("output", "listing", "map"):
        if key in data and not isinstance(data[key], str):
            raise _bad(config.locate(key), f"mlc.toml `{key}` must be a path string")

    def here(p: str | None) -> str | None:
        return None if p is None else os.path.relpath(os.path.join(config.root, p))

    return ProjectBuild([here(s) for s in sources], here(data.get("output", DEFAULT_OUTPUT)),
                        here(data.get("listing")), here(data.get("map")), str(config.root))
