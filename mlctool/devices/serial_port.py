"""A serial port served on the running asyncio loop with one of framing.py's receivers:
bytes in, whole frames to a handler, replies out. Shared by the two Modbus servers on a
serial line, `mlc device serve` (devices/xc100/server.py) and `mlc run --serve rtu:...`
(commission/net.py), so the port's options and its failure rules are said once."""

from __future__ import annotations

import asyncio
from collections.abc import Callable

from mlctool.devices.framing import RECEIVERS, Frame

READ_CHUNK = 4096


class SerialLine:
    """An open port (8N1, non-blocking) whose frames go to `on_frame` as they complete."""

    def __init__(self, device: str, baud: int, framing: str, on_frame: Callable[[Frame], None],
                 write_timeout_s: float):
        import serial  # pyserial: only a serial line needs it

        self._errors = (serial.SerialException, OSError)
        try:
            self.port = serial.Serial(device, baud, bytesize=8, parity="N", stopbits=1, timeout=0,
                                      write_timeout=write_timeout_s)
        except (serial.SerialException, ValueError) as e:
            raise OSError(str(e)) from None
        self.receiver = RECEIVERS[framing]()
        self._on_frame = on_frame
        self._loop = asyncio.get_running_loop()
        self._loop.add_reader(self.port.fileno(), self._readable)

    def _readable(self) -> None:
        try:
            data = self.port.read(READ_CHUNK)
        except self._errors:
            return
        for f in self.receiver.feed(data, self._loop.time()) if data else ():
            self._on_frame(f)

    def reply(self, frame: Frame, pdu: bytes) -> None:
        try:
            self.port.write(self.receiver.encode(frame, pdu))
        except self._errors:
            pass  # nobody reads the line: the reply is lost, as on a bus

    def close(self) -> None:
        self._loop.remove_reader(self.port.fileno())
        self.port.close()
