"""Targets: each a folder of data files taken from its manual (see model.py)."""

from mlctool.targets.model import Target, available_targets, load_target

__all__ = ["Target", "available_targets", "load_target"]
