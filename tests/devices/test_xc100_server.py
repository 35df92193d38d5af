"""The XC100 as a real Modbus server: pymodbus client over TCP loopback, raw frames over a
pseudo-terminal pair, a burst of junk before a valid request, `mlc device serve` with
Ctrl-C, the co-simulation sample. Everything local and bounded in time."""

from __future__ import annotations

import asyncio
import io
import os
import select
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pymodbus.client import AsyncModbusTcpClient
from pymodbus.framer import FramerType

from conftest import MLC_COMMAND
from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.server import make_server, run_device

ROOT = Path(__file__).resolve().parents[2]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


async def _with_server(dev, framing, client_fn, **link):
    devices = dev if isinstance(dev, dict) else {1: dev}
    server = make_server(devices, framing, **link)
    stop = asyncio.Event()
    task = asyncio.create_task(run_device(server, 8.0, stop=stop))
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
    (["--tcp", ""], "E801"),  # was "cannot open serial None" (issue 30.18)
    (["--serial", ""], "E801"),
])
def test_serve_bad_options_are_diagnostics(mlc, args, code):
    r = mlc("device", "serve", "xc100", *args)
    assert r.code == 2 and code in r.err and "Traceback" not in r.err
    assert "None" not in r.err


def test_cosimulation_sample_passes(mlc, tmp_path):
    vcd = tmp_path / "xc100.vcd"
    r = mlc("sim", "samples/nc5/xc100_points.il", "--stimulus", "samples/nc5/xc100_points.stim",
            "--vcd", str(vcd), cwd=ROOT)
    assert r.code == 0, r.err
    assert "10 passed, 0 failed" in r.out
    text = vcd.read_text()
    assert "XC1.pos" in text  # the cylinder position (0.01 mm) is a waveform, the model's own
    assert f"b{12950:b} " in text  # 12950 = 129.50 mm, the end of P3


def test_model_parameters_are_checked(mlc, tmp_path):
    (tmp_path / "p.il").write_text("LD X0\nOUT Y0\nEND\n")
    for bad, word in (("p1=FLY:10", "unknown move mode"), ("r0703=11", "0..10"),
                      ("r0123=1", "no XC100 parameter"), ("in1=X0", "in1"),
                      ("stroke=-1", "stroke"), ("mirror=M0", "mirror"), ("speed=1", "speed"),
                      # 8.1: "資料長度 | 7、8 BIT | 8 BIT" (RTU: 8 data bits), "停止位元 | 1 BIT"
                      ("r0A01=1 r0A04=1", "8 data bits only in RTU mode"),
                      ("stop=2", "1 stop bit"), ("stopbits=1", "no stop-bit setting")):
        (tmp_path / "s.stim").write_text(f"model xc100 in1=Y0 out1=X1 {bad}\nrun 10ms\n")
        r = mlc("sim", "p.il", "--stimulus", "s.stim", cwd=tmp_path)
        assert r.code == 2 and ("E601" in r.err or "E602" in r.err) and word in r.err, (bad, r.err)


def _rtu(hexframe: str) -> bytes:
    from mlctool.devices.framing import crc16

    adu = bytes.fromhex(hexframe)
    return adu + crc16(adu).to_bytes(2, "little")


def _ascii(hexframe: str) -> bytes:
    adu = bytes.fromhex(hexframe)
    return b":" + (adu + bytes([-sum(adu) & 0xFF])).hex().upper().encode() + b"\r\n"


def _mbap(tid: int, hexframe: str) -> bytes:
    adu = bytes.fromhex(hexframe)
    return tid.to_bytes(2, "big") + b"\0\0" + len(adu).to_bytes(2, "big") + adu


def _exchange(port: int, payload: bytes, want: int, wait_s: float = 3.0) -> bytes:
    """Send `payload` in one sendall (one TCP segment on loopback) and read `want` bytes."""
    with socket.create_connection(("127.0.0.1", port), timeout=wait_s) as s:
        s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        s.sendall(payload)
        got, deadline = b"", time.monotonic() + wait_s
        while len(got) < want and time.monotonic() < deadline:
            chunk = s.recv(4096)
            if not chunk:
                break
            got += chunk
        return got


# read 1000H (ActionStatus), write 2014H (speed %) = 100 with FC06, read 2014H back (8.4)
PIPELINE = ("01 03 10 00 00 01", "01 06 20 14 00 64", "01 03 20 14 00 01")
PIPELINE_REPLIES = ("01 03 02 00 00", "01 06 20 14 00 64", "01 03 02 00 64")


def test_modbus_tcp_unit_ff_addresses_a_single_device():
    """Modbus TCP implementation guide: a server addressed by IP takes unit id 0xFF; with one
    station served it is that station (the reply keeps 0xFF); with two it is no device (0BH)."""
    for devices, want in (({3: c.new_xc100()}, "FF 03 02 00 00"),
                          ({1: c.new_xc100(), 2: c.new_xc100()}, "FF 83 0B")):
        port = free_port()
        frame = _mbap(5, "FF 03 10 00 00 01")

        async def client(frame=frame, want=want, port=port):
            loop = asyncio.get_running_loop()
            return await loop.run_in_executor(None, _exchange, port, frame, len(_mbap(5, want)))

        got = asyncio.run(_with_server(devices, "tcp", client, tcp=("127.0.0.1", port)))
        assert got == _mbap(5, want)


@pytest.mark.parametrize("framing", ["rtu", "ascii", "tcp"])
def test_every_frame_of_one_segment_is_answered_in_order(framing):
    """Issue 21 #2: three requests in one TCP segment, a write among them, get three replies
    in order and the write takes effect (before: only the first was answered)."""
    dev = c.new_xc100()
    port = free_port()
    if framing == "rtu":
        payload = b"".join(_rtu(f) for f in PIPELINE)
        want = b"".join(_rtu(f) for f in PIPELINE_REPLIES)
    elif framing == "ascii":
        payload = b"".join(_ascii(f) for f in PIPELINE)
        want = b"".join(_ascii(f) for f in PIPELINE_REPLIES)
    else:
        payload = b"".join(_mbap(k + 7, f) for k, f in enumerate(PIPELINE))
        want = b"".join(_mbap(k + 7, f) for k, f in enumerate(PIPELINE_REPLIES))

    async def client():
        loop = asyncio.get_running_loop()
        return await loop.run_in_executor(None, _exchange, port, payload, len(want))

    got = asyncio.run(_with_server(dev, framing, client, tcp=("127.0.0.1", port)))
    assert got == want


def test_modbus_tcp_pymodbus_client_two_stations():
    """Issue 20: Modbus TCP (MBAP, unit id = station) with two XC100s on one line, each its
    own model; a unit with no device gets exception 0BH (gateway: no response)."""
    from pymodbus.client import ModbusTcpClient

    devices = {1: c.new_xc100(), 2: c.new_xc100()}
    port = free_port()

    def talk():
        cl = ModbusTcpClient("127.0.0.1", port=port, timeout=2, retries=1)
        assert cl.connect()
        try:
            w1 = cl.write_register(0x2014, 40, device_id=1)
            w2 = cl.write_registers(0x2002, [0, 12345], device_id=2)  # ABSamount, 32-bit (8.4)
            r1 = cl.read_holding_registers(0x2014, count=1, device_id=1)
            r2 = cl.read_holding_registers(0x2014, count=1, device_id=2)
            a2 = cl.read_holding_registers(0x2002, count=2, device_id=2)
            none = cl.read_holding_registers(0x1000, count=1, device_id=9)
            fc4 = cl.read_input_registers(0x1000, count=1, device_id=1)
            return (w1.isError(), w2.isError(), r1.registers, r2.registers, a2.registers,
                    none.exception_code, fc4.exception_code)
        finally:
            cl.close()

    async def client():
        return await asyncio.get_running_loop().run_in_executor(None, talk)

    got = asyncio.run(_with_server(devices, "tcp", client, tcp=("127.0.0.1", port)))
    w1, w2, r1, r2, a2, none, fc4 = got
    assert not w1 and not w2
    assert r1 == [40] and r2 != [40]  # station 2 is a model of its own
    assert a2 == [0, 12345]
    assert none == 0x0B and fc4 == 1  # 8.3 (1): FC04 is not a function of the XC100


def test_serve_cli_stays_quiet_when_a_pipelining_client_leaves():
    """Issue 21 #17: a client that pipelines many requests and disconnects made pymodbus log
    ~10 MB of hex dumps; the server's stderr stays its own few lines."""
    port = free_port()
    p = subprocess.Popen([*MLC_COMMAND, "device", "serve", "xc100", "--tcp", f"127.0.0.1:{port}",
                          "--rtu", "--duration", "20s"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        assert "serving" in p.stderr.readline()
        burst = b"".join(_rtu(PIPELINE[0]) for _ in range(2000)) + b"\x01\x03\x10" * 3000
        for _ in range(5):
            with socket.create_connection(("127.0.0.1", port), timeout=2) as s:
                s.sendall(burst)
                s.shutdown(socket.SHUT_RDWR)
        with socket.create_connection(("127.0.0.1", port), timeout=2) as s:
            s.sendall(_rtu(PIPELINE[0]))
            assert s.recv(16) == _rtu(PIPELINE_REPLIES[0])  # still answering
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=5)
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 0
    assert len(err) < 500 and "Traceback" not in err and "recv" not in err, err[:2000]


@pytest.mark.parametrize("option,value", [("--lead", "nan"), ("--lead", "inf"),
                                          ("--lead", "-5"), ("--stroke", "nan"),
                                          ("--stroke", "-inf"), ("--lead", "NaN")])
def test_serve_refuses_non_finite_model_sizes(mlc, option, value):
    """Issue 21 #17: --lead nan was accepted (every comparison with nan is false)."""
    r = mlc("device", "serve", "xc100", "--tcp", "127.0.0.1:5020", "--duration", "1s",
            option, value)
    assert r.code == 2 and "Traceback" not in r.err and option in r.err, r.err


@pytest.mark.parametrize("args", [
    ["--tcp", "127.0.0.1:5020", "--framing", "tcp", "--rtu"],
    ["--serial", "/dev/null", "--framing", "tcp"],
    ["--tcp", "127.0.0.1:5020", "--station", "2", "--station", "2"],
])
def test_serve_framing_and_station_conflicts(mlc, args):
    r = mlc("device", "serve", "xc100", *args)
    assert r.code == 2 and "E801" in r.err and "Traceback" not in r.err, r.err


_REQUESTS = st.sampled_from(list(PIPELINE) + ["01 10 20 02 00 02 04 00 00 30 39",
                                              "02 03 90 10 00 10", "00 06 20 14 00 05",
                                              "01 2B 0E 01 00", "01 41 01 02 03"])


@settings(max_examples=150, deadline=None, derandomize=True)
@given(frames=st.lists(_REQUESTS, min_size=1, max_size=8), cuts=st.lists(st.integers(0, 400)),
       framing=st.sampled_from(["rtu", "ascii", "tcp"]))
def test_stream_receivers_find_every_frame_however_the_stream_is_cut(frames, cuts, framing):
    """A Modbus stream fuzz target (issue 21): valid frames, cut anywhere into reads, come out
    whole and in order; nothing is lost, nothing is invented."""
    from mlctool.devices.framing import RECEIVERS

    encode = {"rtu": _rtu, "ascii": _ascii, "tcp": lambda f: _mbap(3, f)}[framing]
    stream = b"".join(encode(f) for f in frames)
    receiver = RECEIVERS[framing]()
    got, at = [], 0
    for cut in sorted(set(k % (len(stream) + 1) for k in cuts)) + [len(stream)]:
        got += receiver.feed(stream[at:cut], 0.0)
        at = max(at, cut)
    assert [bytes([g.unit]) + g.pdu for g in got] == [bytes.fromhex(f) for f in frames]


@settings(max_examples=150, deadline=None, derandomize=True)
@given(junk=st.binary(max_size=600), framing=st.sampled_from(["rtu", "ascii", "tcp"]))
def test_junk_then_silence_then_a_valid_frame(junk, framing):
    """Any junk, then the line's resynchronisation point (RTU: a silence; ASCII: a new ':'
    line; Modbus TCP: a new connection after a broken header), then a request: it is read."""
    from mlctool.devices.framing import RECEIVERS

    receiver = RECEIVERS[framing]()
    receiver.feed(junk, 0.0)
    if framing == "tcp" and (receiver.broken or receiver.buf):
        receiver = RECEIVERS[framing]()  # the connection was closed / the client reconnects
    frame = {"rtu": _rtu, "ascii": lambda f: b"\r\n" + _ascii(f), "tcp": lambda f: _mbap(3, f)}[framing]
    got = receiver.feed(frame(PIPELINE[1]), 1.0)
    assert [bytes([g.unit]) + g.pdu for g in got][-1:] == [bytes.fromhex(PIPELINE[1])]


def test_status_view_shows_the_line_and_a_refused_setting():
    """The model's status says why a setting was refused (issue 20: 8.1 line settings)."""
    from rich.console import Console

    from mlctool.devices.xc100.modbus import handle_pdu
    from mlctool.devices.xc100.status import render

    dev = c.new_xc100()
    dev.unlocked = True
    assert handle_pdu(dev, 1, 1, bytes.fromhex("06 0A 04 00 01"))  # RTU: accepted, after reboot
    assert handle_pdu(dev, 1, 1, bytes.fromhex("06 0A 01 00 01")) == bytes.fromhex("86 03")
    console = Console(width=200, record=True, file=io.StringIO())
    console.print(render({1: dev, 2: c.new_xc100()}, "XC100 test"))
    text = console.export_text()
    assert "19200 8-N-1 ASCII" in text and "acts after the next power-up" in text
    assert "refused" in text and "8 data bits only in RTU mode" in text
    assert "station 2" in text


def test_status_view_never_shows_minus_zero():
    """A position a hair below zero is 0.00 mm, not -0.00 mm (issue 30.18)."""
    from rich.console import Console

    from mlctool.devices.xc100.status import render

    dev = c.new_xc100()
    dev.act = -0.4  # pulses
    dev.vel = -0.3
    console = Console(width=200, record=True, file=io.StringIO())
    console.print(render({1: dev}, "XC100 test"))
    text = console.export_text()
    assert "-0.00" not in text and "0.00 mm  (" in text and "0.00 mm/s" in text
