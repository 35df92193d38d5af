"""What the NC5 gives the simulator beyond its tables: its NC side as a device model
(`model nc5 ...`, nc/model.py; docs/nc5.md). The instructions need nothing of their own."""

from mlctool.targetapi.simulation import ModelKind, Simulation
from mlctool.targets.nc5.nc.published import SIGNALS

SIMULATION = Simulation(models=(ModelKind("nc5", "mlctool.targets.nc5.nc.model:NcModel", SIGNALS),))
