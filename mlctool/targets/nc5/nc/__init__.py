"""The NC side of the NC5: a virtual CNC the MLC program runs against (manual ch. 5 and 6).

Belongs here: the `model nc5 ...` device model and its channel state machine (model.py),
the part-program subset it runs (program.py), the special M/D addresses it
reads and writes (addresses.py) and the signals it publishes (published.py).
Does not belong here: the table of every special relay and register (the checker's,
mlctool/targets/nc5/signals.*), the engine (mlctool/sim/), generic device models
(mlctool/devices/).
"""
