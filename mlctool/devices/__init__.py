"""Device (plant) models for `mlc sim`: a registry from the stimulus `model KIND` name."""

from __future__ import annotations

from mlctool.devices.base import DeviceModel, ModelIO, ParamError
from mlctool.devices.conveyor import Conveyor

MODELS: dict[str, type[DeviceModel]] = {m.kind: m for m in (Conveyor,)}

__all__ = ["MODELS", "DeviceModel", "ModelIO", "ParamError"]
