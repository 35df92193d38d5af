"""The simulated PLC as a Modbus slave (mlctool/commission/): pymodbus's client reads and
writes every area of every map over Modbus TCP and RTU frames while scans run; the
protocol's exceptions; write permissions; writes land between scans."""

from __future__ import annotations

import socket
import struct
import time

import pytest
from livekit import live_plc, on_scan_thread
from pymodbus.client import ModbusTcpClient
from pymodbus.framer import FramerType

from mlctool.commission.modbus_map import Permissions, load_map
from mlctool.commission.modbus_slave import Request, parse
from mlctool.sim.state import Machine
from mlctool.targetapi import load_target

VS = load_target("vs")
PROGRAM = """
LD M10
OUT Y10
LDI M1
MOV D10 D11
"""


def client(servers, framing="tcp"):
    c = ModbusTcpClient("127.0.0.1", port=servers[0].bound_port, timeout=3,
                        framer=FramerType.RTU if framing == "rtu" else FramerType.SOCKET)
    assert c.connect()
    return c


def machine_value(live, device, number, half=0, bit=False):
    def read(m):
        if bit:
            return m.bits[device][number]
        if device == "C" and m.is_c32(number):
            return (m.cval[number] & 0xFFFFFFFF) >> (16 * half) & 0xFFFF
        if device == "C":
            return m.cval[number] & 0xFFFF
        if device in m.words:
            return m.words[device][number]
        return m.bits[device][number]
    return on_scan_thread(live, read)


def ends(entry):
    """The first and last device of a map entry, with the address of each."""
    last_addr = entry.last - (entry.words - 1)
    return [(entry.first, entry.lo), (last_addr, entry.hi)]


@pytest.mark.parametrize("map_name,framing", [("vs", "tcp"), ("vs", "rtu"), ("fx", "tcp"), ("fx", "rtu"),
                                              ("dvp", "tcp")])
def test_every_area_of_the_map_reads_and_writes_while_scans_run(map_name, framing):
    mapping = load_map(map_name, VS)
    perms = Permissions(VS)
    url = "modbus-tcp://127.0.0.1:0" if framing == "tcp" else "rtu+tcp://127.0.0.1:0"
    with live_plc(PROGRAM, serve=(url,), map_name=map_name) as (live, servers):
        c = client(servers, framing)
        for entry in mapping.tables["coils"]:
            for addr, n in ends(entry):
                if perms.writable(entry.device, n):
                    assert not c.write_coil(addr, True, device_id=1).isError(), (entry, addr)
                    assert machine_value(live, entry.device, n, bit=True) == 1, (entry, n)
                else:  # inputs X, numbers the VS has not (M8192-): the machine's, read only
                    assert c.write_coil(addr, True, device_id=1).isError(), (entry, addr)
                    on_scan_thread(live, lambda m, d=entry.device, n=n: m.bits[d].__setitem__(n, 1))
                assert c.read_coils(addr, count=1, device_id=1).bits[0] is True, (entry, addr)
                assert c.read_discrete_inputs(addr, count=1, device_id=1).bits[0] is True, (entry, addr)
        for entry in mapping.tables["holding"]:
            for addr, n in ends(entry):
                words = [0x1234 + n, 0x8765][:entry.words]
                assert not c.write_registers(addr, words, device_id=1).isError(), (entry, addr)
                for half, w in enumerate(words):
                    assert machine_value(live, entry.device, n, half) == w, (entry, n, half)
                assert c.read_holding_registers(addr, count=entry.words, device_id=1).registers == words
                assert c.read_input_registers(addr, count=entry.words, device_id=1).registers == words
        assert live.stats.scans > 0 and live.fault is None
        c.close()


def test_writes_land_between_scans_and_the_program_sees_them():
    with live_plc(PROGRAM) as (live, servers):
        c = client(servers)
        assert c.write_coil(10, True, device_id=1).bits == [True]  # M10 (vs map: M n at n)
        assert c.write_register(10, 4321, device_id=1).registers == [4321]  # D10
        before = live.stats.scans
        deadline = time.monotonic() + 2
        while time.monotonic() < deadline:  # the next scan copies them: Y10 (21008), D11
            if c.read_coils(21008, count=1, device_id=1).bits[0] and \
                    c.read_holding_registers(11, count=1, device_id=1).registers == [4321]:
                break
        assert c.read_coils(21008, count=1, device_id=1).bits[0] is True
        assert c.read_holding_registers(11, count=1, device_id=1).registers == [4321]
        assert live.stats.scans > before
        # 32-bit pairs: D20/D21 as one value, low word first
        value = -123456789 & 0xFFFFFFFF
        c.write_registers(20, [value & 0xFFFF, value >> 16], device_id=1)
        assert on_scan_thread(live, lambda m: m.words["D"][20] | m.words["D"][21] << 16) == value
        c.close()


def test_read_only_and_the_allow_list():
    with live_plc(PROGRAM, perms=Permissions(VS, read_only=True)) as (live, servers):
        c = client(servers)
        r = c.write_register(100, 7, device_id=1)
        assert r.isError() and r.exception_code == 2
        assert not c.read_holding_registers(100, count=1, device_id=1).isError()
        c.close()
    allow = [("M", 0, 99), ("D", 100, 199), ("X", 0, 7)]
    with live_plc(PROGRAM, perms=Permissions(VS, allow=allow)) as (live, servers):
        c = client(servers)
        assert not c.write_register(150, 7, device_id=1).isError()
        assert c.write_register(200, 7, device_id=1).isError()
        assert not c.write_coil(99, True, device_id=1).isError()
        assert c.write_coils(98, [True, True, True], device_id=1).isError()  # M100 is not allowed: none written
        assert on_scan_thread(live, lambda m: m.bits["M"][100]) == 0
        assert not c.write_coil(20007, True, device_id=1).isError()  # X7: allowed by name
        c.close()


def test_special_read_only_devices_are_never_written():
    m9000 = next(a for a in VS.devices["M"].areas if a.write == "system")
    perms = Permissions(VS, allow=[("M", 0, 9511)])
    assert not perms.writable("M", m9000.lo) and perms.writable("M", 0)


def test_protocol_exceptions():
    mapping = load_map("vs", VS)
    perms = Permissions(VS)

    def code(pdu):
        reply = parse(pdu, mapping, perms)
        assert isinstance(reply, bytes), reply
        return reply[0], reply[1]

    assert code(bytes([0x2B, 0x0E, 1, 0])) == (0xAB, 1)  # a function not served
    assert code(struct.pack(">BHH", 3, 0, 0)) == (0x83, 3)  # quantity 0
    assert code(struct.pack(">BHH", 3, 0, 126)) == (0x83, 3)  # over 125
    assert code(struct.pack(">BHH", 1, 0, 2001)) == (0x81, 3)
    assert code(struct.pack(">BHH", 3, 9500, 20)) == (0x83, 2)  # runs past D9511
    assert code(struct.pack(">BHH", 5, 0, 0x1234)) == (0x85, 3)  # a coil is FF00 or 0000
    assert code(struct.pack(">BHHB", 0x10, 0, 2, 3) + b"abc") == (0x90, 3)  # byte count
    assert code(struct.pack(">BHH", 5, 20000, 0xFF00)) == (0x85, 2)  # X0: read only
    assert code(b"\x03\x00") == (0x83, 3)  # too short
    # a well-formed read of M0-M15 runs on a machine
    m = Machine(VS, 1)
    m.bits["M"][3] = 1
    request = parse(struct.pack(">BHH", 1, 0, 16), mapping, perms)
    assert isinstance(request, Request) and request.execute(m) == bytes([1, 2, 0b1000, 0])


def test_wrong_station_and_junk_over_tcp():
    with live_plc(PROGRAM, station=3) as (live, servers):
        port = servers[0].bound_port
        c = ModbusTcpClient("127.0.0.1", port=port, timeout=3)
        assert c.connect()
        r = c.read_holding_registers(0, count=1, device_id=5)
        assert r.isError() and r.exception_code == 0x0B  # a gateway: nobody at unit 5
        assert not c.read_holding_registers(0, count=1, device_id=3).isError()
        with socket.create_connection(("127.0.0.1", port), timeout=3) as s:  # not Modbus: closed
            s.sendall(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n")
            assert s.recv(100) == b""
        assert not c.read_holding_registers(0, count=1, device_id=255).isError()  # the server goes on
        c.close()
