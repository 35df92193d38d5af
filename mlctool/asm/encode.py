"""Checked modules <-> object files, and the name a source gets inside an object.

Objects never hold absolute paths: a source is named relative to the project root (the
folder of mlc.toml, else the current directory) or, outside it, by its file name.
"""

from __future__ import annotations

import dataclasses
import os
import re

from mlctool.asm.objfile import Directive, ObjectFile, Unit
from mlctool.program import Image, Module
from mlctool.syntax.parser import parse
from mlctool.syntax.source import SourceText

# A line whose first statement word starts with a dot (after an optional step number).
_DIRECTIVE_LINE = re.compile(r"[ \t\f\v,\u3000\uFF0C]*(?:[0-9]+[ \t\f\v,\u3000\uFF0C]+)?\.")


def source_name(path: str, root: str | None = None) -> str:
    """The name stored for `path`: relative to `root` (default cwd), '/'-separated."""
    root = os.path.abspath(root or os.getcwd())
    full = os.path.abspath(path)
    try:
        rel = os.path.relpath(full, root)
    except ValueError:  # another drive (Windows)
        rel = os.path.basename(full)
    if rel.startswith(".."):
        rel = os.path.basename(full)
    return rel.replace(os.sep, "/")


def directives_of(path: str, lines: list[str]) -> tuple[Directive, ...]:
    """Every directive of a source, as written, with its line and column."""
    out = []
    for number, text in enumerate(lines, 1):
        if not _DIRECTIVE_LINE.match(text):
            continue
        for st in parse(SourceText(path, text + "\n")).statements:
            if st.kind == "directive":
                words = [st.name.text] + [w.text for w in st.operands]
                out.append(Directive(number, st.name.col, " ".join(words)))
    return tuple(out)


def renamed(module: Module, name: str) -> Module:
    """The module under its object name (every instruction's file too)."""
    if module.path == name:
        return module
    instrs = [dataclasses.replace(i, file=name) for i in module.instrs]
    return dataclasses.replace(module, path=name, instrs=instrs)


def object_from_module(module: Module, directives: tuple[Directive, ...] = ()) -> ObjectFile:
    unit = Unit(module.path, module.library, 0, module.total_steps, tuple(sorted(module.exports)),
                dict(module.symbols), directives)
    return ObjectFile("module", module.target, [unit], list(module.instrs), [0] * len(module.instrs))


def module_from_object(obj: ObjectFile) -> Module:
    u = obj.units[0]
    return Module(u.path, obj.target, list(obj.instrs), set(u.exports), dict(u.symbols), u.library)


def image_from_object(obj: ObjectFile) -> Image:
    symbols: dict[str, str] = {}
    for u in obj.units:
        symbols.update(u.symbols)
    return Image(obj.target, list(obj.instrs), [(u.path, u.first, u.end) for u in obj.units], symbols,
                 [(u.path, d.text) for u in obj.units for d in u.directives], obj.digest)


def unit_instrs(obj: ObjectFile, k: int) -> list:
    """The instructions a unit's source held (linker-inserted ones left out), in order."""
    return [ins for n, (ins, u) in enumerate(zip(obj.instrs, obj.unit_of)) if u == k and n not in obj.inserted]
