"""The MPS/MRD/MPP forms that GX Works2 and WPLSoft emit (issue 16 #1): a load block combined
by ANB/ORB inside a branch (after MRD, after MPP, after a coil while an MPS is open), nested
MPS, outputs before and after the branches. Each program (written for this test in the
vendors' style) checks clean on every target, draws, converts back to IL, and simulates, on
every engine, to the logic worked out by hand, for all 256 combinations of X0..X7."""

from __future__ import annotations

import functools
from collections.abc import Callable

import pytest

from mlctool.check import check_texts
from mlctool.ladder.document import build_sheet
from mlctool.ladder.network import Rung, build_items, items_to_il
from mlctool.ladder.svg import sheets_svg
from mlctool.ladder.term import sheets_text
from mlctool.program import Image
from mlctool.sim.campaign.batch import LaneProgram
from mlctool.sim.engines.engine import ENGINES, scanner
from mlctool.sim.scan import load_program
from mlctool.sim.state import Machine, parse_device_name
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target

TARGETS = {name: load_target(name) for name in ("nc5", "vs")}

X = tuple[bool, ...]  # X0..X7


def _program(*lines: str) -> str:
    return "\n".join(lines) + "\nEND\n"


# name -> (IL, {output: logic over X0..X7 worked out by hand})
FORMS: dict[str, tuple[str, dict[str, Callable[[X], bool]]]] = {
    # the example: a block after MPS, after MRD (none) and after MPP
    "block_after_mps_and_mpp": (_program(
        "LD X0", "MPS", "LD X1", "OR X2", "ANB", "OUT Y0",
        "MRD", "AND X3", "OUT Y1",
        "MPP", "LD X4", "OR X5", "ANB", "OUT Y2"), {
        "Y0": lambda x: x[0] and (x[1] or x[2]),
        "Y1": lambda x: x[0] and x[3],
        "Y2": lambda x: x[0] and (x[4] or x[5])}),
    # after MRD: two series blocks in parallel (ORB), then ANB with the branch point
    "orb_block_after_mrd": (_program(
        "LD X0", "MPS", "AND X1", "OUT Y0",
        "MRD", "LDI X2", "AND X3", "LD X4", "ANI X5", "ORB", "ANB", "OUT Y1",
        "MPP", "AND X6", "OUT Y2"), {
        "Y0": lambda x: x[0] and x[1],
        "Y1": lambda x: x[0] and ((not x[2] and x[3]) or (x[4] and not x[5])),
        "Y2": lambda x: x[0] and x[6]}),
    # nested MPS with blocks on both levels
    "nested_mps_with_blocks": (_program(
        "LD X0", "OR X1", "MPS", "AND X2",
        "MPS", "LD X3", "OR X4", "ANB", "OUT Y0",
        "MPP", "LDI X5", "OR X6", "ANB", "OUT Y1",
        "MPP", "LD X7", "ORI X3", "ANB", "OUT Y2"), {
        "Y0": lambda x: (x[0] or x[1]) and x[2] and (x[3] or x[4]),
        "Y1": lambda x: (x[0] or x[1]) and x[2] and (not x[5] or x[6]),
        "Y2": lambda x: (x[0] or x[1]) and (x[7] or not x[3])}),
    # a block right after a coil while the MPS is open (the line continues past the coil)
    "block_after_coil_in_branch": (_program(
        "LD X0", "MPS", "AND X1", "OUT Y0", "LD X2", "OR X3", "ANB", "OUT Y1",
        "MPP", "AND X4", "OUT Y2"), {
        "Y0": lambda x: x[0] and x[1],
        "Y1": lambda x: x[0] and x[1] and (x[2] or x[3]),
        "Y2": lambda x: x[0] and x[4]}),
    "orb_block_after_coil_in_branch": (_program(
        "LD X0", "MPS", "AND X1", "OUT Y0", "LD X2", "AND X3", "LD X4", "AND X5", "ORB", "ANB",
        "OUT Y1", "MPP", "OUT Y2"), {
        "Y0": lambda x: x[0] and x[1],
        "Y1": lambda x: x[0] and x[1] and ((x[2] and x[3]) or (x[4] and x[5])),
        "Y2": lambda x: x[0]}),
    # a coil before the branches; two coils after the last one
    "coil_before_and_after_branches": (_program(
        "LD X0", "AND X1", "OUT Y0", "MPS", "AND X2", "OUT Y1",
        "MPP", "LD X3", "OR X4", "ANB", "OUT Y2", "OUT Y3"), {
        "Y0": lambda x: x[0] and x[1],
        "Y1": lambda x: x[0] and x[1] and x[2],
        "Y2": lambda x: x[0] and x[1] and (x[3] or x[4]),
        "Y3": lambda x: x[0] and x[1] and (x[3] or x[4])}),
    # a block combined and then continued by AND; a branch of a relay; a one-contact block
    "block_then_and_and_relay": (_program(
        "LD X0", "MPS", "LD X1", "AND X2", "LD X3", "AND X4", "ORB", "ANB", "AND X5", "OUT Y0",
        "MRD", "ANI X7", "OUT M0",
        "MPP", "LDI X6", "ANB", "OUT Y1"), {
        "Y0": lambda x: x[0] and ((x[1] and x[2]) or (x[3] and x[4])) and x[5],
        "M0": lambda x: x[0] and not x[7],
        "Y1": lambda x: x[0] and not x[6]}),
    # WPLSoft: MPS right after an ANB, rungs following each other, a branch of a bare coil
    "rungs_in_a_row": (_program(
        "LD X0", "LD X1", "OR X2", "ANB", "MPS", "AND X3", "OUT Y0",
        "MPP", "LD X4", "OR X5", "ANB", "OUT Y1",
        "LD X6", "OUT Y2",
        "LD X7", "MPS", "OUT Y3", "MPP", "LD X0", "ANB", "OUT Y4"), {
        "Y0": lambda x: x[0] and (x[1] or x[2]) and x[3],
        "Y1": lambda x: x[0] and (x[1] or x[2]) and (x[4] or x[5]),
        "Y2": lambda x: x[6],
        "Y3": lambda x: x[7],
        "Y4": lambda x: x[7] and x[0]}),
    # three levels: MRD and MPP on the inner levels, blocks and coils on every one
    "three_levels": (_program(
        "LD X0", "MPS", "AND X1",
        "MPS", "AND X2", "OUT Y0", "MRD", "LD X3", "OR X4", "ANB", "OUT Y1", "MPP", "OUT Y2",
        "MRD", "LD X5", "ORI X6", "ANB",
        "MPS", "AND X7", "OUT Y3", "MPP", "OUT Y4",
        "MPP", "OUT Y5"), {
        "Y0": lambda x: x[0] and x[1] and x[2],
        "Y1": lambda x: x[0] and x[1] and (x[3] or x[4]),
        "Y2": lambda x: x[0] and x[1],
        "Y3": lambda x: x[0] and (x[5] or not x[6]) and x[7],
        "Y4": lambda x: x[0] and (x[5] or not x[6]),
        "Y5": lambda x: x[0]}),
}

ALL_X: list[X] = [tuple(bool(n >> k & 1) for k in range(8)) for n in range(256)]


def _checked(text: str, target):
    r = check_texts([SourceText("t.il", text)], target)
    assert not r.diagnostics, [(d.span.line, d.code, d.message) for d in r.diagnostics]  # clean
    return r.modules[0].instrs


def _outputs_per_scan(instrs, target, engine: str, watch: list[str], select: str | None = None) -> list[dict[str, bool]]:
    prog = load_program(Image(target.name, instrs), target)
    m = Machine(target, len(prog.steps))
    scan = scanner(prog, m, engine)
    if select is not None:
        parse_device_name(select, target).write(m, 1)
    xs = [parse_device_name(f"X{k}", target) for k in range(8)]
    views = {name: parse_device_name(name, target) for name in watch}
    seen = []
    for x in ALL_X:
        for view, v in zip(xs, x, strict=True):
            view.write(m, v)
        scan()
        seen.append({name: bool(view.read(m)) for name, view in views.items()})
    return seen


SELECT = 100  # M100 + k selects the k-th form of FORMS (sorted) in _all_forms()'s program


@functools.cache
def _all_forms(target_name: str):
    """Every form in one program, each behind `LDI M<SELECT + k> / CJ P<k>` (a form not
    selected runs nothing), for the native engine: a build takes seconds, one per target then,
    not one per form."""
    lines = []
    for k, name in enumerate(sorted(FORMS)):
        lines += [f"LDI M{SELECT + k}", f"CJ P{k}", FORMS[name][0].removesuffix("END\n").strip(), f"P{k}:"]
    r = check_texts([SourceText("t.il", _program(*lines))], TARGETS[target_name])
    assert not [d for d in r.diagnostics if d.severity == "error"], [(d.span.line, d.code, d.message) for d in r.diagnostics]
    return r.modules[0].instrs


def _expected(logic: dict[str, Callable[[X], bool]]) -> list[dict[str, bool]]:
    return [{name: bool(f(x)) for name, f in logic.items()} for x in ALL_X]


@pytest.mark.parametrize("target_name", sorted(TARGETS))
@pytest.mark.parametrize("form", sorted(FORMS))
def test_stack_form_checks_draws_and_simulates(form, target_name):
    text, logic = FORMS[form]
    target = TARGETS[target_name]
    instrs = _checked(text, target)
    want = _expected(logic)
    for engine in ENGINES:
        if engine == "native":  # the form in the one program of them all (_all_forms)
            got = _outputs_per_scan(_all_forms(target_name), target, engine, list(logic),
                                    f"M{SELECT + sorted(FORMS).index(form)}")
        else:
            got = _outputs_per_scan(instrs, target, engine, list(logic))
        assert got == want, engine
    # the ladder: one rung (or one per LD after a coil outside any MPS), drawn every way
    items = build_items(instrs)
    rungs = sum(isinstance(i, Rung) for i in items)
    sheet = build_sheet("t.il", instrs, {"t.il": text.splitlines()})
    assert sheets_svg([sheet]).count('class="rung"') == rungs
    assert sheets_text([sheet]).plain
    # the picture converts back to IL that checks clean and runs the same logic
    again = items_to_il(items, instrs, target)
    text2 = "\n".join(" ".join((i.mnemonic, *i.texts)) for i in again) + "\n"
    instrs2 = _checked(text2, target)
    assert _outputs_per_scan(instrs2, target, "interp", list(logic)) == want, text2


@pytest.mark.parametrize("form", sorted(FORMS))
def test_stack_form_runs_the_same_on_bit_lanes(form):
    """`mlc sim` batches run bit-sliced lanes (sim/campaign/batch.py): 256 lanes = every input."""
    text, logic = FORMS[form]
    target = TARGETS["nc5"]
    lp = LaneProgram(load_program(Image("nc5", _checked(text, target)), target))
    assert lp.ok
    slots = dict(lp.slots)
    for name in [f"X{k}" for k in range(8)] + list(logic):
        slots.setdefault((name[0], int(name[1:])), len(slots))
    state = [0] * len(slots)
    for k in range(8):
        state[slots[("X", k)]] = sum(1 << n for n, x in enumerate(ALL_X) if x[k])
    lp.scan(state, [0] * 4096, (1 << 256) - 1)
    got = [{name: bool(state[slots[(name[0], int(name[1:]))]] >> n & 1) for name in logic}
           for n in range(256)]
    assert got == _expected(logic)


def test_rung_counts_follow_the_program_not_the_coils():
    """The forms above are one rung each (two blocks after a coil are no new rung), except
    where a load follows a coil with no MPS open."""
    target = TARGETS["nc5"]
    counts = {form: sum(isinstance(i, Rung) for i in build_items(_checked(FORMS[form][0], target)))
              for form in FORMS}
    assert counts == {**dict.fromkeys(FORMS, 1), "rungs_in_a_row": 3}


@pytest.mark.parametrize("target_name", sorted(TARGETS))
def test_load_after_coil_without_anb_still_ends_the_rung(target_name):
    """A load after a coil inside an MPS branch that no ANB/ORB takes up starts a new rung:
    the open MPS is the error (E308), reported once at the MPS (the note names where the rung
    ends), and the next rungs are not dragged in."""
    text = _program("LD X0", "MPS", "AND X1", "OUT Y0", "LD X2", "OUT Y1", "LD X3", "OUT Y2")
    r = check_texts([SourceText("t.il", text)], TARGETS[target_name])
    errors = [d for d in r.diagnostics if d.severity == "error"]
    assert [(d.code, d.span.line) for d in errors] == [("E308", 2)]
    assert errors[0].notes == ("the rung ends before LD at line 5",)


@pytest.mark.parametrize("target_name", sorted(TARGETS))
def test_or_after_a_branch_coil_is_still_refused(target_name):
    """OR straight after MPP whose branch point lies before a coil reaches back across it."""
    text = _program("LD X0", "MPS", "AND X1", "OUT Y0", "MPP", "OR X2", "OUT Y1")
    r = check_texts([SourceText("t.il", text)], TARGETS[target_name])
    assert [d.code for d in r.diagnostics if d.severity == "error"] == ["E311"]
