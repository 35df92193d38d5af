"""RS S m D n n1 (6-10 FNC 80): non-protocol serial send and receive on port CPn1, on the
virtual clock of sim/seriallink.py.

Per port (target.toml [serial_ports], + stride per port): send request M9100, receive done
M9101, send remaining D9102 ("送信剩餘資料數"), received count D9101. M9161 (`eight_bit`)
chooses the data unit: Off 16-bit (two bytes a word, low byte first), On 8-bit (the low byte
of each word). While the condition is On:

- the send request found On starts sending S..S+m-1 at the execution's time; each byte takes
  the port's character time (start bit, data bits, parity, stop bit at its baud: the settings
  of the device attached to the port, else 19200 8N1, seriallink.LineSettings); every
  execution writes the units not yet sent to the remaining register, and the one that finds
  the last byte sent turns the send request Off (the manual: "M9100 turns Off by itself").
- receiving: nothing arrives without a device on the port (a device model that answers RS
  frames is not written yet): the receive done relay and count stay as they are.

DECISIONS: the remaining count is in the instruction's units (words in the 16-bit mode,
bytes in the 8-bit mode), m = 0 completes at once; the condition going Off abandons a send
in progress (the remaining register 0; the request relay stays as the program left it, so
the next On sends again from the start).
"""

from __future__ import annotations

from mlctool.sim import seriallink
from mlctool.sim.fx.common import op_error, relay
from mlctool.sim.state import Machine, SimFault

MAX_UNITS = 4096  # m, n = 0..4096 (6-10 page note)


def _ports(m: Machine) -> dict:
    return m.target.settings.get("serial_ports", {})


def _port_count(m: Machine) -> int:
    count = _ports(m).get("count", {})
    return count.get(m.target.model or "", max(count.values(), default=5)) if isinstance(count, dict) else count


def _number(m: Machine, key: str, port: int) -> int:
    return _ports(m)[key] + _ports(m).get("stride", 10) * (port - 1)


def _bits_per_char(settings: seriallink.LineSettings) -> int:
    return 1 + settings.data_bits + (0 if settings.parity == "none" else 1) + 1


def rs(m: Machine, s) -> None:
    src, count_ref, _dst, _n_ref, port_ref = s.ops
    port = port_ref.get(m)
    if not 1 <= port <= _port_count(m):
        raise SimFault(f"RS {' '.join(s.ins.texts)}: port CP{port} does not exist on this model "
                       f"(CP1-CP{_port_count(m)})")
    sending = m.ext.setdefault("rs_sending", {})
    remaining = _number(m, "rs_remaining_register", port)
    request = _number(m, "rs_send_relay", port)
    if not m.acc:
        if sending.pop(port, None) is not None:
            m.words["D"][remaining] = 0
        return
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
    sent = min(state["bytes"], (m.now_us - state["start_us"]) * link.baud // (_bits_per_char(link) * 1_000_000))
    left = state["bytes"] - sent
    m.words["D"][remaining] = -(-left // state["per_unit"])
    m.writer[("D", remaining)] = m.pc
    if left == 0:
        m.bits["M"][request] = 0
        m.writer[("M", request)] = m.pc
        del sending[port]


def _start(m: Machine, src, units: int, port: int) -> dict:
    """The bytes of S..S+units-1 go on the line from now (kept in the port's log)."""
    eight = bool(relay(m, "eight_bit"))
    words = m.words[src.kind]
    a = src.addr(m, max(units, 1))
    data = bytearray()
    for w in words[a:a + units]:
        data += bytes([w & 0xFF]) if eight else bytes([w & 0xFF, (w >> 8) & 0xFF])
    link = seriallink.port(m, f"CP{port}")
    link.exchanges.append(seriallink.Exchange(m.now_us, bytes(data), m.now_us + link.settings.char_us(len(data))))
    del link.exchanges[:-64]
    return {"start_us": m.now_us, "bytes": len(data), "per_unit": 1 if eight else 2}


SERIAL_RS_ACTIONS = {"rs": rs}
