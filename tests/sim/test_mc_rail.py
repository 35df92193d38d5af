"""The rail of a master-control block (VS 3-6 MC/MCR) and of a step ladder block (4-1-3,
4-6-1): while it is Off every rung hanging on it is Off whatever its contacts, so OR, ORB,
ANB, MPS/MRD/MPP and INV cannot bring power back. Each engine is checked on fixed programs,
and seeded random programs with nested MC blocks are checked against the other engine AND
against a small oracle written here from the rule (not from the engine), so a bug both
engines share still fails."""

from __future__ import annotations

import random

import pytest

from mlctool.sim.campaign.batch import LaneProgram
from mlctool.sim.campaign.word_lanes import WordLaneProgram
from mlctool.sim.engines.engine import Scanner
from mlctool.sim.scan import load_program
from mlctool.sim.state import Machine
from vskit import VS, image_of

ENGINES = ("interp", "compiled")


def scanner(il: str, engine: str) -> tuple[Scanner, Machine]:
    image = image_of(il)
    assert image is not None, il
    prog = load_program(image, VS)
    m = Machine(VS, len(prog.steps))
    return Scanner(prog, m, engine), m


def bit(m: Machine, name: str) -> int:
    return int(m.bits[name[0]][int(name[1:], 8 if name[0] in "XY" else 10)])


def setbit(m: Machine, name: str, v: int) -> None:
    m.bits[name[0]][int(name[1:], 8 if name[0] in "XY" else 10)] = v


# (program body, inputs; every named output must be 0: the MC condition M100 is Off)
OFF_BLOCKS = {
    "or": "LD X0\nOR X1\nOUT Y0",
    "ori": "LD X1\nORI X0\nOUT Y0",
    "orb": "LD X0\nLD X1\nAND X2\nORB\nOUT Y0",
    "anb": "LD X0\nOR X1\nLD X0\nOR X2\nANB\nOUT Y0",
    "mps": "LD X0\nOR X1\nMPS\nAND X2\nOUT Y0\nMRD\nOUT Y1\nMPP\nOUT Y2",
    "inv": "LD X0\nINV\nOUT Y0",
    "compare": "LD X0\nOR= D0 K0\nOUT Y0",
    "set": "LD X0\nOR X1\nSET Y0",
    "apply": "LD X0\nOR X1\nMOV K7 D1\nLD X0\nOR X1\nOUT Y0",
}


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("case", sorted(OFF_BLOCKS))
def test_an_off_mc_block_has_no_power_whatever_its_contacts(engine, case):
    il = f"LD M100\nMC N0\n{OFF_BLOCKS[case]}\nMCR N0\nLD X1\nOUT Y7\nEND"
    sc, m = scanner(il, engine)
    setbit(m, "X1", 1)
    setbit(m, "X2", 1)
    sc()
    assert [bit(m, f"Y{k}") for k in range(3)] == [0, 0, 0]
    assert m.words["D"][1] == 0  # MOV idle
    assert bit(m, "Y7") == 1  # after MCR the rail is the left-hand rail again
    setbit(m, "M100", 1)  # On: the block runs normally
    sc()
    assert bit(m, "Y0") == 1


@pytest.mark.parametrize("engine", ENGINES)
def test_an_inner_block_inside_an_off_outer_block_is_off(engine):
    il = ("LD M100\nMC N0\nLD X0\nOR X1\nMC N1\nLD X0\nOR X1\nOUT Y0\nMCR N1\nLD X0\nOR X1\nOUT Y1\n"
          "MCR N0\nLD X1\nOUT Y2\nEND")
    sc, m = scanner(il, engine)
    setbit(m, "X1", 1)
    sc()
    assert (bit(m, "Y0"), bit(m, "Y1"), bit(m, "Y2")) == (0, 0, 1)
    setbit(m, "M100", 1)
    sc()
    assert (bit(m, "Y0"), bit(m, "Y1"), bit(m, "Y2")) == (1, 1, 1)


@pytest.mark.parametrize("engine", ENGINES)
def test_mcr_of_an_inner_level_gives_back_the_outer_level_rail(engine):
    """After MCR N1 the rail is N0's (Off when M100 is Off, On otherwise), not the left rail."""
    il = ("LD M100\nMC N0\nLD M101\nMC N1\nLD X1\nOUT Y0\nMCR N1\nLD X0\nOR X1\nOUT Y1\nMCR N0\nEND")
    sc, m = scanner(il, engine)
    setbit(m, "X1", 1)
    setbit(m, "M101", 1)
    sc()
    assert (bit(m, "Y0"), bit(m, "Y1")) == (0, 0)
    setbit(m, "M100", 1)
    setbit(m, "M101", 0)
    sc()
    assert (bit(m, "Y0"), bit(m, "Y1")) == (0, 1)


@pytest.mark.parametrize("engine", ENGINES)
def test_a_step_block_run_once_more_after_its_step_went_off_has_no_power(engine):
    """4-1-3: the scan after S20 went Off runs its block with the bus Off: OUT coils Off even
    through an OR of an On contact."""
    il = "LD X5\nSET S20\nSTL S20\nLD X0\nOR X1\nOUT Y1\nLD X3\nSET S21\nSTL S21\nLD X4\nOUT Y2\nRET\nEND"
    sc, m = scanner(il, engine)
    setbit(m, "X5", 1)
    setbit(m, "X1", 1)
    sc()
    assert bit(m, "Y1") == 1
    setbit(m, "X5", 0)
    setbit(m, "X3", 1)  # transfer to S21
    sc()
    sc()  # S20 Off: its block runs once more with the bus Off
    assert (bit(m, "S20"), bit(m, "S21"), bit(m, "Y1")) == (0, 1, 0)


@pytest.mark.parametrize("engine", ENGINES)
def test_ret_gives_back_the_mc_rail_around_a_step_ladder(engine):
    """A step ladder inside an On MC N0 block: after RET the rail is the block's (On), and
    with the block Off the rungs after RET are Off."""
    il = ("LD M100\nMC N0\nLD X5\nSET S20\nSTL S20\nLD X0\nOUT Y1\nRET\nLD X0\nOR X1\nOUT Y2\nMCR N0\nEND")
    sc, m = scanner(il, engine)
    setbit(m, "X1", 1)
    setbit(m, "M100", 1)
    sc()
    assert bit(m, "Y2") == 1
    setbit(m, "M100", 0)
    sc()
    assert bit(m, "Y2") == 0


def test_the_bit_sliced_lanes_do_not_take_programs_that_move_the_rail():
    """The batch lanes model no rail: MC/STL programs run scenario by scenario (the
    interpreter). Lanes that learn MC must gate by the rail like decode._railed."""
    for il in ("LD M100\nMC N0\nLD X0\nOR X1\nOUT Y0\nMCR N0\nEND",
               "LD X5\nSET S20\nSTL S20\nLD X0\nOR X1\nOUT Y1\nRET\nEND"):
        prog = load_program(image_of(il), VS)
        assert not LaneProgram(prog).ok
        assert not WordLaneProgram(prog).ok


# ------------------------------------------------------------------ random programs + oracle

INPUTS = [f"X{k}" for k in range(6)] + [f"M{k}" for k in range(6)]
COILS = [f"Y{k}" for k in range(6)] + [f"M{k}" for k in range(6)]


def gen_expr(r: random.Random, depth: int = 0):
    k = r.randrange(6 if depth < 2 else 2)
    if k <= 1:
        return ("c", r.choice(INPUTS), r.random() < 0.3)
    if k == 2:
        return ("and", gen_expr(r, depth + 1), gen_expr(r, depth + 1))
    if k in (3, 4):
        return ("or", gen_expr(r, depth + 1), gen_expr(r, depth + 1))
    return ("inv", gen_expr(r, depth + 1))


def emit(e) -> list[str]:
    """IL of expression `e` (starting with a load)."""
    if e[0] == "c":
        return [f"{'LDI' if e[2] else 'LD'} {e[1]}"]
    if e[0] == "inv":
        return emit(e[1]) + ["INV"]
    word, block = ("AND", "ANB") if e[0] == "and" else ("OR", "ORB")
    left, right = e[1], e[2]
    if right[0] == "c":
        return emit(left) + [f"{'ANI' if word == 'AND' and right[2] else 'ORI' if right[2] else word} {right[1]}"]
    return emit(left) + emit(right) + [block]


def value(e, dev: dict) -> bool:
    if e[0] == "c":
        return bool(dev[e[1]]) != e[2]
    if e[0] == "inv":
        return not value(e[1], dev)
    a, b = value(e[1], dev), value(e[2], dev)
    return (a and b) if e[0] == "and" else (a or b)


def gen_items(r: random.Random, level: int, n: int) -> list:
    items = []
    for _ in range(n):
        k = r.randrange(10)
        if k == 0 and level < 7:
            items.append(("mc", gen_expr(r), level, gen_items(r, level + 1, r.randrange(1, 4))))
        elif k == 1:  # one point, three branches (MPS/MRD/MPP)
            items.append(("mps", gen_expr(r), [(gen_expr(r, 2), r.choice(COILS)) for _ in range(3)]))
        else:
            what = r.choice(["OUT", "OUT", "SET", "RST", "INC"])
            items.append(("rung", gen_expr(r), what, f"D{r.randrange(3)}" if what == "INC" else r.choice(COILS)))
    return items


def emit_items(items) -> list[str]:
    out = []
    for it in items:
        if it[0] == "rung":
            out += emit(it[1]) + [f"{it[2]} {it[3]}"]
        elif it[0] == "mps":
            out += emit(it[1])
            for k, (e, c) in enumerate(it[2]):
                out += [("MPS", "MRD", "MPP")[k]] + emit(e) + ["ANB", f"OUT {c}"]
        else:
            out += emit(it[1]) + [f"MC N{it[2]}"] + emit_items(it[3]) + [f"MCR N{it[2]}"]
    return out


def oracle(items, dev: dict, rail: bool = True) -> None:
    """The rule itself (3-6): a rung's power is its contacts' logic AND the rail; OUT follows
    the power, SET/RST and INC act only with power; an MC level's rail is the outer rail AND
    its condition."""
    for it in items:
        if it[0] == "rung":
            on = rail and value(it[1], dev)
            what, d = it[2], it[3]
            if what == "OUT":
                dev[d] = int(on)
            elif on and what == "SET":
                dev[d] = 1
            elif on and what == "RST":
                dev[d] = 0
            elif on and what == "INC":
                dev[d] = (dev[d] + 1) & 0xFFFF
        elif it[0] == "mps":
            base = rail and value(it[1], dev)
            for e, c in it[2]:
                dev[c] = int(base and value(e, dev))
        else:
            oracle(it[3], dev, rail and value(it[1], dev))


@pytest.mark.parametrize("seed", range(12))
def test_random_mc_programs_follow_the_rule_on_every_engine(seed):
    r = random.Random(seed)
    items = gen_items(r, 0, 8)
    items.append(("mc", gen_expr(r), 0, gen_items(r, 1, 4)))  # at least one block
    il = "\n".join(emit_items(items) + ["END"])
    runs = [scanner(il, e) for e in ENGINES]
    words = ["D0", "D1", "D2"]
    dev = dict.fromkeys(INPUTS + COILS + words, 0)
    for _scan in range(25):
        for x in INPUTS[:6]:
            dev[x] = int(r.random() < 0.5)
        for sc, m in runs:
            for x in INPUTS[:6]:
                setbit(m, x, dev[x])
            sc()
        oracle(items, dev)
        for sc, m in runs:
            got = {c: bit(m, c) for c in COILS} | {w: m.words["D"][int(w[1:])] for w in words}
            want = {c: dev[c] for c in COILS} | {w: dev[w] for w in words}
            assert got == want, (sc.engine, il)
