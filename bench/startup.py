"""Start-up cost of `mlc` as a linter runs it: whole processes, CPU time of the child.

Measured (issue 14, goal <= 150 ms CPU for `mlc check` on a 20-line file, bytecode cached):
- `python -c pass`: the floor, the interpreter alone;
- `mlc --help` and `mlc check tiny.il` (TINY below: 20 lines with a directive and a label);
- rendering text diagnostics: per diagnostic, in-process (render_text to /dev/null) and whole
  process (`mlc check --show-all` on 20,000 double coils, against `mlc check`, which shows 50).

Each command runs once to warm the bytecode cache, then ROUNDS times, the commands
interleaved so each sees the same stretches of a busy machine; median and range of the
child's CPU time (user + system, from os.wait4).
Run: make bench  (or .venv/bin/python bench/startup.py)
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(__file__))
from gen import mlc_command  # noqa: E402

ROUNDS = 9
GOAL_CHECK_MS = 150
GOAL_RENDER_US = 20

TINY = """; tiny: a start/stop latch with a timer (20 lines)
.define START X0
.define STOP  X1
.define LAMP  Y0
LD START          ; latch
OR M0
ANI STOP
OUT M0
LD M0
TMR T0 K10
LD T0
OUT LAMP
LD X2
CJ P1
MOV K5 D0
P1:
LD X3
ADD D0 K1 D1
OUT Y1
END
"""


def child_cpu(cmd: list[str], cwd: str) -> tuple[float, int]:
    """(CPU seconds of the child process alone, exit code)"""
    p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    return usage.ru_utime + usage.ru_stime, p.returncode


def rounds(commands: dict[str, list[str]], cwd: str, n: int = ROUNDS) -> dict[str, list[float]]:
    for cmd in commands.values():  # warm-up: bytecode cached, files in the page cache
        child_cpu(cmd, cwd)
    times: dict[str, list[float]] = {name: [] for name in commands}
    for _ in range(n):
        for name, cmd in commands.items():
            cpu, code = child_cpu(cmd, cwd)
            if code not in (0, 1):
                raise SystemExit(f"{name}: exit {code}")
            times[name].append(cpu)
    return times


def render_cost_in_process(path: str) -> tuple[int, float]:
    """(diagnostics, best microseconds per diagnostic) of render_text into /dev/null"""
    from mlctool.check import check_files
    from mlctool.report import render_text
    from mlctool.targetapi import load_target

    result = check_files([path], load_target("nc5"))
    best = float("inf")
    with open(os.devnull, "w") as sink:
        for _ in range(3):
            t = time.process_time()
            render_text(result.diagnostics, result.lines, sink)
            best = min(best, time.process_time() - t)
    n = len(result.diagnostics)
    return n, best / n * 1e6


def main() -> None:
    mlc = mlc_command()
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "tiny.il"), "w") as f:
            f.write(TINY)
        with open(os.path.join(d, "coils.il"), "w") as f:
            f.write("LD X0\nOUT M0\n" * 20001 + "END\n")  # 20,000 W401
        env_cmds = {
            "python -c pass": [sys.executable, "-c", "pass"],
            "mlc --help": [mlc, "--help"],
            "mlc check tiny.il": [mlc, "check", "tiny.il"],
        }
        times = rounds(env_cmds, d)
        whole = rounds({"all": [mlc, "check", "--show-all", "coils.il"],
                        "summarised": [mlc, "check", "coils.il"]}, d, 3)
        n, per_diag = render_cost_in_process(os.path.join(d, "coils.il"))
    print(f"start-up, CPU time of the child process, {ROUNDS} interleaved rounds (median, range):")
    for name, ts in times.items():
        ms = sorted(t * 1000 for t in ts)
        print(f"  {name:20} {statistics.median(ms):6.0f} ms   ({ms[0]:.0f}-{ms[-1]:.0f})")
    check = statistics.median(times["mlc check tiny.il"]) * 1000
    print(f"  goal: mlc check on a 20-line file <= {GOAL_CHECK_MS} ms: {'met' if check <= GOAL_CHECK_MS else 'NOT met'}")
    shown_all, summarised = min(whole["all"]), min(whole["summarised"])
    print(f"rendering diagnostics: {n:,} W401, in-process render_text {per_diag:.1f} us each; whole process "
          f"`check --show-all` {shown_all:.2f} s vs `check` (50 shown) {summarised:.2f} s CPU (best of 3): "
          f"{(shown_all - summarised) / (n - 50) * 1e6:.1f} us each; goal <= {GOAL_RENDER_US} us: "
          f"{'met' if per_diag <= GOAL_RENDER_US else 'NOT met'}")


if __name__ == "__main__":
    main()
