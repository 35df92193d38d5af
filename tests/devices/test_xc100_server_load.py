"""Load and fault test of `mlc device serve`'s server (issue 20), on loopback, bounded in count
and time: 200 concurrent Modbus TCP clients, malformed frames, half-open, slow and silent
connections, a client that leaves mid-frame and one that never reads its replies; all the
while, every valid request is answered, in order and correctly."""

from __future__ import annotations

import asyncio
import random
import socket
import struct
import time

from mlctool.devices.framing import crc16
from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.server import make_server, run_device

CLIENTS = 200
REQUESTS_EACH = 5


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def mbap(tid: int, unit: int, pdu: bytes) -> bytes:
    return struct.pack(">HHHB", tid, 0, len(pdu) + 1, unit) + pdu


def rtu(adu: bytes) -> bytes:
    return adu + crc16(adu).to_bytes(2, "little")


async def read_reply(reader: asyncio.StreamReader) -> tuple[int, int, bytes]:
    head = await reader.readexactly(7)
    tid, _pid, length, unit = struct.unpack(">HHHB", head)
    return tid, unit, await reader.readexactly(length - 1)


async def good_client(port: int, k: int) -> int:
    """Writes its own value to its station's speed register (2014H) and reads it back."""
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    unit = 1 + k % 2
    ok = 0
    try:
        for n in range(REQUESTS_EACH):
            value = 1 + (k * 7 + n) % 100
            tid = k * 16 + n
            writer.write(mbap(tid, unit, struct.pack(">BHH", 0x06, 0x2014, value)))
            writer.write(mbap(tid + 1000 * 16, unit, struct.pack(">BHH", 0x03, 0x1000, 1)))
            await writer.drain()
            echo = await read_reply(reader)
            status = await read_reply(reader)
            assert echo == (tid, unit, struct.pack(">BHH", 0x06, 0x2014, value)), echo
            assert status[0] == tid + 1000 * 16 and status[2][:2] == b"\x03\x02", status
            ok += 1
    finally:
        writer.close()
    return ok


async def junk_client(port: int, seed: int) -> None:
    rnd = random.Random(seed)
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    for _ in range(20):
        writer.write(bytes(rnd.randrange(256) for _ in range(rnd.randrange(1, 300))))
    writer.write(mbap(1, 1, b"\x03\x10\x00\x00\x01")[:5] + b"\xff" * 40)  # a length of 0xFFxx
    try:
        await writer.drain()
        await asyncio.wait_for(reader.read(), 3.0)  # closed by the server or by EOF
    except (ConnectionError, TimeoutError):
        pass
    writer.close()


async def half_open(port: int, partial: bytes, hold: asyncio.Event) -> None:
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    writer.write(partial)
    await writer.drain()
    await hold.wait()
    writer.close()


async def leaves_mid_frame(port: int) -> None:
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    frame = mbap(5, 1, struct.pack(">BHH", 0x06, 0x2014, 77))
    writer.write(frame[:9])
    await writer.drain()
    writer.transport.abort()  # RST, mid-frame


async def slow_client(port: int) -> bytes:
    """A valid request one byte every 10 ms: answered once complete."""
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    for b in mbap(9, 2, struct.pack(">BHH", 0x03, 0x1000, 1)):
        writer.write(bytes([b]))
        await writer.drain()
        await asyncio.sleep(0.01)
    reply = await asyncio.wait_for(read_reply(reader), 3.0)
    writer.close()
    return reply[2]


async def never_reads(port: int, hold: asyncio.Event) -> None:
    """Pipelines 20,000 requests and reads no reply."""
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    writer.transport.get_extra_info("socket").setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    writer.write(mbap(1, 1, struct.pack(">BHH", 0x03, 0x1008, 2)) * 20000)
    await hold.wait()
    writer.transport.abort()


def test_server_under_load_and_faults_keeps_answering():
    devices = {1: c.new_xc100(), 2: c.new_xc100()}
    port = free_port()
    server = make_server(devices, "tcp", tcp=("127.0.0.1", port))

    async def scenario():
        stop, hold = asyncio.Event(), asyncio.Event()
        task = asyncio.create_task(run_device(server, 30.0, stop=stop))
        await asyncio.sleep(0.2)
        t0 = time.monotonic()
        try:
            holders = [asyncio.create_task(half_open(port, b"", hold)) for _ in range(40)]
            holders += [asyncio.create_task(half_open(port, mbap(3, 1, b"\x03\x10\x00")[:k % 9], hold))
                        for k in range(20)]
            holders.append(asyncio.create_task(never_reads(port, hold)))
            await asyncio.sleep(0.2)
            faults = [junk_client(port, s) for s in range(10)] + [leaves_mid_frame(port) for _ in range(10)]
            results = await asyncio.wait_for(asyncio.gather(
                slow_client(port), *(good_client(port, k) for k in range(CLIENTS)), *faults), 20.0)
            slow, goods = results[0], results[1:1 + CLIENTS]
            # the server still answers on a fresh connection, with everything still open
            last = await asyncio.wait_for(good_client(port, 0), 3.0)
            hold.set()
            await asyncio.gather(*holders)
            return slow, goods, last, time.monotonic() - t0
        finally:
            stop.set()
            await asyncio.wait_for(task, 10.0)

    slow, goods, last, seconds = asyncio.run(scenario())
    assert slow[:2] == b"\x03\x02"
    assert goods == [REQUESTS_EACH] * CLIENTS and last == REQUESTS_EACH
    assert server.accepted >= CLIENTS + 60  # the goods and the held connections at least
    assert seconds < 20
    assert server.line.requests >= 2 * CLIENTS * REQUESTS_EACH  # every good request was read
    assert devices[1].regs[0x2014] and devices[2].regs[0x2014]  # both stations were written


def test_rtu_line_keeps_answering_after_junk_and_a_cut_frame():
    """RTU tunnelled over TCP (serial servers): junk, then a frame cut by a disconnect, on
    other connections; a client on its own connection is answered throughout."""
    dev = c.new_xc100()
    port = free_port()
    server = make_server({1: dev}, "rtu", tcp=("127.0.0.1", port))
    read = rtu(bytes.fromhex("01 03 10 00 00 01"))

    async def scenario():
        stop = asyncio.Event()
        task = asyncio.create_task(run_device(server, 10.0, stop=stop))
        await asyncio.sleep(0.2)
        try:
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            answers = []
            for k in range(5):
                _r, w = await asyncio.open_connection("127.0.0.1", port)
                w.write(bytes(random.Random(k).randrange(256) for _ in range(2000)) + read[:5])
                await w.drain()
                w.transport.abort()
                writer.write(read * 3)
                await writer.drain()
                answers.append(await asyncio.wait_for(reader.readexactly(21), 2.0))
            writer.close()
            return answers
        finally:
            stop.set()
            await asyncio.wait_for(task, 5.0)

    answers = asyncio.run(scenario())
    assert answers == [rtu(bytes.fromhex("01 03 02 00 00")) * 3] * 5
