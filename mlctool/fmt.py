"""`mlc fmt`: one canonical layout for IL source.

- mnemonics upper-case, padded so operands start in one column; operands separated by one
  blank; device names and constants upper-case (symbols keep their spelling);
- labels (`P10`, `P10:`) and directives at column 1, as written otherwise;
- comments kept: whole-line comments as they are, trailing comments aligned (by display
  width: a Chinese label name takes two columns a character, so comments line up on screen);
- one blank line before each rung (a load after an output, a label or a free-standing
  instruction), moved above the rung's leading comment lines; runs of blank lines folded;
- step numbers dropped, kept, or renumbered with the computed addresses.

Formatting changes layout only: the statements, and so the assembled code, stay the same.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from mlctool.diagnostics import Diagnostic
from mlctool.syntax.operands import OperandSyntaxError, parse_operand
from mlctool.syntax.parser import Statement, parse
from mlctool.syntax.source import SourceText, display_width, pad
from mlctool.targetapi import Target

MNEMONIC_WIDTH = 8
COMMENT_COLUMN = 40
_COMMENT = re.compile(r"(;|//).*$")


@dataclass(frozen=True)
class FormatOptions:
    steps: str = "drop"  # drop | keep | renumber


def _comment(text: str) -> str:
    m = _COMMENT.search(text)
    return m.group(0).rstrip() if m else ""


def _operand(text: str) -> str:
    try:
        parse_operand(text)
    except OperandSyntaxError:
        return text  # a symbol: keep the user's spelling
    return text.upper()


def _statement_text(st: Statement, step: str | None) -> str:
    head = f"{step} " if step else ""
    if st.kind == "label":
        return f"{head}{st.name.text.upper()}:"
    if st.kind == "directive":
        return head + " ".join([st.name.text.lower()] + [w.text for w in st.operands])
    name = st.name.text.upper()
    if not st.operands:
        return head + name
    return head + pad(name, MNEMONIC_WIDTH - 1) + " " + " ".join(_operand(w.text) for w in st.operands)


def _starts_rung(cls: str | None, prev_cls: str | None) -> bool:
    """A blank line goes before a label, and before a load that follows an output or a
    free-standing instruction (not one that directly follows its label)."""
    if cls == "label":
        return prev_cls is not None
    return cls == "load" and prev_cls in ("output", "free", "nop")


def _class_of(st: Statement, target: Target) -> str | None:
    if st.kind == "label" or (st.kind == "instr" and re.fullmatch(r"[Pp][0-9]+", st.name.text) and not st.operands):
        return "label"
    spec = target.instruction(st.name.text) if st.kind == "instr" else None
    return spec.cls if spec else None


def format_source(src: SourceText, target: Target, options: FormatOptions = FormatOptions()
                  ) -> tuple[str | None, list[Diagnostic]]:
    """Formatted text, or None with the syntax errors when the file cannot be formatted safely."""
    from mlctool.check.labels import restrict_names

    parsed = restrict_names(parse(src), target)  # Chinese names only where the target has them
    if parsed.diagnostics:
        return None, parsed.diagnostics
    addresses: dict[int, int] = {}
    if options.steps == "renumber":
        from mlctool.check.resolve import resolve

        module, _ = resolve(parsed, target)
        addresses = {ins.line: ins.addr for ins in module.instrs}
    by_line = {st.line: st for st in parsed.statements}
    out: list[str] = []
    prev_cls: str | None = None
    for number, raw in enumerate(parsed.lines, 1):
        st = by_line.get(number)
        comment = _comment(raw)
        if st is None:
            if not raw.strip():
                if out and out[-1] != "":
                    out.append("")
            else:
                out.append(raw.strip() if comment == raw.strip() else raw.rstrip())
            continue
        cls = _class_of(st, target)
        if _starts_rung(cls, prev_cls):
            k = len(out)
            while k > 0 and out[k - 1] and _COMMENT.match(out[k - 1]):
                k -= 1  # the rung's own comment lines go with it
            if k > 0 and out[k - 1] != "":
                out.insert(k, "")
        step = None
        if options.steps == "keep" and st.step is not None:
            step = st.step.text
        elif options.steps == "renumber" and number in addresses:
            step = f"{addresses[number]:05d}"
        text = _statement_text(st, step)
        if comment:
            text = f"{pad(text, COMMENT_COLUMN - 1)} {comment}" if display_width(text) < COMMENT_COLUMN - 1 \
                else f"{text} {comment}"
        out.append(text)
        if cls is not None:
            prev_cls = cls
    while out and out[-1] == "":
        out.pop()
    return "\n".join(out) + "\n", []
