"""Grid -> box-drawing text for the terminal, printed through rich.

Each grid row is two text lines: the device above, the wire with its symbol below. Wires are
drawn as connection masks per character and turned into box-drawing characters at the end,
so branch joints come out as ┬ ├ ┼ ┤ ┴ without special cases.
"""

from __future__ import annotations

from rich.console import Console
from rich.text import Text

from mlctool.ladder.document import RowView, RungView, Sheet, instr_text, operand_texts
from mlctool.ladder.layout import Cell, Output
from mlctool.syntax.source import display_width

TW = 11  # characters per contact column
LMT = 7  # characters left of the rail (step addresses, labels)
L, R, U, D = 1, 2, 4, 8
BOX = {L | R: "─", U | D: "│", R | D: "┌", L | D: "┐", R | U: "└", L | U: "┘", L | R | D: "┬",
       L | R | U: "┴", U | D | R: "├", U | D | L: "┤", L | R | U | D: "┼", L: "─", R: "─", U: "│",
       D: "│"}
CONTACT = {"": "┤ ├", "/": "┤/├", "↑": "┤↑├", "↓": "┤↓├"}
STYLES = {"step": "bold magenta", "coil": "bold cyan", "box": "bold cyan", "label": "bold red", "addr": "dim",
          "comment": "green", "note": "green italic", "symbol": "dim"}


class Canvas:
    def __init__(self, width: int, height: int):
        self.mask = [[0] * width for _ in range(height)]
        self.chars: dict[tuple[int, int], tuple[str, str]] = {}
        self.width = width

    def hline(self, y: int, x0: int, x1: int) -> None:
        for x in range(min(x0, x1), max(x0, x1)):
            self.mask[y][x] |= R
            self.mask[y][x + 1] |= L

    def vline(self, x: int, y0: int, y1: int) -> None:
        for y in range(min(y0, y1), max(y0, y1)):
            self.mask[y][x] |= D
            self.mask[y + 1][x] |= U

    def put(self, x: int, y: int, s: str, style: str = "") -> None:
        k = 0
        for ch in s:
            wide = display_width(ch) == 2  # a Chinese label name: the next cell is its right half
            for cell, c in ((x + k, ch), (x + k + 1, "")) if wide else ((x + k, ch),):
                if 0 <= cell < self.width:
                    self.chars[(cell, y)] = (c, style)
            k += 2 if wide else 1

    def center(self, x0: int, x1: int, y: int, s: str, style: str = "") -> None:
        s = s[:max(1, x1 - x0 - 1)]
        self.put(x0 + (x1 - x0 - display_width(s) + 1) // 2, y, s, style)

    def text(self) -> Text:
        out = Text()
        for y, row in enumerate(self.mask):
            line = Text()
            for x, m in enumerate(row):
                ch, style = self.chars.get((x, y), (BOX.get(m, " "), ""))
                line.append(ch, style)
            line.rstrip()
            out.append(line)
            out.append("\n")
        return out


def _cx(x: int) -> int:
    return LMT + x * TW  # column 0 starts on the rail, as the SVG's branch buses do


def _wy(y: int) -> int:
    return 2 * y + 1


def _cell(cv: Canvas, c: Cell) -> None:
    x0, x1, y = _cx(c.x), _cx(c.x + c.w), _wy(c.y)
    cv.hline(y, x0, x1)
    if c.kind == "contact":
        cv.center(x0, x1, y, CONTACT.get(c.glyph, "┤ ├"))
        cv.center(x0, x1, y - 1, operand_texts(c.ins)[0][0])
    elif c.kind == "compare":
        (s1, _), (s2, _) = operand_texts(c.ins)[:2]
        rel = ("D" if c.ins.spec.width == 32 else "") + c.glyph
        cv.center(x0, x1, y, f"[{s1}{rel}{s2}]")
    elif c.kind in ("inv", "nop"):
        cv.center(x0, x1, y, "╱" if c.kind == "inv" else "")
        cv.center(x0, x1, y - 1, c.kind.upper(), "symbol")
    elif c.kind == "edge":  # MEP/MEF: the edge of the result so far
        cv.center(x0, x1, y, c.glyph)
        cv.center(x0, x1, y - 1, c.ins.mnemonic, "symbol")
    elif c.kind == "step":  # the state box of a step ladder step (VS 4-6-2 (b))
        cv.center(x0, x1, y, f"[{operand_texts(c.ins)[0][0]}]", STYLES["step"])
        cv.center(x0, x1, y - 1, "STL", "symbol")
    else:
        cv.center(x0, x1, y, "┤⇤├")
        cv.center(x0, x1, y - 1, f"@{c.glyph}", "symbol")


def _output(cv: Canvas, sheet: Sheet, ox: int, y: int, o: Output) -> None:
    if o.kind == "pin":  # a further input of the box drawn on an earlier row
        cv.put(ox, y, f"▷{o.letter}", STYLES["box"])
        return
    if o.kind == "coil":
        s = f"({o.letter or ' '})"
        cv.put(ox, y, s, STYLES["coil"])
        cv.put(ox, y - 1, operand_texts(o.ins)[0][0], STYLES["coil"])
    else:
        s = "[" + " ".join((o.ins.mnemonic, *(d for d, _ in operand_texts(o.ins)))) + "]"
        cv.put(ox, y, s, STYLES["box"])
    note = sheet.notes.get(o.index)
    if note:
        cv.put(ox + len(s) + 2, y, "; " + note, STYLES["note"])


def item_text(sheet: Sheet, it: RungView | RowView, cols: int, width: int) -> Text:
    ox = _cx(cols) + 2
    rows = it.grid.height if isinstance(it, RungView) else 1
    cv = Canvas(width, 2 * rows)
    cv.vline(LMT, 0, 2 * rows - 1)
    cv.mask[0][LMT] |= U  # the rail runs on to the rungs above and below
    cv.mask[-1][LMT] |= D
    if isinstance(it, RowView):
        ins = it.row.ins
        if ins.spec.cls == "label":
            cv.put(0, 1, instr_text(ins)[2:].rjust(LMT - 1), STYLES["label"])
        else:
            cv.put(0, 1, str(ins.addr).rjust(LMT - 1), STYLES["addr"])
            cv.hline(1, LMT, ox - 1)
            _output(cv, sheet, ox, 1, Output(0, 0, "box", ins, it.row.index))
    else:
        g = it.grid
        cv.put(0, 1, str(it.addr).rjust(LMT - 1), STYLES["addr"])
        for w in g.wires:
            if w.y0 == w.y1:
                cv.hline(_wy(w.y0), _cx(w.x0), _cx(w.x1))
            else:
                cv.vline(_cx(w.x0), _wy(w.y0), _wy(w.y1))
        for o in g.outputs:
            cv.hline(_wy(o.y), _cx(o.x), ox - 1)
        for c in g.cells:
            _cell(cv, c)
        for o in g.outputs:
            _output(cv, sheet, ox, _wy(o.y), o)
        for x, y in g.rails:
            cv.put(_cx(x), _wy(y), "┃")
        for x, y in g.ends:
            cv.put(_cx(x), _wy(y), "┤")
    out = Text()
    for c in it.comment:
        out.append(" " * (LMT + 2) + "; " + c + "\n", STYLES["comment"])
    out.append_text(cv.text())
    return out


def sheets_text(sheets: list[Sheet]) -> Text:
    cols = max((sh.width for sh in sheets), default=1)
    width = _cx(cols) + 200
    out = Text()
    for sh in sheets:
        out.append(f"{sh.path}\n", "bold")
        for it in sh.items:
            out.append_text(item_text(sh, it, cols, width))
    return out


def print_sheets(sheets: list[Sheet], console: Console | None = None) -> None:
    console = console or Console(highlight=False, soft_wrap=True)
    console.print(sheets_text(sheets), end="")
