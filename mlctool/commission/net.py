"""The servers of `mlc run --serve`: their addresses, the network thread, and the Modbus
slave over TCP (MBAP, or RTU/ASCII frames tunnelled over TCP) and over a serial device.

Every server runs on one asyncio loop in one daemon thread (NetThread); none touches the
machine: a request becomes a job for the scan loop (commission/exchange.py) and the reply
is sent when the scan loop has run it. Security (docs/reliability.md, "Threat model"):
- an address is 127.0.0.1 unless `--listen` names another (the CLI warns: W750);
- at most `max_clients` connections per server; one more is closed at once (not an older
  one: a flood cannot push out the HMI that was there first);
- one request at a time per connection (the next frame is read after the reply), and the
  exchange's per-client bound behind that;
- frames are the protocol's own size (framing.py: MBAP <= 260 bytes, RTU <= 256, an ASCII
  line <= 513); a frame begun must end within FRAME_TIMEOUT_S, a silent connection is
  closed after IDLE_TIMEOUT_S, a client that reads no replies for WRITE_TIMEOUT_S too.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import re
import threading
from dataclasses import dataclass, field

from mlctool.commission.exchange import Exchange
from mlctool.commission.modbus_map import Map, Permissions
from mlctool.commission.modbus_slave import parse
from mlctool.devices.framing import (
    BUSY,
    GATEWAY_NO_RESPONSE,
    RECEIVERS,
    SERVER_FAILURE,
    Frame,
    exception_pdu,
)
from mlctool.devices.serial_port import SerialLine

LOOPBACK = ("127.0.0.1", "localhost")
READ_CHUNK = 4096
FRAME_TIMEOUT_S = 5.0
IDLE_TIMEOUT_S = 300.0
WRITE_TIMEOUT_S = 5.0
REPLY_TIMEOUT_S = 2.0  # the scan loop did not run the job in time: exception 06 (busy)
DEFAULT_MAX_CLIENTS = 256
NET_NICENESS = 10
SCHEMES = {"modbus-tcp": "tcp", "rtu+tcp": "rtu", "ascii+tcp": "ascii", "rtu": "rtu", "ascii": "ascii",
           "opc.tcp": None}
BAUDS = (300, 600, 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200)  # 003 7-3-5


class EndpointError(ValueError):
    """A --serve address that cannot be served (E750)."""


@dataclass(frozen=True)
class Endpoint:
    url: str
    scheme: str
    host: str = ""
    port: int = 0
    device: str = ""  # a serial device
    baud: int = 19200

    @property
    def framing(self) -> str | None:
        return SCHEMES[self.scheme]

    @property
    def public(self) -> bool:
        """Bound beyond this machine (W750)."""
        return bool(self.host) and self.host not in LOOPBACK


def parse_endpoint(text: str, listen: str | None) -> Endpoint:
    """`modbus-tcp://127.0.0.1:5502`, `rtu+tcp://HOST:PORT`, `ascii+tcp://...`,
    `rtu:/dev/ttyUSB0?baud=19200`, `ascii:...`, `opc.tcp://127.0.0.1:4840`. A host that is
    not loopback must be the `listen` address; an empty host is `listen`, else 127.0.0.1."""
    scheme, sep, rest = text.partition(":")
    if not sep or scheme not in SCHEMES:
        raise EndpointError(f"--serve {text[:80]!r}: expected one of "
                            + ", ".join(f"{s}://..." if s not in ("rtu", "ascii") else f"{s}:DEVICE" for s in SCHEMES))
    if scheme in ("rtu", "ascii"):
        device, _, query = rest.removeprefix("//").partition("?")
        baud = 19200
        if query:
            mt = re.fullmatch(r"baud=([0-9]{1,6})", query)
            if not mt or int(mt[1]) not in BAUDS:
                raise EndpointError(f"--serve {text[:80]!r}: ?baud= takes one of {', '.join(map(str, BAUDS))}")
            baud = int(mt[1])
        if not device:
            raise EndpointError(f"--serve {text[:80]!r}: name the serial device ({scheme}:/dev/ttyUSB0)")
        return Endpoint(text, scheme, device=device, baud=baud)
    mt = re.fullmatch(r"//(\[[0-9a-fA-F:.]+\]|[A-Za-z0-9.\-]*):([0-9]{1,5})/?", rest)
    if not mt or not 0 <= int(mt[2]) < 65536:  # 0: the system chooses (printed when serving)
        raise EndpointError(f"--serve {text[:80]!r}: expected {scheme}://HOST:PORT, e.g. {scheme}://127.0.0.1:5502")
    host = mt[1].strip("[]") or listen or "127.0.0.1"
    if host not in LOOPBACK and host != listen:
        raise EndpointError(f"--serve {text[:80]!r}: only 127.0.0.1 is served unless --listen {host} "
                            "names the address (docs/commissioning.md, Security)")
    return Endpoint(text, scheme, "127.0.0.1" if host == "localhost" else host, int(mt[2]))


@dataclass
class Slave:
    """What a Modbus server serves: the map, the write permissions, the station."""

    mapping: Map
    perms: Permissions
    station: int = 1


@dataclass
class ServerStats:
    accepted: int = 0
    refused: int = 0  # connections over max_clients
    requests: int = 0
    busy: int = 0  # requests answered 06: the scan loop's queue was full or late
    dropped: int = 0  # connections closed for a slow or silent client, or a broken stream
    clients: set = field(default_factory=set)


class ModbusServer:
    def __init__(self, endpoint: Endpoint, slave: Slave, exchange: Exchange,
                 max_clients: int = DEFAULT_MAX_CLIENTS):
        self.endpoint = endpoint
        self.framing = endpoint.framing
        self.slave = slave
        self.exchange = exchange
        self.max_clients = max_clients
        self.stats = ServerStats()
        self._server: asyncio.base_events.Server | None = None
        self._port = None
        self._tasks: set[asyncio.Task] = set()

    @property
    def bound_port(self) -> int:
        """The TCP port (the one the system chose for port 0)."""
        return self._server.sockets[0].getsockname()[1] if self._server else 0

    async def start(self) -> None:
        if self.endpoint.device:
            await self._open_serial()
        else:
            self._server = await asyncio.start_server(self._client, self.endpoint.host, self.endpoint.port,
                                                      limit=READ_CHUNK, backlog=512)

    async def stop(self) -> None:
        if self._server is not None:
            self._server.close()
            for task in list(self._tasks):
                task.cancel()
            await asyncio.gather(*self._tasks, return_exceptions=True)
            self._server = None
        if self._port is not None:
            self._port.close()
            self._port = None

    async def answer(self, frame: Frame, client: object) -> bytes | None:
        """The reply PDU to one frame; None: silence (another station, a broadcast)."""
        unit, pdu, station = frame.unit, frame.pdu, self.slave.station
        tcp = self.framing == "tcp"
        broadcast = unit == 0 and not tcp
        if not (unit == station or broadcast or (tcp and unit in (0, 0xFF))):
            if tcp and pdu:  # a Modbus TCP client waits for every reply: nobody is there
                return exception_pdu(pdu[0], GATEWAY_NO_RESPONSE)
            return None
        self.stats.requests += 1
        request = parse(pdu, self.slave.mapping, self.slave.perms)
        if isinstance(request, bytes):
            return None if broadcast else request
        if broadcast and request.values is None:
            return None  # a broadcast read: nothing to do, nobody to answer
        loop = asyncio.get_running_loop()
        reply = loop.create_future()

        def done(result, error) -> None:
            loop.call_soon_threadsafe(_settle, reply, result, error)

        if not self.exchange.submit(client, request.execute, done):
            self.stats.busy += 1
            return None if broadcast else exception_pdu(request.fc, BUSY)
        try:
            result = await asyncio.wait_for(reply, REPLY_TIMEOUT_S)
        except TimeoutError:
            self.stats.busy += 1
            return None if broadcast else exception_pdu(request.fc, BUSY)
        if isinstance(result, BaseException):
            return None if broadcast else exception_pdu(request.fc, SERVER_FAILURE)
        return None if broadcast else result

    async def _client(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        stats = self.stats
        if len(stats.clients) >= self.max_clients:
            stats.refused += 1
            writer.close()
            return
        task = asyncio.current_task()
        self._tasks.add(task)
        stats.accepted += 1
        client = object()
        stats.clients.add(client)
        receiver = RECEIVERS[self.framing]()
        loop = asyncio.get_running_loop()
        begun = None  # when the unfinished frame in the receiver began
        try:
            while True:
                if receiver.buf:
                    begun = begun or loop.time()
                    wait = FRAME_TIMEOUT_S - (loop.time() - begun)
                else:
                    begun, wait = None, IDLE_TIMEOUT_S
                if wait <= 0:
                    stats.dropped += 1
                    break
                data = await asyncio.wait_for(reader.read(READ_CHUNK), wait)
                if not data:
                    break
                replies = []
                for f in receiver.feed(data, loop.time()):
                    reply = await self.answer(f, client)
                    if reply is not None:
                        replies.append(receiver.encode(f, reply))
                if replies:
                    writer.write(b"".join(replies))
                    await asyncio.wait_for(writer.drain(), WRITE_TIMEOUT_S)
                if receiver.broken:
                    stats.dropped += 1
                    break
        except TimeoutError:
            stats.dropped += 1
        except (ConnectionError, OSError, asyncio.IncompleteReadError):
            pass  # the connection ends; the server and the other connections go on
        except asyncio.CancelledError:
            pass  # the server stops (asyncio's stream callback would log a cancelled handler)
        finally:
            stats.clients.discard(client)
            self._tasks.discard(task)
            writer.close()

    async def _open_serial(self) -> None:
        frames: asyncio.Queue = asyncio.Queue(maxsize=16)  # a bus has one master: a few at most
        client = object()

        def on_frame(f: Frame) -> None:
            if frames.full():
                self.stats.busy += 1  # dropped, as a busy slave misses a frame
            else:
                frames.put_nowait(f)

        line = SerialLine(self.endpoint.device, self.endpoint.baud, self.framing, on_frame, WRITE_TIMEOUT_S)

        async def worker() -> None:
            while True:
                f = await frames.get()
                reply = await self.answer(f, client)
                if reply is not None:
                    line.reply(f, reply)

        self._port = line
        task = asyncio.get_running_loop().create_task(worker())
        self._tasks.add(task)


def _settle(future: asyncio.Future, result, error) -> None:
    if not future.done():
        future.set_result(error if error is not None else result)


class NetThread:
    """An asyncio loop on a daemon thread, for the servers."""

    def __init__(self) -> None:
        self.loop = asyncio.new_event_loop()
        self.thread = threading.Thread(target=self._main, name="mlc-run-servers", daemon=True)
        self.servers: list = []

    def _main(self) -> None:
        # below the scan thread for the system's scheduler (raising a thread's niceness needs
        # no privilege); the interpreter's switch interval is lowered by LiveRun
        with contextlib.suppress(AttributeError, OSError):
            os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), NET_NICENESS)
        asyncio.set_event_loop(self.loop)
        self.loop.run_forever()

    def start(self, servers: list) -> None:
        """Start every server (OSError, RuntimeError: one could not be opened; those started
        are stopped again)."""
        self.thread.start()
        for server in servers:
            try:
                asyncio.run_coroutine_threadsafe(server.start(), self.loop).result(30)
            except BaseException:
                self.stop()
                raise
            self.servers.append(server)

    def call(self, coro, timeout: float = 30):
        """Run a coroutine on the servers' loop and wait for its result (tests, OPC UA)."""
        return asyncio.run_coroutine_threadsafe(coro, self.loop).result(timeout)

    def stop(self) -> None:
        for server in reversed(self.servers):
            try:
                asyncio.run_coroutine_threadsafe(server.stop(), self.loop).result(10)
            except Exception:  # a server that cannot stop cleanly: the loop still ends
                pass
        self.servers = []
        if self.thread.is_alive():
            self.loop.call_soon_threadsafe(self.loop.stop)
            self.thread.join(10)
