"""Named program labels (target.toml `named_labels`, VS 2-10): `FILL_DONE:` defines a label that
CJ/CALL name instead of a P number.

A name stands for a P number that the program does not use itself, so everything after the
resolver (structure checks, object files, linker, simulator) sees ordinary P labels. Numbers
are given from the top of the P range downward, in order of definition over all the files
checked together, skipping every P number written anywhere in them and the END labels:
deterministic, and the same source always gets the same numbers (objdump --il round trips).

Names may hold Han ideographs where `named_labels` has `cjk_width` (VS 2-10: "8個中文字或16個
英文數字", so an ideograph counts 2 of the 16; mixed names like the manual's table name
變頻器1通訊 count 5 x 2 + 1 = 11). On every other target a word holding one is a syntax error
(E103, the statement dropped), as it was before the grammar knew them.
"""

from __future__ import annotations

import re

from mlctool.check.interrupts import pointer_named
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.syntax.operands import (
    CJK_CHAR,
    CJK_RANGES,
    SYMBOL,
    WIDE_SYMBOL,
    LazyPattern,
    OperandSyntaxError,
    name_width,
    parse_operand,
)
from mlctool.syntax.parser import ParsedFile
from mlctool.targetapi.model import Target

_P = re.compile(r"P([0-9]+)", re.IGNORECASE)
NAME = LazyPattern(f"[A-Za-z_{CJK_RANGES}][A-Za-z0-9_{CJK_RANGES}]*")


def cjk_width(target: Target) -> int:
    """What a Han ideograph counts in a name of the target (0: the target has none)."""
    rule = target.settings.get("named_labels")
    return int(rule.get("cjk_width", 0)) if isinstance(rule, dict) else 0


def is_symbol_name(text: str, target: Target) -> bool:
    """A name `.define` may give or an operand may be: ASCII, or with ideographs where the target has them."""
    return bool(SYMBOL.fullmatch(text) or (cjk_width(target) and WIDE_SYMBOL.fullmatch(text)))


def restrict_names(parsed: ParsedFile, target: Target) -> ParsedFile:
    """On a target without ideographs in names, a statement holding one (outside a "string")
    is a syntax error at that character, and is dropped like any line that does not parse."""
    text = "\n".join(parsed.lines)
    if cjk_width(target) or text.isascii() or not CJK_CHAR.search(text):
        return parsed  # (a file without ideographs, the usual case: one scan of its lines)
    kept = []
    for st in parsed.statements:
        hit = next(((w, m) for w in [st.name, *st.operands] if not w.text.startswith('"')
                    and (m := CJK_CHAR.search(w.text))), None)
        if hit is None:
            kept.append(st)
            continue
        w, m = hit
        parsed.diagnostics.append(diag(parsed.path, Span.at(st.line, w.col + m.start()), "E103",
                                       f"unexpected character {m.group()!r}: names with Chinese characters "
                                       f"are not available on target {target.name}"))
    parsed.statements[:] = kept
    return parsed


def is_label_name(text: str, target: Target) -> bool:
    """Could be a named label: letters, digits, _ (ideographs where the target has them); not
    an operand (X1, K5, P3), not a mnemonic."""
    if not NAME.fullmatch(text) or text.upper() in target.instructions or pointer_named(text, target):
        return False
    if not cjk_width(target) and CJK_CHAR.search(text):
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
    wide = cjk_width(target)
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
            if not is_label_name(w.text, target) or not is_symbol_name(w.text, target):
                continue  # the resolver reports it as a bad label
            if (size := name_width(w.text, wide or 1)) > longest:
                diags.append(diag(f.path, span, "E203", f"label name {w.text!r} is longer than {longest} "
                                  + (f"characters ({size}: a Chinese character counts {wide}, {pointer.section})"
                                     if wide and CJK_CHAR.search(w.text) else f"characters ({pointer.section})")))
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
