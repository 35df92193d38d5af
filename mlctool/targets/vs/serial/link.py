"""PLC-to-PLC links of the Vigor VS (manual 003): LINK S1 S2 n (6-10 FNC 89, EASY LINK, the
"VS Computer Link Master" of 7-3-3) and CPUL S1 S2 n (6-10 FNC 87, CPU Link, 7-3-7), working
through `.table` rows (docs/vs.md "LINK and CPUL") with peer stations modelled as
`model vsplc link=CPn station=k` (mlctool/devices/vsplc.py, memory in targets/vs/serial/peers.py).

Both: while the condition is On the table's rows run one after the other, over and over; Off
stops at once. S2 is cleared before the first row (LINK page: "會先將D100清除為0"; CPUL:
DECISION, the same); the first error is kept in S2 (low byte status, high byte station) until
the program clears it; S2+1 = the row in progress (1-based, DECISION as MBUS). Status: 0
normal, 4 device error (LINK: DECISION, a word device paired with a bit device), 0AH no
answer (time-out), 0BH communication error (two peers with one station number).

Time on the virtual clock. A row's message takes (11 + data bytes) x 11 bits / baud (+20 us
for CPUL), the estimate the manual prints in 7-3-7 (DECISION: LINK's request and answer use
it too, data bytes counted in the direction that carries them). LINK follows the scan, as
MBUS (7-3-7: "Easy Link ... 依循PLC的掃描週期"): the LINK execution of the first scan after a
row's answer is complete takes it and starts the next row; done relay M9104 (+10 per port)
On for one scan per pass, error relay M9103 On at an error. CPUL is processed "in real time,
not by the scan" (6-10): each execution completes every row whose time has passed, one
after another from the start, so a pass of rows takes exactly the sum of the row times.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from mlctool.sim.hardware import seriallink
from mlctool.sim.state import Machine, SimFault
from mlctool.targets.vs.serial import peers
from mlctool.targets.vs.serial.mbus import _enabled, _set_relay, tables

OK, DEVICE_ERROR, TIMEOUT, COMM_ERROR = 0, 4, 0x0A, 0x0B
READ, WRITE = 0, 1
BROADCAST = 255


@dataclass
class LinkState:
    kind: str  # LINK | CPUL
    owner: int  # step index of the instruction
    table: int
    work: tuple[str, int]
    rows: list
    row: int = 0
    busy_until: int | None = None  # the row in flight completes (us)
    status: int = OK  # its outcome
    snapshot: list = field(default_factory=list)  # LINK write: the values sent
    clock: int = 0  # CPUL: when the next row starts
    done_on: bool = False


def _message_us(data_bytes: int, baud: int, extra_us: int = 0) -> int:
    return -(-(11 + data_bytes) * 11 * 1_000_000 // baud) + extra_us


def _bytes(kind: str, length: int) -> int:
    return -(-length // 8) if kind in peers.BIT_KINDS else 2 * length


def _write_work(m: Machine, st: LinkState, offset: int, value: int) -> None:
    kind, a = st.work
    m.words[kind][a + offset] = value & 0xFFFF
    m.writer[(kind, a + offset)] = m.pc


def _error(m: Machine, st: LinkState, status: int, station: int, n: int | None) -> None:
    kind, a = st.work
    if m.words[kind][a] == 0:
        _write_work(m, st, 0, station << 8 | status)
    if n is not None:
        _set_relay(m, "error_relay", n, True)


def _begin(m: Machine, s, kind: str) -> tuple[int, seriallink.Port, LinkState | None]:
    n = s.ops[2].get(m)
    seriallink.check_port(m, s, n)
    port = seriallink.port(m, f"CP{n}")
    st = port.master if isinstance(port.master, LinkState) and port.master.owner == s.index else None
    return n, port, st


def _start(m: Machine, s, port: seriallink.Port, kind: str) -> LinkState:
    q = s.ins.operands[0].number + s.ops[0].index_value(m)
    rows = tables(m, kind).get(q)
    if not rows:
        raise SimFault(f"{kind} {s.ins.texts[0]}: table Q{q} has no rows (.table Q{q} {kind} ...)")
    if kind == "CPUL":
        for r in rows:
            dev, length = r.fields["devices"], r.value("length")
            if dev.kind in peers.BIT_KINDS and (dev.number % 8 or length % 8):
                raise SimFault(f"CPUL table Q{q}: {dev.kind}{dev.number} x {length}: a bit range starts "
                               "at a multiple of 8 and is 8n long (6-10 CPUL)")
    st = LinkState(kind, s.index, q, (s.ins.operands[1].kind, s.ops[1].addr(m, 4)), rows, clock=m.now_us)
    port.master = st
    _write_work(m, st, 0, 0)
    return st


def _next_row(m: Machine, st: LinkState) -> int | None:
    """Index of the next enabled row from st.row (wrapping), None when every row is disabled."""
    for k in range(len(st.rows)):
        i = (st.row + k) % len(st.rows)
        if _enabled(m, st.rows[i]):
            return i
    return None


# ---------------------------------------------------------------- LINK (FNC 89)

def link(m: Machine, s) -> None:
    n, port, st = _begin(m, s, "LINK")
    if not m.acc:
        if st is not None:
            if st.done_on:
                _set_relay(m, "done_relay", n, False)
            port.master = None
        return
    if st is None:
        st = _start(m, s, port, "LINK")
        _set_relay(m, "error_relay", n, False)
    if st.done_on:
        _set_relay(m, "done_relay", n, False)
        st.done_on = False
    if st.busy_until is not None:
        if m.now_us < st.busy_until:
            return
        _finish_link(m, port, st, n)
    i = _next_row(m, st)
    if i is None:
        return
    st.row = i
    _write_work(m, st, 1, i + 1)
    _send_link(m, port, st)


def _send_link(m: Machine, port: seriallink.Port, st: LinkState) -> None:
    row = st.rows[st.row]
    cmd, station, length = row.value("command"), row.value("station"), row.value("length")
    master, slave = row.fields["master"], row.fields["slave"]
    data = _bytes(master.kind, length)
    baud = port.settings.baud
    request = _message_us(data if cmd == WRITE else 0, baud)
    st.snapshot = peers.own_block(m, master.kind, master.number, length) if cmd == WRITE else []
    if station == BROADCAST:
        st.busy_until, st.status = m.now_us + request, OK
        return
    answering = [p for p in port.stations.get(station, {}).values() if p.answers(port)]
    if not answering:
        st.busy_until, st.status = m.now_us + request + port.timeout_us, TIMEOUT
        return
    answer = _message_us(data if cmd == READ else 0, baud)
    st.busy_until = m.now_us + request + answering[0].reply_us + answer
    mismatch = (master.kind in peers.BIT_KINDS) != (slave.kind in peers.BIT_KINDS)
    st.status = COMM_ERROR if len(answering) > 1 else DEVICE_ERROR if mismatch else OK


def _finish_link(m: Machine, port: seriallink.Port, st: LinkState, n: int) -> None:
    row = st.rows[st.row]
    station, length = row.value("station"), row.value("length")
    master, slave = row.fields["master"], row.fields["slave"]
    p = int(port.name[2:])
    if st.status != OK:
        _error(m, st, st.status, station, n)
    elif row.value("command") == READ:
        peers.set_own_block(m, master.kind, master.number,
                            peers.peer_block(m, p, station, slave.kind, slave.number, length))
    else:
        targets = ([k for k, ps in port.stations.items() if any(x.answers(port) for x in ps.values())]
                   if station == BROADCAST else [station])
        for k in targets:
            peers.set_peer_block(m, p, k, slave.kind, slave.number, st.snapshot)
    st.busy_until = None
    st.row += 1
    if not any(_enabled(m, r) for r in st.rows[st.row:]):
        st.row = 0
        _set_relay(m, "done_relay", n, True)  # the whole table once (6-10 LINK ■M9104)
        st.done_on = True


# ---------------------------------------------------------------- CPUL (FNC 87)

def cpul(m: Machine, s) -> None:
    _n, port, st = _begin(m, s, "CPUL")
    if not m.acc:
        if st is not None:
            port.master = None
        return
    if st is None:
        st = _start(m, s, port, "CPUL")
    while True:
        if st.busy_until is None:
            i = _next_row(m, st)
            if i is None:
                st.clock = m.now_us
                return
            st.row = i
            _write_work(m, st, 1, i + 1)
            st.busy_until = st.clock + _cpul_row_us(m, port, st)
        if st.busy_until > m.now_us:
            return
        _finish_cpul(m, port, st)
        st.clock, st.busy_until = st.busy_until, None
        st.row += 1


def _cpul_row_us(m: Machine, port: seriallink.Port, st: LinkState) -> int:
    row = st.rows[st.row]
    station = row.value("station")
    dev = row.fields["devices"]
    t = _message_us(_bytes(dev.kind, row.value("length")), port.settings.baud, 20)  # 7-3-7
    answering = [p for p in port.stations.get(station, {}).values() if p.answers(port)]
    st.status = OK if station == port.station or len(answering) == 1 else \
        COMM_ERROR if answering else TIMEOUT
    return t + (port.timeout_us if st.status == TIMEOUT else 0)


def _finish_cpul(m: Machine, port: seriallink.Port, st: LinkState) -> None:
    row = st.rows[st.row]
    station, length, dev = row.value("station"), row.value("length"), row.fields["devices"]
    p = int(port.name[2:])
    if st.status != OK:
        _error(m, st, st.status, station, None)
        return
    if station == port.station:
        values = peers.own_block(m, dev.kind, dev.number, length)
    else:
        values = peers.peer_block(m, p, station, dev.kind, dev.number, length)
        peers.set_own_block(m, dev.kind, dev.number, values)
    for k, ps in port.stations.items():  # every other station takes the sender's data
        if k != station and any(x.answers(port) for x in ps.values()):
            peers.set_peer_block(m, p, k, dev.kind, dev.number, values)


PLC_LINK_ACTIONS = {"link": link, "cpul": cpul}
