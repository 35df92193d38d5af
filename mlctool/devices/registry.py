"""The device (plant) models of `mlc sim` by their stimulus `model KIND` name.
A model is added here with its class (devices/base.py DeviceModel) and documented in
docs/stimulus.md "Device models".
"""

from __future__ import annotations

from mlctool.devices.base import DeviceModel
from mlctool.devices.conveyor import Conveyor
from mlctool.devices.stepper import Stepper
from mlctool.devices.vsplc import VsPlc
from mlctool.devices.xc100.simmodel import XC100Model

MODELS: dict[str, type[DeviceModel]] = {m.kind: m for m in (Conveyor, XC100Model, VsPlc, Stepper)}
