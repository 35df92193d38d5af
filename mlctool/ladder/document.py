"""What every renderer draws: per source file, its rungs laid out and its label/free rows,
with the source comments and the texts shown beside each element."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from mlctool.ladder.layout import Grid, layout_rung
from mlctool.ladder.network import Item, Row, Rung, build_items
from mlctool.program import Image, Instr
from mlctool.syntax.source import display_width
from mlctool.targetapi.model import Target
from mlctool.targetapi.signals import device_signal, signals_of

COMMENT_MARKS = (";", "//")
DEFINE = re.compile(r"\s*\.define\s+(\S+)\s+([^\s;/]+)", re.IGNORECASE)


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
    # device or symbol (upper case) -> the line comment of the `.define` that names it
    device_comments: dict[str, str] = field(default_factory=dict)

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
    return Sheet(path, views, notes, instrs, names, device_comments(instrs, lines))


def image_sheet(image: Image, lines: dict[str, list[str]], target: Target) -> Sheet:
    """The ladder of a linked program (the simulation report's, the live monitor's): one
    sheet named by the files of its modules."""
    names = [p for p, _, _ in image.modules] or sorted({i.file for i in image.instrs if i.file})
    return build_sheet(" + ".join(names), list(image.instrs), lines, target)


def device_comments(instrs: list[Instr], lines: dict[str, list[str]]) -> dict[str, str]:
    """A `.define NAME DEV ; comment` line's comment, by NAME and by DEV: the device comment
    vendor tools show under a contact (the first definition of a device wins)."""
    out: dict[str, str] = {}
    for path in dict.fromkeys(ins.file for ins in instrs):
        for text in lines.get(path, []):
            m = DEFINE.match(text)
            c = line_comment(text) if m else None
            if c:
                out.setdefault(m[1].upper(), c)
                out.setdefault(m[2].upper(), c)
    return out


def operand_texts(ins: Instr) -> list[tuple[str, str]]:
    """(device as resolved, symbol as written or "") per operand."""
    out = []
    for op, text in zip(ins.operands, ins.texts, strict=False):
        dev = str(op)
        out.append((dev, text if text.upper() != dev.upper() else ""))
    return out


def comment_of(sheet: Sheet, index: int) -> str:
    """The comment drawn under a contact or coil (`--comments`): for a contact its own line
    comment, else (and for a coil, whose line comment is drawn beside it) the comment of
    the `.define` of its device."""
    ins = sheet.instrs[index]
    own = sheet.notes.get(index, "") if ins.spec.cls != "output" else ""
    if own or not ins.operands:
        return own
    dev, sym = operand_texts(ins)[0]
    return sheet.device_comments.get(sym.upper()) or sheet.device_comments.get(dev.upper(), "")


def clip(s: str, n: int) -> str:
    """s in at most n display columns (Chinese characters count two), cut with `…`: the one
    rule of the SVG and the terminal drawings."""
    if display_width(s) <= n:
        return s
    while s and display_width(s) > n - 1:
        s = s[:-1]
    return s + "…"


def fold(text: str, width: int, lines: int) -> list[str]:
    """`text` in at most `lines` lines of `width` display columns (Chinese characters count
    two), broken at spaces where it can; what does not fit ends in `…`."""
    out: list[str] = []
    cur = ""
    for word in text.split():
        while word:
            joined = f"{cur} {word}" if cur else word
            if display_width(joined) <= width:
                cur, word = joined, ""
            elif cur:
                out.append(cur)
                cur = ""
            else:  # a word longer than a line: cut it
                cut = 0
                while cut < len(word) and display_width(word[:cut + 1]) <= width:
                    cut += 1
                out.append(word[:cut])
                word = word[cut:]
    if cur:
        out.append(cur)
    if len(out) > lines:
        out = out[:lines]
        tail = out[-1]
        while tail and display_width(tail + "…") > width:
            tail = tail[:-1]
        out[-1] = tail + "…"
    return out


def instr_text(ins: Instr) -> str:
    """The instruction as written, e.g. `MOV K8 V0` (symbols kept)."""
    return " ".join((ins.mnemonic, *ins.texts))


def box_text(ins: Instr) -> str:
    """The text of an instruction box: its devices, e.g. `MOV K8 D0` (the symbols are
    drawn under it)."""
    return " ".join((ins.mnemonic, *(d for d, _ in operand_texts(ins))))


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
        words += [c for c in map(sheet.device_comments.get, (d.upper() for d, _ in operand_texts(ins))) if c]
    return " ".join(words)
