"""Named program labels (target.toml `named_labels`, VS 2-10): `FILL_DONE:` defines a label that
CJ/CALL name instead of a P number.

A name stands for a P number that the program does not use itself, so everything after the
resolver (structure checks, object files, linker, simulator) sees ordinary P labels. Numbers
are given from the top of the P range downward, in order of definition over all the files
checked together, skipping every P number written anywhere in them and the END labels:
deterministic, and the same source always gets the same numbers (objdump --il round trips).
"""

from __future__ import annotations

import re

from mlctool.check.interrupts import pointer_named
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.syntax.operands import SYMBOL, OperandSyntaxError, parse_operand
from mlctool.syntax.parser import ParsedFile
from mlctool.targets.model import Target

_P = re.compile(r"P([0-9]+)", re.IGNORECASE)
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def is_label_name(text: str, target: Target) -> bool:
    """Could be a named label: letters, digits, _; not an operand (X1, K5, P3), not a mnemonic."""
    if not NAME.fullmatch(text) or text.upper() in target.instructions or pointer_named(text, target):
        return False
    try:
        parse_operand(text, target.operand_syntax)
    except OperandSyntaxError:
        return True
    return False


def assign_named_labels(files: list[ParsedFile], target: Target
                        ) -> tuple[dict[str, dict[str, int]], list[Diagnostic]]:
    """-> (file -> {NAME: P number}, diagnostics: names too long, duplicates, no free P)."""
    rule = target.settings.get("named_labels")
    if not rule:
        return {}, []
    longest = int(rule.get("max_length", 16))
    pointer = target.devices.get("P")
    if pointer is None:
        return {}, []
    used = set(target.end_labels)
    for f in files:
        for st in f.statements:
            for w in [st.name, *st.operands]:
                if m := _P.fullmatch(w.text):
                    used.add(int(m[1]))
    free = (p for p in range(pointer.hi, pointer.lo - 1, -1) if p not in used)
    names: dict[str, dict[str, int]] = {}
    diags: list[Diagnostic] = []
    for f in files:
        own = names.setdefault(f.path, {})
        for st in f.statements:
            if st.kind != "label" or _P.fullmatch(st.name.text):
                continue
            w, key = st.name, st.name.text.upper()
            span = Span(st.line, w.col, st.line, w.end_col)
            if not is_label_name(w.text, target) or not SYMBOL.fullmatch(w.text):
                continue  # the resolver reports it as a bad label
            if len(w.text) > longest:
                diags.append(diag(f.path, span, "E203", f"label name {w.text!r} is longer than {longest} "
                                  f"characters ({pointer.section})"))
                continue
            if key in own:
                continue  # a duplicate: the structure check reports it (E303)
            p = next(free, None)
            if p is None:
                diags.append(diag(f.path, span, "E205", f"label {w.text}: P numbers and label names together "
                                  f"exceed P{pointer.lo}-P{pointer.hi} ({pointer.section})"))
                continue
            own[key] = p
    return names, diags
