"""`mlc device serve` speed: Modbus requests answered per second on loopback (issue 20;
figures in docs/bench.md).

The server runs as `python -m mlctool device serve xc100 --framing F --station 1 --station 2`
in its own process; this process is the client side, raw sockets (a client library would
measure itself). Cases, each for a few seconds of wall time:
- 1 client, one request at a time (FC03 read of 2 registers): the round-trip rate;
- 16 clients at once, one request at a time each;
- 1 client pipelining 32 requests per write (the server answers every frame of a segment);
for the tcp (MBAP) and rtu framings. Mixed requests: FC03 of 1008H (position, 2 words) and
FC06 of 2014H, to stations 1 and 2.

Run: python bench/server_speed.py [SECONDS_PER_CASE]
"""

from __future__ import annotations

import asyncio
import os
import socket
import struct
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from mlctool.devices.framing import crc16  # noqa: E402

REPLY_SIZE = {("tcp", 0x03): 13, ("tcp", 0x06): 12, ("rtu", 0x03): 9, ("rtu", 0x06): 8}


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def requests(framing: str) -> list[tuple[bytes, int]]:
    out = []
    for k, (unit, pdu) in enumerate([(1, struct.pack(">BHH", 3, 0x1008, 2)),
                                     (2, struct.pack(">BHH", 6, 0x2014, 50)),
                                     (2, struct.pack(">BHH", 3, 0x1008, 2)),
                                     (1, struct.pack(">BHH", 6, 0x2014, 60))]):
        if framing == "tcp":
            frame = struct.pack(">HHHB", k, 0, len(pdu) + 1, unit) + pdu
        else:
            adu = bytes([unit]) + pdu
            frame = adu + crc16(adu).to_bytes(2, "little")
        out.append((frame, REPLY_SIZE[(framing, pdu[0])]))
    return out


async def client(port: int, framing: str, depth: int, until: float) -> int:
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    reqs = requests(framing)
    batch = [reqs[k % len(reqs)] for k in range(depth)]
    payload = b"".join(f for f, _ in batch)
    want = sum(n for _, n in batch)
    done = 0
    while time.monotonic() < until:
        writer.write(payload)
        await reader.readexactly(want)
        done += depth
    writer.close()
    return done


async def case(port: int, framing: str, clients: int, depth: int, seconds: float) -> float:
    until = time.monotonic() + seconds
    t0 = time.monotonic()
    counts = await asyncio.gather(*(client(port, framing, depth, until) for _ in range(clients)))
    return sum(counts) / (time.monotonic() - t0)


def main() -> None:
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 3.0
    print(f"mlc device serve xc100, loopback, {os.cpu_count()} cores; requests answered per second")
    print(f"  {'framing':8} {'case':40} {'requests/s':>11}")
    for framing in ("tcp", "rtu"):
        port = free_port()
        server = subprocess.Popen([sys.executable, "-m", "mlctool", "device", "serve", "xc100",
                                   "--tcp", f"127.0.0.1:{port}", "--framing", framing,
                                   "--station", "1", "--station", "2", "--duration", "120s"],
                                  stderr=subprocess.PIPE, text=True)
        try:
            server.stderr.readline()  # "serving ..."
            for label, clients, depth in (("1 client, 1 request at a time", 1, 1),
                                          ("16 clients, 1 request at a time each", 16, 1),
                                          ("1 client, 32 requests per write", 1, 32)):
                rate = asyncio.run(case(port, framing, clients, depth, seconds))
                print(f"  {framing:8} {label:40} {rate:11,.0f}", flush=True)
        finally:
            server.terminate()
            server.communicate(timeout=10)


if __name__ == "__main__":
    main()
