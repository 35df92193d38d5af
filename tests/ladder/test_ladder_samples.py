"""Every bundled sample of every target draws (issue 21 #5): `mlc ladder` as SVG, HTML and on
the terminal, and `mlc sim --report` where the sample has a stimulus. Step ladders (STL/RET)
draw each step as a state box on the rail with its rungs on the step's bus, and multi-input
instructions (FBs FUN140) with one input line per block."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from conftest import SAMPLES, run_mlc
from mlctool.ladder.svg import PAGE_W
from mlctool.syntax.source import display_width

TARGET_DIRS = ("nc5", "vs", "fbs")
ALL = [(t, p) for t in TARGET_DIRS for p in sorted((SAMPLES / t).glob("*.il"))]
PROJECT = [("nc5", p) for p in sorted((SAMPLES / "project" / "src").glob("*.il"))]
STEP_LADDERS = ("container_fill", "fountain", "fountain_modes", "traffic_light")


def _extra(il: Path) -> list[str]:
    """Options a sample's header names for `mlc sim` (the FBs tables: `--table R5000=...`)."""
    text = il.read_text("utf-8")
    return [a for m in re.finditer(r"--table (R\d+)=samples/(\S+)", text)
            for a in ("--table", f"{m[1]}={SAMPLES / m[2]}")]


def _id(case) -> str:
    return f"{case[0]}/{case[1].name}"


def test_every_target_has_samples_here():
    assert {t for t, _ in ALL} == set(TARGET_DIRS)
    assert {p.stem for _, p in ALL} >= {*STEP_LADDERS, "home_and_run"}


@pytest.mark.parametrize("case", ALL, ids=_id)
def test_sample_draws_every_way(case, tmp_path):
    target, il = case
    for out in ("l.svg", "l.html"):
        r = run_mlc("ladder", "--target", target, str(il), "-o", str(tmp_path / out))
        assert r.code == 0, r.err
        assert (tmp_path / out).stat().st_size > 0
    for width in (100, 60):  # the real programs fit the terminal width, wrapped where they must
        r = run_mlc("ladder", "--target", target, "--term", "--width", str(width), str(il))
        assert r.code == 0, r.err
        assert "END" in r.out
        assert max(display_width(line) for line in r.out.splitlines()) <= width
    svg = (tmp_path / "l.svg").read_text("utf-8")
    assert int(re.search(r'<svg [^>]*width="(\d+)"', svg).group(1)) <= PAGE_W
    stim = il.with_suffix(".stim")
    if stim.exists():
        page = tmp_path / "r.html"
        r = run_mlc("sim", "--target", target, str(il), "--stimulus", str(stim), *_extra(il),
                    "--report", str(page))
        assert r.code in (0, 1), r.err  # 1: an expectation failed (the page is still written)
        assert page.stat().st_size > 0


def test_project_sources_draw_together(tmp_path):
    r = run_mlc("ladder", "--target", "nc5", *(str(p) for _, p in PROJECT), "-o", str(tmp_path / "l.svg"))
    assert r.code == 0, r.err


@pytest.mark.parametrize("name", STEP_LADDERS)
def test_step_ladder_draws_each_step_as_a_state_box(name, tmp_path):
    il = SAMPLES / "vs" / f"{name}.il"
    steps = re.findall(r"^\s*STL\s+(S\d+)", il.read_text("utf-8"), re.M)
    assert steps
    r = run_mlc("ladder", "--target", "vs", "--term", str(il))
    assert r.code == 0, r.err
    for s in steps:
        assert f"[{s}]" in r.out, s
    r = run_mlc("ladder", "--target", "vs", str(il), "-o", str(tmp_path / "l.svg"))
    svg = (tmp_path / "l.svg").read_text("utf-8")
    assert svg.count('class="box step"') == len(steps)
    # one drawn rung per step: the step's own rungs hang on its bus
    assert svg.count('class="rung"') >= len(set(steps))


def test_step_report_lights_the_active_step(tmp_path):
    """--report: a step's state box is an element the page lights, in the scans at whose end
    its step is active (docs/ladder.md "Lighting"). Every step of the traffic light is, but
    S0: X0 is pressed from 0 ms, so S0 transfers to S10 in scan 0 itself and is Off at its end."""
    il = SAMPLES / "vs" / "traffic_light.il"
    page = tmp_path / "r.html"
    r = run_mlc("sim", "--target", "vs", str(il), "--stimulus", str(il.with_suffix(".stim")),
                "--report", str(page))
    assert r.code == 0, r.err
    html = page.read_text("utf-8")
    boxes = {int(i) for i in re.findall(r'class="el" data-i="(\d+)"><line[^>]*/><line[^>]*/><rect class="box step"', html)}
    power = json.loads(re.search(r'<script type="application/json" id="power">(.*?)</script>', html, re.S)[1])
    lit = {i for scan in power["deltas"] for i in scan}
    assert len(boxes) == 11 and sorted(boxes - lit) == [2], sorted(boxes - lit)  # 2: STL S0


def test_joined_steps_are_boxes_in_series():
    """Consecutive STLs (steps joining before a transfer) draw their boxes in series on one line."""
    from mlctool.check import check_texts
    from mlctool.ladder.network import Leaf, Rung, build_items
    from mlctool.syntax.source import SourceText
    from mlctool.targetapi import load_target

    text = ("LD M9002\nSET S20\nSET S21\nSTL S20\nOUT Y0\n"
            "STL S21\nSTL S23\nLD X0\nSET S22\nSTL S22\nOUT Y2\nRET\nEND\n")
    r = check_texts([SourceText("t.il", text)], load_target("vs"))
    assert not r.errors, r.diagnostics
    rungs = [i for i in build_items(r.modules[0].instrs) if isinstance(i, Rung)]
    steps = [i for i in rungs if i.step]
    first = [[e.ins.texts[0] for e in s.root.lines[0].elems if isinstance(e, Leaf) and e.ins.spec.cls == "bus"]
             for s in steps]
    assert first == [["S20"], ["S21", "S23"], ["S22"]]


def test_multi_input_box_gets_one_line_per_input():
    """FUN140 takes EN, PAU and ABT, one block each (FBs): EN drives the box, the others end
    at its input pins."""
    r = run_mlc("ladder", "--target", "fbs", "--term", str(SAMPLES / "fbs" / "home_and_run.il"))
    assert r.code == 0, r.err
    assert r.out.count("▷PAU") == 2 and r.out.count("▷ABT") == 2


def _operand_texts(target, spec) -> list[list[str]]:
    """A few operands of the kinds each operand of `spec` allows, lowest numbers first."""
    out = []
    for o in spec.operands:
        texts: list[str] = []
        for kind in sorted(o.kinds):
            if kind == "K":
                texts += ["K1", "K2"]
            elif kind == "H":
                texts.append("H1")
            elif kind.startswith("Kn"):
                texts.append(f"K1{kind[2:]}0")
            elif kind in target.devices:
                texts.append(f"{kind}{target.devices[kind].lo if kind != 'P' else 1}")
        out.append(texts[:3])
    return out


@pytest.mark.parametrize("target_name", TARGET_DIRS)
def test_every_instruction_that_checks_draws(target_name):
    """Each instruction of the target, in the rung forms it takes (after a contact, after
    three blocks for multi-input boxes, alone on the rail), draws and converts back to IL
    whenever `mlc check` accepts the program (MEP/MEF crashed the drawing)."""
    import itertools

    from mlctool.check import check_texts
    from mlctool.ladder.document import build_sheet
    from mlctool.ladder.network import build_items, items_to_il
    from mlctool.ladder.svg import sheets_svg
    from mlctool.ladder.term import sheets_text
    from mlctool.syntax.source import SourceText
    from mlctool.targetapi import load_target

    target = load_target(target_name)
    drawn = 0
    for name, spec in sorted(target.instructions.items()):
        for combo in itertools.islice(itertools.product(*_operand_texts(target, spec)), 30):
            line = " ".join((name, *combo))
            forms = (f"LD X0\n{line}\nEND\n", f"LD X0\n{line}\nOUT Y0\nEND\n",
                     f"LD X0\nLD X1\nLD X2\n{line}\nEND\n",
                     f"LD X0\nCJ P1\nP1:\nLD X0\n{line}\nEND\n", f"{line}\nLD X0\nOUT Y0\nEND\n")
            texts = [t for t in forms if not check_texts([SourceText("t.il", t)], target).errors]
            for text in texts[:1]:
                instrs = check_texts([SourceText("t.il", text)], target).modules[0].instrs
                sheet = build_sheet("t.il", instrs, {"t.il": text.splitlines()})
                assert sheets_svg([sheet]) and sheets_text([sheet]).plain, text
                items_to_il(build_items(instrs), instrs, target)
                drawn += 1
            if texts:
                break
    assert drawn >= len(target.instructions) // 2
