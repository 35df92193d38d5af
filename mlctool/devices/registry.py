"""The device (plant) models of `mlc sim` by their stimulus `model KIND` name.
A model is added here with its class (devices/base.py DeviceModel) and documented in
docs/stimulus.md "Device models". A target adds its own (targetapi ModelKind: the NC5's
virtual NC) through its Simulation: models_of(target) has both.
"""

from __future__ import annotations

import importlib

from mlctool.devices.base import DeviceModel
from mlctool.devices.conveyor import Conveyor
from mlctool.devices.stepper import Stepper
from mlctool.devices.vsplc import VsPlc
from mlctool.devices.xc100.simmodel import XC100Model

MODELS: dict[str, type[DeviceModel]] = {m.kind: m for m in (Conveyor, XC100Model, VsPlc, Stepper)}


def models_of(target) -> dict[str, type[DeviceModel]]:
    """The models a stimulus of `target` may name: the generic ones and the target's own."""
    from mlctool.sim.state import add_target_models
    from mlctool.targetapi.registry import simulation_of

    own = simulation_of(target).models
    if not own:
        return MODELS
    add_target_models(target)  # their signal names, also when no name was read yet
    found = dict(MODELS)
    for kind in own:
        module, _, attr = kind.model.partition(":")
        found[kind.kind] = getattr(importlib.import_module(module), attr)
    return found
