"""The XC100 as a real Modbus server (pymodbus does the framing and the serving).

pymodbus decodes RTU (CRC-16) and ASCII (LRC) frames and runs the TCP or serial transport;
every PDU, whatever its function code, goes to modbus.handle_pdu, which answers the way the
XC100 does (8.3) rather than the way a generic server would. Two receiver rules of the line
are added to pymodbus's framers:
- RTU: bytes left over from a damaged frame are dropped after a silence of more than
  RTU_GAP_S (the bus's inter-frame gap), so the next request is read cleanly;
- ASCII: ':' always starts a new message, so junk before it never eats a good frame.
The model advances on the server's clock (the wall clock of this process); the model itself
only sees time steps.
"""

from __future__ import annotations

import asyncio
import time

from pymodbus.datastore import ModbusServerContext
from pymodbus.exceptions import NoSuchIdException
from pymodbus.framer import FramerAscii, FramerRTU, FramerType
from pymodbus.pdu import DecodePDU, ModbusPDU
from pymodbus.server import ModbusSerialServer, ModbusTcpServer

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


class XC100Context(ModbusServerContext):
    """Routes requests to the device; pymodbus treats it as a legacy simulator context."""

    def __init__(self, dev: c.Xc100, station: int) -> None:  # noqa: D107 - no super(): no datastore
        self.dev = dev
        self.station = station
        self.old_simulator = True
        self.simdevices = []
        self._devices = {}

    def device_ids(self) -> list[int]:
        return [self.station]

    def handle(self, unit: int, pdu: bytes) -> bytes | None:
        return handle_pdu(self.dev, self.station, unit, pdu)


def make_server(dev: c.Xc100, station: int, framing: str, tcp: tuple[str, int] | None = None,
                serial: str | None = None, baudrate: int = 19200):
    """A pymodbus server for `dev` (call inside a running event loop)."""
    ctx = XC100Context(dev, station)
    kind = FramerType.ASCII if framing == "ascii" else FramerType.RTU
    common = dict(framer=kind, ignore_missing_devices=True, broadcast_enable=True)
    if tcp is not None:
        server = ModbusTcpServer(ctx, address=tcp, **common)
    else:
        server = ModbusSerialServer(ctx, port=serial, baudrate=baudrate, **common)
    server.decoder = XC100Decoder(True)
    server.framer = LineAscii if framing == "ascii" else LineRTU
    return server


async def run_device(dev: c.Xc100, server, duration_s: float | None,
                     on_tick=None, stop: asyncio.Event | None = None, on_ready=None) -> None:
    """Serve until `duration_s` passes or `stop` is set, advancing the model every tick."""
    await server.serve_forever(background=True)
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
            c.advance(dev, int((now - last) * 1e6))
            last = now
            if on_tick:
                on_tick()
    finally:
        await server.shutdown()
