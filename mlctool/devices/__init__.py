"""Device (plant) models for `mlc sim`: a registry from the stimulus `model KIND` name."""

from __future__ import annotations

from mlctool.devices.base import DeviceModel, ModelIO, ParamError
from mlctool.devices.conveyor import Conveyor
from mlctool.devices.vsplc import VsPlc
from mlctool.devices.xc100.simmodel import XC100Model

MODELS: dict[str, type[DeviceModel]] = {m.kind: m for m in (Conveyor, XC100Model, VsPlc)}

__all__ = ["MODELS", "DeviceModel", "ModelIO", "ParamError"]
