"""Whole-process `mlc check` throughput on a generated 64k-step program (lines/s).

Goal (issue 2): >= 50,000 lines/s on the project machine (2 cores); issue 19: >= 100,000.
Also: lines/s for files of bad lines at two sizes (linear in the number of errors, issue 21).
Run: make bench  (or .venv/bin/python bench/check_speed.py)
"""

from __future__ import annotations

import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from gen import bad_program, mlc_command, program, timed  # noqa: E402


def main() -> None:
    mlc = mlc_command()
    text = program(64000)
    lines = text.count("\n")
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "big.il")
        with open(path, "w") as f:
            f.write(text)
        runs = [timed([mlc, "check", path]) for _ in range(5)]
        startup = min(timed([mlc, "--version"]) for _ in range(3))
    wall = min(r[0] for r in runs)
    cpu = min(r[1] for r in runs)
    code = runs[0][2]
    print(f"mlc check (lint on): {lines} lines, exit {code}; best of 5: wall {wall:.3f} s = "
          f"{lines / wall:,.0f} lines/s, CPU {cpu:.3f} s = {lines / cpu:,.0f} lines/s "
          f"(whole process; startup wall {startup[0]:.3f} s)")
    bad_lines(mlc)


def bad_lines(mlc: str) -> None:
    """Files where every line is wrong, at two sizes: the work per line must not grow with
    the number of errors (issue 21 #11: 200k bad lines took 859 s when it did)."""
    rates = []
    with tempfile.TemporaryDirectory() as d:
        for n in (20000, 80000):
            path = os.path.join(d, f"bad{n}.il")
            with open(path, "w") as f:
                f.write(bad_program(n))
            cpu = min(timed([mlc, "check", path])[1] for _ in range(2))
            rates.append(n / cpu)
            print(f"mlc check, {n:,} bad lines (about one error or warning each; text output, 50 shown "
                  f"per code): CPU {cpu:.2f} s = {n / cpu:,.0f} lines/s")
    print(f"  lines/s at 80k / at 20k: {rates[1] / rates[0]:.2f} (1.0 = linear; quadratic would give ~0.25)")



if __name__ == "__main__":
    main()
