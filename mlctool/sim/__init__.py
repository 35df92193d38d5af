"""The simulator engine: target-independent.

Belongs here: machine state (state.py), operands, decoding (decode.py), the scan and program
flow (scan.py), the generic routines every target shares (semantics.py: contacts, coils,
timers, counters, moves, arithmetic, floats), the compiled engine (compile*.py, codegen.py,
engine.py), batch lanes, stimulus, traces and reports, the serial line (seriallink.py),
motion and pulse trains. Targets plug in through mlctool.targetapi (their Simulation).
Does not belong here: any import of mlctool.targets.*, any one controller's instructions or
peripherals (tests/test_architecture.py).
"""
