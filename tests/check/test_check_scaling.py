"""`mlc check` does work linear in the number of lines and diagnostics (issue 21 #11: 200k bad
lines took 859 s). No timing: the Python-level work is counted (profiler events), and
bench/check_speed.py reports lines/s for a file of bad lines at two sizes."""

from __future__ import annotations

import random
import sys

from mlctool.check import broken_lines, check_texts
from mlctool.diagnostics import Span, diag
from mlctool.program import Module
from mlctool.syntax.source import decode
from mlctool.targetapi import load_target

# lines that each give one or more errors or warnings of different checks
BAD = ["FOO X0", "OUT Y99999", "LD", "MOV K1", "P1:", "LD X0 X1", "@@", "MPS", "ANB", "OUT M0",
       "LD X0", "AND D0", "CALL P7", "CJ P9", "SET M5", "DMOV K1 D1", "FOR K3", "NEXT", "SRET",
       "FEND", ".define A", ".export P1", "ADD K1 K2 K3", "RST Y99999"]


def bad_program(lines: int, seed: int = 1) -> str:
    rnd = random.Random(seed)
    return "".join(rnd.choice(BAD) + "\n" for _ in range(lines)) + "END\n"


def _profiled_events(text: str) -> tuple[int, int]:
    """(profiler events of one check, diagnostics found)"""
    target = load_target("nc5")
    src, _ = decode("bad.il", text.encode())
    check_texts([src], target)  # warm caches (tables, regexes) outside the count
    events = 0

    def count(frame, event, arg):
        nonlocal events
        events += 1

    sys.setprofile(count)
    try:
        result = check_texts([src], target)
    finally:
        sys.setprofile(None)
    return events, len(result.diagnostics)


def test_work_grows_linearly_with_bad_lines():
    small, small_diags = _profiled_events(bad_program(300))
    large, large_diags = _profiled_events(bad_program(1200))
    assert large_diags > 3.5 * small_diags > 0
    # a quadratic step in Python code (a loop over diagnostics per diagnostic) gives ~16x
    assert large / small < 4.6, (small, large)


def test_broken_lines_per_file():
    mods = [Module("a.il", "nc5", []), Module("b.il", "nc5", [])]
    diags = [diag(f, Span.at(line), code, "m") for f, line, code in
             [("a.il", 3, "E201"), ("a.il", 3, "E103"), ("a.il", 7, "E103"), ("b.il", 2, "E205"),
              ("c.il", 1, "E201")]]
    assert broken_lines(mods, diags) == {"a.il": frozenset({3, 7}), "b.il": frozenset()}
