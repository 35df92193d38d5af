"""VS serial instructions (manual 6-10, 6-13): MBUS (Modbus master), RS (non-protocol), LINK
and CPUL with peer stations (peers.py: their memory, named CP1#2.D10).

Belongs here: the instructions' routines and their port state. Does not belong here: the
line itself (bytes on a virtual clock) and the Modbus frames, which the XC100 model and `mlc
device serve` share: mlctool/sim/hardware/seriallink.py.
"""
