"""The XC100's Modbus application layer (manual 004 ch. 8): one request PDU in, one response
PDU (or silence) out. Framing (RTU CRC-16, ASCII LRC, MBAP) is devices/framing.py's.

Rules of 8.2/8.3 kept here:
- only the controller's station answers (station = rotary CH + 1, 01H-10H); station 0 is a
  broadcast, executed only when 0A03H = 1 and never answered;
- function codes 03H, 06H, 10H; anything else is exception 01 with FC + 80H, and a function
  code already >= 80H is echoed unchanged (8.3 ②);
- exception priority: the lowest code wins (01 before 02 before 03).
"""

from __future__ import annotations

import struct

from mlctool.devices.framing import ILLEGAL_ADDRESS, ILLEGAL_FUNCTION, ILLEGAL_VALUE, exception_pdu
from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100 import registers as r

READ, WRITE_ONE, WRITE_MANY = 0x03, 0x06, 0x10
MAX_LOG = 8


def handle_pdu(dev: c.Xc100, station: int, unit: int, pdu: bytes) -> bytes | None:
    """Answer one request addressed to `unit`; None = no response on the line."""
    if unit != station and unit != 0:
        return None
    if not pdu:
        return None
    if unit == 0 and c.param(dev, "Broadcast") == 0:
        return None  # 5.8 0A03H = 0: broadcasts are ignored
    reply = _answer(dev, pdu)
    _log(dev, unit, pdu, reply)
    return None if unit == 0 else reply


def _answer(dev: c.Xc100, pdu: bytes) -> bytes:
    fc = pdu[0]
    if fc not in (READ, WRITE_ONE, WRITE_MANY):
        return exception_pdu(fc, ILLEGAL_FUNCTION)
    body = pdu[1:]
    if len(body) < 4:
        return exception_pdu(fc, ILLEGAL_VALUE)
    addr, second = struct.unpack(">HH", body[:4])
    if fc == READ:
        if len(body) != 4:
            return exception_pdu(fc, ILLEGAL_VALUE)
        words = r.read_words(dev, addr, second)
        if isinstance(words, int):
            return exception_pdu(fc, words)
        return bytes([fc, 2 * len(words)]) + b"".join(struct.pack(">H", w) for w in words)
    if fc == WRITE_ONE:  # the second field is the value (8.4 example: 201EH <- 0003H)
        if len(body) != 4:
            return exception_pdu(fc, ILLEGAL_VALUE)
        code = r.write_words(dev, addr, [second])
        return exception_pdu(fc, code) if code else pdu
    count = second
    data = body[5:]
    declared = body[4] if len(body) > 4 else -1
    if len(body) < 5 or declared != 2 * count or len(data) != declared:
        # 8.3 03: the data does not match the declared quantity; an address error still wins
        if _addresses_bad(addr, count):
            return exception_pdu(fc, ILLEGAL_ADDRESS)
        return exception_pdu(fc, ILLEGAL_VALUE)
    words = list(struct.unpack(f">{count}H", data))
    code = r.write_words(dev, addr, words)
    return exception_pdu(fc, code) if code else bytes([fc]) + struct.pack(">HH", addr, count)


def _addresses_bad(addr: int, count: int) -> bool:
    regs = r.register_map()
    if addr + count > 0x10000:
        return True
    return any(a not in regs or not regs[a].write for a in range(addr, addr + max(count, 1)))


def _log(dev: c.Xc100, unit: int, pdu: bytes, reply: bytes) -> None:
    text = f"unit {unit}: {pdu.hex(' ').upper()} -> {reply.hex(' ').upper()}"
    dev.requests = (dev.requests + [text])[-MAX_LOG:]
