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
from mlctool.fileio import same_file

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


@dataclass
class Scope:
    """What a command works on (docs/project.md, "One rule for every command"): the files it
    loads (relative to the current folder) and, of those, the modules the command line named
    (`focus`; empty: all of them). `tables` are the project's register tables as `--table`
    specs ([SR=]FILE, the file relative to the current folder)."""

    files: list[str]
    focus: list[str]
    tables: list[str]
    project: bool  # the files are the project's (mlc.toml `sources`)


def project_scope(files: list[str] | tuple[str, ...], config: Config) -> Scope:
    """No FILE inside a project: the project (its sources, its tables). FILEs that are all
    modules of the project: the whole project, focused on them (the project's spelling of
    each). Other FILEs, or no project: the FILEs as given. No FILE and no project: E510."""
    if not files:
        job = project_build(config)
        return Scope(job.sources, [], project_tables(config), True)
    sources = config.data.get("sources") if config.root is not None else None
    if not isinstance(sources, list) or not sources:
        return Scope(list(files), [], [], False)
    job = project_build(config)
    focus = []
    for path in files:
        same = next((s for s in job.sources if os.path.exists(path) and same_file(path, s)), None)
        if same is None:
            return Scope(list(files), [], [], False)
        if same not in focus:
            focus.append(same)
    return Scope(job.sources, focus, project_tables(config), True)


def project_tables(config: Config) -> list[str]:
    """mlc.toml `tables` ("[SR=]FILE", FILE relative to mlc.toml) as specs whose FILE is
    relative to the current folder, as `--table` takes them."""
    if config.root is None:
        return []
    out = []
    for spec in config.data.get("tables") or []:
        path = table_file(spec)
        sr = spec[:len(spec) - len(path)]
        out.append(sr + os.path.relpath(os.path.join(config.root, path)))
    return out


def table_file(spec: str) -> str:
    """The file of a table spec [SR=]FILE (a path with `=` in a folder name stays whole)."""
    head, eq, rest = spec.partition("=")
    return rest if eq and "/" not in head and os.sep not in head else spec
