"""Whole-process `mlc build` + link throughput on a generated 64k-step program (steps/s).

The program is a 62k-step main module (bench/gen.py) that CALLs into a 2k-step subroutine
library, so the figure covers check, assembly, linking and writing .mlx, map and listing.
Also timed: `mlc link` alone of the two object modules, and `mlc objdump --json`.
Run: make bench  (or .venv/bin/python bench/build_speed.py)
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from gen import mlc_command, program, timed  # noqa: E402

LIBRARY_STEPS = 2000


def library() -> str:
    rungs = [f"LD X{n % 32}\nINC D{20000 + n}\n" for n in range(LIBRARY_STEPS // 4 - 1)]
    return ".library\n.export P10\nP10:\n" + "".join(rungs) + "SRET\n"


def main() -> None:
    mlc = mlc_command()
    text = program(64000 - LIBRARY_STEPS).replace("END\n", "LD X0\nCALL P10\nEND\n")
    with tempfile.TemporaryDirectory() as d:
        for name, body in (("main.il", text), ("lib.il", library())):
            with open(os.path.join(d, name), "w") as f:
                f.write(body)
        build = [mlc, "build", "main.il", "lib.il", "-o", "p.mlx", "--map", "p.map", "--listing", "p.lst"]
        runs = [timed(build, d) for _ in range(5)]
        assert runs[0][2] == 0, "build failed"
        info = json.loads(subprocess.run([mlc, "objdump", "--json", "p.mlx"], cwd=d, capture_output=True,
                                         text=True, check=True).stdout)
        steps = info["total_steps"]
        subprocess.run([mlc, "build", "-c", "main.il", "lib.il"], cwd=d, check=True, capture_output=True)
        link = min(timed([mlc, "link", "main.mlo", "lib.mlo", "-o", "q.mlx"], d)[0] for _ in range(3))
        dump = min(timed([mlc, "objdump", "--json", "p.mlx"], d)[0] for _ in range(3))
        size = os.path.getsize(os.path.join(d, "p.mlx"))
    wall = min(r[0] for r in runs)
    cpu = min(r[1] for r in runs)
    print(f"mlc build + link: {steps} steps, {len(info['instructions'])} instructions, .mlx {size:,} bytes; "
          f"best of 5: wall {wall:.3f} s = {steps / wall:,.0f} steps/s, CPU {cpu:.3f} s = "
          f"{steps / cpu:,.0f} steps/s (whole process, writes .mlx + map + listing)")
    print(f"mlc link of the two .mlo alone: wall {link:.3f} s = {steps / link:,.0f} steps/s; "
          f"mlc objdump --json: {dump:.3f} s")



if __name__ == "__main__":
    main()
