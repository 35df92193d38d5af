"""Network -> grid: where each contact, wire, branch bus and output goes, in cell units.

Coordinates: x counts contact columns from the left rail, y counts rows. A point (x, y) is
the left edge of column x at the height of row y's wire; an element of width w in row y
runs from (x, y) to (x + w, y). A rung's outputs sit in its own output column, right of
the last column a line of the rung reaches (`Grid.width`). A rung wider than the page is cut
into pieces by `wrap`, as GX Works folds a wide rung: each line crossing a cut ends in a
numbered continuation marker and goes on from the marker of the same number at the start
of the next piece.

Renderers only draw what is here; they never look at the network again.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from mlctool.ladder.network import Coil, Group, Leaf, Line, Node, Parallel, Pin, Rung, Tap
from mlctool.program import Instr

# contact glyphs by `op` (instructions.toml): what the symbol between the bars shows
CONTACT_GLYPH = {
    "contact": "", "contact_not": "/", "contact_rise": "↑", "contact_fall": "↓",
}
# comparison contacts (API 39-56) are boxes two columns wide with the relation inside
COMPARE_REL = {"cmp_eq": "=", "cmp_ne": "<>", "cmp_gt": ">", "cmp_lt": "<", "cmp_ge": ">=",
               "cmp_le": "<="}
# coils by `op`: the letter inside the coil; every other output is an instruction box
COIL_LETTER = {"out": "", "set": "S", "rst": "R"}
# MEP/MEF (VS 3-3): the edge of the result so far, drawn as an arrow on the line
RESULT_EDGE = {"result_rise": "↑", "result_fall": "↓"}
# width in columns of the series elements that are not plain contacts, by instruction class
CLASS_WIDTH = {"inv": 1, "nop": 1}
BIT_COIL_KINDS = ("Y", "M", "A")  # OUT/SET/RST of these are coils, everything else a box


@dataclass(frozen=True, slots=True)
class Cell:
    """A series element: contact, comparison box, INV, NOP, or a branch-point tap."""

    x: int
    y: int
    w: int
    kind: str  # contact | compare | inv | nop | tap | step (STL's state box) | edge (MEP/MEF)
    #            | wrap_out / wrap_in (the continuation marker `glyph` of a wrapped rung)
    ins: Instr | None
    index: int  # instruction index (-1: tap)
    glyph: str = ""  # contact glyph, relation of a comparison, or the tap's step address


@dataclass(frozen=True, slots=True)
class Wire:
    x0: int
    y0: int
    x1: int
    y1: int


@dataclass(frozen=True, slots=True)
class Output:
    """A coil or instruction box in the output column; its wire starts at (x, y)."""

    x: int
    y: int
    kind: str  # coil | box | pin (a further input of the multi-input box `ins`, named `letter`)
    ins: Instr
    index: int
    letter: str = ""


@dataclass(frozen=True, slots=True)
class Frame:
    """A Group: the block an INV inside it inverts."""

    x0: int
    y0: int
    x1: int
    y1: int


@dataclass
class Grid:
    cells: list[Cell] = field(default_factory=list)
    wires: list[Wire] = field(default_factory=list)
    outputs: list[Output] = field(default_factory=list)
    frames: list[Frame] = field(default_factory=list)
    rails: list[tuple[int, int]] = field(default_factory=list)  # lines fed from the rail
    ends: list[tuple[int, int]] = field(default_factory=list)  # lines that drive nothing
    dots: list[tuple[int, int]] = field(default_factory=list)  # branch points
    width: int = 0  # columns used by contacts
    height: int = 0  # rows

    def reach(self, x: int) -> None:
        self.width = max(self.width, x)


def leaf_width(leaf: Leaf) -> int:
    spec = leaf.ins.spec
    if spec.op in COMPARE_REL:
        return 2
    return CLASS_WIDTH.get(spec.cls, 1)


def size(elems: list) -> tuple[int, int]:
    """(width, height) of series elements."""
    w, h = 0, 1
    for e in elems:
        ew, eh = _elem_size(e)
        w += ew
        h = max(h, eh)
    return w, h


def _elem_size(e) -> tuple[int, int]:
    if isinstance(e, Leaf):
        return leaf_width(e), 1
    if isinstance(e, Tap):
        return 1, 1
    if isinstance(e, Parallel):
        sizes = [size(b) for b in e.branches]
        return max(w for w, _ in sizes), sum(h for _, h in sizes)
    if isinstance(e, Group):
        return size(e.elems)
    raise TypeError(f"not a series element: {type(e).__name__}")  # pragma: no cover


def _leaf_cell(leaf: Leaf, x: int, y: int) -> Cell:
    spec = leaf.ins.spec
    if spec.op in COMPARE_REL:
        return Cell(x, y, 2, "compare", leaf.ins, leaf.index, COMPARE_REL[spec.op])
    if spec.cls in CLASS_WIDTH:
        return Cell(x, y, 1, spec.cls, leaf.ins, leaf.index)
    if spec.op in RESULT_EDGE:
        return Cell(x, y, 1, "edge", leaf.ins, leaf.index, RESULT_EDGE[spec.op])
    if spec.cls == "bus":
        return Cell(x, y, 1, "step", leaf.ins, leaf.index)
    return Cell(x, y, 1, "contact", leaf.ins, leaf.index, CONTACT_GLYPH.get(spec.op, ""))


def place_series(elems: list, x: int, y: int, g: Grid) -> int:
    """Place elements from (x, y); return the x where the series ends."""
    for e in elems:
        x = _place(e, x, y, g)
    return x


def _place(e, x: int, y: int, g: Grid) -> int:
    if isinstance(e, Leaf):
        cell = _leaf_cell(e, x, y)
        g.cells.append(cell)
        return x + cell.w
    if isinstance(e, Tap):
        g.cells.append(Cell(x, y, 1, "tap", None, -1, str(e.node.addr)))
        return x + 1
    if isinstance(e, Group):
        end = place_series(e.elems, x, y, g)
        g.frames.append(Frame(x, y, end, y + size(e.elems)[1] - 1))
        return end
    w, _ = _elem_size(e)
    row = y
    for b in e.branches:  # Parallel: branches stacked, joined by buses on both sides
        end = place_series(b, x, row, g)
        if end < x + w:
            g.wires.append(Wire(end, row, x + w, row))
        last = row
        row += size(b)[1]
    g.wires.append(Wire(x, y, x, last))
    g.wires.append(Wire(x + w, y, x + w, last))
    return x + w


def _place_node(node: Node, x: int, y: int, g: Grid) -> int:
    """Lines of a branch point from (x, y) downwards; return the rows used."""
    row = y
    fed = [y]  # rows joined by the branch bus: the incoming line and the lines it feeds
    for line in node.lines:
        h = _place_line(line, x, row, g)
        if line.from_rail:
            g.rails.append((x, row))
        elif row != y:
            fed.append(row)
        row += h
    if len(fed) > 1:
        g.wires.append(Wire(x, y, x, fed[-1]))
        g.dots.append((x, y))
    return row - y


def _place_line(line: Line, x: int, y: int, g: Grid) -> int:
    end = place_series(line.elems, x, y, g)
    h = size(line.elems)[1]
    if isinstance(line.to, Coil):
        g.reach(end)
        ins = line.to.ins
        letter = COIL_LETTER.get(ins.spec.op)
        kind = "coil" if letter is not None and _bit_operand(ins) else "box"
        g.outputs.append(Output(end, y, kind, ins, line.to.index, letter or ""))
    elif isinstance(line.to, Pin):
        g.reach(end)
        g.outputs.append(Output(end, y, "pin", line.to.coil.ins, line.to.coil.index, line.to.name))
    elif isinstance(line.to, Node):
        h = max(h, _place_node(line.to, end, y, g))
    else:
        g.reach(end)
        g.ends.append((end, y))
    return h


def _bit_operand(ins: Instr) -> bool:
    # RST D0 or RST T0 clears a register too: drawn as an instruction box, RST Y0 as a coil
    return bool(ins.operands) and ins.operands[0].kind in BIT_COIL_KINDS


def layout_rung(rung: Rung) -> Grid:
    g = Grid()
    g.height = _place_node(rung.root, 0, 0, g)
    g.dots = [d for d in g.dots if d[0] > 0]  # the rail itself needs no branch dot
    return g


# --------------------------------------------------------------- wrapping a wide rung

MIN_COLS = 4  # a piece holds at least this many columns (a cut never splits a cell)


def wrap(g: Grid, cols: int) -> list[Grid]:
    """The grid as pieces at most `cols` columns wide (markers included), each with its
    outputs in its own output column: an output goes in the piece where its line ends.

    A cut at column c goes where no cell spans c; among the columns of the right half of
    what the piece may hold it takes the one that the fewest lines cross, then one with no
    branch bus on it, then the rightmost. (Only where comparison boxes, two columns wide,
    overlap every column it could be cut at is a piece wider than `cols`.) The pieces after the first start with a column of
    incoming markers; a piece with crossing lines ends with a column of outgoing ones."""
    cols = max(cols, MIN_COLS)
    if g.width <= cols:
        return [g]
    cover: dict[int, set[int]] = {}  # row -> unit columns [i, i+1] a line runs through
    for c in g.cells:
        cover.setdefault(c.y, set()).update(range(c.x, c.x + c.w))
    for w in g.wires:
        if w.y0 == w.y1:
            cover.setdefault(w.y0, set()).update(range(min(w.x0, w.x1), max(w.x0, w.x1)))
    buses = [w for w in g.wires if w.x0 == w.x1]

    def splits_cell(c: int) -> bool:
        return any(cell.x < c < cell.x + cell.w for cell in g.cells)

    def crossing(c: int) -> list[int]:
        rows = []
        for y in range(g.height):
            row = cover.get(y, ())
            if c - 1 in row and (c in row or any(b.x0 == c and min(b.y0, b.y1) <= y <= max(b.y0, b.y1)
                                                 for b in buses)):
                rows.append(y)
        return rows

    cuts: list[tuple[int, list[int]]] = []
    start = 0
    while g.width - start + (start > 0) > cols:
        room = cols - (start > 0) - 1  # columns of this piece left of its outgoing markers
        low, high = start + max(1, (room + 1) // 2), start + room
        options = [c for c in range(low, high + 1) if not splits_cell(c)] or \
            [c for c in range(start + 1, high + 1) if not splits_cell(c)]
        while not options:  # cells of width 2 on every column of the range: go a column further
            high += 1
            options = [c for c in range(start + 1, high + 1) if not splits_cell(c)]
        best = min(options, key=lambda c: (len(crossing(c)), any(b.x0 == c for b in buses), -c))
        cuts.append((best, crossing(best)))
        start = best
    return _pieces(g, cuts)


def _pieces(g: Grid, cuts: list[tuple[int, list[int]]]) -> list[Grid]:
    bounds = [0] + [c for c, _ in cuts] + [g.width]
    marks: list[list[str]] = []  # per cut, the marker number of each crossing line
    for _, rows in cuts:
        first = sum(len(m) for m in marks) + 1
        marks.append([str(first + n) for n in range(len(rows))])
    pieces = []
    for k in range(len(bounds) - 1):
        p = _piece(g, bounds[k], bounds[k + 1], k, len(bounds) - 2)
        if k:  # the lines the cut before this piece crossed go on here
            p.cells += [Cell(0, y, 1, "wrap_in", None, -1, m) for y, m in zip(cuts[k - 1][1], marks[k - 1],
                                                                              strict=True)]
        if k < len(cuts):
            x = bounds[k + 1] - bounds[k] + (1 if k else 0)
            p.cells += [Cell(x, y, 1, "wrap_out", None, -1, m) for y, m in zip(cuts[k][1], marks[k], strict=True)]
        _measure(p)
        pieces.append(_squeeze(p))
    return pieces


def _piece(g: Grid, a: int, b: int, k: int, last: int) -> Grid:
    """What of the grid lies between the cuts at columns a and b, moved to the piece's own
    columns (after the column of incoming markers, except in the first piece)."""
    off = 1 if k else 0

    def right_of_cut(x: int) -> bool:  # branch buses, rail bars, dots: in the piece right of a cut
        return a <= x < b or (k == last and x == b)

    def on_bus(x: int, y: int) -> bool:
        return any(w.x0 == x and w.x1 == x and min(w.y0, w.y1) <= y <= max(w.y0, w.y1) for w in g.wires)

    def line_end_here(x: int, y: int) -> bool:
        # the end of a line (an output, an end) at a cut goes with the piece left of it,
        # unless a branch bus on the cut feeds it: then with the bus, right of it
        return right_of_cut(x) if x in (a, b) and on_bus(x, y) else a < x <= b or (k == 0 and x == a)

    p = Grid()
    for c in g.cells:
        if a <= c.x and c.x + c.w <= b:
            p.cells.append(Cell(c.x - a + off, c.y, c.w, c.kind, c.ins, c.index, c.glyph))
    for w in g.wires:
        if w.y0 == w.y1:
            x0, x1 = max(min(w.x0, w.x1), a), min(max(w.x0, w.x1), b)
            if x0 < x1:
                p.wires.append(Wire(x0 - a + off, w.y0, x1 - a + off, w.y1))
        elif right_of_cut(w.x0):
            p.wires.append(Wire(w.x0 - a + off, w.y0, w.x1 - a + off, w.y1))
    p.outputs = [Output(o.x - a + off, o.y, o.kind, o.ins, o.index, o.letter) for o in g.outputs
                 if line_end_here(o.x, o.y)]
    for f in g.frames:
        x0, x1 = max(f.x0, a), min(f.x1, b)
        if x0 < x1:
            p.frames.append(Frame(x0 - a + off, f.y0, x1 - a + off, f.y1))
    p.rails = [(x - a + off, y) for x, y in g.rails if right_of_cut(x)]
    p.ends = [(x - a + off, y) for x, y in g.ends if line_end_here(x, y)]
    p.dots = [(x - a + off, y) for x, y in g.dots if right_of_cut(x)]
    return p


def _measure(p: Grid) -> None:
    ends = [c.x + c.w for c in p.cells] + [max(w.x0, w.x1) for w in p.wires]
    ends += [o.x for o in p.outputs] + [x for x, _ in p.ends]
    p.width = max(ends, default=0)


def _squeeze(p: Grid) -> Grid:
    """The piece with the rows it does not use taken out (a long first line wrapped leaves
    the short lines of its branch point in the first piece)."""
    used: set[int] = set()
    used.update(c.y for c in p.cells)
    used.update(o.y for o in p.outputs)
    used.update(y for _, y in p.rails + p.ends + p.dots)
    for w in p.wires:
        used.update(range(min(w.y0, w.y1), max(w.y0, w.y1) + 1))
    for f in p.frames:
        used.update(range(f.y0, f.y1 + 1))
    row = {y: k for k, y in enumerate(sorted(used))}
    q = Grid(width=p.width, height=len(row))
    q.cells = [Cell(c.x, row[c.y], c.w, c.kind, c.ins, c.index, c.glyph) for c in p.cells]
    q.wires = [Wire(w.x0, row[w.y0], w.x1, row[w.y1]) for w in p.wires]
    q.outputs = [Output(o.x, row[o.y], o.kind, o.ins, o.index, o.letter) for o in p.outputs]
    q.frames = [Frame(f.x0, row[f.y0], f.x1, row[f.y1]) for f in p.frames]
    q.rails = [(x, row[y]) for x, y in p.rails]
    q.ends = [(x, row[y]) for x, y in p.ends]
    q.dots = [(x, row[y]) for x, y in p.dots]
    return q
