"""Start and memory of `mlc sim` on large linked programs (issue 19 §2), whole processes.

- start: the 64k-step program of bench/gen.py (38,651 instructions) built once to a .mlx,
  then `mlc sim p.mlx --scans 1 --json` in a child process: CPU time of the child (user +
  system, os.wait4) from its start to its exit, i.e. interpreter, imports, reading and
  decoding the object, building the simulation, the first scan and the report. Cold: the
  on-disk cache off (MLC_CACHE=off); warm: a cache folder the first run filled (the decoded
  object and the compiled code, mlctool/cache.py). ROUNDS interleaved rounds (cold, warm,
  cold, warm ...), median and range. Goal <= 1 s.
- memory: a 256k-instruction program (gen.py at 430,000 steps, capacity raised in mlc.toml)
  run for 2 scans, cold and warm; peak resident memory of the child (ru_maxrss). Goal <= 300 MB.

Before a figure is printed the compared runs must agree: the JSON result (final values,
expectations) of every cold and warm run is the same, else exit 1.
Run: make bench, or .venv-bench/bin/python bench/start_memory.py [start memory].
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from gen import byte_compiled, program  # noqa: E402

ROUNDS = int(os.environ.get("BENCH_ROUNDS", "5"))
MLC = [sys.executable, "-m", "mlctool"]


def run(cmd: list[str], cwd: str, env: dict) -> tuple[float, float, str]:
    """(CPU seconds, peak MB, stdout) of one child process (os.wait4 reaps it: its own usage);
    an exit status other than 0 or 1 stops the bench."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        p = subprocess.Popen(cmd, cwd=cwd, env=env, stdout=out, stderr=err)
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = code = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        if code not in (0, 1):
            raise SystemExit(f"{' '.join(cmd)}: exit {code}\n{err.read().decode()[-2000:]}")
        return usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024, out.read().decode()


def build(d: str, steps: int, capacity: int | None = None) -> str:
    with open(os.path.join(d, "p.il"), "w") as f:
        f.write(program(steps))
    if capacity:
        with open(os.path.join(d, "mlc.toml"), "w") as f:
            f.write(f"capacity = {capacity}\n")
    run(MLC + ["build", "p.il", "-o", "p.mlx"], d, dict(os.environ))
    return os.path.join(d, "p.mlx")


def envs(d: str) -> tuple[dict, dict]:
    cold = dict(os.environ, MLC_CACHE="off")
    warm = dict(os.environ, MLC_CACHE_DIR=os.path.join(d, "cache"))
    warm.pop("MLC_CACHE", None)
    return cold, warm


def compared(name: str, outputs: list[str]) -> None:
    if len(set(outputs)) != 1:
        raise SystemExit(f"{name}: the runs' JSON results differ (cold and warm must agree)")


def fmt(xs: list[float], unit: str, scale: float = 1.0) -> str:
    m = statistics.median(xs) * scale
    return f"{m:,.2f} {unit} ({min(xs) * scale:,.2f}-{max(xs) * scale:,.2f})"


def bench_start() -> None:
    with tempfile.TemporaryDirectory() as d:
        build(d, 64000)
        cold_env, warm_env = envs(d)
        cmd = MLC + ["sim", "p.mlx", "--scans", "1", "--json"]
        first_cpu, _, first_out = run(cmd, d, warm_env)  # fills the cache
        cold, warm, outs = [], [], [first_out]
        for _ in range(ROUNDS):
            c, _, out = run(cmd, d, cold_env)
            cold.append(c)
            outs.append(out)
            c, _, out = run(cmd, d, warm_env)
            warm.append(c)
            outs.append(out)
        compared("start", outs)
        base, _, _ = run([sys.executable, "-c", "pass"], d, cold_env)
        w = statistics.median(warm)
        print(f"\nstart: mlc sim of the 64k-step .mlx (38,651 instructions) to its first scan, whole process, "
              f"CPU; {ROUNDS} interleaved rounds, median (range); verified: the same JSON result every run")
        print(f"  cold (MLC_CACHE=off)          {fmt(cold, 's')}")
        print(f"  first run, filling the cache  {first_cpu:.2f} s")
        print(f"  warm (object and code cached) {fmt(warm, 's')}   goal <= 1 s: {'met' if w <= 1 else 'not met'}")
        print(f"  (python -c pass: {base:.2f} s)")


def bench_memory() -> None:
    with tempfile.TemporaryDirectory() as d:
        build(d, 430000, capacity=1_000_000)
        cold_env, warm_env = envs(d)
        cmd = MLC + ["sim", "p.mlx", "--scans", "2", "--json"]
        run(cmd, d, warm_env)  # fills the cache
        cold_c, cold_m, out_c = run(cmd, d, cold_env)
        warm_c, warm_m, out_w = run(cmd, d, warm_env)
        compared("memory", [out_c, out_w])
        with open(os.path.join(d, "p.il")) as f:
            instrs = sum(1 for line in f if line.strip() and not line.startswith(";"))
        print(f"\nmemory: mlc sim --scans 2 of a {instrs:,}-instruction .mlx, peak resident memory of the process "
              "(ru_maxrss); verified: the same JSON result")
        print(f"  cold (MLC_CACHE=off): {cold_m:,.0f} MB ({cold_c:.1f} s CPU)")
        print(f"  warm (cached):        {warm_m:,.0f} MB ({warm_c:.1f} s CPU)   goal <= 300 MB: "
              f"{'met' if warm_m <= 300 else 'not met'} warm, {'met' if cold_m <= 300 else 'not met'} cold")


def main() -> None:
    byte_compiled()
    for name in sys.argv[1:] or ["start", "memory"]:
        {"start": bench_start, "memory": bench_memory}[name]()


if __name__ == "__main__":
    main()
