"""Device (plant) models for `mlc sim` and the field devices `mlc device serve` plays.

Belongs here: the machines around the PLC that a stimulus adds (conveyor, a peer VS PLC, the
XC100 servo controller, a stepper motor on a pulse axis; `registry.MODELS` by their `model
KIND` name) and their I/O to the simulated PLC (`base.ModelIO`), and the one home of serial
and Modbus framing (`framing`). Does not belong here: PLC instructions (those are the
engine's or a target's, mlctool/sim/, mlctool/targets/).

The package imports nothing itself, so the engine can use `devices.framing` without loading
the models (which import the engine).
"""
