"""Inputs that are not what `mlc check` expects (issue 14): a file that is no source (a
stimulus, an object, a vendor export) is named for what it is with the command that takes
it (E111); a program written for another target gets a note naming that target.

Both run only when something is already wrong, or by a file's suffix: a clean check pays
nothing for them.
"""

from __future__ import annotations

import os

from mlctool.config import Config
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
_TARGET_SHAPED = frozenset({"E103", "E105", "E201", "E202", "E203", "E204", "E205", "E209", "E211", "E215"})
MIN_ERRORS = 5  # fewer: a few typos, not a program for another target
MAX_LINES = 10_000  # beyond: checking again on each target costs more than the hint is worth


def likely_targets(sources: list[SourceText], target_name: str, config: Config | None,
                   diags: list[Diagnostic]) -> tuple[list[str], int]:
    """The other targets the sources check (nearly) clean on, with their error count, when
    they fail on this one with many errors of the instruction/device kinds; ([], 0) otherwise."""
    shaped = sum(d.code in _TARGET_SHAPED and d.severity == "error" for d in diags)
    if shaped < MIN_ERRORS or not sources or sum(s.text.count("\n") for s in sources) > MAX_LINES:
        return [], 0
    from mlctool.check import check_texts
    from mlctool.targets import available_targets, load_target

    errors = sum(d.severity == "error" for d in diags)
    unknown = _unknown_mnemonics(sources, diags)
    found: dict[str, int] = {}
    for name in available_targets():
        if name == target_name:
            continue
        t = load_target(name)
        # cheap first: most of the unknown mnemonics must be the other target's (a file of
        # garbage is not checked again on every target)
        if unknown and 2 * sum(m in t.instructions or m in t.variants for m in unknown) < len(unknown):
            continue
        other = check_texts(sources, t, config).errors
        if other <= errors // 10:  # "clean or nearly": a tenth of the errors at most
            found[name] = other
    best = min(found.values(), default=0)
    return sorted(n for n, e in found.items() if e == best), best


def _unknown_mnemonics(sources: list[SourceText], diags: list[Diagnostic]) -> list[str]:
    """The mnemonics of the E201 diagnostics, upper case, as written at their spans."""
    lines = {s.path: s.text.split("\n") for s in sources}
    out = []
    for d in diags:
        if d.code == "E201" and d.file in lines and d.span.line <= len(lines[d.file]):
            out.append(lines[d.file][d.span.line - 1][d.span.col - 1:d.span.end_col - 1].upper())
    return out


def wrong_target_note(candidates: list[str], their_errors: int, target_name: str, errors: int) -> str:
    """'note: this looks like a `--target vs` program ...'"""
    options = " or ".join(f"`--target {n}`" for n in candidates)
    on = " and ".join(candidates)
    return (f"note: this looks like a {options} program: {errors} errors on {target_name}, "
            f"{their_errors or 'none'} on {on}; choose the target with --target or `target` in mlc.toml")
