"""TOYO XC100 servo electric-cylinder controller (manual 004): the device model, its Modbus
register map and server, and the `mlc sim` adapter. See docs/xc100.md."""
