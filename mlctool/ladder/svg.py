"""Grid -> SVG. One drawing per rung or row; `sheets_svg` stacks them into one file.

Every element that can conduct (contact, coil, box) is a `<g class="el" data-i=N>` with the
instruction index N, so the HTML report can light it up for a chosen scan. Text is plain
SVG <text> (searchable in a browser); sizes are whole pixels so the output is byte-stable.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from xml.sax.saxutils import escape

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

CW = 84  # contact column width
RH = 64  # row height
WIRE_Y = 34  # wire height inside a row
LM = 60  # left margin: step addresses and labels; the rail is at x = LM
CHAR = 7.3  # width of one character of the 12 px monospace font
SMALL_CHAR = 6.1  # ... of the 10 px one
COMMENT_H = 16  # one comment line above a rung
GAP = 10  # space between rungs
PIECE_GAP = 6  # space between the pieces of a wrapped rung
PAGE_W = 1200  # a drawing is at most this wide: it fits a 1280 px browser window with the page's margins
MIN_OUT_W, MAX_OUT_W = 64, 320  # an output box's width
MIN_NOTE = 8  # characters of an output's line comment worth drawing beside it (else: tooltip only)
DEVICE_COMMENT_LINES = 2  # lines of a device comment under a contact (--comments)
DEVICE_COMMENT_CHARS = 13  # characters per line (10 px font, one column)
SMALL_LINE = 12  # line pitch of the small text under a symbol

STYLE = """
.lad text{font-family:"DejaVu Sans Mono",Menlo,Consolas,monospace;font-size:12px;fill:#111}
.lad .wire{stroke:#222;stroke-width:1.5;fill:none}
.lad .rail{stroke:#222;stroke-width:3}
.lad .sym{stroke:#222;stroke-width:2;fill:none}
.lad .box{stroke:#222;stroke-width:1.5;fill:#fff}
.lad .box.step{stroke-width:2.5}
.lad .frame{stroke:#777;stroke-width:1;stroke-dasharray:4 3;fill:none}
.lad .dot{fill:#222}
.lad .wrap{stroke:#555;stroke-width:1.5;fill:#eee}
.lad text.small{font-size:10px;fill:#555}
.lad text.dcomment{font-size:10px;fill:#2a6a2a}
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
    """What all rungs of one drawing share: the columns a piece of a rung may use, the
    width of output boxes, the row height and the drawing's width."""

    cols: int
    out_w: int
    rh: int = RH
    comments: bool = False  # device comments under contacts and coils
    page: int = PAGE_W
    width: int = 0

    def gy(self, y: int) -> int:
        return y * self.rh + WIRE_Y


def _px(chars: int) -> int:
    return int(chars * CHAR + 0.999)


def _esc(s: str) -> str:
    return escape(s, {'"': "&quot;"})


def geometry(sheets: list[Sheet], comments: bool = False, page: int = PAGE_W) -> Geometry:
    """The drawing's geometry: boxes as wide as the widest output's text (within
    MIN_OUT_W..MAX_OUT_W), as many contact columns as fit the page beside them."""
    out_chars = 6
    for sh in sheets:
        for it in sh.items:
            for o in (it.grid.outputs if isinstance(it, RungView) else [it.row]):
                out_chars = max(out_chars, display_width(box_text(o.ins)), display_width(instr_text(o.ins)))
    out_w = min(MAX_OUT_W, max(MIN_OUT_W, _px(out_chars) + 16))
    cols = max(MIN_COLS, (page - LM - 12 - out_w) // CW)
    geo = Geometry(cols, out_w, RH + (DEVICE_COMMENT_LINES * SMALL_LINE + 4 if comments else 0), comments, page)
    width = LM + _px(max((display_width(sh.path) * 14 // 12 for sh in sheets), default=0))
    for sh in sheets:
        for it in sh.items:
            width = max(width, _item_width(sh, it, geo))
    return dataclasses.replace(geo, width=min(page, width + 12))


def _item_width(sheet: Sheet, it: RungView | RowView, geo: Geometry) -> int:
    width = max((LM + 8 + _px(display_width(c)) for c in it.comment), default=0)
    if isinstance(it, RowView):
        outs = [(LM, it.row.index, "box")]
    else:
        outs = [(LM + p.width * CW, o.index, o.kind) for p in pieces(it, geo) for o in p.outputs]
        width = max([width] + [LM + p.width * CW for p in pieces(it, geo)])
    for ox, index, kind in outs:
        end = _output_end(ox, kind, geo)
        note = sheet.notes.get(index)
        width = max(width, end + (8 + _px(display_width(note)) if note else 0))
    return width


def _output_end(ox: int, kind: str, geo: Geometry) -> int:
    return ox + {"coil": 46, "pin": 40}.get(kind, geo.out_w)



def _text(x: float, y: float, s: str, cls: str = "", anchor: str = "middle") -> str:
    c = f' class="{cls}"' if cls else ""
    a = f' text-anchor="{anchor}"' if anchor != "start" else ""
    return f'<text x="{x:g}" y="{y:g}"{c}{a}>{_esc(s)}</text>'


def _line(x0: float, y0: float, x1: float, y1: float, cls: str = "wire") -> str:
    return f'<line class="{cls}" x1="{x0:g}" y1="{y0:g}" x2="{x1:g}" y2="{y1:g}"/>'


def _gx(x: int) -> int:
    return LM + x * CW


def _title(sheet: Sheet, index: int, text: str) -> str:
    note = sheet.notes.get(index)
    return f"<title>{_esc(text + (' ; ' + note if note else ''))}</title>"


def _labels(sheet: Sheet, index: int, x: float, y: int, geo: Geometry) -> list[str]:
    """Device above the symbol; under it the symbol as written (if any), then with
    --comments the device comment (document.comment_of)."""
    ins = sheet.instrs[index]
    devs = operand_texts(ins)
    out = []
    if devs:
        out.append(_text(x, y - 18, clip(devs[0][0], CW // 7)))
        below = devs[0][1] or sheet.names.get(index, "")  # the written symbol, else a signal's name
        under = [(clip(below, DEVICE_COMMENT_CHARS), "small")] if below else []
        if geo.comments:
            under += [(t, "dcomment") for t in fold(comment_of(sheet, index), DEVICE_COMMENT_CHARS,
                                                     DEVICE_COMMENT_LINES + 1 - len(under))]
        out += [_text(x, y + 26 + k * SMALL_LINE, t, cls) for k, (t, cls) in enumerate(under)]
    return out


def _marker(mid: float, y: int, number: str) -> str:
    """A continuation marker: a tag pointing right with the number of the line it carries."""
    return (f'<path class="wrap" d="M{mid - 12:g},{y - 9} L{mid + 4:g},{y - 9} L{mid + 12:g},{y} '
            f'L{mid + 4:g},{y + 9} L{mid - 12:g},{y + 9} Z"/>' + _text(mid - 2, y + 4, number, "small"))


def _cell(sheet: Sheet, c: Cell, geo: Geometry) -> str:
    x0, y = _gx(c.x), geo.gy(c.y)
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
        parts += _labels(sheet, c.index, mid, y, geo)
    elif c.kind == "compare":
        (s1, sym1), (s2, sym2) = operand_texts(c.ins)[:2]
        rel = ("D" if c.ins.spec.width == 32 else "") + c.glyph
        parts += [_line(x0, y, x0 + 10, y), _line(x1 - 10, y, x1, y),
                  f'<rect class="box" x="{x0 + 10}" y="{y - 13}" width="{x1 - x0 - 20}" height="26"/>',
                  _text(mid, y + 4, clip(f"{s1} {rel} {s2}", 2 * CW // 7 - 3))]
        if sym1 or sym2:
            parts.append(_text(mid, y + 26, clip(f"{sym1 or s1} {rel} {sym2 or s2}", 2 * CW // 6 - 1), "small"))
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
    elif c.kind == "wrap_out":  # the line goes on at the marker of the same number below
        return ("<g>" + _line(x0, y, mid - 12, y) + _marker(mid, y, c.glyph)
                + f"<title>continued on the next line at {_esc(c.glyph)}</title></g>")
    elif c.kind == "wrap_in":
        return ("<g>" + _marker(mid, y, c.glyph) + _line(mid + 12, y, x1, y)
                + f"<title>continued from {_esc(c.glyph)} on the line above</title></g>")
    else:  # tap: the power at the branch point made at step c.glyph
        parts += [_line(x0, y, mid - 12, y), _line(mid + 12, y, x1, y),
                  f'<rect class="box" x="{mid - 12:g}" y="{y - 10}" width="24" height="20"/>',
                  _text(mid, y + 4, "⇤", "small"), _text(mid, y - 18, f"@{c.glyph}", "small")]
        return "<g>" + "".join(parts) + "<title>power at the branch point of step " \
            f"{_esc(c.glyph)} (MPS stack)</title></g>"
    return f'<g class="el" data-i="{c.index}">' + "".join(parts) + _title(sheet, c.index, instr_text(c.ins)) + "</g>"


def _output(sheet: Sheet, geo: Geometry, ox: int, o: Output, y: int) -> list[str]:
    """The output `o` in the output column at x = ox, its line comment beside it."""
    parts = []
    index = o.index
    if o.kind == "pin":  # a further input of the box drawn on an earlier row
        return [_line(ox, y, ox + 10, y), _text(ox + 14, y + 4, o.letter, "small", "start")]
    if o.kind == "coil":
        cx = ox + 30
        g = [_line(ox, y, cx - 12, y),
             f'<path class="sym" d="M{cx - 6},{y - 12} A14,14 0 0,0 {cx - 6},{y + 12}"/>',
             f'<path class="sym" d="M{cx + 6},{y - 12} A14,14 0 0,1 {cx + 6},{y + 12}"/>']
        if o.letter:
            g.append(_text(cx, y + 4, o.letter))
        g += _labels(sheet, index, cx, y, geo)
    else:
        w = geo.out_w - 8
        chars = int((w - 8) / CHAR)
        g = [f'<rect class="box" x="{ox + 4}" y="{y - 13}" width="{w}" height="26"/>',
             _text(ox + 4 + w / 2, y + 4, clip(box_text(o.ins), chars))]
        if any(s for _, s in operand_texts(o.ins)):
            g.append(_text(ox + 4 + w / 2, y + 26, clip(instr_text(o.ins), int((w - 4) / SMALL_CHAR)), "small"))
    parts.append(f'<g class="el" data-i="{index}">' + "".join(g) + _title(sheet, index, instr_text(o.ins)) + "</g>")
    note = sheet.notes.get(index)
    x = _output_end(ox, o.kind, geo) + 8
    room = int((geo.page - 4 - x) / 6.7)  # 11 px italic
    if note and room >= MIN_NOTE:
        parts.append(_text(x, y + 4, clip(note, room), "note", "start"))
    return parts


def pieces(it: RungView, geo: Geometry) -> list[Grid]:
    return wrap(it.grid, geo.cols)


def item_height(it: RungView | RowView, geo: Geometry) -> int:
    body = sum(p.height * geo.rh + PIECE_GAP for p in pieces(it, geo)) - PIECE_GAP \
        if isinstance(it, RungView) else geo.rh
    return len(it.comment) * COMMENT_H + body


def item_svg(sheet: Sheet, it: RungView | RowView, geo: Geometry) -> list[str]:
    """The drawing of one rung or row, top at y = 0, as SVG elements."""
    top = len(it.comment) * COMMENT_H
    text_room = int((geo.page - LM - 16) / CHAR)
    parts = [_text(LM + 8, 12 + k * COMMENT_H, clip(c, text_room), "comment", "start")
             for k, c in enumerate(it.comment)]
    # the rail runs on through the comment lines and the gap to the next rung
    body: list[str] = [_line(LM, -top, LM, item_height(it, geo) - top + GAP, "rail")]
    if isinstance(it, RowView):
        ins, y = it.row.ins, geo.gy(0)
        if ins.spec.cls == "label":
            body.append(_text(LM - 8, y + 4, instr_text(ins)[2:] if ins.mnemonic == "P" else instr_text(ins),
                              "label", "end"))
        else:
            body.append(_text(LM - 8, y + 4, str(ins.addr), "addr", "end"))
            body.append(_line(LM, y, LM + 4, y))
            body += _output(sheet, geo, LM, Output(0, 0, "box", ins, it.row.index), y)
        parts.append(f'<g transform="translate(0,{top})">' + "".join(body) + "</g>")
        return parts
    body.append(_text(LM - 8, geo.gy(0) + 4, str(it.addr), "addr", "end"))
    y0 = 0
    for g in pieces(it, geo):
        body.append(f'<g transform="translate(0,{y0})">' if y0 else "<g>")
        body += _piece_svg(sheet, g, geo)
        body.append("</g>")
        y0 += g.height * geo.rh + PIECE_GAP
    parts.append(f'<g transform="translate(0,{top})">' + "".join(body) + "</g>")
    return parts


def _piece_svg(sheet: Sheet, g: Grid, geo: Geometry) -> list[str]:
    ox = _gx(g.width)  # the piece's own output column
    gy = geo.gy
    body = [_line(_gx(w.x0), gy(w.y0), _gx(w.x1), gy(w.y1)) for w in g.wires]
    body += [_cell(sheet, c, geo) for c in g.cells]
    for o in g.outputs:
        body.append(_line(_gx(o.x), gy(o.y), ox, gy(o.y)))
        body += _output(sheet, geo, ox, o, gy(o.y))
    for f in g.frames:
        body.append(f'<rect class="frame" x="{_gx(f.x0) + 3}" y="{gy(f.y0) - 28}" '
                    f'width="{_gx(f.x1) - _gx(f.x0) - 6}" height="{(f.y1 - f.y0) * geo.rh + 50}"/>')
    for x, y in g.rails:
        body.append(_line(_gx(x) + 2, gy(y) - 12, _gx(x) + 2, gy(y) + 12, "rail"))
    for x, y in g.ends:
        body.append(_line(_gx(x), gy(y) - 6, _gx(x), gy(y) + 6, "sym"))
    body += [f'<circle class="dot" cx="{_gx(x)}" cy="{gy(y)}" r="3"/>' for x, y in g.dots]
    return body


def sheets_svg(sheets: list[Sheet], comments: bool = False) -> str:
    """One SVG: each file's title, then its rungs and rows stacked in program order."""
    geo = geometry(sheets, comments)
    y = 0
    parts: list[str] = []
    for no, sh in enumerate(sheets):
        parts.append(f'<g class="sheet" transform="translate(0,{y})">'
                     + _text(8, 18, sh.path, "file", "start") + "</g>")
        y += 30
        for it in sh.items:
            cls = "rung" if isinstance(it, RungView) else "row"
            parts.append(f'<g class="{cls}" id="{_esc(anchor(no, it))}" '
                         f'transform="translate(0,{y})">' + "".join(item_svg(sh, it, geo)) + "</g>")
            y += item_height(it, geo) + GAP
    return (f'<svg xmlns="http://www.w3.org/2000/svg" class="lad" width="{geo.width}" height="{y}" '
            f'viewBox="0 0 {geo.width} {y}">\n<style>\n{STYLE}\n</style>\n' + "\n".join(parts) + "\n</svg>\n")


def anchor(file_no: int, it: RungView | RowView) -> str:
    """A stable id: file number and step address (rows at the same address get a suffix)."""
    kind = "s" if isinstance(it, RungView) else "p" if it.row.ins.spec.cls == "label" else "f"
    return f"f{file_no}-{kind}{it.addr}"
