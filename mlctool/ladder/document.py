"""What every renderer draws: per source file, its rungs laid out and its label/free rows,
with the source comments and the texts shown beside each element."""

from __future__ import annotations

from dataclasses import dataclass, field

from mlctool.ladder.layout import Grid, layout_rung
from mlctool.ladder.network import Item, Row, Rung, build_items
from mlctool.program import Instr
from mlctool.targetapi.model import Target
from mlctool.targetapi.signals import device_signal, signals_of

COMMENT_MARKS = (";", "//")


@dataclass
class RungView:
    rung: Rung
    grid: Grid
    comment: list[str]  # comment lines written above the rung

    @property
    def addr(self) -> int:
        return self.rung.addr


@dataclass
class RowView:
    row: Row
    comment: list[str]

    @property
    def addr(self) -> int:
        return self.row.addr


@dataclass
class Sheet:
    """One program file as a ladder: items in program order."""

    path: str
    items: list[RungView | RowView]
    notes: dict[int, str] = field(default_factory=dict)  # instruction index -> line comment
    instrs: list[Instr] = field(default_factory=list)
    # instruction index -> the manual's name of its first signal operand (NC5 special M/D),
    # drawn under the device where no symbol is written
    names: dict[int, str] = field(default_factory=dict)

    @property
    def width(self) -> int:
        return max((it.grid.width for it in self.items if isinstance(it, RungView)), default=1)

    @property
    def rungs(self) -> int:
        return sum(isinstance(it, RungView) for it in self.items)


def line_comment(text: str) -> str | None:
    """The comment of a source line, without its mark; None if it has none."""
    cut = [k for k in (text.find(m) for m in COMMENT_MARKS) if k >= 0]
    return text[min(cut):].lstrip(";/").strip() if cut else None


def _is_comment_only(text: str) -> bool:
    return text.lstrip().startswith(COMMENT_MARKS)


def _first_index(it: Item) -> int:
    return it.start if isinstance(it, Rung) else it.index


def build_sheet(path: str, instrs: list[Instr], lines: dict[str, list[str]], target: Target | None = None) -> Sheet:
    """`lines`: source lines by file (a linked image holds instructions of several files).
    `target`: where its signals (NC5 special M/D) name devices: an instruction whose line has
    no comment gets the signals' descriptions as its comment."""
    items = build_items(instrs)
    notes: dict[int, str] = {}
    names: dict[int, str] = {}
    signals = target is not None and signals_of(target) is not None
    for k, ins in enumerate(instrs):
        src = lines.get(ins.file, [])
        c = line_comment(src[ins.line - 1]) if 0 < ins.line <= len(src) else None
        if c:
            notes[k] = c
        if signals:
            found = [at for op in ins.operands if not (op.is_const or op.index or op.is_group)
                     and (at := device_signal(target, op.device, op.number)) is not None]
            if found:
                names[k] = found[0].signal.name
                if not c:
                    notes[k] = "; ".join(at.describe() for at in found)
    views: list[RungView | RowView] = []
    prev = ("", 0)  # file and line of the previous item's last instruction
    for it in items:
        first = instrs[_first_index(it)]
        src = lines.get(first.file, [])
        start = prev[1] if prev[0] == first.file else 0
        above = [line_comment(t) for t in src[start:max(start, first.line - 1)] if _is_comment_only(t)]
        above = [c for c in above if c]
        last = instrs[it.stop - 1] if isinstance(it, Rung) else first
        prev = (last.file, last.line)
        views.append(RungView(it, layout_rung(it), above) if isinstance(it, Rung) else RowView(it, above))
    return Sheet(path, views, notes, instrs, names)


def operand_texts(ins: Instr) -> list[tuple[str, str]]:
    """(device as resolved, symbol as written or "") per operand."""
    out = []
    for op, text in zip(ins.operands, ins.texts, strict=False):
        dev = str(op)
        out.append((dev, text if text.upper() != dev.upper() else ""))
    return out


def instr_text(ins: Instr) -> str:
    """The instruction as written, e.g. `MOV K8 V0` (symbols kept)."""
    return " ".join((ins.mnemonic, *ins.texts))


def search_text(sheet: Sheet, it: RungView | RowView) -> str:
    """Everything a reader may search a rung by: devices, symbols, mnemonics, comments."""
    if isinstance(it, RowView):
        idx = [it.row.index]
    else:
        idx = range(it.rung.start, it.rung.stop)
    words = list(it.comment)
    for k in idx:
        ins = sheet.instrs[k]
        words.append(instr_text(ins))
        words += [d for d, _ in operand_texts(ins)]
        if k in sheet.notes:
            words.append(sheet.notes[k])
    return " ".join(words)
