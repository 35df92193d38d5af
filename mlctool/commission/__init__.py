"""Virtual commissioning: `mlc run`, the simulated PLC in real time, reachable by HMIs, SCADA
and OPC UA clients (docs/commissioning.md).

Belongs here: pacing scans to the wall clock (realtime.py), the one door from the servers to
the machine (exchange.py), the Modbus slave's maps, permissions and requests (modbus_map.py,
maps.toml, modbus_slave.py), the servers and their network thread (net.py), OPC UA
(opcua.py). Does not belong here: Modbus framing (devices/framing.py), what a scan does
(sim/).
"""
