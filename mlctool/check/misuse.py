"""Inputs that are not what `mlc check` expects (issue 14): a file that is no source (a
stimulus, an object, a vendor export) is named for what it is with the command that takes
it (E111); a program written for another target: other_target.py.

Both run only when something is already wrong, or by a file's suffix: a clean check pays
nothing for them.
"""

from __future__ import annotations

import os

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.syntax.source import SourceText

_OBJECT_SUFFIXES = (".mlo", ".mlx")
_EXPORT_SUFFIXES = (".csv", ".tsv", ".txt")


def not_a_source_by_name(path: str) -> Diagnostic | None:
    """E111 for a stimulus file or an object file, known by its suffix."""
    low = path.lower()
    if low.endswith(".stim"):
        return diag(path, Span.at(1), "E111", "a stimulus file, not a program: "
                    f"`mlc sim PROGRAM --stimulus {path}` runs a program against it")
    if low.endswith(_OBJECT_SUFFIXES):
        linked = low.endswith(".mlx")
        kind = "a linked program" if linked else "an object module"
        return diag(path, Span.at(1), "E111", f"{kind} (built by `mlc build`), not a source: "
                    f"`mlc objdump {path}` lists it" + (f", `mlc sim {path}` runs it" if linked else ""))
    return None


def not_a_source_by_content(src: SourceText) -> Diagnostic | None:
    """E111 for a GX Works2 / GX Developer export (header rows IL cannot read). WPLSoft rows
    (`000001,LD,X0`) are IL as they are and are checked."""
    if not src.path.lower().endswith(_EXPORT_SUFFIXES):
        return None
    from mlctool.imports import detect

    fmt = detect(src.text)
    if fmt not in ("gxworks2", "gxdeveloper"):
        return None
    name = {"gxworks2": "a GX Works2", "gxdeveloper": "a GX Developer"}[fmt]
    il = os.path.splitext(src.path)[0] + ".il"
    return diag(src.path, Span.at(1), "E111", f"{name} export, not a source: "
                f"`mlc import {src.path} -o {il}` converts it to IL")


# errors that say "this target has no such instruction, device or syntax"
