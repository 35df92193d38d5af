"""The XC100 as a real Modbus server: `mlc device serve` (docs/xc100.md).

One or more XC100 models share one line, as devices on one RS-485 bus do, each at its own
station. The server reads a byte stream (a TCP connection or a serial port), cuts it into
every complete frame it holds, in order, and answers each through modbus.handle_pdu, the
XC100's own request handling (8.3). Framings:
- rtu: unit, PDU, CRC-16 (8.1); over TCP for serial-server (gateway) setups, or on a port;
- ascii: ':', hex, LRC, CR LF (8.1), the XC100's factory setting;
- tcp: Modbus TCP (MBAP header: transaction, protocol 0, length, unit = station), what HMIs,
  SCADA tools and PLC Modbus clients speak.
The receivers are ours rather than pymodbus's server: pymodbus answers one frame per read
and drops the rest of a segment (issue 21 #2), and logs whole buffers as hex on errors
(issue 21 #17). Receiver rules of the line:
- RTU: a frame's length follows from its function code (8.4) and its CRC must match; after
  a damaged frame the receiver drops bytes until the line has been silent for more than
  RTU_GAP_S (the bus's inter-frame gap), so the next request is read cleanly;
- ASCII: ':' always starts a new message, so junk before it never eats a good frame.
The model advances on the server's clock (the wall clock of this process); the model itself
only sees time steps. The pymodbus framers below (XC100Decoder, LineRTU, LineAscii) read the
single frames of the simulated line in `mlc sim` (simmodel.py).
"""

from __future__ import annotations

import asyncio
import binascii
import logging
import struct
import time
from typing import NamedTuple

from pymodbus.exceptions import NoSuchIdException
from pymodbus.framer import FramerAscii, FramerRTU
from pymodbus.pdu import DecodePDU, ModbusPDU

from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.modbus import handle_pdu

TICK_S = 0.01
RTU_GAP_S = 0.02
MAX_FC10_BYTES = 120  # 60 words (8.5)


class XC100Request(ModbusPDU):
    """Any request PDU, kept raw for handle_pdu."""

    function_code = 0

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.raw = b""

    def decode(self, data: bytes) -> None:
        self.raw = bytes(data)

    @classmethod
    def calculateRtuFrameSize(cls, data: bytes) -> int:
        """RTU frames carry no length; 8.4 fixes it per function code. An unknown code (or an
        impossible FC10 byte count) takes what has arrived, so its CRC decides."""
        fc = data[1]
        if fc in (0x03, 0x06):
            return 8
        if fc == 0x10:
            if len(data) < 7:
                return 0
            if data[6] <= MAX_FC10_BYTES and data[6] == 2 * int.from_bytes(data[4:6], "big"):
                return data[6] + 9
        return len(data)

    async def datastore_update(self, context, device_id: int) -> ModbusPDU:
        reply = context.handle(self.dev_id, bytes([self.function_code]) + self.raw)
        if reply is None:
            raise NoSuchIdException("no response")  # pymodbus then stays silent
        return RawResponse(reply)


class RawResponse(ModbusPDU):
    def __init__(self, pdu: bytes) -> None:
        super().__init__()
        self.function_code = pdu[0]
        self.payload = pdu[1:]

    def encode(self) -> bytes:
        return self.payload


class XC100Decoder(DecodePDU):
    """Every function code decodes to XC100Request (the XC100 answers unknown ones itself)."""

    def lookupPduClass(self, data: bytes):
        return XC100Request

    def decode(self, frame: bytes) -> ModbusPDU | None:
        if not frame:
            return None
        pdu = XC100Request()
        pdu.function_code = frame[0]
        pdu.decode(frame[1:])
        return pdu


class LineRTU(FramerRTU):
    def __init__(self, decoder) -> None:
        super().__init__(decoder)
        self._last = 0.0
        self._pending = 0

    def decode(self, data: bytes):
        now = time.monotonic()
        skip = self._pending if now - self._last > RTU_GAP_S else 0
        self._last = now
        skip = min(skip, len(data))
        used, dev_id, tid, frame = super().decode(data[skip:])
        self._pending = len(data) - skip - used
        return used + skip, dev_id, tid, frame


class LineAscii(FramerAscii):
    def decode(self, data: bytes):
        skip = 0
        while True:
            end = data.find(self.end, skip)
            if end < 0:
                break
            start = data.rfind(self.START, skip, end)
            if start < 0:  # a line without ':' is noise
                skip = end + len(self.end)
                continue
            skip = start
            try:
                used, dev_id, tid, frame = super().decode(data[skip:])
            except ValueError:  # a non-hex station field: drop the line
                skip = end + len(self.end)
                continue
            return skip + used, dev_id, tid, frame
        return skip, 0, 0, self.EMPTY


MAX_CONNECTIONS = 256  # beyond this the least recently active connection is closed
MAX_PENDING = 1024  # bytes of an unfinished frame a receiver keeps (an RTU frame is <= 256)
ASCII_MAX_LINE = 513  # ':' + 2 x 255 hex + LRC (8.1)
WRITE_TIMEOUT_S = 5.0  # a client that reads no replies for this long is disconnected
READ_CHUNK = 4096
FRAMINGS = ("ascii", "rtu", "tcp")
GATEWAY_NO_RESPONSE = 0x0B  # Modbus TCP: the unit behind the gateway did not answer
UNIT_ANY = 0xFF  # Modbus TCP: "the MODBUS Unit Identifier is useless. The value 0xFF has to be
# used" for a server addressed by IP (Modbus Messaging on TCP/IP Implementation Guide 4.4.2)


def quiet_pymodbus() -> None:
    """pymodbus logs whole receive buffers as hex on its errors (megabytes for a client that
    pipelines and leaves, issue 21 #17); the server's own lines are all that is printed."""
    logging.getLogger("pymodbus").setLevel(logging.CRITICAL + 10)


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


class Frame(NamedTuple):
    unit: int
    pdu: bytes
    tid: int = 0  # Modbus TCP transaction id, echoed in the reply


def crc16(data: bytes) -> int:
    """Modbus CRC-16 (8.1), as sent: low byte first when packed little-endian."""
    crc = 0xFFFF
    table = _CRC_TABLE
    for b in data:
        crc = (crc >> 8) ^ table[(crc ^ b) & 0xFF]
    return crc


def _crc_table() -> list[int]:
    table = []
    for byte in range(256):
        crc = byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
        table.append(crc)
    return table


_CRC_TABLE = _crc_table()

# Request lengths on an RTU line (unit + PDU + CRC) by function code: fixed, or (position of
# the byte count, bytes before and after the counted data). Modbus application protocol 1.1b.
RTU_FIXED = {0x01: 8, 0x02: 8, 0x03: 8, 0x04: 8, 0x05: 8, 0x06: 8, 0x07: 4, 0x08: 8,
             0x0B: 4, 0x0C: 4, 0x11: 4, 0x16: 10, 0x18: 6, 0x2B: 7}
RTU_COUNTED = {0x0F: (6, 9), 0x10: (6, 9), 0x17: (10, 13)}


def rtu_frame_size(buf: bytes) -> int:
    """The length of the frame at the start of `buf`: > 0 a complete frame whose CRC
    matches, 0 not complete yet, -1 damaged (its CRC does not match)."""
    if len(buf) < 4:
        return 0
    fc = buf[1]
    if fc in RTU_FIXED:
        size = RTU_FIXED[fc]
    elif fc in RTU_COUNTED:
        at, extra = RTU_COUNTED[fc]
        if len(buf) <= at:
            return 0
        size = extra + buf[at]
    else:  # a code of no known length (the XC100 answers it with exception 01): its CRC ends it
        return _crc_search(buf)
    if len(buf) < size:
        return 0
    return size if crc16(buf[:size - 2]) == buf[size - 2] | buf[size - 1] << 8 else -1


def _crc_search(buf: bytes) -> int:
    """The shortest prefix (4-256 bytes) that ends with its own CRC."""
    crc = 0xFFFF
    table = _CRC_TABLE
    limit = min(len(buf), 256)
    for k in range(limit - 2):
        crc = (crc >> 8) ^ table[(crc ^ buf[k]) & 0xFF]
        if k >= 1 and crc == buf[k + 1] | buf[k + 2] << 8:
            return k + 3
    return -1 if len(buf) >= 256 else 0


class RtuReceiver:
    def __init__(self) -> None:
        self.broken = False  # never: these framings resynchronise
        self.buf = b""
        self.last = float("-inf")
        self.discarding = False

    def feed(self, data: bytes, now: float) -> list[Frame]:
        if now - self.last > RTU_GAP_S:  # the line was silent: whatever came before has ended
            self.buf = b""
            self.discarding = False
        self.last = now
        if self.discarding:
            return []
        buf = self.buf + data
        frames = []
        while buf:
            size = rtu_frame_size(buf)
            if size == 0:
                break
            if size < 0:  # lost sync: wait for the next silence
                self.discarding = True
                buf = b""
                break
            frames.append(Frame(buf[0], buf[1:size - 2]))
            buf = buf[size:]
        if len(buf) > MAX_PENDING:
            self.discarding, buf = True, b""
        self.buf = buf
        return frames

    @staticmethod
    def encode(frame: Frame, pdu: bytes) -> bytes:
        adu = bytes([frame.unit]) + pdu
        return adu + struct.pack("<H", crc16(adu))


class AsciiReceiver:
    def __init__(self) -> None:
        self.broken = False  # never: these framings resynchronise
        self.buf = b""

    def feed(self, data: bytes, now: float) -> list[Frame]:
        buf = self.buf + data
        frames = []
        while True:
            end = buf.find(b"\r\n")
            if end < 0:
                if len(buf) > ASCII_MAX_LINE:  # no end in sight: keep only a last start
                    start = buf.rfind(b":")
                    buf = buf[start:] if start >= 0 and len(buf) - start <= ASCII_MAX_LINE else b""
                break
            line, buf = buf[:end], buf[end + 2:]
            start = line.rfind(b":")  # ':' always starts a new message
            if start < 0:
                continue  # a line without ':' is noise
            try:
                raw = binascii.a2b_hex(line[start + 1:])
            except (binascii.Error, ValueError):
                continue  # not hex: dropped
            if len(raw) < 3 or sum(raw) & 0xFF:
                continue  # too short or a wrong LRC: dropped silently (8.3 defines no answer)
            frames.append(Frame(raw[0], raw[1:-1]))
        self.buf = buf
        return frames

    @staticmethod
    def encode(frame: Frame, pdu: bytes) -> bytes:
        adu = bytes([frame.unit]) + pdu
        lrc = -sum(adu) & 0xFF
        return b":" + binascii.b2a_hex(adu + bytes([lrc])).upper() + b"\r\n"


class MbapReceiver:
    """Modbus TCP: a 7-byte MBAP header (transaction, protocol 0, length, unit) before the
    PDU. A header that is not Modbus (protocol id not 0, length outside 2-254) leaves no way
    to find the next frame: the connection is closed, as Modbus TCP devices do."""

    def __init__(self) -> None:
        self.buf = b""
        self.broken = False  # the stream has lost its frame boundaries: close after answering

    def feed(self, data: bytes, now: float) -> list[Frame]:
        buf = self.buf + data
        frames = []
        while len(buf) >= 7:
            tid, pid, length, unit = struct.unpack(">HHHB", buf[:7])
            if pid != 0 or not 2 <= length <= 254:
                self.broken = True
                buf = b""
                break
            if len(buf) < 6 + length:
                break
            frames.append(Frame(unit, buf[7:6 + length], tid))
            buf = buf[6 + length:]
        self.buf = buf
        return frames

    @staticmethod
    def encode(frame: Frame, pdu: bytes) -> bytes:
        return struct.pack(">HHHB", frame.tid, 0, len(pdu) + 1, frame.unit) + pdu


RECEIVERS = {"rtu": RtuReceiver, "ascii": AsciiReceiver, "tcp": MbapReceiver}


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
        quiet_pymodbus()
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
            asyncio.get_running_loop().remove_reader(self._port.fileno())
            self._port.close()
            self._port = None

    def answer(self, frame: Frame) -> bytes | None:
        unit = frame.unit
        if self.framing == "tcp" and unit == UNIT_ANY and len(self.line.devices) == 1:
            unit = next(iter(self.line.devices))  # a device addressed by its IP alone
        reply = self.line.answer(unit, frame.pdu)
        if reply is None and self.framing == "tcp" and frame.unit and frame.unit not in self.line.devices:
            # Modbus TCP clients wait for every reply: as a gateway, say nobody is there
            reply = bytes([frame.pdu[0] | 0x80, GATEWAY_NO_RESPONSE])
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
        import serial  # pyserial

        try:
            port = serial.Serial(self.serial, self.baudrate, bytesize=8, parity="N", stopbits=1,
                                 timeout=0, write_timeout=WRITE_TIMEOUT_S)
        except (serial.SerialException, ValueError) as e:
            raise OSError(str(e)) from None
        receiver = RECEIVERS[self.framing]()
        loop = asyncio.get_running_loop()

        def readable() -> None:
            try:
                data = port.read(READ_CHUNK)
            except (serial.SerialException, OSError):
                return
            if data:
                for f in receiver.feed(data, loop.time()):
                    if (reply := self.answer(f)) is not None:
                        try:
                            port.write(receiver.encode(f, reply))
                        except (serial.SerialException, OSError):
                            pass  # nobody reads the line: the reply is lost, as on a bus

        loop.add_reader(port.fileno(), readable)
        self._port = port


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
