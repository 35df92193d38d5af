"""Network -> grid: where each contact, wire, branch bus and output goes, in cell units.

Coordinates: x counts contact columns from the left rail, y counts rows. A point (x, y) is
the left edge of column x at the height of row y's wire; an element of width w in row y
runs from (x, y) to (x + w, y). Outputs sit in one column right of all contact columns,
chosen by the renderer (`Grid.width` is the last column a line reaches), so the coils of
every rung of a program line up as in a ladder editor.

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
