"""The compiled engine's generated code for every sample and bench program, to compare a
refactoring's before and after (issue 15: moving code must not change what the engine runs).

    python tools/dump_compiled.py > before.txt    # ... change the code ...
    python tools/dump_compiled.py > after.txt && diff before.txt after.txt

Each program prints as `== <name> <target> <sha256 of the generated source>` followed by the
source with --full, or the reason the program runs on the interpreter (Unsupported); the program key (a hash of
the compiler version, the target name and the program) is left out, it names no behaviour.
"""

from __future__ import annotations

import glob
import hashlib
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "bench"))

from mlctool.asm import program_from_paths  # noqa: E402
from mlctool.sim.engines.compile import Unsupported, _Gen, program_key  # noqa: E402
from mlctool.sim.scan import load_program  # noqa: E402
from mlctool.targetapi import load_target  # noqa: E402


def programs():
    """(name, target name, [paths] or IL text)."""
    for target in ("nc5", "vs", "fbs"):
        for path in sorted(glob.glob(os.path.join(ROOT, "samples", target, "*.il"))):
            yield os.path.relpath(path, ROOT), target, [path]
    project = os.path.join(ROOT, "samples", "project", "src")
    yield "samples/project", "nc5", [os.path.join(project, f) for f in ("conveyor.il", "pickplace.il")]
    import gen
    import sim_speed

    yield "bench bool1000", "nc5", sim_speed.bool1000_il()
    yield "bench mixed", "nc5", sim_speed.mixed_il()
    yield "bench mixed_words", "nc5", sim_speed.mixed_words_il()
    yield "bench vs bool1000", "vs", sim_speed.bool1000_il()
    timed = []
    for k, (a, b, c, *_) in enumerate(sim_speed.bool1000_rungs()[:100]):
        timed += [f"LD M{a}", f"ANI M{b}", f"OUT T{k} K50", f"LD M{c}", f"OUT C{k} K10"]
    yield "bench vs timers+counters", "vs", "\n".join(timed) + "\nEND\n"
    yield "bench gen 4000", "nc5", gen.program(4000)


def image(target, source):
    if isinstance(source, list):
        img, diags, _ = program_from_paths(source, target)
        return img
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "bench.il")
        with open(path, "w", encoding="utf-8") as f:
            f.write(source)
        img, diags, _ = program_from_paths([path], target)
    return img


def main() -> None:
    full = "--full" in sys.argv
    for name, tname, source in programs():
        target = load_target(tname)
        img = image(target, source)
        if img is None:
            print(f"== {name} {tname} (does not build)")
            continue
        prog = load_program(img, target)
        try:  # the generator itself: compile_program hides the reason a program is not compiled
            code = _Gen(prog, program_key(prog)).build()
        except Unsupported as e:
            print(f"== {name} {tname} interpreter: {e}")
            continue
        digest = hashlib.sha256(code.source.encode()).hexdigest()
        print(f"== {name} {tname} {digest}")
        if full:
            print(code.source)


if __name__ == "__main__":
    main()
