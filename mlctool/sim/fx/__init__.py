"""FX-family routines (Vigor VS) beyond semantics_fx.py, one small module per manual chapter
(shift, data, floats, strings, clock); semantics_fx merges their tables into its own (keyed
by `op`, like semantics.py).

Importing any of them loads semantics first: semantics -> semantics_fx -> these modules is
the one import order that has no cycle."""

from mlctool.sim import semantics  # noqa: F401
