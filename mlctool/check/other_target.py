"""A program written for another target (issue 14): when it fails on its target with many
instruction/device errors but checks (nearly) clean on another, a note names that one.

Runs only when something is already wrong: a clean check pays nothing for it. Apart from
check/misuse.py because it checks again (it imports the checker, which imports misuse.py).
"""

from __future__ import annotations

from mlctool.config import Config
from mlctool.diagnostics import Diagnostic
from mlctool.syntax.source import SourceText

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
    from mlctool.targetapi import available_targets, load_target

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
