"""VS serial instructions (manual 6-10, 6-13): MBUS (Modbus master), RS (non-protocol), LINK
and CPUL with peer stations (peers.py: their memory, named CP1#2.D10). The line itself (bytes
on a virtual clock) and the Modbus frames are the engine's: mlctool/sim/seriallink.py."""
