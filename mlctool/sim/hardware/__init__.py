"""The hardware around the scan, on virtual time and solved analytically: pulse trains on
inputs (pulses.py), a pulse axis's speed profile (motion.py), pulse pins traced inside a
window (pin_window.py), the RS-485 line between the PLC's ports and device models
(seriallink.py).

Belongs here: generic hardware a target's routines and the run drive (the VS positioning,
high-speed counters and MBUS build on it). Imports the machine only. Does not belong here:
a controller's instructions (mlctool/targets/), device models (mlctool/devices/), frame
encoding (mlctool/devices/framing.py), stimulus syntax (stimulus/).
"""
