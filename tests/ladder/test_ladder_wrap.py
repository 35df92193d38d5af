"""Wide rungs (issue 28, item 2): a rung wider than the page is cut into pieces joined by
numbered continuation markers, as GX Works folds it; every rung has its own output column;
the terminal ladder fits --width; symbols and device comments are shown under contacts."""

from __future__ import annotations

import re
from collections import Counter

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mlctool.ladder.document import build_sheet
from mlctool.ladder.layout import Grid, wrap
from mlctool.ladder.network import build_items
from mlctool.ladder.svg import PAGE_W, sheets_svg
from mlctool.ladder.term import sheets_text
from mlctool.syntax.source import display_width
from tests.ladder.test_ladder_network import module, program

WIDE_40 = "\n".join(["LD X0"] + [f"AND M{i}" for i in range(1, 40)] + ["OUT Y0", "END"])


def nest(blocks: int, tail: int) -> str:
    """`blocks` ORB pairs joined by ANB, then an MPS with a long middle branch."""
    lines: list[str] = []
    for b in range(blocks):
        lines += [f"LD X{4 * b}", f"AND X{4 * b + 1}", f"LD X{4 * b + 2}", f"AND X{4 * b + 3}", "ORB"]
        lines += ["ANB"] if b else []
    lines += ["MPS", "AND M100", "OUT Y0", "MRD"] + [f"ANI M{200 + i}" for i in range(tail)]
    return "\n".join(lines + ["OUT Y1", "MPP", "OUT Y2", "END"])


def sheet_of(text: str, path: str = "t.il"):
    r = module(text)
    assert not r.errors, r.diagnostics
    return build_sheet(path, r.modules[0].instrs, {path: text.splitlines()})


class Points:
    """Union-find over the points of a drawing: what a wire joins is one electrical node."""

    def __init__(self):
        self.up: dict = {}

    def find(self, p):
        self.up.setdefault(p, p)
        while self.up[p] != p:
            self.up[p] = self.up[self.up[p]]
            p = self.up[p]
        return p

    def join(self, a, b) -> None:
        self.up[self.find(a)] = self.find(b)


def _wire_up(pts: Points, g: Grid, tag) -> None:
    for w in g.wires:
        if w.y0 == w.y1:
            for x in range(min(w.x0, w.x1), max(w.x0, w.x1)):
                pts.join((tag, x, w.y0), (tag, x + 1, w.y0))
        else:
            for y in range(min(w.y0, w.y1), max(w.y0, w.y1)):
                pts.join((tag, w.x0, y), (tag, w.x0, y + 1))


def _terminals(pts: Points, g: Grid, tag, nets: dict) -> None:
    """Each element's left and right terminal, added to the net of its point."""
    for c in g.cells:
        if c.kind.startswith("wrap"):
            continue
        name = (c.kind, c.index, c.glyph)
        nets.setdefault(pts.find((tag, c.x, c.y)), []).append((name, "in"))
        nets.setdefault(pts.find((tag, c.x + c.w, c.y)), []).append((name, "out"))
    for o in g.outputs:
        nets.setdefault(pts.find((tag, o.x, o.y)), []).append((("output", o.index, o.letter), "in"))
    for x, y in g.ends:
        nets.setdefault(pts.find((tag, x, y)), []).append((("end",), "in"))


def topology(pieces: list[Grid]) -> Counter:
    """The drawing as a multiset of nets, each the sorted element terminals it joins; the
    markers of a wrapped drawing join their two pieces as a wire would."""
    pts = Points()
    for k, g in enumerate(pieces):
        _wire_up(pts, g, k)
    for y in range(pieces[0].height):  # the left rail
        pts.join((0, 0, y), "rail")
    for k, g in enumerate(pieces):
        outs = {c.glyph: c for c in g.cells if c.kind == "wrap_out"}
        if outs:
            ins = {c.glyph: c for c in pieces[k + 1].cells if c.kind == "wrap_in"}
            assert sorted(ins) == sorted(outs)  # every marker has its partner, on the next piece
            for n, c in outs.items():
                pts.join((k, c.x, c.y), (k + 1, ins[n].x + 1, ins[n].y))
    nets: dict = {}
    for k, g in enumerate(pieces):
        _terminals(pts, g, k, nets)
    rail = pts.find("rail")
    return Counter((r == rail, tuple(sorted(map(str, v)))) for r, v in nets.items())


def check_wrap(grid: Grid, cols: int) -> list[Grid]:
    pieces = wrap(grid, cols)
    assert topology(pieces) == topology([grid])
    if len(pieces) > 1:  # wider only where 2-column comparison boxes leave no column to cut at
        assert all(p.width <= cols or any(c.kind == "compare" for c in p.cells) for p in pieces), \
            [p.width for p in pieces]
    return pieces


def test_a_40_contact_rung_wraps_into_pieces_joined_in_order():
    sheet = sheet_of(WIDE_40)
    grid = sheet.items[0].grid
    assert grid.width == 40
    pieces = check_wrap(grid, 12)
    assert len(pieces) == 4
    assert [c.glyph for c in pieces[0].cells if c.kind == "wrap_out"] == ["1"]
    assert [c.glyph for c in pieces[1].cells if c.kind == "wrap_in"] == ["1"]
    # the contacts in program order across the pieces; the coil in the last one
    order = [c.index for p in pieces for c in sorted(p.cells, key=lambda c: c.x) if c.index >= 0]
    assert order == list(range(40))
    assert [len(p.outputs) for p in pieces] == [0, 0, 0, 1]


def test_deep_nests_wrap_keeping_every_connection():
    wide_15 = "\n".join(["LD X0"] + [f"ANI M{i}" for i in range(1, 15)] + ["OUT Y1", "LD X1", "OUT Y2", "END"])
    grids = [sheet_of(nest(blocks, tail)).items[0].grid for blocks, tail in ((6, 12), (3, 30), (1, 2))]
    for grid in grids + [sheet_of(wide_15).items[0].grid]:
        for cols in (4, 5, 7, 12):
            check_wrap(grid, cols)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(program(), st.integers(4, 7))
def test_random_rungs_wrap_keeping_every_connection(text, cols):
    r = module(text)
    if r.errors:
        return
    for item in build_sheet("t.il", r.modules[0].instrs, {}).items:
        if hasattr(item, "grid"):
            check_wrap(item.grid, cols)


def test_each_rung_has_its_own_output_column():
    sheet = sheet_of("LD X0\nOUT Y0\n" + "\n".join(["LD X1"] + [f"AND M{i}" for i in range(8)]) + "\nOUT Y1\nEND")
    svg = sheets_svg([sheet])
    # the short rung's coil right after its contact (column 1), not beside the 9-contact rung's
    coil_x = [float(x) for x in re.findall(r'<path class="sym" d="M([\d.]+),', svg)]
    assert coil_x[0] < coil_x[2] and coil_x[0] == 60 + 84 + 30 - 6


def test_a_40_contact_rung_fits_1280_px_in_svg():
    svg = sheets_svg([sheet_of(WIDE_40)])
    width = int(re.search(r'<svg [^>]*width="(\d+)"', svg).group(1))
    assert width <= PAGE_W
    assert svg.count('class="wrap"') == 2 * 3  # three cuts, each a marker at both ends


def test_a_40_contact_rung_fits_100_columns_in_the_terminal(mlc, tmp_path):
    src = tmp_path / "wide.il"
    src.write_text(WIDE_40 + "\n")
    r = mlc("ladder", str(src), "--term", "--width", "100")
    assert r.code == 0, r.err
    lines = r.out.splitlines()
    assert max(display_width(line) for line in lines) <= 100
    for i in range(1, 40):
        assert f" M{i} " in r.out or r.out.count(f"M{i}") >= 1
    assert sum(line.count("⇒") for line in lines) == 2 * (r.out.count("⇒") // 2) > 0
    narrow = mlc("ladder", str(src), "--width", "60")
    assert narrow.code == 0 and max(display_width(line) for line in narrow.out.splitlines()) <= 60
    assert mlc("ladder", str(src), "--width", "59").code == 2  # usage error: too narrow


def test_terminal_shows_symbols_and_with_comments_device_comments(mlc, tmp_path):
    src = tmp_path / "c.il"
    src.write_text(".define START X7 ; start key of the pump\n.define PUMP Y3 ; main pump\n"
                   "LD START\nANI X1 ; stop\nOUT PUMP\nEND\n")
    r = mlc("ladder", str(src), "--width", "80")
    assert r.code == 0, r.err
    assert "START" in r.out and "PUMP" in r.out and "main pump" not in r.out
    r = mlc("ladder", str(src), "--width", "80", "--comments")
    assert r.code == 0
    lines = r.out.splitlines()
    start = next(k for k, line in enumerate(lines) if "START" in line)
    # under the symbol: the .define's comment folded into the column; the ANI's own comment
    assert "start key" in lines[start + 1] and "stop" in lines[start]
    assert "main pump" in r.out
    svg = tmp_path / "c.svg"
    assert mlc("ladder", str(src), "--comments", "-o", str(svg)).code == 0
    text = svg.read_text("utf-8")
    assert re.search(r'class="dcomment"[^>]*>start key of<', text) and re.search(r'class="dcomment"[^>]*>stop<', text)
    assert mlc("ladder", str(src), "-o", str(svg)).code == 0
    assert "dcomment" not in svg.read_text("utf-8").split("</style>")[1]
    page = tmp_path / "c.html"  # the HTML page's search finds a rung by its device comments
    assert mlc("ladder", str(src), "-o", str(page)).code == 0
    assert re.search(r'<div class="rung" id="f0-s0" data-text="[^"]*start key of the pump[^"]*main pump',
                     page.read_text("utf-8"))


def test_wrapped_terminal_text_is_deterministic():
    sheet = sheet_of(nest(6, 12))
    assert sheets_text([sheet], 100).plain == sheets_text([sheet_of(nest(6, 12))], 100).plain
    assert len(build_items(sheet.instrs)) == 2
