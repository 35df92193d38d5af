"""A simulated PLC running in real time on a thread, with its servers: for the tests of
mlctool/commission/ (the CLI: tests/cli/test_cli_run.py)."""

from __future__ import annotations

import contextlib
import threading

import simkit
from mlctool.commission.exchange import Exchange
from mlctool.commission.modbus_map import Permissions, load_map
from mlctool.commission.net import ModbusServer, NetThread, Slave, parse_endpoint
from mlctool.commission.realtime import LiveRun
from mlctool.sim.run.run import Simulation
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targetapi import load_target


@contextlib.contextmanager
def live_plc(il: str, target_name: str = "vs", period_us: int = 2000, stim: str = "",
             serve: tuple[str, ...] = ("modbus-tcp://127.0.0.1:0",), map_name: str = "vs",
             perms: Permissions | None = None, station: int = 1, max_clients: int = 256,
             exchange: Exchange | None = None, keep_jitters: bool = False, image=None):
    """Yield (live, servers): scans run on a thread until the block ends."""
    target = load_target(target_name)
    if image is None:
        image = simkit.image_of(il + "\nEND", target=target)
    st, diags = parse_stimulus_text("t.stim", stim, target)
    assert not diags
    sim = Simulation(image, target, st, [], period_us, [], False)
    live = LiveRun(sim, exchange=exchange, keep_jitters=keep_jitters)
    perms = perms or Permissions(target)
    servers = []
    for url in serve:
        ep = parse_endpoint(url, None)
        if ep.framing is None:
            from mlctool.commission.opcua import OpcUaServer

            servers.append(OpcUaServer(ep, live, target, image, perms))
        else:
            servers.append(ModbusServer(ep, Slave(load_map(map_name, target), perms, station), live.exchange,
                                        max_clients))
    net = NetThread()
    net.start(servers)
    thread = threading.Thread(target=live.run, args=(None,), daemon=True)
    thread.start()
    try:
        yield live, servers
    finally:
        live.stop.set()
        live.exchange.wake()
        thread.join(10)
        net.stop()


def on_scan_thread(live: LiveRun, job):
    """job(machine) run by the scan loop between scans; its result."""
    done = threading.Event()
    box = {}

    def finish(result, error):
        box["r"], box["e"] = result, error
        done.set()

    assert live.exchange.submit("test", job, finish)
    assert done.wait(5)
    if box["e"] is not None:
        raise box["e"]
    return box["r"]

