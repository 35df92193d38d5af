"""Whole-process `mlc check` throughput on a generated 64k-step program (lines/s).

Goal (issue 2): >= 50,000 lines/s on the project machine (2 cores).
Run: make bench  (or .venv/bin/python bench/check_speed.py)
"""

from __future__ import annotations

import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from gen import mlc_command, program, timed  # noqa: E402


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



if __name__ == "__main__":
    main()
