"""Batch campaigns (issue 19 §2): many stimulus files against one program, end to end.

- bool lanes: 1024 scenarios of bool1000 (bench/sim_speed.py's program: 200 rungs, 1000
  instructions + END), each a generated .stim file of 20 `#SCAN Mn=0/1` lines and `run #1000`,
  through run_batch (mlc sim PROGRAM --stimulus 'dir/*.stim' and mlc test use it): reading and
  parsing the files, naming the devices, the bit-sliced kernel and every scenario's RunResult
  are in the time. Figure: scenario-instructions/s = 1024 x 1000 scans x 1001 instructions /
  CPU seconds. Goal >= 5 G.
- word lanes: 1024 scenarios of mixed-words (sim_speed.py: TMR, CNT, MOV, ADD, SUB, MUL, LD>,
  DADD; numpy lanes) against the same scenarios one by one (compiled engine); goal >= 10x.
- cluster: the same bool1000 campaign and a one-by-one campaign (lanes off) run locally and
  on a Dask LocalCluster of 2 worker processes (mlctool/sim/campaign/cluster.py); scenarios/s, wall
  time (the work is in other processes).

Every ratio is printed after a check that the compared runs did the same work: the same
RunResults (final values in the same order, expectations) scenario by scenario, else exit 1.
CPU time (time.process_time) except for the cluster; ROUNDS interleaved rounds (A, B, A, B
...), median and range. Run: make bench, or .venv-bench/bin/python bench/batch_speed.py
[lanes words cluster].
"""

from __future__ import annotations

import os
import random
import statistics
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(__file__))

from sim_speed import NC5, bool1000_il, build, executed_per_scan, mixed_words_il  # noqa: E402

from mlctool.sim.campaign.batch import Options, run_batch  # noqa: E402

ROUNDS = int(os.environ.get("BENCH_ROUNDS", "3"))
N, SCANS = 1024, 1000
SINGLE = 24  # scenarios run one by one for the ratios


def bool_stimuli(d: str, n: int = N, seed: int = 1) -> list[str]:
    rnd = random.Random(seed)
    paths = []
    for k in range(n):
        lines = [f"#{rnd.randrange(SCANS)} M{rnd.randrange(1000)}={rnd.randrange(2)}" for _ in range(20)]
        path = os.path.join(d, f"s{k:04}.stim")
        with open(path, "w") as f:
            f.write("\n".join(lines) + f"\nrun #{SCANS}\n")
        paths.append(path)
    return paths


def word_stimuli(d: str, n: int = N, seed: int = 1) -> list[str]:
    rnd = random.Random(seed)
    paths = []
    for k in range(n):
        lines = [f"#{rnd.randrange(SCANS)} X{rnd.randrange(8)}={rnd.randrange(2)}" for _ in range(10)]
        lines += [f"#{rnd.randrange(SCANS)} M{rnd.randrange(17)}={rnd.randrange(2)}" for _ in range(10)]
        lines += [f"#{rnd.randrange(SCANS)} M1000={rnd.randrange(2)}" for _ in range(3)]
        lines += [f"#{rnd.randrange(SCANS)} D{800 + rnd.randrange(16)}={rnd.randrange(-30, 30)}" for _ in range(5)]
        path = os.path.join(d, f"w{k:04}.stim")
        with open(path, "w") as f:
            f.write("\n".join(lines) + f"\nrun #{SCANS}\n")
        paths.append(path)
    return paths


def cpu(fn):
    t = time.process_time()
    out = fn()
    return time.process_time() - t, out


def same_results(name: str, a: list, b: list) -> None:
    """The scenarios of two runs agree result by result, device order included, or exit 1."""
    bad = [x.stim for x, y in zip(a, b, strict=True)
           if x.result != y.result or (x.result is not None and list(x.result.devices.items())
                                        != list(y.result.devices.items()))]
    if bad:
        raise SystemExit(f"{name}: {len(bad)} scenarios differ between the compared runs, e.g. {bad[:3]}")


def med(xs: list[float]) -> str:
    return f"{statistics.median(xs):.3f} s ({min(xs):.3f}-{max(xs):.3f})"


def lanes_against_single(name: str, image, paths: list[str], ran_as: str) -> tuple[list[float], float, float]:
    """Interleaved rounds of the whole batch (as lanes) and its first SINGLE scenarios one by
    one; exits unless every scenario ran as `ran_as` lanes and the first SINGLE equal their
    single runs. -> (batch CPU times, CPU per scenario as a lane, CPU per scenario alone)."""
    few = paths[:SINGLE]
    batch_t, single_t = [], []
    for _ in range(ROUNDS):
        t, (lanes, stats) = cpu(lambda: run_batch(image, NC5, paths, Options()))
        batch_t.append(t)
        t, (single, _) = cpu(lambda: run_batch(image, NC5, few, Options(), lanes=False))
        single_t.append(t)
    if getattr(stats, ran_as) != N:
        raise SystemExit(f"{name}: only {getattr(stats, ran_as)} of {N} scenarios ran as {name}")
    same_results(name, lanes[:SINGLE], single)
    return batch_t, statistics.median(batch_t) / N, statistics.median(single_t) / SINGLE


def bench_lanes() -> None:
    image = build(bool1000_il())
    instrs = executed_per_scan(image, lambda m: None)
    with tempfile.TemporaryDirectory() as d:
        batch_t, per_lane, per_single = lanes_against_single("bool lanes", image, bool_stimuli(d), "lanes")
        rate = N * SCANS * instrs / statistics.median(batch_t)
        print(f"\nbatch, bool lanes: {N} scenarios x {SCANS} scans of bool1000 ({instrs} instructions/scan), "
              f"end to end through run_batch (files read and parsed, results built)")
        print(f"  CPU {med(batch_t)}: {rate / 1e9:.2f} G scenario-instructions/s (goal >= 5 G: "
              f"{'met' if rate >= 5e9 else 'not met'})")
        print(f"  verified: the first {SINGLE} scenarios equal their one-by-one runs (compiled engine); "
              f"per scenario {per_lane * 1e3:.2f} ms as a lane vs {per_single * 1e3:.1f} ms alone: "
              f"{per_single / per_lane:,.0f}x")


def bench_words() -> None:
    image = build(mixed_words_il())
    instrs = executed_per_scan(image, lambda m: None)
    with tempfile.TemporaryDirectory() as d:
        batch_t, per_lane, per_single = lanes_against_single("word lanes", image, word_stimuli(d), "word_lanes")
        ratio = per_single / per_lane
        print(f"\nbatch, word lanes: {N} scenarios x {SCANS} scans of mixed-words ({instrs} instructions/scan) "
              f"as numpy lanes; CPU {med(batch_t)}: {N * SCANS * instrs / statistics.median(batch_t) / 1e6:,.0f} M "
              f"scenario-instructions/s")
        print(f"  verified: the first {SINGLE} scenarios equal their one-by-one runs; per scenario "
              f"{per_lane * 1e3:.2f} ms as a lane vs {per_single * 1e3:.1f} ms alone: {ratio:.1f}x "
              f"(goal >= 10x: {'met' if ratio >= 10 else 'not met'})")


def bench_cluster() -> None:
    try:
        from distributed import LocalCluster
    except ImportError:
        print("\ncluster: skipped (no dask distributed in this environment: pip install 'mlctool[cluster]')")
        return
    image = build(bool1000_il())
    with tempfile.TemporaryDirectory() as d, \
            LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        paths = bool_stimuli(d)
        few = paths[:64]
        cases = [("bool1000 lanes, 1024 scenarios", paths, True), ("bool1000 one by one, 64 scenarios", few, False)]
        print("\ncluster: scenarios/s locally (1 process) and on a Dask LocalCluster (2 worker processes, "
              "1 thread each), wall time, 2 interleaved rounds, best")
        for name, ps, lanes in cases:
            local_t, remote_t = [], []
            for _ in range(2):
                t = time.perf_counter()
                local, _ = run_batch(image, NC5, ps, Options(), lanes=lanes)
                local_t.append(time.perf_counter() - t)
                t = time.perf_counter()
                remote, _ = run_batch(image, NC5, ps, Options(), lanes=lanes, cluster=cluster.scheduler_address)
                remote_t.append(time.perf_counter() - t)
            same_results(f"cluster, {name}", local, remote)
            lo, re = len(ps) / min(local_t), len(ps) / min(remote_t)
            print(f"  {name:36s} local {lo:8,.0f}/s   cluster {re:8,.0f}/s   cluster/local {re / lo:.2f}x "
                  "(verified: same results)")


def main() -> None:
    which = sys.argv[1:] or ["lanes", "words", "cluster"]
    for name in which:
        {"lanes": bench_lanes, "words": bench_words, "cluster": bench_cluster}[name]()


if __name__ == "__main__":
    main()
