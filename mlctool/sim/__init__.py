"""The simulator engine: target-independent.

Belongs here, at this level: the machine (state.py: devices, memory, faults; unit_words.py;
signals.py, the model-owned signals a DeviceView reads), operands, decoding (decode.py), the
scan and program flow (scan.py) and the generic routines every target shares (semantics.py:
contacts, coils, timers, counters, moves, arithmetic, floats). Around it, one sub-package per
part, each importing only the machine and the parts listed before it:
hardware/ (pulse trains, axis motion, pulse pins, the serial line), engines/ (the compiled
and native engines), stimulus/ (stimulus files), run/ (one run: Simulation, its JSON, VCD,
W608) and campaign/ (many runs: mlc test's suite, batches and their lanes, clusters,
coverage, JUnit). Targets plug in through mlctool.targetapi (their Simulation).
Does not belong here: any import of mlctool.targets.*, any one controller's instructions or
peripherals (tests/test_architecture.py).
"""
