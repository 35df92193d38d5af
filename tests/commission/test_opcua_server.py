"""The simulated PLC as an OPC UA server (mlctool/commission/opcua.py): an asyncua client
browses, reads a device by its symbol, gets data-change notifications and writes with the
permissions (issue 32)."""

from __future__ import annotations

import asyncio

from asyncua import Client, ua
from livekit import live_plc

from mlctool.commission.modbus_map import Permissions
from mlctool.targetapi import load_target
from tests.conftest import SAMPLES

# the conveyor sample, and an NC5 signal (M21000 cycle start, channel 1) to show by its name
CONVEYOR = (SAMPLES / "nc5" / "conveyor.il").read_text(encoding="utf-8").replace("END", "LD M21000\nOUT M5\n")


async def _client_session(port: int) -> dict:
    out = {}
    async with Client(f"opc.tcp://127.0.0.1:{port}/", timeout=5) as client:
        plc = await client.nodes.objects.get_child(["2:PLC"])
        out["names"] = {(await n.read_browse_name()).Name for n in await plc.get_children()}
        motor = await plc.get_child(["2:MOTOR"])  # Y0 by its symbol
        out["motor_id"] = motor.nodeid.Identifier
        out["motor_display"] = (await motor.read_display_name()).Text
        out["motor_before"] = await motor.read_value()
        signal = client.get_node("ns=2;s=M21000")
        out["signal_display"] = (await signal.read_display_name()).Text
        out["signal_description"] = (await signal.read_description()).Text
        seen = []

        class Handler:
            def datachange_notification(self, node, val, data):
                seen.append(val)

        sub = await client.create_subscription(10, Handler())
        await sub.subscribe_data_change(motor)
        running = await plc.get_child(["2:RUNNING"])  # M0
        await running.write_value(ua.DataValue(ua.Variant(True, ua.VariantType.Boolean)))
        for _ in range(200):
            if True in seen:
                break
            await asyncio.sleep(0.01)
        out["seen"] = list(seen)
        out["motor_after"] = await motor.read_value()
        start = await plc.get_child(["2:START"])  # X0: an input, read only by default
        try:
            await start.write_value(ua.DataValue(ua.Variant(True, ua.VariantType.Boolean)))
            out["x0_write"] = "accepted"
        except ua.UaStatusCodeError as e:
            out["x0_write"] = type(e).__name__
        out["x0_after"] = await start.read_value()
        await sub.delete()
    return out


def test_an_opcua_client_reads_by_symbol_subscribes_and_writes():
    nc5 = load_target("nc5")
    with live_plc(CONVEYOR, target_name="nc5", serve=("opc.tcp://127.0.0.1:0",), period_us=5000,
                  perms=Permissions(nc5)) as (live, servers):
        r = asyncio.run(asyncio.wait_for(_client_session(servers[0].bound_port), 30))
    assert {"MOTOR", "RUNNING", "START", "D0"} <= r["names"]
    assert r["motor_id"] == "Y0" and r["motor_display"] == "MOTOR"
    assert r["signal_display"] == "M21000 cycle start" and "MLC->NC" in r["signal_description"]
    assert r["motor_before"] is False and r["motor_after"] is True
    assert True in r["seen"]  # the data-change notification of Y0 turning on
    assert r["x0_write"] != "accepted" and r["x0_after"] is False
    assert servers[0].stats.requests == 1
