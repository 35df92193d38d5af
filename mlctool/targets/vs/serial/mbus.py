"""MBUS S1 S2 n (Vigor VS, manual 003 6-13 FNC 149, 7-3-6): the PLC as Modbus master on
port CPn, working through the communication table S1 (`.table` rows, docs/vs.md "MBUS").

While the condition is On the table's rows are exchanged one after the other, over and
over; the whole table done turns the port's done relay (M9104 + 10(n-1)) On for one scan.
The condition going Off stops at once (a request still being sent is cut off). S2..S2+3 is
the work area: before the first row S2 is cleared; the first error is kept in S2 (low byte:
status, high byte: station) until the program clears S2, and turns the port's error relay
(M9103 + 10(n-1)) On. Status codes (6-13): 0 normal, 2 length error, 4 device error,
7 command error, 0AH time-out (no answer), 0BH communication error.

Timing: the exchange is done on the virtual clock of sim/hardware/seriallink.py. A request goes out
at the MBUS execution; its answer is taken (read data written, next row sent) by the MBUS
execution of the first scan that starts after the answer is complete, so a row takes at
least one scan, as the OS processes communication between scans (7-3-7).

Decisions where the manual is silent (docs/vs.md "MBUS"): exception 01 -> 7, 02 -> 4,
03 -> 2, any other answer that is not the expected one -> 0BH; time-out 500 ms unless the
link sets one; S2+1 = number of the row in progress (1-based); the error relay stays On
until the program resets it or MBUS starts again; rows whose disable contact is On are
skipped, and with every row disabled nothing is sent and the done relay stays Off.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import TYPE_CHECKING

from mlctool.sim.hardware import seriallink
from mlctool.sim.state import Machine, SimFault

if TYPE_CHECKING:
    from mlctool.check.tables import Row

KIND = "MBUS"
OK, LENGTH_ERROR, DEVICE_ERROR, COMMAND_ERROR, TIMEOUT, COMM_ERROR = 0, 2, 4, 7, 0x0A, 0x0B
EXCEPTION_STATUS = {1: COMMAND_ERROR, 2: DEVICE_ERROR, 3: LENGTH_ERROR}
READ, WRITE_ONE, WRITE_MANY = 0x03, 0x06, 0x10


@dataclass
class Master:
    """The MBUS instruction that holds port CPn, and where it is in its table."""

    owner: int  # step index of the MBUS instruction
    table: int  # Q number
    work: tuple[str, int]  # S2 (device kind, number)
    rows: list[Row]
    row: int = 0  # index of the row in flight or next
    exchange: seriallink.Exchange | None = None
    done_on: bool = False  # the done relay was turned On by the previous execution


def tables(m: Machine, kind: str = KIND) -> dict[int, list[Row]]:
    """Q number -> the rows of one table kind (MBUS, DTBL ...), from the program's `.table`
    directives (parsed once per run and kind)."""
    key = f"{kind.lower()}_tables"
    cache = m.ext.get(key)
    if cache is None:
        from mlctool.check.tables import parse_row  # the checker's reading of a row

        symbols = m.image.symbols if m.image is not None else {}
        cache = {}
        for _path, text in m.image.directives if m.image is not None else ():
            words = text.split()
            if words[0].lower() != ".table":
                continue
            row, _problems = parse_row(m.target, words[1:], symbols)  # checked at build
            if row is not None and row.kind == kind:
                cache.setdefault(row.table, []).append(row)
        m.ext[key] = cache
    return cache


def _relay(m: Machine, which: str, n: int) -> int | None:
    ports = m.target.settings.get("serial_ports", {})
    base = ports.get(which)
    return None if base is None else base + ports.get("stride", 10) * (n - 1)


def _set_relay(m: Machine, which: str, n: int, on: bool) -> None:
    r = _relay(m, which, n)
    if r is not None:
        m.bits["M"][r] = 1 if on else 0


def _write_work(m: Machine, st: Master, offset: int, value: int) -> None:
    kind, n = st.work
    m.words[kind][n + offset] = value & 0xFFFF
    m.writer[(kind, n + offset)] = m.pc


def mbus(m: Machine, s) -> None:
    n = s.ops[2].get(m)
    seriallink.check_port(m, s, n)
    port = seriallink.port(m, f"CP{n}")
    st = port.master if isinstance(port.master, Master) and port.master.owner == s.index else None
    if not m.acc:
        if st is not None:
            _stop(m, port, st, n)
        return
    q = s.ins.operands[0].number + s.ops[0].index_value(m)  # Q may be V/Z-indexed (1-3)
    if st is None or st.table != q:
        st = _start(m, s, port, q, n)
    if st.done_on:  # On for exactly one scan: from the completing MBUS to the next one
        _set_relay(m, "done_relay", n, False)
        st.done_on = False
    if st.exchange is not None and not _finish(m, port, st, n):
        return  # still waiting for the answer
    _send_next(m, port, st)


def _start(m: Machine, s, port: seriallink.Port, q: int, n: int) -> Master:
    rows = tables(m).get(q)
    if not rows:
        raise SimFault(f"MBUS {s.ins.texts[0]}: table Q{q} has no rows (.table Q{q} MBUS ...)")
    if isinstance(port.master, Master):  # another MBUS on this port: it stops
        _stop(m, port, port.master, n)
    work = s.ins.operands[1]
    st = Master(s.index, q, (work.kind, s.ops[1].addr(m, 4)), rows)
    port.master = st
    _write_work(m, st, 0, 0)  # 6-13: S2 is cleared before the first row
    _set_relay(m, "error_relay", n, False)
    return st


def _stop(m: Machine, port: seriallink.Port, st: Master, n: int) -> None:
    if st.exchange is not None and st.exchange.cancelled_us is None:
        st.exchange.cancelled_us = m.now_us
    if st.done_on:
        _set_relay(m, "done_relay", n, False)
    port.master = None


def _enabled(m: Machine, row: Row) -> bool:
    c = row.fields.get("disable")
    return c is None or not m.bits[c.kind][c.number]


def _send_next(m: Machine, port: seriallink.Port, st: Master) -> None:
    for _ in range(len(st.rows)):
        st.row %= len(st.rows)
        row = st.rows[st.row]
        if _enabled(m, row):
            _write_work(m, st, 1, st.row + 1)
            st.exchange = port.send(m.now_us, row.value("station"), request_pdu(m, row))
            return
        st.row += 1
    st.exchange = None  # every row disabled: nothing to send


def request_pdu(m: Machine, row: Row) -> bytes:
    fc, addr, count = row.value("command"), row.value("slave"), row.value("length")
    master = row.fields["master"]
    words = m.words[master.kind][master.number:master.number + count]
    if fc == READ:
        return struct.pack(">BHH", fc, addr, count)
    if fc == WRITE_ONE:
        return struct.pack(">BHH", fc, addr, words[0])
    return struct.pack(f">BHHB{count}H", fc, addr, count, 2 * count, *words)


def _finish(m: Machine, port: seriallink.Port, st: Master, n: int) -> bool:
    """Take the answer of the exchange in flight; False while it is not complete."""
    ex, row = st.exchange, st.rows[st.row]
    deadline = ex.arrive_us + port.timeout_us
    if ex.broadcast:
        if m.now_us < ex.arrive_us:
            return False
        status = OK
    elif ex.reply is not None and ex.reply_us <= deadline:
        if m.now_us < ex.reply_us:
            return False
        status = _take_reply(m, port, row, ex)
    elif m.now_us < deadline:
        return False
    else:
        status = TIMEOUT
    if status != OK:
        _error(m, st, n, status, row.value("station"))
    st.exchange = None
    st.row += 1
    if not any(_enabled(m, r) for r in st.rows[st.row:]):
        st.row = 0
        _set_relay(m, "done_relay", n, True)  # the whole table once (6-13 ■M9104)
        st.done_on = True
    return True


def _error(m: Machine, st: Master, n: int, status: int, station: int) -> None:
    kind, a = st.work
    if m.words[kind][a] == 0:  # only the first error is kept (6-13)
        _write_work(m, st, 0, station << 8 | status)
    _set_relay(m, "error_relay", n, True)


def _take_reply(m: Machine, port: seriallink.Port, row: Row, ex: seriallink.Exchange) -> int:
    got = seriallink.decode(port.settings, ex.reply)
    if got is None or got[0] != row.value("station") or not got[1]:
        return COMM_ERROR
    pdu, fc = got[1], row.value("command")
    if pdu[0] == fc | 0x80 and len(pdu) == 2:
        return EXCEPTION_STATUS.get(pdu[1], COMM_ERROR)
    if pdu[0] != fc:
        return COMM_ERROR
    if fc == READ:
        count = row.value("length")
        if len(pdu) != 2 + 2 * count or pdu[1] != 2 * count:
            return LENGTH_ERROR
        master = row.fields["master"]
        for k, w in enumerate(struct.unpack(f">{count}H", pdu[2:])):
            m.words[master.kind][master.number + k] = w
            m.writer[(master.kind, master.number + k)] = m.pc
        return OK
    request = seriallink.decode(port.settings, ex.request)[1]
    expected = request if fc == WRITE_ONE else request[:5]
    return OK if pdu == expected else COMM_ERROR


MBUS_ACTIONS = {"mbus": mbus}
