"""The simulated PLC as an OPC UA server (asyncua; `mlc run --serve opc.tcp://127.0.0.1:4840`).

Nodes (DECISION: the devices the program names, its symbols' devices and the models'
signals, not the whole memory: an NC5's 65536 M and 65536 D would be 131072 nodes): one
variable per device under Objects/PLC, NodeId `ns=2;s=<device>` (`ns=2;s=D100`), BrowseName
the symbol when the program defines one (`MOTOR`), else the device; DisplayName the symbol,
else the NC5 signal's English name with the device (`M21000 cycle start`), else the device;
Description the device and its signal row (targetapi/signals.py).

Values are published after every scan (the scan thread hands the changes over; the server
loop writes them, and subscriptions see them at the scan rate). A client's write lands as a
Modbus write does, between two scans through the exchange (commission/exchange.py), on nodes
the permissions let it write (the others are read only: BadUserAccessDenied). No security
policy and anonymous access: as Modbus, for a bench (docs/commissioning.md, Security).
"""

from __future__ import annotations

import threading

from asyncua import Server, ua

from mlctool.commission.modbus_map import Permissions
from mlctool.commission.net import ServerStats
from mlctool.commission.realtime import LiveRun
from mlctool.sim.decode import program_devices
from mlctool.sim.state import DeviceView, NameError_, parse_device_name
from mlctool.targetapi.signals import device_signal

NAMESPACE = "urn:mlctool:plc"


def _variant_type(view: DeviceView) -> ua.VariantType:
    if view.view in ("bit",):
        return ua.VariantType.Boolean
    if view.view == "f":
        return ua.VariantType.Float
    if view.view == "d" or view.view == "group":
        return ua.VariantType.Int32
    if view.kind in ("T", "C") or view.view == "h":
        return ua.VariantType.UInt16  # raw present values (DeviceView.read)
    return ua.VariantType.Int16


class OpcUaServer:
    def __init__(self, endpoint, live: LiveRun, target, image, perms: Permissions):
        self.endpoint = endpoint
        self.live = live
        self.target = target
        self.perms = perms
        names = {v: k for k, v in image.symbols.items()}  # device text -> symbol
        views = set(program_devices(live.sim.prog)) | set(live.sim.views)
        for text in image.symbols.values():
            try:
                views.add(parse_device_name(text, target))
            except NameError_:
                pass  # a symbol for a constant or an operand that is no device
        self.nodes = sorted(views, key=DeviceView.sort_key)
        self.symbols = {v: names.get(v.name) for v in self.nodes}
        self.stats = ServerStats()  # requests: client writes; no connection figures (asyncua's)
        self._server: Server | None = None
        self._ids: dict[DeviceView, ua.NodeId] = {}
        self._types: dict[DeviceView, ua.VariantType] = {}
        self._by_id: dict[ua.NodeId, DeviceView] = {}
        self._last: list = [None] * len(self.nodes)
        self._changes: dict[DeviceView, object] = {}  # published by the scan thread, not yet written
        self._lock = threading.Lock()
        self._flushing = False
        self._ours: dict[ua.NodeId, ua.DataValue] = {}
        self._loop = None

    @property
    def bound_port(self) -> int:
        """The TCP port (the one the system chose for port 0)."""
        binary = self._server.bserver if self._server is not None else None
        if binary is None or binary._server is None:
            return self.endpoint.port
        return binary._server.sockets[0].getsockname()[1]

    async def start(self) -> None:
        import asyncio
        import logging

        logging.getLogger("asyncua").setLevel(logging.ERROR)  # its INFO lines are not ours to print
        self._loop = asyncio.get_running_loop()
        server = Server()
        await server.init()
        server.set_endpoint(f"opc.tcp://{self.endpoint.host}:{self.endpoint.port}/")
        server.set_server_name("mlctool simulated PLC")
        server.set_security_policy([ua.SecurityPolicyType.NoSecurity])
        idx = await server.register_namespace(NAMESPACE)
        plc = await server.nodes.objects.add_object(idx, "PLC")
        for i, view in enumerate(self.nodes):
            vtype = _variant_type(view)
            value = self._value(view, view.read(self.live.sim.m))
            self._last[i] = value
            symbol = self.symbols[view]
            node_id = ua.NodeId(view.name, idx)
            node = await plc.add_variable(node_id, ua.QualifiedName(symbol or view.name, idx),
                                          ua.Variant(value, vtype))
            found = device_signal(self.target, view.kind, view.number) if view.view in ("bit", "w", "d") else None
            display = symbol or (f"{view.name} {found.signal.english}" if found else view.name)
            await node.write_attribute(ua.AttributeIds.DisplayName,
                                       ua.DataValue(ua.Variant(ua.LocalizedText(display), ua.VariantType.LocalizedText)))
            description = found.describe() if found else (f"{view.name} ({symbol})" if symbol else view.name)
            await node.write_attribute(ua.AttributeIds.Description,
                                       ua.DataValue(ua.Variant(ua.LocalizedText(description), ua.VariantType.LocalizedText)))
            if self._writable(view):
                await node.set_writable()
                server.set_attribute_value_setter(node_id, self._setter)
            self._ids[view], self._types[view], self._by_id[node_id] = node_id, vtype, view
        await server.start()
        self._server = server
        self.live.after_scan.append(self._publish)

    async def stop(self) -> None:
        if self._publish in self.live.after_scan:
            self.live.after_scan.remove(self._publish)
        if self._server is not None:
            await self._server.stop()
            self._server = None

    def _writable(self, view: DeviceView) -> bool:
        if view.kind.startswith("@") or view.view == "group":
            return False
        return all(self.perms.writable(view.kind, view.number + i) for i in range(2 if view.view in ("d", "f") else 1))

    @staticmethod
    def _value(view: DeviceView, value):
        return bool(value) if view.view == "bit" else value

    # -- the scan thread: after every scan, the changed values
    def _publish(self, _scans: int) -> None:
        m = self.live.sim.m
        changed = []
        for i, view in enumerate(self.nodes):
            value = view.read(m)
            if value != self._last[i]:
                self._last[i] = value
                changed.append((view, value))
        if not changed:
            return
        with self._lock:
            self._changes.update(changed)  # a slow loop gets the latest values, not a backlog
            if self._flushing:
                return
            self._flushing = True
        self._loop.call_soon_threadsafe(lambda: self._loop.create_task(self._flush()))

    # -- the server loop
    async def _flush(self) -> None:
        with self._lock:
            changes, self._changes, self._flushing = self._changes, {}, False
        server = self._server
        if server is None:
            return
        for view, value in changes.items():
            node_id = self._ids[view]
            dv = ua.DataValue(ua.Variant(self._value(view, value), self._types[view]))
            self._ours[node_id] = dv
            await server.write_attribute_value(node_id, dv)

    def _setter(self, node, attr, value: ua.DataValue) -> None:
        """Every write of a writable node's value: ours (the scan's values) are stored; a
        client's is stored and becomes a job for the scan loop."""
        node.attributes[attr].value = value
        if self._ours.pop(node.nodeid, None) is value:
            return
        view = self._by_id[node.nodeid]
        written = value.Value.Value
        self.stats.requests += 1
        if not self.live.exchange.submit(self, lambda m: view.write(m, written), lambda _r, _e: None):
            self.stats.busy += 1
