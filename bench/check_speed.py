"""Whole-process `mlc check` throughput on a generated 64k-step program (lines/s).

Goal (issue 2): >= 50,000 lines/s on the project machine (2 cores).
Run: make bench  (or .venv/bin/python bench/check_speed.py)
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(__file__))
from gen import program  # noqa: E402


def main() -> None:
    mlc = shutil.which("mlc", path=os.path.dirname(sys.executable)) or shutil.which("mlc")
    text = program(64000)
    lines = text.count("\n")
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "big.il")
        with open(path, "w") as f:
            f.write(text)
        runs = [_time([mlc, "check", path]) for _ in range(5)]
        startup = min(_time([mlc, "--version"]) for _ in range(3))
    wall = min(r[0] for r in runs)
    cpu = min(r[1] for r in runs)
    code = runs[0][2]
    print(f"mlc check (lint on): {lines} lines, exit {code}; best of 5: wall {wall:.3f} s = "
          f"{lines / wall:,.0f} lines/s, CPU {cpu:.3f} s = {lines / cpu:,.0f} lines/s "
          f"(whole process; startup wall {startup[0]:.3f} s)")


def _time(cmd) -> tuple[float, float, int]:
    """(wall s, CPU s of the child, exit code): CPU time is steadier on a busy machine."""
    before = os.times()
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True)
    wall = time.perf_counter() - t
    after = os.times()
    cpu = (after.children_user - before.children_user) + (after.children_system - before.children_system)
    return wall, cpu, r.returncode


if __name__ == "__main__":
    main()
