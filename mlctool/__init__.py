"""mlctool: check, build and simulate PLC instruction-list programs."""

__version__ = "0.1.0"
