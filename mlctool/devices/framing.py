"""Modbus serial and TCP framing, the one home for it (mlctool/devices/): RTU (unit, PDU,
CRC-16), ASCII (':', hex, LRC, CR LF) and Modbus TCP (MBAP header). Pure functions and
stream receivers over bytes; nothing here reads a clock or opens a port (a receiver is told
the time of each chunk).

Users: `mlc device serve` (devices/xc100/server.py: byte streams from TCP or a serial port),
the simulated RS-485 line of `mlc sim` (sim/hardware/seriallink.py: whole frames with times, the PLC
master's requests and the device models' answers). Modbus application protocol 1.1b; the
XC100 manual 004 8.1 (frames), 8.4 (request lengths). Also here, as every Modbus server
here answers with them: the exception codes and the exception reply PDU (protocol 1.1b, 7).

Stream receiver rules:
- RTU: a frame's length follows from its function code and its CRC must match; after a
  damaged frame the receiver drops bytes until the line has been silent for more than
  RTU_GAP_S (the bus's inter-frame gap), so the next request is read cleanly;
- ASCII: ':' always starts a new message, so junk before it never eats a good frame;
- TCP: a header that is not Modbus leaves no way to find the next frame (`broken`).
"""

from __future__ import annotations

import binascii
import struct
from typing import NamedTuple

RTU_GAP_S = 0.02
MAX_PENDING = 1024  # bytes of an unfinished frame a receiver keeps (an RTU frame is <= 256)
ASCII_MAX_LINE = 513  # ':' + 2 x 255 hex + LRC (8.1)
FRAMINGS = ("ascii", "rtu", "tcp")
ILLEGAL_FUNCTION, ILLEGAL_ADDRESS, ILLEGAL_VALUE, SERVER_FAILURE, BUSY = 0x01, 0x02, 0x03, 0x04, 0x06
GATEWAY_NO_RESPONSE = 0x0B  # Modbus TCP: the unit behind the gateway did not answer


class Frame(NamedTuple):
    unit: int
    pdu: bytes
    tid: int = 0  # Modbus TCP transaction id, echoed in the reply


def exception_pdu(fc: int, code: int) -> bytes:
    """The exception reply to function `fc`: the function code with its high bit set, the code."""
    return bytes([fc | 0x80, code])


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


def lrc(data: bytes) -> int:
    """Modbus ASCII LRC: the two's complement of the byte sum (8.1)."""
    return -sum(data) & 0xFF


def encode(framing: str, frame: Frame, pdu: bytes) -> bytes:
    """The frame that carries `pdu` to or from `frame.unit` (and, for tcp, `frame.tid`)."""
    return RECEIVERS[framing].encode(frame, pdu)


def decode(framing: str, data: bytes) -> Frame | None:
    """One whole received frame (rtu or ascii) -> Frame; None when it is not a valid frame
    (a wrong CRC/LRC, not hex, too short)."""
    if framing == "ascii":
        if len(data) < 9 or data[:1] != b":" or data[-2:] != b"\r\n":
            return None
        try:
            raw = binascii.a2b_hex(data[1:-2])
        except (binascii.Error, ValueError):
            return None
        if len(raw) < 3 or lrc(raw[:-1]) != raw[-1]:
            return None
        return Frame(raw[0], raw[1:-1])
    if len(data) < 4 or crc16(data[:-2]) != data[-2] | data[-1] << 8:
        return None
    return Frame(data[0], data[1:-2])


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
        return b":" + binascii.b2a_hex(adu + bytes([lrc(adu)])).upper() + b"\r\n"


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
