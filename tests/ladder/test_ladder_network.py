"""IL rung -> network -> IL: the manual's examples take the expected shape, and random valid
rungs convert back to instruction lists the simulator runs with the same results."""

from __future__ import annotations

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from mlctool.check import check_texts
from mlctool.ladder.document import build_sheet
from mlctool.ladder.network import (
    Coil,
    Group,
    Leaf,
    Node,
    Parallel,
    Row,
    Rung,
    Tap,
    build_items,
    items_to_il,
)
from mlctool.ladder.svg import sheets_svg
from mlctool.ladder.term import sheets_text
from mlctool.program import Image
from mlctool.sim.scan import load_program, run_scan
from mlctool.sim.state import Machine
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target

NC5 = load_target("nc5")


def module(text: str):
    r = check_texts([SourceText("t.il", text.strip() + "\n")], NC5)
    return r


def items_of(text: str):
    r = module(text)
    assert not r.errors, r.diagnostics
    return build_items(r.modules[0].instrs), r.modules[0].instrs


def names(elems) -> list:
    """Series elements as nested lists of operand texts (Parallel -> ("|", branches))."""
    out = []
    for e in elems:
        if isinstance(e, Leaf):
            out.append(e.ins.texts[0] if e.ins.texts else e.ins.mnemonic)
        elif isinstance(e, Parallel):
            out.append(("|", [names(b) for b in e.branches]))
        elif isinstance(e, Group):
            out.append(("[]", names(e.elems)))
        elif isinstance(e, Tap):
            out.append("TAP")
    return out


def test_anb_example_is_two_parallel_blocks_in_series():
    items, _ = items_of("LD X0\nOR X2\nLD X1\nOR X3\nANB\nOUT Y1\nEND")
    rung, end = items
    assert isinstance(rung, Rung) and isinstance(end, Row)
    (line,) = rung.root.lines
    assert names(line.elems) == [("|", [["X0"], ["X2"]]), ("|", [["X1"], ["X3"]])]
    assert isinstance(line.to, Coil) and line.to.ins.texts == ("Y1",)


def test_orb_example_is_two_series_blocks_in_parallel():
    items, _ = items_of("LD X0\nAND X1\nLD X2\nAND X3\nORB\nOUT Y1\nEND")
    (line,) = items[0].root.lines
    assert names(line.elems) == [("|", [["X0", "X1"], ["X2", "X3"]])]


def test_mps_example_is_one_branch_point_with_three_lines():
    items, _ = items_of("LD X0\nMPS\nAND X1\nOUT Y1\nMRD\nAND X2\nOUT M0\nMPP\nOUT Y2\nEND")
    (line,) = items[0].root.lines
    assert names(line.elems) == ["X0"]
    assert isinstance(line.to, Node)
    got = [(names(sub.elems), sub.to.ins.texts[0]) for sub in line.to.lines]
    assert got == [(["X1"], "Y1"), (["X2"], "M0"), ([], "Y2")]


def test_output_continued_by_and_branches_like_mps():
    items, _ = items_of("LD X0\nOUT Y0\nAND X1\nOUT Y1\nEND")
    (line,) = items[0].root.lines
    assert [(names(s.elems), s.to.ins.texts[0]) for s in line.to.lines] == [([], "Y0"), (["X1"], "Y1")]


def test_inv_inside_a_block_is_scoped_by_a_group():
    items, _ = items_of("LD X0\nLD X1\nINV\nANB\nOUT Y0\nEND")
    (line,) = items[0].root.lines
    assert names(line.elems) == ["X0", ("[]", ["X1", "INV"])]


def test_or_across_a_branch_point_uses_a_tap_and_keeps_order():
    items, instrs = items_of("LD X0\nMPS\nAND X1\nOR X2\nOUT Y1\nMPP\nOUT Y2\nEND")
    rung = items[0]
    assert rung.has_tap
    fork = rung.root.lines[0].to
    first, second = fork.lines
    assert first.from_rail and names(first.elems) == [("|", [["TAP", "X1"], ["X2"]])]
    assert second.to.ins.texts == ("Y2",)
    assert [i.mnemonic for i in items_to_il(items, instrs, NC5)] == [i.mnemonic for i in instrs]


def test_labels_and_free_instructions_are_rows():
    items, _ = items_of("LD X0\nCJ P1\nP1\nFOR K2\nLD X1\nOUT Y1\nNEXT\nFEND\nP2\nSRET\nEND")
    kinds = [type(i).__name__ if isinstance(i, Rung) else i.ins.mnemonic for i in items]
    assert kinds == ["Rung", "P", "FOR", "Rung", "NEXT", "FEND", "P", "SRET", "END"]


# ------------------------------------------------------------ random rungs, simulated

CONTACTS = ["{c} X{n}", "{c}I X{n}", "{c}P X{n}", "{c}F X{n}", "{c} M{n}", "{c}= D0 K{n}",
            "{c}> D0 K{n}"]
FORMS = {"LD": ("LD", "LD"), "AND": ("AND", "AN"), "OR": ("OR", "OR")}


@st.composite
def contact(draw, cls: str) -> str:
    pattern = draw(st.sampled_from(CONTACTS))
    full, short = FORMS[cls]
    c = short if pattern.startswith("{c}I") else full
    return pattern.format(c=c, n=draw(st.integers(0, 3)))


@st.composite
def block(draw, depth: int) -> list[str]:
    """A condition block: starts with a load, ends with one result."""
    out = [draw(contact("LD"))]
    for _ in range(draw(st.integers(0, 3))):
        kind = draw(st.sampled_from(["and", "or", "inv", "nop", "anb", "orb"] if depth else ["and", "or", "inv"]))
        if kind in ("and", "or"):
            out.append(draw(contact(kind.upper())))
        elif kind in ("inv", "nop"):
            out.append(kind.upper())
        else:
            out += draw(block(depth - 1)) + [kind.upper()]
    return out


@st.composite
def output_side(draw, depth: int, state: dict) -> list[str]:
    """Outputs, ANDs after outputs, and MPS/MRD/MPP forks. state["driven"]: an output was
    seen in the rung (then OR/blocks are no longer legal, as mlc check says)."""
    out: list[str] = []
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["out", "and", "inv", "fork"] if depth else ["out", "and"]))
        if kind == "and":
            out.append(draw(contact("AND")))
        elif kind == "inv":
            out.append("INV")
        elif kind == "fork":
            n = draw(st.integers(2, 3))
            for k in range(n):
                out.append("MPS" if k == 0 else "MRD" if k < n - 1 else "MPP")
                if not state["driven"] and draw(st.booleans()):
                    # reaches back across the branch point: OR, or a block joined by ANB/ORB
                    out += ([draw(contact("OR"))] if draw(st.booleans())
                            else draw(block(1)) + [draw(st.sampled_from(["ANB", "ORB"]))])
                out += draw(output_side(depth - 1, state))
            continue
        coil = draw(st.sampled_from(["OUT Y{n}", "OUT M{n}", "SET Y{n}", "RST Y{n}", "MOV K{n} D1"]))
        out.append(coil.format(n=draw(st.integers(0, 3))))
        state["driven"] = True
    if not state["driven"]:
        out.append("OUT Y5")
        state["driven"] = True
    return out


@st.composite
def program(draw) -> str:
    lines: list[str] = []
    for _ in range(draw(st.integers(1, 3))):
        lines += draw(block(2)) + draw(output_side(2, {"driven": False}))
    return "\n".join(lines + ["END"])


def simulate(instrs, inputs) -> list[bytes]:
    prog = load_program(Image("nc5", instrs), NC5)
    m = Machine(NC5, len(prog.steps))
    seen = []
    for xs, d0 in inputs:
        for k, v in enumerate(xs):
            m.bits["X"][k] = v
        m.words["D"][0] = d0
        run_scan(prog, m)
        seen.append(bytes(m.bits["Y"][:8]) + bytes(m.bits["M"][:4]) + bytes([m.words["D"][1] & 0xFF]))
    return seen


INPUTS = st.lists(st.tuples(st.lists(st.integers(0, 1), min_size=4, max_size=4), st.integers(0, 4)),
                  min_size=1, max_size=8)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(program(), INPUTS)
def test_il_network_il_simulates_the_same(text, inputs):
    r = module(text)
    assume(not r.errors)
    instrs = r.modules[0].instrs
    items = build_items(instrs)
    again = items_to_il(items, instrs, NC5)
    assert simulate(again, inputs) == simulate(instrs, inputs), "\n" + text
    # the regenerated IL is itself valid and converts to the same picture
    if not any(isinstance(i, Rung) and i.has_tap for i in items):
        text2 = "\n".join(" ".join((i.mnemonic, *i.texts)) for i in again)
        r2 = module(text2)
        assert not r2.errors, (text2, r2.diagnostics)
    # and every such rung draws
    sheet = build_sheet("t.il", instrs, {"t.il": text.splitlines()})
    assert sheets_svg([sheet]).count('class="rung"') == sum(isinstance(i, Rung) for i in items)
    assert sheets_text([sheet]).plain
