"""Grid -> box-drawing text for the terminal, printed through rich.

Each grid row is two text lines: the device above, the wire with its symbol below. Wires are
drawn as connection masks per character and turned into box-drawing characters at the end,
so branch joints come out as ┬ ├ ┼ ┤ ┴ without special cases.
"""

from __future__ import annotations

from dataclasses import dataclass

from rich.console import Console
from rich.text import Text

from mlctool.ladder.document import (
    RowView,
    RungView,
    Sheet,
    box_text,
    clip,
    comment_of,
    fold,
    instr_text,
    operand_texts,
)
from mlctool.ladder.layout import MIN_COLS, Cell, Grid, Output, wrap
from mlctool.syntax.source import display_width

TW = 11  # characters per contact column
LMT = 7  # characters left of the rail (step addresses, labels)
DEFAULT_WIDTH = 100  # characters, when the output is not a terminal and no width is given
MIN_WIDTH = 60  # the rail, MIN_COLS contact columns and a coil
DEVICE_COMMENT_LINES = 2  # lines of a device comment under a contact (--comments)
L, R, U, D = 1, 2, 4, 8
BOX = {L | R: "─", U | D: "│", R | D: "┌", L | D: "┐", R | U: "└", L | U: "┘", L | R | D: "┬",
       L | R | U: "┴", U | D | R: "├", U | D | L: "┤", L | R | U | D: "┼", L: "─", R: "─", U: "│",
       D: "│"}
CONTACT = {"": "┤ ├", "/": "┤/├", "↑": "┤↑├", "↓": "┤↓├"}
STYLES = {"step": "bold magenta", "coil": "bold cyan", "box": "bold cyan", "label": "bold red", "addr": "dim",
          "comment": "green", "note": "green italic", "symbol": "dim", "dcomment": "green"}


@dataclass(frozen=True, slots=True)
class Layout:
    """What all rungs of one printout share: its width in characters, the contact columns a
    piece of a rung may use, and whether device comments are shown."""

    width: int
    cols: int
    comments: bool = False


def _out_text(ins) -> str:
    return "[" + box_text(ins) + "]"


def text_layout(sheets: list[Sheet], width: int = DEFAULT_WIDTH, comments: bool = False) -> Layout:
    """As many contact columns as fit `width` beside the widest output (counted up to a
    third of the width; a wider one is cut at the edge)."""
    out = 6
    for sh in sheets:
        for it in sh.items:
            for o in (it.grid.outputs if isinstance(it, RungView) else [it.row]):
                out = max(out, display_width(_out_text(o.ins)))
    width = max(width, MIN_WIDTH)
    return Layout(width, max(MIN_COLS, (width - LMT - 3 - min(out, width // 3)) // TW), comments)


class Canvas:
    def __init__(self, width: int, height: int):
        self.mask = [[0] * width for _ in range(height)]
        self.chars: dict[tuple[int, int], tuple[str, str]] = {}
        self.width = width

    def hline(self, y: int, x0: int, x1: int) -> None:
        for x in range(min(x0, x1), min(max(x0, x1), self.width - 1)):
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



def _under(sheet: Sheet, index: int, lay: Layout) -> list[str]:
    """The lines under a contact or coil: the symbol as written, then the device comment."""
    ins = sheet.instrs[index]
    if not ins.operands or index < 0:
        return []
    sym = operand_texts(ins)[0][1]
    out = [clip(sym, TW - 1)] if sym else []
    if lay.comments:
        out += fold(comment_of(sheet, index), TW - 1, DEVICE_COMMENT_LINES)
    return out


class _Piece:
    """One piece of a rung on the canvas: its grid, first text line and lines per row."""

    def __init__(self, g: Grid, top: int, per_row: int):
        self.g, self.top, self.per_row = g, top, per_row

    def wy(self, y: int) -> int:
        return self.top + y * self.per_row + 1


def _cell(cv: Canvas, sheet: Sheet, pc: _Piece, c: Cell, lay: Layout) -> None:
    x0, x1, y = _cx(c.x), _cx(c.x + c.w), pc.wy(c.y)
    if c.kind == "wrap_in":  # a line continued from the marker of the same number above
        cv.hline(y, x0 + 3, x1)
        cv.put(x0 + 1, y, f"{c.glyph}⇒", STYLES["symbol"])
        return
    if c.kind == "wrap_out":
        cv.hline(y, x0, x0 + 2)
        cv.put(x0 + 2, y, f"⇒{c.glyph}", STYLES["symbol"])
        return
    cv.hline(y, x0, x1)
    if c.kind == "contact":
        cv.center(x0, x1, y, CONTACT.get(c.glyph, "┤ ├"))
        cv.center(x0, x1, y - 1, operand_texts(c.ins)[0][0])
        for k, t in enumerate(_under(sheet, c.index, lay)):
            cv.center(x0, x1, y + 1 + k, t, STYLES["dcomment" if k or not operand_texts(c.ins)[0][1] else "symbol"])
    elif c.kind == "compare":
        (s1, _), (s2, _) = operand_texts(c.ins)[:2]
        rel = ("D" if c.ins.spec.width == 32 else "") + c.glyph
        cv.center(x0, x1, y, clip(f"[{s1}{rel}{s2}]", x1 - x0 - 1))
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


def _output(cv: Canvas, sheet: Sheet, ox: int, y: int, o: Output, lay: Layout) -> None:
    if o.kind == "pin":  # a further input of the box drawn on an earlier row
        cv.put(ox, y, f"▷{o.letter}", STYLES["box"])
        return
    if o.kind == "coil":
        s = f"({o.letter or ' '})"
        cv.put(ox, y, s, STYLES["coil"])
        cv.put(ox, y - 1, operand_texts(o.ins)[0][0], STYLES["coil"])
        for k, t in enumerate(_under(sheet, o.index, lay)):
            cv.put(ox, y + 1 + k, t, STYLES["dcomment" if k or not operand_texts(o.ins)[0][1] else "symbol"])
    else:
        s = clip(_out_text(o.ins), lay.width - ox)
        cv.put(ox, y, s, STYLES["box"])
    note = sheet.notes.get(o.index)
    room = lay.width - (ox + display_width(s) + 4)
    if note and room >= 6:
        cv.put(ox + display_width(s) + 2, y, "; " + clip(note, room), STYLES["note"])


def _lines_per_row(sheet: Sheet, it: RungView, lay: Layout) -> int:
    """Two text lines per grid row (device, wire), and as many more as the longest text
    under a contact or coil of the rung."""
    idx = [c.index for c in it.grid.cells if c.kind == "contact"]
    idx += [o.index for o in it.grid.outputs if o.kind == "coil"]
    return 2 + max((len(_under(sheet, i, lay)) for i in idx), default=0)


def item_text(sheet: Sheet, it: RungView | RowView, lay: Layout) -> Text:
    if isinstance(it, RowView):
        per_row, grids = 2, []
    else:
        per_row, grids = _lines_per_row(sheet, it, lay), wrap(it.grid, lay.cols)
    pcs, top = [], 0
    for g in grids:
        pcs.append(_Piece(g, top, per_row))
        top += g.height * per_row
    height = max(top, 2)
    cv = Canvas(lay.width, height)
    cv.vline(LMT, 0, height - 1)
    cv.mask[0][LMT] |= U  # the rail runs on to the rungs above and below
    cv.mask[height - 1][LMT] |= D
    if isinstance(it, RowView):
        ins = it.row.ins
        if ins.spec.cls == "label":
            cv.put(0, 1, instr_text(ins)[2:].rjust(LMT - 1), STYLES["label"])
        else:
            cv.put(0, 1, str(ins.addr).rjust(LMT - 1), STYLES["addr"])
            cv.hline(1, LMT, LMT + 1)
            _output(cv, sheet, LMT + 2, 1, Output(0, 0, "box", ins, it.row.index), lay)
    else:
        cv.put(0, 1, str(it.addr).rjust(LMT - 1), STYLES["addr"])
        for pc in pcs:
            _draw_piece(cv, sheet, pc, lay)
    out = Text()
    for c in it.comment:
        out.append(clip(" " * (LMT + 2) + "; " + c, lay.width) + "\n", STYLES["comment"])
    out.append_text(cv.text())
    return out


def _draw_piece(cv: Canvas, sheet: Sheet, pc: _Piece, lay: Layout) -> None:
    g = pc.g
    ox = _cx(g.width) + 2  # the piece's own output column
    for w in g.wires:
        if w.y0 == w.y1:
            cv.hline(pc.wy(w.y0), _cx(w.x0), _cx(w.x1))
        else:
            cv.vline(_cx(w.x0), pc.wy(w.y0), pc.wy(w.y1))
    for o in g.outputs:
        cv.hline(pc.wy(o.y), _cx(o.x), ox - 1)
    for c in g.cells:
        _cell(cv, sheet, pc, c, lay)
    for o in g.outputs:
        _output(cv, sheet, ox, pc.wy(o.y), o, lay)
    for x, y in g.rails:
        cv.put(_cx(x), pc.wy(y), "┃")
    for x, y in g.ends:
        cv.put(_cx(x), pc.wy(y), "┤")


def sheets_text(sheets: list[Sheet], width: int = DEFAULT_WIDTH, comments: bool = False) -> Text:
    lay = text_layout(sheets, width, comments)
    out = Text()
    for sh in sheets:
        out.append(clip(sh.path, lay.width) + "\n", "bold")
        for it in sh.items:
            out.append_text(item_text(sh, it, lay))
    return out


def print_sheets(sheets: list[Sheet], width: int | None = None, comments: bool = False,
                 console: Console | None = None) -> None:
    """Print on the terminal, as wide as `width` or else the terminal (DEFAULT_WIDTH when
    the output is not a terminal)."""
    console = console or Console(highlight=False, soft_wrap=True)
    if width is None:
        width = console.width if console.is_terminal else DEFAULT_WIDTH
    console.print(sheets_text(sheets, width, comments), end="")
