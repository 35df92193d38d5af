"""The build pipeline: sources and objects -> checked object modules -> a linked program.

Sources given together are checked together (so a CALL may name another module's exported
label); objects are read and verified. Every function here returns data and diagnostics;
the CLI decides what to write.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from mlctool.asm.encode import directives_of, object_from_module, renamed, source_name
from mlctool.asm.objfile import MAGIC, ObjectError, ObjectFile, decode, read_header_target
from mlctool.check import check_files
from mlctool.config import Config
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.fileio import open_input
from mlctool.program import Module
from mlctool.targetapi import Target

OBJECT_SUFFIXES = (".mlo", ".mlx")


@dataclass
class Inputs:
    objects: list[ObjectFile] = field(default_factory=list)  # module objects, in the order given
    programs: list[tuple[str, ObjectFile]] = field(default_factory=list)  # linked programs given
    diagnostics: list[Diagnostic] = field(default_factory=list)
    lines: dict[str, list[str]] = field(default_factory=dict)  # source lines by file name
    checked_together: frozenset[str] = frozenset()  # sources the checker saw in one run

    @property
    def errors(self) -> bool:
        return any(d.severity == "error" for d in self.diagnostics)


def with_capacity(target: Target, config: Config | None) -> Target:
    if config is not None and config.capacity:
        return dataclasses.replace(target, capacity=int(config.capacity))
    return target


def is_object(path: str) -> bool:
    if path.lower().endswith(OBJECT_SUFFIXES):
        return True
    try:
        with open_input(path) as f:
            return f.read(len(MAGIC)) == MAGIC
    except OSError:
        return False


def read_object(path: str, target: Target) -> tuple[ObjectFile | None, Diagnostic | None]:
    """Read and verify one object file; a bad file gives one diagnostic (E100, E501-E503)."""
    try:
        with open_input(path) as f:
            data = f.read()
    except OSError as e:
        return None, diag(path, Span.at(1), "E100", f"cannot read: {e.strerror or e}")
    try:
        return decode(data, target), None
    except ObjectError as e:
        return None, diag(path, Span.at(1), e.code, str(e))


def object_target(path: str) -> str | None:
    """The target an object file names, or None if it cannot be read as an object."""
    try:
        with open_input(path) as f:
            return read_header_target(f.read())
    except (OSError, ObjectError):
        return None


def _external_calls(modules: list[Module]) -> set[tuple[str, int]]:
    """(file, line) of each CALL to a P its own module does not define."""
    out = set()
    for m in modules:
        own = m.labels()
        for ins in m.instrs:
            if ins.spec.op == "call" and ins.operands and not ins.operands[0].index \
                    and ins.operands[0].number not in own:
                out.add((m.path, ins.line))
    return out


def load_inputs(paths: list[str], target: Target, config: Config | None,
                root: str | None = None, separate: bool = False) -> Inputs:
    """Check the sources (together) and read the objects. `root` set: name sources as
    objects store them (relative to root); None: keep the paths as given. `separate`:
    compiling object modules, so a CALL to a label no source defines is left to the linker
    (a relocation) instead of being an error."""
    out = Inputs()
    sources = [p for p in paths if not is_object(p)]
    modules = {}
    if sources:
        result = check_files(sources, target, config)
        if separate:
            external = _external_calls(result.modules)
            result.diagnostics = [d for d in result.diagnostics
                                  if not (d.code == "E304" and (d.file, d.span.line) in external)]
        out.diagnostics += result.diagnostics
        for m in result.modules:
            name = source_name(m.path, root) if root is not None else m.path
            modules[m.path] = (renamed(m, name), directives_of(m.path, result.lines.get(m.path, [])))
            out.lines[name] = result.lines.get(m.path, [])
        if result.errors:
            return out
        out.checked_together = frozenset(m.path for m, _ in modules.values())
    loaded: list[tuple[str, ObjectFile]] = []
    for p in paths:
        if p in modules:
            module, directives = modules[p]
            loaded.append((p, object_from_module(module, directives)))
        elif p not in sources:
            obj, problem = read_object(p, target)
            if problem is not None:
                out.diagnostics.append(problem)
            elif obj.kind == "program":
                out.programs.append((p, obj))
            else:
                loaded.append((p, obj))
    names: dict[str, str] = {}
    for p, obj in loaded:
        name = obj.units[0].path
        if name in names:
            out.diagnostics.append(diag(p, Span.at(1), "E508", f"two inputs are named {name!r} "
                                        f"({names[name]} and {p}); module names must differ"))
        names.setdefault(name, p)
        out.objects.append(obj)
    return out
