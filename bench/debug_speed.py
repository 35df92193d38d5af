"""`mlc debug`'s `run` with scan-level conditions against plain `mlc sim` on bool1000
(issue 17: the debugger keeps >= 50 % of the simulator's speed when nothing needs stepping).

Both run the same scans on the compiled engine with no stimulus; the debug session checks a
`break if` condition that never holds and a watch on a device that never changes after every
scan, and takes its time-travel checkpoints (every 100 scans). Prints scans/s of each, the
ratio and whether it meets the goal (a miss exits 0, as bench/sim_speed.py's goals do: `make
bench` goes on to the next bench on a busy machine).

    python bench/debug_speed.py [SCANS]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from sim_speed import NC5, bool1000_il, build  # noqa: E402

from mlctool.debug.session import DebugSession  # noqa: E402
from mlctool.sim.run.run import Simulation  # noqa: E402
from mlctool.sim.stimulus.stimulus import Stimulus  # noqa: E402


def main() -> int:
    scans = int(sys.argv[1]) if len(sys.argv) > 1 else 3000
    image = build(bool1000_il())
    sim = Simulation(image, NC5, Stimulus("<none>", []), [], 10_000, [], False)
    sim.run(10)  # compile and warm up
    t = time.perf_counter()
    sim.run(scans)
    plain = scans / (time.perf_counter() - t)

    s = DebugSession(image, NC5, Stimulus("<none>", []), [], 10_000)
    s.add_condition("D0 > 100 && M999")
    s.add_watch("D1")
    s.run(scans=10)
    t = time.perf_counter()
    stop = s.run(scans=scans)
    debug = scans / (time.perf_counter() - t)
    assert stop.reason == "step", stop
    ratio = debug / plain
    print(f"bool1000: mlc sim {plain:,.0f} scans/s, mlc debug run with a condition and a watch "
          f"{debug:,.0f} scans/s: {ratio:.0%} (goal >= 50 %: {'met' if ratio >= 0.5 else 'missed'})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
