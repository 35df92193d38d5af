"""`mlc verify`: prove a program's properties over every reachable state, or find the scan
sequence that breaks them (docs/verify.md).

Belongs here: the property language, the input space and property monitors, the explicit
and symbolic engines, verdicts and counterexamples. Does not belong here: what an
instruction does (the simulator's engine runs it; the symbolic engine translates it with the
simulator's lane code generator) and the command line (mlctool/cli/verify.py).
"""
