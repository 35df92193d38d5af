"""A hostile crowd cannot stall the scan loop (issue 32, docs/commissioning.md "Security"):
`mlc run` in its own process, 200 clients at once (100 pollers reading 100 registers, 40
sending junk, 40 slow ones that never finish a frame, 20 connecting and closing in a loop);
the scans keep their period within the documented bound and an HMI is still answered. The
full-size figures: bench/commission_speed.py."""

from __future__ import annotations

import asyncio
import json
import socket
import struct
import sys
import time

from livekit import live_plc

from mlctool.commission import net
from tests.conftest import ROOT, SAMPLES

sys.path.insert(0, str(ROOT / "bench"))
import commission_speed as load  # noqa: E402

JITTER_BOUND_MS = 250  # docs/commissioning.md, Security: the bound under a flood on 2 shared cores


def test_a_200_client_flood_does_not_stall_the_scans():
    proc, port = load.start_plc(str(SAMPLES / "nc5" / "conveyor.il"), 3, "modbus-tcp://127.0.0.1:0")
    replies, cut = asyncio.run(load.load(port, 3, pollers=100, flood=True))
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 0, err
    figures = json.loads(out)
    stats, server = figures["stats"], figures["servers"][0]
    assert stats["scans"] == 300
    assert stats["jitter_worst_ms"] < JITTER_BOUND_MS, stats
    assert stats["wall_s"] < 3 + JITTER_BOUND_MS / 1000
    assert replies > 100 and cut == 0  # the pollers were answered all along
    assert server["dropped"] > 0  # the junk's connections were closed


def test_a_slow_client_is_let_go_and_the_others_served(monkeypatch):
    monkeypatch.setattr(net, "FRAME_TIMEOUT_S", 0.3)
    with live_plc("LD M0\nOUT Y0") as (live, servers):
        port = servers[0].bound_port
        with socket.create_connection(("127.0.0.1", port), timeout=3) as slow:
            slow.sendall(b"\x00\x01\x00")  # a frame begun, never finished
            with socket.create_connection(("127.0.0.1", port), timeout=3) as hmi:
                hmi.sendall(struct.pack(">HHHBBHH", 7, 0, 6, 1, 3, 0, 2))
                assert hmi.recv(64)[:9] == struct.pack(">HHHBBB", 7, 0, 7, 1, 3, 4)
            started = time.monotonic()
            assert slow.recv(10) == b"" and time.monotonic() - started < 2  # closed by the server
        assert servers[0].stats.dropped == 1
