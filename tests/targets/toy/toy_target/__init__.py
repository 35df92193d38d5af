"""A toy controller, packaged as a third-party target would be (docs/architecture.md "A new
target"): its tables in tables/, one instruction of its own (TWICE) in simulation.py.
tests/targets/test_toy_target.py installs it through an entry point and runs mlc on it."""

from pathlib import Path

from mlctool.targetapi import TargetPackage

TARGET = TargetPackage("toy", Path(__file__).parent / "tables", "toy_target.simulation:SIMULATION")
