"""`mlc run` scan jitter under load (issue 32; figures in docs/commissioning.md, "Speed").

The PLC runs as `python -m mlctool run PROGRAM --scan-time 10ms --duration T --serve ...
--json` in its own process (its figures: scans, mean and worst jitter, overruns); this
process is the clients' side, asyncio over raw sockets (a client library would measure
itself). Cases, each for T seconds of wall time:
- 0, 10, 100 Modbus TCP clients, each reading 100 holding registers (FC03) every 10 ms;
- a 200-client flood: 100 such pollers, 40 clients sending junk (random bytes, reconnecting
  when closed), 40 slow clients (a frame begun, one byte a second), 20 connecting and
  closing in a loop;
- OPC UA: one client subscribed to 1000 nodes (a program of 1000 D registers) at 10 ms.

Run: python bench/commission_speed.py [SECONDS_PER_CASE] (default 10)
"""

from __future__ import annotations

import asyncio
import json
import os
import random
import re
import struct
import subprocess
import sys
import tempfile
import time

ROOT = os.path.join(os.path.dirname(__file__), "..")
sys.path.insert(0, ROOT)
PERIOD_MS = 10
READ_100 = struct.pack(">BHH", 3, 0, 100)


def start_plc(program: str, seconds: float, serve: str) -> tuple[subprocess.Popen, int]:
    env = {**os.environ, "PYTHONPATH": ROOT}
    proc = subprocess.Popen([sys.executable, "-m", "mlctool", "run", program, "--scan-time", f"{PERIOD_MS}ms",
                             "--duration", f"{seconds}s", "--serve", serve, "--json", "--max-clients", "256"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    line = proc.stderr.readline()
    mt = re.search(r"on port ([0-9]+)", line)
    if not mt:
        raise SystemExit(line + proc.stderr.read())
    return proc, int(mt[1])


async def poller(port: int, until: float, counts: list[int]) -> None:
    try:
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
    except OSError:
        return
    tid = 0
    try:
        while time.monotonic() < until:
            tid = (tid + 1) & 0xFFFF
            writer.write(struct.pack(">HHHB", tid, 0, len(READ_100) + 1, 1) + READ_100)
            await reader.readexactly(9 + 200)
            counts[0] += 1
            await asyncio.sleep(PERIOD_MS / 1000)
    except (OSError, asyncio.IncompleteReadError):
        counts[1] += 1
    finally:
        writer.close()


async def junk(port: int, until: float) -> None:
    rng = random.Random(port)
    while time.monotonic() < until:
        try:
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.write(bytes(rng.randrange(256) for _ in range(rng.randrange(1, 600))))
            await writer.drain()
            await asyncio.wait_for(reader.read(1024), 0.2)
            writer.close()
        except (OSError, TimeoutError):
            pass
        await asyncio.sleep(0.01)


async def slow(port: int, until: float) -> None:
    try:
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        frame = struct.pack(">HHHB", 1, 0, len(READ_100) + 1, 1) + READ_100
        for b in frame[:-1]:  # never the last byte
            if time.monotonic() >= until:
                break
            writer.write(bytes([b]))
            await writer.drain()
            await asyncio.sleep(1.0)
        writer.close()
    except OSError:
        pass


async def churn(port: int, until: float) -> None:
    while time.monotonic() < until:
        try:
            _, writer = await asyncio.open_connection("127.0.0.1", port)
            writer.close()
        except OSError:
            pass
        await asyncio.sleep(0.005)


async def load(port: int, seconds: float, pollers: int, flood: bool) -> list[int]:
    until = time.monotonic() + seconds - 0.5
    counts = [0, 0]  # replies, pollers cut off
    tasks = [poller(port, until, counts) for _ in range(pollers)]
    if flood:
        tasks += [junk(port + 0, until) for _ in range(40)] + [slow(port, until) for _ in range(40)] \
            + [churn(port, until) for _ in range(20)]
    await asyncio.gather(*tasks)
    return counts


async def opcua_load(port: int, seconds: float, nodes: int) -> int:
    from asyncua import Client

    seen = [0]

    class Handler:
        def datachange_notification(self, node, val, data):
            seen[0] += 1

    async with Client(f"opc.tcp://127.0.0.1:{port}/", timeout=10) as client:
        plc = await client.nodes.objects.get_child(["2:PLC"])
        children = (await plc.get_children())[:nodes]
        sub = await client.create_subscription(PERIOD_MS, Handler())
        await sub.subscribe_data_change(children)
        await asyncio.sleep(seconds - 2)
    return seen[0]


def case(name: str, program: str, seconds: float, pollers: int = 0, flood: bool = False,
         opcua_nodes: int = 0) -> None:
    serve = "opc.tcp://127.0.0.1:0" if opcua_nodes else "modbus-tcp://127.0.0.1:0"
    proc, port = start_plc(program, seconds, serve)
    if opcua_nodes:
        extra = f"{asyncio.run(opcua_load(port, seconds, opcua_nodes)):,} notifications"
    else:
        replies, cut = asyncio.run(load(port, seconds, pollers, flood))
        extra = f"{replies:,} replies ({replies / max(seconds - 0.5, 0.1):,.0f}/s)" + (f", {cut} pollers cut off" if cut else "")
    out, err = proc.communicate(timeout=seconds + 30)
    figures = json.loads(out)
    s, srv = figures["stats"], figures["servers"][0]
    print(f"| {name} | {s['scans']} | {s['jitter_mean_ms']:.3f} | {s['jitter_worst_ms']:.2f} | {s['overruns']} | "
          f"{extra}; refused {srv['refused']}, busy {srv['busy']}, dropped {srv['dropped']} |", flush=True)


def main() -> None:
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 10.0
    program = os.path.join(ROOT, "samples", "nc5", "conveyor.il")
    print(f"mlc run, scan {PERIOD_MS} ms, {seconds:g} s per case, CPython {sys.version.split()[0]}, "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}\n")
    print("| case | scans | jitter mean ms | jitter worst ms | overruns | clients |")
    print("|---|---|---|---|---|---|")
    case("no client", program, seconds)
    case("10 Modbus clients, 100 registers / 10 ms", program, seconds, pollers=10)
    case("100 Modbus clients, 100 registers / 10 ms", program, seconds, pollers=100)
    case("200-client flood (100 pollers, 40 junk, 40 slow, 20 churning)", program, seconds, pollers=100, flood=True)
    with tempfile.TemporaryDirectory() as tmp:
        big = os.path.join(tmp, "d1000.il")
        with open(big, "w") as f:
            f.write("LDI M1\n" + "".join(f"ADD D{n} K1 D{n}\n" for n in range(1000)) + "END\n")
        case("OPC UA, 1 client subscribed to 1000 changing nodes", big, seconds, opcua_nodes=1000)


if __name__ == "__main__":
    main()
