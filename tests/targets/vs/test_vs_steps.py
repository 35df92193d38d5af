"""VS step counts: the FX3U convention (target.toml step_convention, [[step_rules]]), one
case per rule; the addresses are what a GX Works2 FX3U export numbers the same rows."""

from __future__ import annotations

import pytest

from vskit import image_of

# (IL line, steps): the FX3U program-step counts
CASES = [
    ("LD X0", 1), ("LD M100", 1), ("LD M9000", 1), ("AND M9255", 1), ("ANI M9256", 2), ("OUT M9000", 2), ("LD D0.3", 3), ("LDI S20", 1), ("LD T5", 1),
    ("LDP X1", 2), ("ANDF D0.1", 3),
    ("OUT Y0", 1), ("OUT M9034", 2), ("OUT D1.2", 3), ("OUT T0 K50", 3), ("OUT C0 K10", 3),
    ("OUT C200 K10", 5), ("OUT C235 K100", 5),
    ("SET M5", 1), ("SET M9040", 2), ("SET D2.0", 3),
    ("RST Y0", 1), ("RST M9040", 2), ("RST T0", 2), ("RST C0", 2), ("RST C235", 2), ("RST S20", 2),
    ("RST D0", 3), ("RST D9004", 3), ("RST R5", 3), ("RST V0", 3), ("RST Z1", 3), ("RST D3.4", 3),
    ("PLS M0", 2), ("PLF Y1", 2), ("MC N0", 3), ("MCR N0", 2),
    ("MOV K1 D0", 5), ("DMOV K1 D0", 9), ("MOVP H10 D0", 5), ("DADD D0 D2 D4", 13),
    ("LD= D0 K5", 5), ("LDD> D0 K5", 9), ("ZRST M0 M10", 5), ("INC D0", 3), ("DINC D0", 5),
    ("MEP", 1), ("INV", 1), ("ANB", 1), ("MPS", 1), ("MRD", 1), ("MPP", 1), ("NOP", 1),
]


# the rung around each line, so that it checks clean: (before, after)
_AROUND = {
    "load": ([], ["OUT Y7"]), "and": (["LD X0"], ["OUT Y7"]), "output": (["LD X0"], []),
    "MPS": (["LD X0"], ["OUT Y6", "MPP", "OUT Y7"]), "MRD": (["LD X0", "MPS", "OUT Y6"], ["OUT Y5", "MPP", "OUT Y7"]),
    "MPP": (["LD X0", "MPS", "OUT Y6"], ["OUT Y7"]), "ANB": (["LD X0", "LD X1"], ["OUT Y7"]),
    "MC": (["LD X0"], ["MCR N0"]), "MCR": (["LD X0", "MC N0"], []), "NOP": ([], []),
    "MEP": (["LD X0"], ["OUT Y7"]), "INV": (["LD X0"], ["OUT Y7"]),
}


@pytest.mark.parametrize(("line", "steps"), CASES, ids=[c[0] for c in CASES])
def test_fx3u_step_count(line, steps):
    kind = line.split()[0]
    key = kind if kind in _AROUND else "load" if kind.startswith("LD") else \
        "and" if kind.startswith(("AND", "AN", "OR")) else "output"
    before, after = _AROUND[key]
    il = "\n".join([*before, line, *after, "END"]) + "\n"
    image = image_of(il)
    assert image is not None, il
    at = {i.line: i for i in image.instrs}
    this = at[len(before) + 1]
    following = at[len(before) + 2]
    assert (this.steps, following.addr - this.addr) == (steps, steps), il
