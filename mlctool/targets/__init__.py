"""The built-in targets, one package per controller (nc5, vs, fbs), each registered in
pyproject.toml's `mlctool.targets` entry points as a third-party target would be.

Belongs here: one folder per controller holding everything about it (docs/architecture.md).
Does not belong here: code several targets share (that is the engine, mlctool/sim/, or the
interface, mlctool/targetapi/); generic code never imports these packages.
"""

# the interface's loaders, for code written when they lived here (new code: mlctool.targetapi)
from mlctool.targetapi import Target, available_targets, load_target  # noqa: E402

__all__ = ["Target", "available_targets", "load_target"]
