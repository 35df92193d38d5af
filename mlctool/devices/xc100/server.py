"""The XC100 as a real Modbus server: `mlc device serve` (docs/xc100.md).

One or more XC100 models share one line, as devices on one RS-485 bus do, each at its own
station. The server reads a byte stream (a TCP connection or a serial port), cuts it into
every complete frame it holds, in order, and answers each through modbus.handle_pdu, the
XC100's own request handling (8.3). Framings:
- rtu: unit, PDU, CRC-16 (8.1); over TCP for serial-server (gateway) setups, or on a port;
- ascii: ':', hex, LRC, CR LF (8.1), the XC100's factory setting;
- tcp: Modbus TCP (MBAP header: transaction, protocol 0, length, unit = station), what HMIs,
  SCADA tools and PLC Modbus clients speak.
The frames and the stream receivers are devices/framing.py's, shared with the simulated line
of `mlc sim`; they are ours rather than pymodbus's server: pymodbus answers one frame per read
and drops the rest of a segment (issue 21 #2), and logs whole buffers as hex on errors
(issue 21 #17). The model advances on the server's clock (the wall clock of this process);
the model itself only sees time steps.
"""

from __future__ import annotations

import asyncio

from mlctool.devices.framing import FRAMINGS, GATEWAY_NO_RESPONSE, RECEIVERS, Frame, exception_pdu
from mlctool.devices.serial_port import SerialLine
from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.modbus import handle_pdu

TICK_S = 0.01


MAX_CONNECTIONS = 256  # beyond this the least recently active connection is closed
WRITE_TIMEOUT_S = 5.0  # a client that reads no replies for this long is disconnected
READ_CHUNK = 4096
UNIT_ANY = 0xFF  # Modbus TCP: "the MODBUS Unit Identifier is useless. The value 0xFF has to be
# used" for a server addressed by IP (Modbus Messaging on TCP/IP Implementation Guide 4.4.2)


class Line:
    """The devices on one line, by station (1-16, 8.2), as on one RS-485 bus."""

    def __init__(self, devices: dict[int, c.Xc100]) -> None:
        self.devices = dict(sorted(devices.items()))
        self.requests = 0  # frames received and read (answered or not)

    def answer(self, unit: int, pdu: bytes) -> bytes | None:
        """What the line sends back for one request; None = silence. A broadcast (unit 0)
        goes to every device and none answers (8.2)."""
        self.requests += 1
        if unit == 0:
            for station, dev in self.devices.items():
                handle_pdu(dev, station, 0, pdu)
            return None
        dev = self.devices.get(unit)
        return None if dev is None else handle_pdu(dev, unit, unit, pdu)




class Server:
    """A Modbus server for a Line over TCP (loopback) or a serial port."""

    def __init__(self, line: Line, framing: str, tcp: tuple[str, int] | None = None,
                 serial: str | None = None, baudrate: int = 19200) -> None:
        if framing not in FRAMINGS:
            raise ValueError(f"framing {framing!r}")
        if framing == "tcp" and serial is not None:
            raise ValueError("Modbus TCP framing needs a TCP link")
        self.line = line
        self.framing = framing
        self.tcp = tcp
        self.serial = serial
        self.baudrate = baudrate
        self.connections: dict[asyncio.StreamWriter, float] = {}  # writer -> last activity
        self.accepted = 0
        self.evicted = 0
        self._server: asyncio.base_events.Server | None = None
        self._port = None
        self._tasks: set[asyncio.Task] = set()

    async def start(self) -> None:
        """Open the link (OSError if it cannot be opened)."""
        if self.tcp is not None:
            self._server = await asyncio.start_server(self._client, self.tcp[0], self.tcp[1],
                                                      limit=READ_CHUNK, backlog=512)
        else:
            self._open_serial()

    async def shutdown(self) -> None:
        if self._server is not None:
            self._server.close()
            for writer in list(self.connections):
                writer.close()
            for task in list(self._tasks):
                task.cancel()
            await asyncio.gather(*self._tasks, return_exceptions=True)
            await self._server.wait_closed()
            self._server = None
        if self._port is not None:
            self._port.close()
            self._port = None

    def answer(self, frame: Frame) -> bytes | None:
        unit = frame.unit
        if self.framing == "tcp" and unit == UNIT_ANY and len(self.line.devices) == 1:
            unit = next(iter(self.line.devices))  # a device addressed by its IP alone
        reply = self.line.answer(unit, frame.pdu)
        if reply is None and self.framing == "tcp" and frame.unit and frame.unit not in self.line.devices:
            # Modbus TCP clients wait for every reply: as a gateway, say nobody is there
            reply = exception_pdu(frame.pdu[0], GATEWAY_NO_RESPONSE)
        return reply

    async def _client(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        task = asyncio.current_task()
        self._tasks.add(task)
        loop = asyncio.get_running_loop()
        self.accepted += 1
        if len(self.connections) >= MAX_CONNECTIONS:  # close the least recently active one
            oldest = min(self.connections, key=self.connections.get)
            self.connections.pop(oldest)
            oldest.close()
            self.evicted += 1
        self.connections[writer] = loop.time()
        receiver = RECEIVERS[self.framing]()
        try:
            while True:
                data = await reader.read(READ_CHUNK)
                if not data:
                    break
                now = loop.time()
                if writer in self.connections:
                    self.connections[writer] = now
                frames = receiver.feed(data, now)
                replies = [receiver.encode(f, r) for f in frames if (r := self.answer(f)) is not None]
                if replies:
                    writer.write(b"".join(replies))
                    await asyncio.wait_for(writer.drain(), WRITE_TIMEOUT_S)
                if receiver.broken:
                    break
        except (ConnectionError, TimeoutError, OSError):
            pass  # the connection ends; the server and the other connections go on
        finally:
            self.connections.pop(writer, None)
            self._tasks.discard(task)
            writer.close()

    def _open_serial(self) -> None:
        def on_frame(f: Frame) -> None:
            if (reply := self.answer(f)) is not None:
                self._port.reply(f, reply)

        self._port = SerialLine(self.serial, self.baudrate, self.framing, on_frame, WRITE_TIMEOUT_S)


def make_server(devices: dict[int, c.Xc100], framing: str, tcp: tuple[str, int] | None = None,
                serial: str | None = None, baudrate: int = 19200) -> Server:
    """A server for `devices` (station -> model) on one line."""
    return Server(Line(devices), framing, tcp=tcp, serial=serial, baudrate=baudrate)


async def run_device(server: Server, duration_s: float | None, on_tick=None,
                     stop: asyncio.Event | None = None, on_ready=None) -> None:
    """Serve until `duration_s` passes or `stop` is set, advancing every model each tick."""
    await server.start()
    if on_ready:
        on_ready()
    loop = asyncio.get_running_loop()
    start = last = loop.time()
    stop = stop or asyncio.Event()
    try:
        while not stop.is_set():
            if duration_s is not None and loop.time() - start >= duration_s:
                break
            try:
                await asyncio.wait_for(stop.wait(), TICK_S)
            except TimeoutError:
                pass
            now = loop.time()
            for dev in server.line.devices.values():
                c.advance(dev, int((now - last) * 1e6))
            last = now
            if on_tick:
                on_tick()
    finally:
        await server.shutdown()
