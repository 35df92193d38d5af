"""The XC100 as a real Modbus server: pymodbus client over TCP loopback, raw frames over a
pseudo-terminal pair, a burst of junk before a valid request, `mlc device serve` with
Ctrl-C, the co-simulation sample. Everything local and bounded in time."""

from __future__ import annotations

import asyncio
import os
import select
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
from pymodbus.client import AsyncModbusTcpClient
from pymodbus.framer import FramerType

from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.server import make_server, run_device

ROOT = Path(__file__).resolve().parents[1]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


async def _with_server(dev, framing, client_fn, **link):
    server = make_server(dev, 1, framing, **link)
    stop = asyncio.Event()
    task = asyncio.create_task(run_device(dev, server, 8.0, stop=stop))
    await asyncio.sleep(0.2)
    try:
        return await asyncio.wait_for(client_fn(), 6.0)
    finally:
        stop.set()
        await asyncio.wait_for(task, 3.0)


@pytest.mark.parametrize("framing", ["rtu", "ascii"])
def test_pymodbus_client_over_tcp_homes_and_moves(framing):
    dev = c.new_xc100(params={0x0802: 400000})  # fast, to keep the test short
    port = free_port()

    async def client():
        kind = FramerType.RTU if framing == "rtu" else FramerType.ASCII
        cl = AsyncModbusTcpClient("127.0.0.1", port=port, framer=kind, timeout=1, retries=2)
        await cl.connect()
        try:
            assert (await cl.write_register(0x2014, 100, device_id=1)).registers == [100]
            await cl.write_register(0x201E, 3, device_id=1)  # 8.4 example: homing
            for _ in range(100):
                await asyncio.sleep(0.05)
                if dev.homed and dev.motion is None:
                    break
            r = await cl.write_registers(0x2002, [0, 20000], device_id=1)  # ABSamount
            assert not r.isError()
            await cl.write_register(0x201E, 1, device_id=1)
            for _ in range(100):
                await asyncio.sleep(0.05)
                if (await cl.read_holding_registers(0x1000, count=1, device_id=1)).registers == [0]:
                    break
            pos = await cl.read_holding_registers(0x1008, count=2, device_id=1)
            bad = await cl.read_holding_registers(0x1002, count=1, device_id=1)
            fc4 = await cl.read_input_registers(0x1000, count=1, device_id=1)
            return pos.registers, bad.exception_code, fc4.exception_code
        finally:
            cl.close()

    regs, bad, fc4 = asyncio.run(_with_server(dev, framing, client, tcp=("127.0.0.1", port)))
    assert regs == [0, 20000] and bad == 2 and fc4 == 1


def test_junk_burst_then_a_valid_request_is_answered():
    dev = c.new_xc100()
    port = free_port()

    async def client():
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        junk = bytes((k * 37 + 11) % 256 for k in range(3000))
        writer.write(junk)
        writer.write(bytes.fromhex("01 10 20 00 00 7F FE 00 00"))  # impossible FC10, no CRC
        writer.write(bytes.fromhex("05 03 10 00 00 01 80 CA"))  # other station / bad CRC
        await writer.drain()
        await asyncio.sleep(0.1)  # the line goes quiet: the receiver drops the leftovers
        writer.write(bytes.fromhex("01 03 10 00 00 01 80 CA"))  # 8.4 read example
        await writer.drain()
        data = await asyncio.wait_for(reader.readexactly(7), 2.0)
        writer.close()
        return data

    data = asyncio.run(_with_server(dev, "rtu", client, tcp=("127.0.0.1", port)))
    assert data == bytes.fromhex("01 03 02 00 00 B8 44")


def test_ascii_over_a_pseudo_terminal_pair():
    pytest.importorskip("serial")
    master, slave = os.openpty()
    path = os.ttyname(slave)
    dev = c.new_xc100()

    async def client():
        loop = asyncio.get_running_loop()

        def exchange(frame: bytes, wait_s: float = 2.0) -> bytes:
            os.write(master, frame)
            got, deadline = b"", time.monotonic() + wait_s
            while not got.endswith(b"\r\n") and time.monotonic() < deadline:
                if select.select([master], [], [], 0.1)[0]:
                    got += os.read(master, 256)
            return got

        junk = exchange(b":zz\r\n#~~:0103\r\n", 0.3)
        read = await loop.run_in_executor(None, exchange, b":010310000001EB\r\n")
        fc4 = await loop.run_in_executor(None, exchange, b":0104201E0003BA\r\n")
        return junk, read, fc4

    try:
        junk, read, fc4 = asyncio.run(_with_server(dev, "ascii", client, serial=path))
    finally:
        os.close(master)
        os.close(slave)
    assert junk == b""
    assert read == b":0103020000FA\r\n"
    assert fc4 == b":0184017A\r\n"  # 8.3 (1), as printed


def test_serve_cli_stops_cleanly_on_ctrl_c():
    port = free_port()
    p = subprocess.Popen([sys.executable, "-c", "from mlctool.cli import main; main()", "device", "serve", "xc100", "--tcp",
                          f"127.0.0.1:{port}", "--rtu", "--duration", "20s"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        line = p.stderr.readline()
        assert "serving XC100 station 1, RTU, tcp 127.0.0.1" in line
        with socket.create_connection(("127.0.0.1", port), timeout=2) as s:
            s.sendall(bytes.fromhex("01 03 10 00 00 01 80 CA"))
            assert s.recv(16) == bytes.fromhex("01 03 02 00 00 B8 44")
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=5)
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 0 and "stopped" in err and "Traceback" not in err


@pytest.mark.parametrize("args,code", [
    (["--tcp", "10.0.0.1:502"], "E801"),
    (["--tcp", "127.0.0.1"], "E801"),
    ([], "E801"),
    (["--tcp", "127.0.0.1:5020", "--serial", "/dev/null"], "E801"),
    (["--tcp", "127.0.0.1:5020", "--duration", "soon"], "E801"),
    (["--serial", "/nonexistent/tty", "--duration", "2s"], "E802"),
])
def test_serve_bad_options_are_diagnostics(mlc, args, code):
    r = mlc("device", "serve", "xc100", *args)
    assert r.code == 2 and code in r.err and "Traceback" not in r.err


def test_cosimulation_sample_passes(mlc, tmp_path):
    vcd = tmp_path / "xc100.vcd"
    r = mlc("sim", "samples/nc5/xc100_points.il", "--stimulus", "samples/nc5/xc100_points.stim",
            "--vcd", str(vcd), cwd=ROOT)
    assert r.code == 0, r.err
    assert "9 passed, 0 failed" in r.out
    text = vcd.read_text()
    assert "D200_d" in text  # the cylinder position (0.01 mm) is a waveform
    assert f"b{12950:b} " in text  # 12950 = 129.50 mm, the end of P3


def test_model_parameters_are_checked(mlc, tmp_path):
    (tmp_path / "p.il").write_text("LD X0\nOUT Y0\nEND\n")
    for bad, word in (("p1=FLY:10", "unknown move mode"), ("r0703=11", "0..10"),
                      ("r0123=1", "no XC100 parameter"), ("in1=X0", "in1"),
                      ("stroke=-1", "stroke"), ("mirror=M0", "mirror"), ("speed=1", "speed")):
        (tmp_path / "s.stim").write_text(f"model xc100 in1=Y0 out1=X1 {bad}\nrun 10ms\n")
        r = mlc("sim", "p.il", "--stimulus", "s.stim", cwd=tmp_path)
        assert r.code == 2 and ("E601" in r.err or "E602" in r.err) and word in r.err, (bad, r.err)
