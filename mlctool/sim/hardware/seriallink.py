"""A serial line (RS-485, half duplex) between the PLC's port CPn and device models, on
virtual time. Nothing here reads a clock or opens a device: frames are bytes with times.

The master (the MBUS routine, targets/vs/serial/mbus.py) puts a request frame on the line at time t;
it has arrived at every device at t + its transmission time. Device models, which step
before each scan (docs/stimulus.md), take the requests that arrived by then, handle each
at its arrival time and answer after their reply delay; the answer is complete at the
master after its own transmission time. A request nobody answers times out.

Transmission time = frame bytes x bits per character / baud: 1 start bit, 7 or 8 data
bits, a parity bit if any, 1 stop bit (the CPU-link estimate of manual 003 7-3-7 uses 11
bits per byte, i.e. 8E1). RTU frames are followed by the 3.5-character silence that ends
them (Modbus RTU framing); ASCII frames count every character (':' hex digits CR LF).

Frames are built and checked by devices/framing.py, as `mlc device serve` does.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from mlctool.devices import framing
from mlctool.sim.state import SimFault

DEFAULT_TIMEOUT_US = 500_000  # [P] the manual leaves it to the port settings (Ladder Master S)
PORT_NAMES = ("CP1", "CP2", "CP3", "CP4", "CP5")


@dataclass(frozen=True)
class LineSettings:
    baud: int = 19200
    data_bits: int = 8
    parity: str = "none"  # none | even | odd
    framing: str = "rtu"  # rtu | ascii

    def char_us(self, chars: int) -> int:
        bits = 1 + self.data_bits + (0 if self.parity == "none" else 1) + 1
        return -(-chars * bits * 1_000_000 // self.baud)

    def frame_us(self, frame: bytes) -> int:
        gap = 4 if self.framing == "rtu" else 0  # 3.5 character silence, rounded up
        return self.char_us(len(frame) + gap)


def encode(settings: LineSettings, station: int, pdu: bytes) -> bytes:
    return framing.encode(settings.framing, framing.Frame(station, b""), pdu)


def decode(settings: LineSettings, frame: bytes) -> tuple[int, bytes] | None:
    """A whole received frame -> (station, PDU), None when it is not a valid frame."""
    got = framing.decode(settings.framing, frame)
    return None if got is None else (got.unit, got.pdu)


@dataclass
class Exchange:
    """One request on the line and what came back."""

    sent_us: int
    request: bytes
    arrive_us: int  # the request has reached the devices
    broadcast: bool = False
    reply: bytes | None = None
    reply_us: int | None = None  # the reply is complete at the master
    answered_by: int = 0  # devices that answered (two answers collide)
    cancelled_us: int | None = None  # the master stopped (MBUS Off): not sent after this
    taken: set[int] = field(default_factory=set)  # ids of the devices that have seen it


@dataclass
class Port:
    name: str
    settings: LineSettings = LineSettings()
    timeout_us: int = DEFAULT_TIMEOUT_US
    configured: bool = False  # set by the first device attached (its line settings)
    devices: dict[int, LineSettings] = field(default_factory=dict)  # device id -> its settings
    exchanges: list[Exchange] = field(default_factory=list)  # the line's log, in order
    master: object = None  # the MBUS state using the port (targets/vs/serial/mbus.py)
    # Non Protocol settings of the PLC's port (7-3-8; the stimulus `port` line): RS start and
    # end characters (None: none), the PLC's own station number (CPU link, 7-3-7)
    start: int | None = None
    end: int | None = None
    station: int = 0
    incoming: list[tuple[int, int]] = field(default_factory=list)  # (complete at us, byte) to the PLC
    stations: dict[int, dict] = field(default_factory=dict)  # peer PLC station -> {device id: model}

    def attach(self, device_id: int, settings: LineSettings, timeout_us: int | None) -> None:
        """Devices and master must agree on the line settings (manual 003 7-1); the port
        takes those of the first device attached. A device set differently hears noise."""
        if not self.configured:
            self.settings = settings
            if timeout_us is not None:
                self.timeout_us = timeout_us
            self.configured = True
        self.devices[device_id] = settings

    def configure(self, settings: LineSettings, timeout_us: int | None) -> None:
        """The PLC's own port settings (the stimulus `port` line): devices must match them."""
        self.settings, self.configured = settings, True
        if timeout_us is not None:
            self.timeout_us = timeout_us

    def deliver(self, t_us: int, data: bytes) -> int:
        """Bytes sent to the PLC from t_us on, one character time each (after what is still
        arriving); returns when the last is complete."""
        t = max(t_us, self.incoming[-1][0] if self.incoming else t_us)
        for b in data:
            t += self.settings.char_us(1)
            self.incoming.append((t, b & (0xFF if self.settings.data_bits == 8 else 0x7F)))
        return t

    def send(self, t_us: int, station: int, pdu: bytes) -> Exchange:
        frame = encode(self.settings, station, pdu)
        ex = Exchange(t_us, frame, t_us + self.settings.frame_us(frame), broadcast=station == 0)
        self.exchanges.append(ex)
        del self.exchanges[:-64]  # a bounded log (tests and reports read the recent ones)
        return ex

    def arrived(self, device_id: int, t_us: int) -> list[Exchange]:
        """Requests that reached `device_id` by t_us and that it has not seen, in order."""
        out = []
        for ex in self.exchanges:
            if device_id in ex.taken or ex.arrive_us > t_us:
                continue
            ex.taken.add(device_id)
            if ex.cancelled_us is None or ex.arrive_us <= ex.cancelled_us:
                out.append(ex)
        return out

    def answer(self, ex: Exchange, device_id: int, reply: bytes, delay_us: int) -> None:
        """A device's answer, sent `delay_us` after the request arrived."""
        if ex.broadcast:
            return
        ex.answered_by += 1
        if ex.answered_by > 1:  # two devices talking at once: the master reads garbage
            ex.reply = b"\x00" + (ex.reply or b"")
            return
        ex.reply = reply
        ex.reply_us = ex.arrive_us + delay_us + self.settings.frame_us(reply)

    def hears(self, device_id: int) -> bool:
        """A device set to other line settings than the master cannot read its frames."""
        return self.devices.get(device_id) == self.settings


def port(machine, name: str) -> Port:
    """The port `name` (CP1..CP5) of a simulated PLC, created on first use. It lives in
    Machine.ext, so a power cycle drops the exchange in flight (devices attach again)."""
    ports = machine.ext.setdefault("serial_ports", {})
    if name not in ports:
        ports[name] = Port(name)
    return ports[name]


def port_count(machine) -> int:
    """How many ports CP1..CPn the model has (target.toml [serial_ports] count, per model)."""
    count = machine.target.settings.get("serial_ports", {}).get("count", {})
    if isinstance(count, dict):
        return count.get(machine.target.model or "", max(count.values(), default=5))
    return count


def check_port(machine, s, n: int) -> None:
    """RS, MBUS, LINK, CPUL: a port the model lacks is a run-time fault naming the step."""
    count = port_count(machine)
    if not 1 <= n <= count:
        raise SimFault(f"{s.ins.mnemonic} {' '.join(s.ins.texts)}: port CP{n} does not exist on "
                       f"this model (CP1-CP{count})")
