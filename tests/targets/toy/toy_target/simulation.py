"""The toy's own instruction for the simulator: TWICE S D (D = 2 x S while the rung is On),
and a register the toy's hardware counts up before every scan (D99: scans since power-on)."""

from mlctool.targetapi import Simulation


def twice(m, s) -> None:
    if m.acc:  # continuous execution, as the engine's application instructions
        s.ops[1].set(m, 2 * s.ops[0].get(m))


def count_scans(m) -> None:
    m.words["D"][99] = (m.words["D"][99] + 1) & 0xFFFF


SIMULATION = Simulation(actions={"twice": twice}, scan_hooks=((count_scans, ("scan_counter",)),))
