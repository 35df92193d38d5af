"""Grid -> SVG. One drawing per rung or row; `sheets_svg` stacks them into one file.

Every element that can conduct (contact, coil, box) is a `<g class="el" data-i=N>` with the
instruction index N, so the HTML report can light it up for a chosen scan. Text is plain
SVG <text> (searchable in a browser); sizes are whole pixels so the output is byte-stable.
"""

from __future__ import annotations

from dataclasses import dataclass
from xml.sax.saxutils import escape

from mlctool.ladder.document import RowView, RungView, Sheet, instr_text, operand_texts
from mlctool.ladder.layout import Cell, Grid, Output
from mlctool.syntax.source import display_width

CW = 84  # contact column width
RH = 64  # row height
WIRE_Y = 34  # wire height inside a row
LM = 60  # left margin: step addresses and labels; the rail is at x = LM
CHAR = 7.3  # width of one character of the 12 px monospace font
COMMENT_H = 16  # one comment line above a rung
GAP = 10  # space between rungs
MAX_NOTE = 60  # characters of an output's line comment shown beside it
MAX_COMMENT = 120  # characters of a rung comment line shown
MAX_NAME = 8  # characters of a signal's name under its device (a cell holds about 8 CJK characters)

STYLE = """
.lad text{font-family:"DejaVu Sans Mono",Menlo,Consolas,monospace;font-size:12px;fill:#111}
.lad .wire{stroke:#222;stroke-width:1.5;fill:none}
.lad .rail{stroke:#222;stroke-width:3}
.lad .sym{stroke:#222;stroke-width:2;fill:none}
.lad .box{stroke:#222;stroke-width:1.5;fill:#fff}
.lad .box.step{stroke-width:2.5}
.lad .frame{stroke:#777;stroke-width:1;stroke-dasharray:4 3;fill:none}
.lad .dot{fill:#222}
.lad text.small{font-size:10px;fill:#555}
.lad text.note{font-size:11px;fill:#2a6a2a;font-style:italic}
.lad text.comment{font-size:12px;fill:#2a6a2a}
.lad text.addr{font-size:11px;fill:#666}
.lad text.label{font-weight:bold;fill:#8a1c1c}
.lad text.file{font-size:14px;font-weight:bold}
.lad .el.on .sym,.lad .el.on .box{stroke:#0a8f2a;stroke-width:3}
.lad .el.on .box{fill:#d9f7df}
.lad .el.on text{fill:#0a6f1f}
""".strip()


@dataclass(frozen=True, slots=True)
class Geometry:
    """Column count and output column width shared by all rungs of one drawing."""

    cols: int
    out_w: int
    note_w: int
    text_w: int = 0  # widest comment line or file name

    @property
    def out_x(self) -> int:
        return LM + self.cols * CW

    @property
    def width(self) -> int:
        return max(self.out_x + self.out_w + self.note_w, self.text_w) + 12


def _px(chars: int) -> int:
    return int(chars * CHAR + 0.999)


def _esc(s: str) -> str:
    return escape(s, {'"': "&quot;"})


def geometry(sheets: list[Sheet]) -> Geometry:
    cols, out_chars, note_chars, text_chars = 1, 6, 0, 0
    for sh in sheets:
        cols = max(cols, sh.width)
        text_chars = max(text_chars, len(sh.path) * 14 // 12)
        for it in sh.items:
            text_chars = max([text_chars] + [min(MAX_COMMENT, len(c)) for c in it.comment])
            outs = it.grid.outputs if isinstance(it, RungView) else [it.row]
            for o in outs:
                out_chars = max(out_chars, display_width(instr_text(o.ins)) + 2)  # CJK names: 2 each
                note_chars = max(note_chars, min(MAX_NOTE, len(sh.notes.get(o.index, ""))))
    return Geometry(cols, max(64, _px(out_chars) + 16), _px(note_chars) + 8 if note_chars else 0,
                    LM + _px(text_chars))


def _clip(s: str, n: int) -> str:
    return s if len(s) <= n else s[:n - 1] + "…"


def _text(x: float, y: float, s: str, cls: str = "", anchor: str = "middle") -> str:
    c = f' class="{cls}"' if cls else ""
    a = f' text-anchor="{anchor}"' if anchor != "start" else ""
    return f'<text x="{x:g}" y="{y:g}"{c}{a}>{_esc(s)}</text>'


def _line(x0: float, y0: float, x1: float, y1: float, cls: str = "wire") -> str:
    return f'<line class="{cls}" x1="{x0:g}" y1="{y0:g}" x2="{x1:g}" y2="{y1:g}"/>'


def _gx(x: int) -> int:
    return LM + x * CW


def _gy(y: int) -> int:
    return y * RH + WIRE_Y


def _title(sheet: Sheet, index: int, text: str) -> str:
    note = sheet.notes.get(index)
    return f"<title>{_esc(text + (' ; ' + note if note else ''))}</title>"


def _labels(sheet: Sheet, index: int, cell_ins, x: float, y: int) -> list[str]:
    """Device above the symbol; below, the written symbol, else the manual's name of a signal
    (NC5 special M/D)."""
    devs = operand_texts(cell_ins)
    out = []
    if devs:
        out.append(_text(x, y - 18, devs[0][0]))
        below = devs[0][1] or sheet.names.get(index, "")
        if below:
            out.append(_text(x, y + 26, _clip(below, MAX_NAME), "small"))
    return out


def _cell(sheet: Sheet, c: Cell) -> str:
    x0, y = _gx(c.x), _gy(c.y)
    x1 = x0 + c.w * CW
    mid = (x0 + x1) / 2
    parts: list[str] = []
    if c.kind == "contact":
        parts += [_line(x0, y, mid - 7, y), _line(mid + 7, y, x1, y),
                  _line(mid - 7, y - 12, mid - 7, y + 12, "sym"), _line(mid + 7, y - 12, mid + 7, y + 12, "sym")]
        if c.glyph == "/":
            parts.append(_line(mid - 11, y + 10, mid + 11, y - 10, "sym"))
        elif c.glyph:
            parts.append(_text(mid, y + 4, c.glyph))
        parts += _labels(sheet, c.index, c.ins, mid, y)
    elif c.kind == "compare":
        (s1, sym1), (s2, sym2) = operand_texts(c.ins)[:2]
        rel = ("D" if c.ins.spec.width == 32 else "") + c.glyph
        parts += [_line(x0, y, x0 + 10, y), _line(x1 - 10, y, x1, y),
                  f'<rect class="box" x="{x0 + 10}" y="{y - 13}" width="{x1 - x0 - 20}" height="26"/>',
                  _text(mid, y + 4, f"{s1} {rel} {s2}")]
        if sym1 or sym2:
            parts.append(_text(mid, y + 26, f"{sym1 or s1} {rel} {sym2 or s2}", "small"))
    elif c.kind == "inv":
        parts += [_line(x0, y, x1, y), _line(mid - 8, y + 12, mid + 8, y - 12, "sym"),
                  _text(mid, y - 18, "INV", "small")]
    elif c.kind == "nop":
        parts += [_line(x0, y, x1, y), _text(mid, y - 8, "NOP", "small")]
    elif c.kind == "edge":  # MEP/MEF: the edge of the result so far, an arrow across the line
        parts += [_line(x0, y, x1, y), _line(mid, y - 12, mid, y + 12, "sym"),
                  _text(mid, y - 18, c.ins.mnemonic, "small")]
        tip = y - 12 if c.glyph == "↑" else y + 12
        back = tip + 6 if c.glyph == "↑" else tip - 6
        parts += [_line(mid - 5, back, mid, tip, "sym"), _line(mid + 5, back, mid, tip, "sym")]
    elif c.kind == "step":  # the state box of a step ladder step (VS 4-6-2 (b))
        parts += [_line(x0, y, x0 + 8, y), _line(x1 - 8, y, x1, y),
                  f'<rect class="box step" x="{x0 + 8}" y="{y - 14}" width="{x1 - x0 - 16}" height="28"/>',
                  _text(mid, y + 4, operand_texts(c.ins)[0][0]), _text(mid, y - 18, "STL", "small")]
    else:  # tap: the power at the branch point made at step c.glyph
        parts += [_line(x0, y, mid - 12, y), _line(mid + 12, y, x1, y),
                  f'<rect class="box" x="{mid - 12:g}" y="{y - 10}" width="24" height="20"/>',
                  _text(mid, y + 4, "⇤", "small"), _text(mid, y - 18, f"@{c.glyph}", "small")]
        return "<g>" + "".join(parts) + "<title>power at the branch point of step " \
            f"{_esc(c.glyph)} (MPS stack)</title></g>"
    return f'<g class="el" data-i="{c.index}">' + "".join(parts) + _title(sheet, c.index, instr_text(c.ins)) + "</g>"


def _output(sheet: Sheet, geo: Geometry, o: Output, index: int, y: int) -> list[str]:
    ox = geo.out_x
    parts = []
    if o.kind == "pin":  # a further input of the box drawn on an earlier row
        return [_line(ox, y, ox + 10, y), _text(ox + 14, y + 4, o.letter, "small", "start")]
    if o.kind == "coil":
        cx = ox + 30
        g = [_line(ox, y, cx - 12, y),
             f'<path class="sym" d="M{cx - 6},{y - 12} A14,14 0 0,0 {cx - 6},{y + 12}"/>',
             f'<path class="sym" d="M{cx + 6},{y - 12} A14,14 0 0,1 {cx + 6},{y + 12}"/>']
        if o.letter:
            g.append(_text(cx, y + 4, o.letter))
        g += _labels(sheet, index, o.ins, cx, y)
        end = cx + 16
    else:
        w = geo.out_w - 8
        g = [f'<rect class="box" x="{ox + 4}" y="{y - 13}" width="{w}" height="26"/>',
             _text(ox + 4 + w / 2, y + 4, " ".join((o.ins.mnemonic, *(d for d, _ in operand_texts(o.ins)))))]
        if any(s for _, s in operand_texts(o.ins)):
            g.append(_text(ox + 4 + w / 2, y + 26, instr_text(o.ins), "small"))
        end = ox + 4 + w
    parts.append(f'<g class="el" data-i="{index}">' + "".join(g) + _title(sheet, index, instr_text(o.ins)) + "</g>")
    note = sheet.notes.get(index)
    if note:
        parts.append(_text(max(end, ox + geo.out_w) + 8, y + 4, _clip(note, MAX_NOTE), "note", "start"))
    return parts


def item_height(it: RungView | RowView) -> int:
    rows = it.grid.height if isinstance(it, RungView) else 1
    return len(it.comment) * COMMENT_H + rows * RH


def item_svg(sheet: Sheet, it: RungView | RowView, geo: Geometry) -> list[str]:
    """The drawing of one rung or row, top at y = 0, as SVG elements."""
    top = len(it.comment) * COMMENT_H
    parts = [_text(LM + 8, 12 + k * COMMENT_H, _clip(c, MAX_COMMENT), "comment", "start")
             for k, c in enumerate(it.comment)]
    # the rail runs on through the comment lines and the gap to the next rung
    body: list[str] = [_line(LM, -top, LM, item_height(it) - top + GAP, "rail")]
    if isinstance(it, RowView):
        ins, y = it.row.ins, _gy(0)
        if ins.spec.cls == "label":
            body.append(_text(LM - 8, y + 4, instr_text(ins)[2:] if ins.mnemonic == "P" else instr_text(ins),
                              "label", "end"))
        else:
            body.append(_text(LM - 8, y + 4, str(ins.addr), "addr", "end"))
            body.append(_line(LM, y, geo.out_x + 4, y))
            body += _output(sheet, geo, Output(0, 0, "box", ins, it.row.index), it.row.index, y)
    else:
        g: Grid = it.grid
        body.append(_text(LM - 8, _gy(0) + 4, str(it.addr), "addr", "end"))
        body += [_line(_gx(w.x0), _gy(w.y0), _gx(w.x1), _gy(w.y1)) for w in g.wires]
        body += [_cell(sheet, c) for c in g.cells]
        for o in g.outputs:
            body.append(_line(_gx(o.x), _gy(o.y), geo.out_x, _gy(o.y)))
            body += _output(sheet, geo, o, o.index, _gy(o.y))
        for f in g.frames:
            body.append(f'<rect class="frame" x="{_gx(f.x0) + 3}" y="{_gy(f.y0) - 28}" '
                        f'width="{_gx(f.x1) - _gx(f.x0) - 6}" height="{(f.y1 - f.y0) * RH + 50}"/>')
        for x, y in g.rails:
            body.append(_line(_gx(x) + 2, _gy(y) - 12, _gx(x) + 2, _gy(y) + 12, "rail"))
        for x, y in g.ends:
            body.append(_line(_gx(x), _gy(y) - 6, _gx(x), _gy(y) + 6, "sym"))
        body += [f'<circle class="dot" cx="{_gx(x)}" cy="{_gy(y)}" r="3"/>' for x, y in g.dots]
    parts.append(f'<g transform="translate(0,{top})">' + "".join(body) + "</g>")
    return parts


def sheets_svg(sheets: list[Sheet]) -> str:
    """One SVG: each file's title, then its rungs and rows stacked in program order."""
    geo = geometry(sheets)
    y = 0
    parts: list[str] = []
    for sh in sheets:
        parts.append(f'<g class="sheet" transform="translate(0,{y})">'
                     + _text(8, 18, sh.path, "file", "start") + "</g>")
        y += 30
        for it in sh.items:
            cls = "rung" if isinstance(it, RungView) else "row"
            parts.append(f'<g class="{cls}" id="{_esc(anchor(sheets.index(sh), it))}" '
                         f'transform="translate(0,{y})">' + "".join(item_svg(sh, it, geo)) + "</g>")
            y += item_height(it) + GAP
    return (f'<svg xmlns="http://www.w3.org/2000/svg" class="lad" width="{geo.width}" height="{y}" '
            f'viewBox="0 0 {geo.width} {y}">\n<style>\n{STYLE}\n</style>\n' + "\n".join(parts) + "\n</svg>\n")


def anchor(file_no: int, it: RungView | RowView) -> str:
    """A stable id: file number and step address (rows at the same address get a suffix)."""
    kind = "s" if isinstance(it, RungView) else "p" if it.row.ins.spec.cls == "label" else "f"
    return f"f{file_no}-{kind}{it.addr}"
