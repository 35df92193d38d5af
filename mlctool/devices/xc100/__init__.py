"""TOYO XC100 servo electric-cylinder controller (manual 004): the device model, its Modbus
register map and server, and the `mlc sim` adapter. See docs/xc100.md.

Belongs here: the controller as a device (axis, registers, alarms, `mlc device serve`).
Does not belong here: the PLC side of its Modbus link (VS MBUS: mlctool/targets/vs/serial/).
"""
