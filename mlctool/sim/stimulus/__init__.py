"""Stimulus files (docs/stimulus.md): the events, forces, expectations and models of a run
(stimulus.py), the lines of the PLC's serial ports (serial_stim.py), times and frequencies
as files and options write them and the error their readers raise (quantities.py, E601).

Belongs here: reading what a run is asked to do. Imports the machine and hardware/ (a port's
line settings). Does not belong here: running it (run/), the device models a `model` line
names (mlctool/devices/).
"""
