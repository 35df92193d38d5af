"""Device (plant) models for `mlc sim`: a registry from the stimulus `model KIND` name.

Belongs here: the machines around the PLC that a stimulus adds (conveyor, a peer VS PLC, the
XC100 servo controller, a stepper motor on a pulse axis) and their I/O to the simulated PLC. Does not belong here: PLC
instructions (those are the engine's or a target's, mlctool/sim/, mlctool/targets/).
"""

from __future__ import annotations

from mlctool.devices.base import DeviceModel, ModelIO, ParamError
from mlctool.devices.conveyor import Conveyor
from mlctool.devices.stepper import Stepper
from mlctool.devices.vsplc import VsPlc
from mlctool.devices.xc100.simmodel import XC100Model

MODELS: dict[str, type[DeviceModel]] = {m.kind: m for m in (Conveyor, XC100Model, VsPlc, Stepper)}

__all__ = ["MODELS", "DeviceModel", "ModelIO", "ParamError"]
