"""RS S m D n n1 (6-10 FNC 80): non-protocol serial send and receive on port CPn1, on the
virtual clock of sim/hardware/seriallink.py.

Per port (target.toml [serial_ports], + stride per port): send request M9100, receive done
M9101, receive time-out M9102, send remaining D9102 ("送信剩餘資料數"), received count D9101.
m and n count bytes ("組"); M9161 (`eight_bit`) chooses how they sit in words: Off 16-bit
(each word two bytes, low byte first), On 8-bit (the low byte of each word, the high byte
unused), as the page's two timing diagrams show (m = K5: D0L D0H D1L D1H D2L / D0L-D4L).
The port's start and end characters (7-3-8, the stimulus `port` line) frame both directions.
While the condition is On:

- send: the request found On starts sending [start] S.. (m bytes) [end] at the execution's
  time, one character time a byte (start, data, parity, stop bits at the port's baud); every
  execution writes the data bytes not yet sent to the remaining register, and the one that
  finds the last byte out turns the request Off ("M9100 turns Off by itself").
- receive: the PLC waits for data while M9101 is Off. Bytes that reached the port since the
  last execution are taken in order: with a start character, bytes before it are dropped;
  data bytes go to D.. as they come and the count register follows; the message ends (M9101
  On) with n bytes, the end character, or a gap longer than the port's time-out after the
  first byte (M9102 and M9101 On). Start and end characters are not stored or counted.

DECISIONS: m = 0 completes at once, n = 0 receives nothing (the page: K0 when not needed);
the condition going Off abandons a send in progress (remaining 0, the request relay as the
program left it) and drops a message half received; bytes arriving while M9101 is On (or
after the end of a message, until the program resets M9101) are lost; the program's
RST M9101 is seen by the next execution, which clears M9102 and the count and waits again
(the page: resetting M9101 resets M9102); a port the model lacks is a run-time fault.
"""

from __future__ import annotations

from mlctool.sim.hardware import seriallink
from mlctool.sim.state import Machine, SimFault
from mlctool.targets.vs.common import op_error, relay

MAX_UNITS = 4096  # m, n = 0..4096 (6-10 page note)


def _ports(m: Machine) -> dict:
    return m.target.settings.get("serial_ports", {})


def _number(m: Machine, key: str, port: int) -> int:
    return _ports(m)[key] + _ports(m).get("stride", 10) * (port - 1)


def _set(m: Machine, kind: str, n: int, value: int) -> None:
    (m.bits if kind == "M" else m.words)[kind][n] = value
    m.writer[(kind, n)] = m.pc


def rs(m: Machine, s) -> None:
    src, count_ref, dst, n_ref, port_ref = s.ops
    port = port_ref.get(m)
    seriallink.check_port(m, s, port)
    sending = m.ext.setdefault("rs_sending", {})
    receiving = m.ext.setdefault("rs_receiving", {})
    if not m.acc:
        if sending.pop(port, None) is not None:
            m.words["D"][_number(m, "rs_remaining_register", port)] = 0
        receiving.pop(port, None)
        return
    _send(m, s, sending, src, count_ref, port)
    _receive(m, s, receiving, dst, n_ref, port)


def _send(m: Machine, s, sending: dict, src, count_ref, port: int) -> None:
    remaining = _number(m, "rs_remaining_register", port)
    request = _number(m, "rs_send_relay", port)
    state = sending.get(port)
    if state is None and m.bits["M"][request]:
        units = count_ref.get(m)
        if not 0 <= units <= MAX_UNITS:
            op_error(m, s, f"m = {units}: must be 0-{MAX_UNITS}")
            return
        state = sending[port] = _start(m, src, units, port)
    if state is None:
        return
    link = seriallink.port(m, f"CP{port}").settings
    sent = min(state["total"], _chars_sent(m.now_us - state["start_us"], link))
    head = state["total"] - state["bytes"] - state["tail"]
    left = state["bytes"] - min(state["bytes"], max(0, sent - head))
    _set(m, "D", remaining, left)
    if sent >= state["total"]:
        _set(m, "M", request, 0)
        del sending[port]


def _chars_sent(elapsed_us: int, link: seriallink.LineSettings) -> int:
    bits = 1 + link.data_bits + (0 if link.parity == "none" else 1) + 1
    return elapsed_us * link.baud // (bits * 1_000_000)


def _start(m: Machine, src, units: int, port: int) -> dict:
    """[start] the m bytes of S.. [end] go on the line from now (kept in the port's log)."""
    eight = bool(relay(m, "eight_bit"))
    words = m.words[src.kind]
    n_words = units if eight else -(-units // 2)
    a = src.addr(m, max(n_words, 1))
    data = bytearray()
    for k in range(units):
        w = words[a + (k if eight else k // 2)]
        data.append(w & 0xFF if eight or k % 2 == 0 else (w >> 8) & 0xFF)
    link = seriallink.port(m, f"CP{port}")
    head = bytes([link.start]) if link.start is not None else b""
    tail = bytes([link.end]) if link.end is not None else b""
    frame = head + bytes(data) + tail
    link.exchanges.append(seriallink.Exchange(m.now_us, frame, m.now_us + link.settings.char_us(len(frame))))
    del link.exchanges[:-64]
    return {"start_us": m.now_us, "bytes": units, "total": len(frame), "tail": len(tail)}


def _receive(m: Machine, s, receiving: dict, dst, n_ref, port: int) -> None:
    done_relay = _number(m, "rs_receive_relay", port)
    timeout_relay = _number(m, "rs_timeout_relay", port)
    count_reg = _number(m, "rs_received_register", port)
    link = seriallink.port(m, f"CP{port}")
    st = receiving.get(port)
    if st is None:  # the first execution with the condition On: waiting from now
        st = receiving[port] = {"from": m.now_us, "done": bool(m.bits["M"][done_relay]), "got": 0,
                                "started": False, "last": None}
    if m.bits["M"][done_relay]:  # a message is waiting for the program: nothing is taken
        st["done"], st["from"] = True, m.now_us
        return
    if st["done"]:  # the program reset M9101: M9102 and the count clear, waiting again
        _set(m, "M", timeout_relay, 0)
        _set(m, "D", count_reg, 0)
        st.update(done=False, got=0, started=False, last=None)
    n = n_ref.get(m)
    if not 0 <= n <= MAX_UNITS:
        op_error(m, s, f"n = {n}: must be 0-{MAX_UNITS}")
        return
    eight = bool(relay(m, "eight_bit"))
    arrived = [(t, b) for t, b in link.incoming if st["from"] < t <= m.now_us]
    link.incoming[:] = [(t, b) for t, b in link.incoming if t > m.now_us]
    st["from"] = m.now_us
    if n == 0:
        return
    timeout = link.timeout_us
    for t, b in arrived:
        if st["last"] is not None and t - st["last"] > timeout:
            _end(m, st, done_relay, timeout_relay)
            return
        if not st["started"]:
            if link.start is not None and b != link.start:
                continue  # not yet the start character: dropped
            st["started"], st["last"] = True, t
            if link.start is not None:
                continue
        st["last"] = t
        if link.end is not None and b == link.end:
            _end(m, st, done_relay)
            return
        _store(m, dst, st["got"], b, eight)
        st["got"] += 1
        _set(m, "D", count_reg, st["got"])
        if st["got"] >= n:
            _end(m, st, done_relay)
            return
    if st["last"] is not None and m.now_us - st["last"] > timeout:
        _end(m, st, done_relay, timeout_relay)


def _store(m: Machine, dst, k: int, b: int, eight: bool) -> None:
    a = dst.addr(m, (k if eight else k // 2) + 1) + (k if eight else k // 2)
    if a > dst.hi:
        raise SimFault(f"RS: received byte {k + 1} goes to {dst.kind}{a}, past {dst.kind}{dst.hi}")
    words = m.words[dst.kind]
    if eight:
        words[a] = b
    elif k % 2 == 0:
        words[a] = b  # a new word: the low byte, the high byte 0 until its byte comes
    else:
        words[a] = (words[a] & 0xFF) | b << 8
    m.writer[(dst.kind, a)] = m.pc


def _end(m: Machine, st: dict, done_relay: int, timeout_relay: int | None = None) -> None:
    _set(m, "M", done_relay, 1)
    if timeout_relay is not None:
        _set(m, "M", timeout_relay, 1)
    st["done"] = True


SERIAL_RS_ACTIONS = {"rs": rs}
