"""Golden structure of the manual's example rungs (2.2 ANB, ORB, MPS/MRD/MPP) in SVG, HTML and
terminal text, every sample drawn, determinism, and `mlc ladder` usage and errors."""

from __future__ import annotations

import glob
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from mlctool.ladder import sheets_from_files
from mlctool.ladder.html import sheets_html
from mlctool.ladder.svg import CW, LM, RH, WIRE_Y, sheets_svg
from mlctool.ladder.term import sheets_text
from mlctool.targetapi import load_target

NC5 = load_target("nc5")
SAMPLES = sorted(glob.glob("samples/nc5/*.il"))
SVG = "{http://www.w3.org/2000/svg}"


def sheets(*paths):
    sh, diags, _ = sheets_from_files(list(paths), NC5)
    assert sh, diags
    return sh


def elements(svg: str) -> list[tuple[str, str, int, int]]:
    """(instruction index, first label, grid column, grid row) of every drawn element."""
    root = ET.fromstring(svg)
    out = []
    for rung in root.iter(f"{SVG}g"):
        if rung.get("class") != "rung":
            continue
        for g in rung.iter(f"{SVG}g"):
            if g.get("class") != "el":
                continue
            first = next(g.iter(f"{SVG}line"), None)
            x = float(first.get("x1")) if first is not None else float(next(g.iter(f"{SVG}rect")).get("x"))
            y = float(first.get("y1")) if first is not None else float(next(g.iter(f"{SVG}rect")).get("y")) + 13
            label = next(g.iter(f"{SVG}text")).text
            out.append((g.get("data-i"), label, int((x - LM) // CW), int((y - WIRE_Y) // RH)))
    return out


def test_anb_golden_structure():
    svg = sheets_svg(sheets("samples/nc5/man_2_2_anb.il"))
    # (X0 + X2) . (X1 + X3) -> Y1: two parallel pairs side by side, Y1 in the output column
    assert elements(svg) == [("0", "X0", 0, 0), ("1", "X2", 0, 1), ("2", "X1", 1, 0), ("3", "X3", 1, 1),
                             ("5", "Y1", 2, 0)]
    assert svg.count('class="rung"') == 1 and svg.count('class="row"') == 1  # + END


def test_orb_golden_structure():
    svg = sheets_svg(sheets("samples/nc5/man_2_2_orb.il"))
    assert elements(svg) == [("0", "X0", 0, 0), ("1", "X1", 1, 0), ("2", "X2", 0, 1), ("3", "X3", 1, 1),
                             ("5", "Y1", 2, 0)]


def test_mps_golden_structure():
    svg = sheets_svg(sheets("samples/nc5/man_2_2_mps.il"))
    assert elements(svg) == [("0", "X0", 0, 0), ("2", "X1", 1, 0), ("5", "X2", 1, 1),
                             ("3", "Y1", 2, 0), ("6", "M0", 2, 1), ("8", "Y2", 2, 2)]
    assert svg.count('class="dot"') == 1  # the one branch point after X0


GOLDEN_TERM = """\
samples/nc5/man_2_2_mps.il
         ; Manual 2.2 MPS, MRD, MPP: one condition feeding three branches (figure lost).
       │    X0         X1      Y1
     0 ├───┤ ├────┬───┤ ├──────( )
       │          │    X2      M0
       │          ├───┤ ├──────( )
       │          │            Y2
       │          └────────────( )
       │
     9 ├─[END]
"""


def test_mps_golden_terminal_text():
    assert sheets_text(sheets("samples/nc5/man_2_2_mps.il")).plain == GOLDEN_TERM


def test_html_is_self_contained_with_anchors_and_search_text():
    page = sheets_html(sheets("samples/nc5/man_2_2_anb.il", "samples/nc5/man_2_2_mps.il"))
    assert page.count('<div class="rung"') == 2
    assert 'id="f0-s0"' in page and 'id="f1-s0"' in page and 'href="#f1-s0"' in page
    # nothing fetched from elsewhere: no external scripts, styles, images or fonts
    assert not re.search(r'(src|href)="(https?:)?//', page)
    assert "@import" not in page and "url(" not in page
    assert re.search(r'data-text="[^"]*Manual 2.2 MPS[^"]*X1[^"]*"', page)


def test_symbols_and_comments_are_shown(tmp_path):
    src = tmp_path / "sym.il"
    src.write_text(".define START X7\n; start the pump\nLD START ; the start key\nOUT Y3 ; pump\nEND\n")
    svg = sheets_svg(sheets(str(src)))
    assert ">X7<" in svg and ">START<" in svg  # device and the symbol written
    assert ">start the pump<" in svg  # rung comment
    assert ">pump<" in svg and "the start key" in svg  # output note, contact tooltip


@pytest.mark.parametrize("path", SAMPLES)
def test_every_sample_draws(path):
    sh = sheets(path)
    svg = sheets_svg(sh)
    ET.fromstring(svg)  # well-formed
    assert svg.count('class="rung"') == sh[0].rungs >= 1
    assert svg == sheets_svg(sheets(path))  # byte-identical for the same input


def test_cli_writes_svg_html_and_term(mlc, tmp_path):
    out = tmp_path / "all.html"
    r = mlc("ladder", *SAMPLES, "-o", str(out))
    assert r.code == 0, r.err
    page = out.read_text("utf-8")
    assert page.count('<section class="file"') == len(SAMPLES)
    first = page
    assert mlc("ladder", *SAMPLES, "-o", str(out)).code == 0
    assert out.read_text("utf-8") == first
    svg = tmp_path / "anb.svg"
    assert mlc("ladder", "samples/nc5/man_2_2_anb.il", "-o", str(svg)).code == 0
    assert svg.read_text("utf-8").startswith("<svg")
    r = mlc("ladder", "samples/nc5/man_2_2_anb.il", "--term")
    assert r.code == 0 and "┤ ├" in r.out and "( )" in r.out


def test_cli_refuses_programs_with_errors(mlc, tmp_path):
    bad = tmp_path / "bad.il"
    bad.write_text("LD X0\nORB\nOUT Y0\nEND\n")
    out = tmp_path / "bad.svg"
    r = mlc("ladder", str(bad), "-o", str(out))
    assert r.code == 1 and "E310" in r.err and "Traceback" not in r.err
    assert not out.exists()


def test_cli_usage_errors(mlc, tmp_path):
    r = mlc("ladder", "samples/nc5/man_2_2_anb.il", "-o", str(tmp_path / "x.png"))
    assert r.code == 2 and ".svg or .html" in r.err
    r = mlc("ladder", str(tmp_path / "missing.il"))
    assert r.code == 2 and "E100" in r.err
    (tmp_path / "no").write_text("a file where the folder would be\n")
    r = mlc("ladder", "samples/nc5/man_2_2_anb.il", "-o", str(tmp_path / "no" / "dir.svg"))
    assert r.code != 0 and "E605" in r.err and "Traceback" not in r.err
    assert Path(tmp_path / "no").is_file()


def test_nc_signals_are_named_where_the_program_says_nothing(mlc, tmp_path):
    """NC5 special M/D (targets/nc5/signals.tsv): the manual's name under the device, its
    one-line description as the comment of a line without one; a written comment wins."""
    (tmp_path / "n.il").write_text("LD M31016\nOUT M21001\nLD X0\nOUT M21000 ; my start\nEND\n", "utf-8")
    r = mlc("ladder", "--target", "nc5", "-o", "n.svg", "n.il", cwd=tmp_path)
    assert r.code == 0, r.err
    root = ET.fromstring((tmp_path / "n.svg").read_text("utf-8"))
    texts = [t.text for t in root.iter(f"{SVG}text")]
    assert "程序執行中" in texts and "程式停止" in texts and "程式啟動" in texts
    assert "M21001 - 程式停止 feed hold, MLC->NC, channel 1, 5.3.2" in texts
    assert "my start" in texts and not any(t and t.startswith("M21000 - ") for t in texts)
    titles = [t.text for t in root.iter(f"{SVG}title")]
    assert "LD M31016 ; M31016 - 程序執行中 program running, NC->MLC, channel 1, 5.3.2" in titles
    term = mlc("ladder", "--target", "nc5", "n.il", cwd=tmp_path)
    assert "; M21001 - 程式停止 feed hold" in term.out
    html = mlc("ladder", "--target", "nc5", "-o", "n.html", "n.il", cwd=tmp_path)
    assert html.code == 0 and "程式停止 feed hold" in (tmp_path / "n.html").read_text("utf-8")
