"""The simulated PLC as a Modbus slave: one request PDU in, one response PDU out (Modbus
application protocol 1.1b, functions 01-06, 0F, 10). Framing is devices/framing.py's.

Two halves, on two threads:
- `parse` (the network thread): checks the request against the protocol and the map and
  the write permissions, and either answers at once (an exception) or gives a Request, every
  address already resolved to its device;
- `Request.execute` (the scan thread, between two scans): reads or writes the machine and
  builds the reply. It does nothing that can fail on a well-formed Request.

Exceptions (DECISION where the protocol leaves the choice): 01 a function not served; 03 a
quantity outside the protocol's limits or a byte count that does not match it; 02 an address
not mapped, and a write to a device the client may not write (Modbus has no "read only"
code; 02 is what FX and DVP slaves answer for it); 06 (busy) when the scan loop's queue is
full (commission/exchange.py).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from mlctool.commission.modbus_map import Map, Permissions
from mlctool.devices.framing import ILLEGAL_ADDRESS, ILLEGAL_FUNCTION, ILLEGAL_VALUE, exception_pdu
from mlctool.sim.state import Machine, s32

READ_COILS, READ_INPUTS, READ_HOLDING, READ_INPUT_REGS = 0x01, 0x02, 0x03, 0x04
WRITE_COIL, WRITE_REGISTER, WRITE_COILS, WRITE_REGISTERS = 0x05, 0x06, 0x0F, 0x10
# quantities per request (Modbus application protocol 1.1b, 6.1-6.12)
MAX_READ_BITS, MAX_READ_WORDS, MAX_WRITE_BITS, MAX_WRITE_WORDS = 2000, 125, 1968, 123

_READS = {READ_COILS: ("coils", MAX_READ_BITS), READ_INPUTS: ("discrete_inputs", MAX_READ_BITS),
          READ_HOLDING: ("holding", MAX_READ_WORDS), READ_INPUT_REGS: ("input_registers", MAX_READ_WORDS)}


@dataclass(slots=True)
class Request:
    fc: int
    addr: int
    cells: list[tuple[str, int, int]]  # (device, number, half) per address
    values: list[int] | None = None  # writes: one per cell
    echo: bytes = b""  # the reply of a write (fixed by the request)

    def execute(self, m: Machine) -> bytes:
        """Read or write `m` (the scan thread, between scans) and the reply PDU."""
        if self.values is None:
            if self.fc in (READ_COILS, READ_INPUTS):
                bits = [_read_bit(m, d, n) for d, n, _ in self.cells]
                packed = bytearray((len(bits) + 7) // 8)
                for i, b in enumerate(bits):
                    if b:
                        packed[i >> 3] |= 1 << (i & 7)
                return bytes([self.fc, len(packed)]) + bytes(packed)
            words = [_read_word(m, d, n, h) for d, n, h in self.cells]
            return bytes([self.fc, 2 * len(words)]) + struct.pack(f">{len(words)}H", *words)
        if self.fc in (WRITE_COIL, WRITE_COILS):
            for (d, n, _), v in zip(self.cells, self.values):
                m.bits[d][n] = v
                m.writer.pop((d, n), None)
        else:
            for (d, n, h), v in zip(self.cells, self.values):
                _write_word(m, d, n, h, v)
        return self.echo


def _read_bit(m: Machine, device: str, n: int) -> int:
    if device == "Y" and m.outputs_disabled():
        return 0  # the terminals, as DeviceView.read shows them
    return m.bits[device][n]


def _read_word(m: Machine, device: str, n: int, half: int) -> int:
    if device == "C":
        value = m.cval[n]
        return (value & 0xFFFFFFFF) >> (16 * half) & 0xFFFF if m.is_c32(n) else value & 0xFFFF
    return m.words[device][n] & 0xFFFF


def _write_word(m: Machine, device: str, n: int, half: int, v: int) -> None:
    if device == "C":
        if m.is_c32(n):
            raw = m.cval[n] & 0xFFFFFFFF
            raw = (raw & ~(0xFFFF << (16 * half))) | (v << (16 * half))
            m.cval[n] = s32(raw)
        else:
            m.cval[n] = v
    else:
        m.words[device][n] = v
    m.writer.pop((device, n), None)


def parse(pdu: bytes, mapping: Map, perms: Permissions) -> Request | bytes:
    """A Request, or the reply to send at once (an exception PDU)."""
    if not pdu:
        return exception_pdu(0, ILLEGAL_FUNCTION)
    fc = pdu[0]
    if fc in _READS:
        table, limit = _READS[fc]
        if len(pdu) != 5:
            return exception_pdu(fc, ILLEGAL_VALUE)
        addr, count = struct.unpack(">HH", pdu[1:5])
        if not 1 <= count <= limit:
            return exception_pdu(fc, ILLEGAL_VALUE)
        cells = mapping.resolve(table, addr, count)
        return exception_pdu(fc, ILLEGAL_ADDRESS) if cells is None else Request(fc, addr, cells)
    if fc in (WRITE_COIL, WRITE_REGISTER):
        if len(pdu) != 5:
            return exception_pdu(fc, ILLEGAL_VALUE)
        addr, value = struct.unpack(">HH", pdu[1:5])
        if fc == WRITE_COIL:
            if value not in (0x0000, 0xFF00):
                return exception_pdu(fc, ILLEGAL_VALUE)
            values = [1 if value else 0]
        else:
            values = [value]
        return _write(fc, addr, values, "coils" if fc == WRITE_COIL else "holding", mapping, perms, pdu)
    if fc in (WRITE_COILS, WRITE_REGISTERS):
        if len(pdu) < 6:
            return exception_pdu(fc, ILLEGAL_VALUE)
        addr, count, size = struct.unpack(">HHB", pdu[1:6])
        data = pdu[6:]
        bits = fc == WRITE_COILS
        limit = MAX_WRITE_BITS if bits else MAX_WRITE_WORDS
        need = (count + 7) // 8 if bits else 2 * count
        if not 1 <= count <= limit or size != need or len(data) != size:
            return exception_pdu(fc, ILLEGAL_VALUE)
        if bits:
            values = [(data[i >> 3] >> (i & 7)) & 1 for i in range(count)]
        else:
            values = list(struct.unpack(f">{count}H", data))
        return _write(fc, addr, values, "coils" if bits else "holding", mapping, perms, pdu[:5])
    return exception_pdu(fc, ILLEGAL_FUNCTION)


def _write(fc: int, addr: int, values: list[int], table: str, mapping: Map, perms: Permissions,
           echo: bytes) -> Request | bytes:
    cells = mapping.resolve(table, addr, len(values))
    if cells is None or not all(perms.writable(d, n) for d, n, _ in cells):
        return exception_pdu(fc, ILLEGAL_ADDRESS)
    return Request(fc, addr, cells, values, echo)
