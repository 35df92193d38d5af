"""The XC100 as an `mlc sim` device model: CN-4 wired to PLC outputs and inputs.

    model xc100 in1=Y0 in2=Y1 ... out1=X0 out2=X1 ... [p1=ABS:100.00:50 ...] [r0703=5 ...]
                [lead=10] [stroke=300] [start=50] [work=MM] [emg=Y20] [name=XC1] [mirror=D200]

`inN` wires CN-4 input N (IN1-IN14) to a PLC output; `outN` wires output N (OUT1-OUT10) to a
PLC input. What each pin means is the XC100's input/output assignment (parameters 0600H-0714H,
defaults of manual 3.8); `rHHHH=V` sets parameter HHHH (hex) before power-up, e.g. r0703=5
puts MOVE on OUT5. `pN=MODE:POS[:SPEED[:TORQUE[:ACC[:DEC[:WAIT[:NEXT]]]]]]` stores point N
(0-127; POS in mm, modes INC ABS ORG +TSL -TSL INC-R ABS-R INC-T ABS-T; the 4.1 screen's
ranges). The model publishes its signals as `NAME.pos`, `NAME.torque` ... (`name=`, default
XC1, XC2 ... in stimulus order; sim/signals.py) for expectations, --watch, JSON and the VCD.
`mirror=Dn`, the older form, writes Dn:d = position in 0.01 mm, Dn+2 ActionStatus, Dn+3
AlarmStatus, Dn+4 ErrorStatus, Dn+5 StepNo into PLC memory every scan.
`link=CPn station=N [baud=] [protocol=rtu|ascii] [reply=TIME] [timeout=TIME]` puts it on the
PLC's RS-485 port for the VS MBUS instruction (sim/hardware/seriallink.py, docs/xc100.md).
"""

from __future__ import annotations

from decimal import Decimal, InvalidOperation
from typing import NamedTuple

from mlctool.devices import framing
from mlctool.devices.base import DeviceModel, ModelIO, ParamError
from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.modbus import handle_pdu
from mlctool.devices.xc100.registers import line_settings_refused
from mlctool.devices.xc100.tables import tables
from mlctool.limits import integer, is_decimal, real
from mlctool.sim.hardware.seriallink import PORT_NAMES, LineSettings
from mlctool.sim.signals import KINDS, MODEL_NAME
from mlctool.sim.state import DeviceView, NameError_, parse_device_name
from mlctool.sim.state import parse_signal_name as parse_signal
from mlctool.targetapi.model import Target

MODE_CODES = {v: k for k, v in tables().modes.items()}


def parse_point(text: str, ppmm: float) -> c.Point:
    """'ABS:100.00:50:1000:300:300:0:-1' -> Point (position converted from mm to pulses)."""
    parts = text.split(":")
    mode = parts[0].upper()
    if mode not in MODE_CODES:
        raise ValueError(f"unknown move mode {parts[0]!r}; modes: {', '.join(MODE_CODES)}")
    if len(parts) > 9:
        raise ValueError("at most MODE:POS:SPEED:TORQUE:ACC:DEC:WAIT:NEXT")
    p = c.Point(mode=MODE_CODES[mode])
    if len(parts) > 1:  # the point-table screen's ranges (4.1), not the registers' (8.2)
        try:
            real(parts[1])  # ASCII digits (Decimal takes "٣" as 3: mlctool/limits.py)
            mm = Decimal(parts[1])
        except (ValueError, InvalidOperation):
            raise ValueError(f"POS {parts[1]!r} is not a number of mm") from None
        f = tables().field("position")
        if not mm.is_finite() or mm.as_tuple().exponent < -2 or not f.ui_allows(int(mm * 100)):
            raise ValueError(f"POS takes {f.ui_lo / 100:.2f}..{f.ui_hi / 100:.2f} mm in steps "
                             f"of 0.01 (4.1), not {parts[1]}")
        p.position = round(float(mm) * ppmm)
    names = ("speed", "torque", "accel", "decel", "wait", "next")
    for name, raw in zip(names, parts[2:]):
        f = tables().field(name)
        try:
            v = integer(raw)
        except ValueError:
            raise ValueError(f"{name} {raw!r} is not an integer") from None
        if not f.ui_allows(v):
            also = f" or {f.default}" if not f.ui_lo <= f.default <= f.ui_hi else ""
            raise ValueError(f"{name} takes {f.ui_lo}..{f.ui_hi}{also} (4.1), not {v}")
        setattr(p, name, v)
    return p


class XC100Model(DeviceModel):
    kind = "xc100"

    def __init__(self, params: dict[str, str], target: Target):
        super().__init__(params, target)
        self.ins = {n: self._bit(f"in{n}", "Y") for n in range(1, 15) if f"in{n}" in params}
        self.outs = {n: self._bit(f"out{n}", "X") for n in range(1, 11) if f"out{n}" in params}
        lead = self._number("lead", "10", 0.1, 100)
        stroke = self._number("stroke", "300", 1, 10000)
        start = self._number("start", str(stroke / 6), 0, stroke)
        work = self._number("work", None, 0, stroke) if "work" in params else None
        self.emg = self._bit("emg", "Y") if "emg" in params else None
        regs = self._line_keys()  # baud= protocol= are the parameters 0A00H / 0A04H
        for key in sorted(k for k in params if k.startswith("r") and k[1:] and _is_hex(k[1:])):
            self.used.add(key)
            regs[int(key[1:], 16)] = self._register(key, params[key])
        for key in ("stop", "stopbits"):
            if key in params:  # 8.1 停止位元 "1 BIT": no parameter, no option
                raise ParamError(key, f"{key}=: the XC100 has no stop-bit setting; its line "
                                      "always has 1 stop bit (manual 004 8.1)")
        probe = c.new_xc100(params={a: v for a, v in regs.items() if a in (0x0A01, 0x0A04)})
        if reason := line_settings_refused(probe, {}):
            key = next(k for k in ("r0a01", "r0a04", "protocol") if k in params)
            raise ParamError(key, f"{reason}; the XC100 refuses this setting (exception 03, "
                                  "ErrorStatus 2)")
        dev = c.new_xc100(lead_mm=lead, stroke_mm=stroke, start_mm=start, work_mm=work, params=regs)
        points = {}
        for key in sorted(k for k in params if k.startswith("p") and is_decimal(k[1:])):
            self.used.add(key)
            n = int(key[1:])
            if n > 127:
                raise ParamError(key, "points are p0..p127")
            try:
                points[n] = parse_point(params[key], c.pulses_per_mm(dev))
            except ValueError as e:
                raise ParamError(key, f"{key}: {e}") from None
        self.name = self._name()
        self.mirror = self._mirror() if "mirror" in params else []
        self.link = self._link()
        self.check_unused()
        if not self.ins and not self.outs and self.link is None:
            raise ParamError("in1", "model xc100 needs wiring (inN=Y.., outN=X..) and/or link=CPn")
        dev.points[:len(dev.points)] = [points.get(n, p) for n, p in enumerate(dev.points)]
        self.dev = dev
        self.last_t: int | None = None

    # -- parameters
    def _bit(self, key: str, kind: str) -> DeviceView:
        """CN-4 inputs are driven by PLC outputs (Y), its outputs drive PLC inputs (X)."""
        view = self.device(key)
        if view.view != "bit" or view.kind != kind:
            side = "a PLC output such as Y0" if kind == "Y" else "a PLC input such as X0"
            raise ParamError(key, f"{key} must be wired to {side}")
        return view

    def _number(self, key: str, default: str | None, lo: float, hi: float) -> float:
        text = self._param(key, default)
        try:
            v = real(text)
        except ValueError:
            raise ParamError(key, f"{key} must be a number of mm, not {text!r}") from None
        if not lo <= v <= hi:
            raise ParamError(key, f"{key} takes {lo:g}..{hi:g} mm, not {v:g}")
        return v

    def _register(self, key: str, text: str) -> int:
        p = tables().by_addr.get(int(key[1:], 16))
        if p is None:
            raise ParamError(key, f"{key}: no XC100 parameter at {key[1:].upper()}H (manual ch. 5)")
        try:
            v = integer(text, 0)
        except ValueError:
            raise ParamError(key, f"{key}: {text!r} is not an integer") from None
        if not p.lo <= v <= p.hi:
            raise ParamError(key, f"{key} ({p.name}, {p.section}) takes {p.lo}..{p.hi}, not {v}")
        return v

    def _name(self) -> str:
        """name=XC1: the model's signals are XC1.pos, XC1.alarm ... (sim/signals.py); without
        it the n-th xc100 of the stimulus is XCn (run.build_models)."""
        if "name" not in self.params:
            return ""
        text = self._param("name", None)
        if not MODEL_NAME.fullmatch(text):
            raise ParamError("name", f"name takes a letter then letters, digits or _ (e.g. XC1), "
                                     f"not {text!r}")
        return text.upper()

    def _mirror(self) -> list[DeviceView]:
        base = self.device("mirror")
        if base.kind != "D" or base.view != "w":
            raise ParamError("mirror", "mirror must be a data register such as D200")
        try:
            names = [f"D{base.number}:d"] + [f"D{base.number + k}" for k in range(2, 6)]
            return [parse_device_name(n, self.target) for n in names]
        except NameError_ as e:
            raise ParamError("mirror", f"mirror needs D{base.number}..D{base.number + 5}: {e}") from None

    def _line_keys(self) -> dict[int, int]:
        regs = {}
        if "baud" in self.params:
            text = self._param("baud", None)
            if text not in BAUDS:
                raise ParamError("baud", f"baud takes {', '.join(BAUDS)} (0A00H), not {text!r}")
            regs[0x0A00] = BAUDS.index(text)
        if "protocol" in self.params:
            text = self._param("protocol", None).lower()
            if text not in ("ascii", "rtu"):
                raise ParamError("protocol", f"protocol takes ascii or rtu (0A04H), not {text!r}")
            regs[0x0A04] = 1 if text == "rtu" else 0
        return regs

    def _link(self) -> Link | None:
        """link=CPn station=1-16 [reply=TIME] [timeout=TIME]: on the PLC's RS-485 port CPn."""
        if "link" not in self.params:
            for key in ("station", "reply", "timeout", "baud", "protocol"):
                if key in self.params:
                    raise ParamError(key, f"{key}= needs link=CPn (the PLC port the XC100 is on)")
            return None
        port = self._param("link", None).upper()
        if port not in PORT_NAMES:
            raise ParamError("link", f"link takes {', '.join(PORT_NAMES)}, not {port!r}")
        text = self._param("station", "1")
        if not is_decimal(text) or not 1 <= int(text) <= 16:
            raise ParamError("station", f"station takes 1-16 (rotary switch CH + 1, 8.2), not {text!r}")
        timeout = self.time("timeout") if "timeout" in self.params else None
        if timeout is not None and timeout <= 0:
            raise ParamError("timeout", "timeout must be longer than 0")
        return Link(port, int(text), self.time("reply", DEFAULT_REPLY), timeout)

    # -- simulation
    def devices(self) -> list[DeviceView]:
        """The wired pins and every signal of the model (so the VCD shows the cylinder)."""
        return list(self.ins.values()) + list(self.outs.values()) + \
            ([self.emg] if self.emg else []) + self.mirror + \
            [parse_signal(f"{self.name}.{s}") for s in KINDS["xc100"] if self.name]

    def step(self, io: ModelIO, t_us: int, period_us: int) -> None:
        dev = self.dev
        if self.link is not None:
            self._serve(io.serial_port(self.link.port), t_us)
        if self.last_t is not None:
            c.advance(dev, t_us - self.last_t)
        self.last_t = t_us
        if self.emg is not None:
            c.set_emergency(dev, bool(io.get(self.emg)))
        c.set_inputs(dev, sum(1 << (n - 1) for n, v in self.ins.items() if io.get(v)))
        bits = c.output_pins(dev)
        for n, view in self.outs.items():
            io.set(view, bits >> (n - 1) & 1)
        if self.name:  # named by run.build_models when not by name=
            io.publish(self.name, signal_values(dev))
        if self.mirror:
            pos = round(dev.act / c.pulses_per_mm(dev) * 100)
            values = [pos, 1 if dev.motion else dev.action, dev.alarm, dev.error, dev.step_no]
            for view, v in zip(self.mirror, values):
                io.set(view, v)


    def _serve(self, port, t_us: int) -> None:
        """Answer the requests that reached the XC100 since the last step, each at the time
        it arrived (the axis is advanced to that moment first): as `mlc device serve` does,
        devices/framing.py reads the frame and modbus.handle_pdu answers (manual 004 ch. 8)."""
        dev, me = self.dev, id(self)
        port.attach(me, line_settings(dev), self.link.timeout)
        for ex in port.arrived(me, t_us):
            if self.last_t is not None and ex.arrive_us > self.last_t:
                c.advance(dev, ex.arrive_us - self.last_t)
                self.last_t = ex.arrive_us
            if not port.hears(me):
                continue  # other line settings than the master: noise, no answer
            kind = "rtu" if dev.boot[0x0A04] else "ascii"
            frame = framing.decode(kind, ex.request)
            if frame is None or not frame.pdu:
                continue  # bad CRC/LRC: dropped silently (8.3 defines no answer)
            reply = handle_pdu(dev, self.link.station, frame.unit, frame.pdu)
            if reply is not None:
                port.answer(ex, me, framing.encode(kind, frame, reply), self.link.reply_us)


def signal_values(dev: c.Xc100) -> dict[str, int]:
    """The model's signals (sim/signals.py KINDS["xc100"]) from its state."""
    mm = c.pulses_per_mm(dev)
    m = dev.motion
    limit = min(m.torque, 1000) if m is not None else (dev.push_current if dev.torque_reached else 0)
    return {
        "pos": round(dev.act / mm * 100), "cmd": round(dev.cmd / mm * 100),
        "speed": round(dev.vel / mm * 100), "action": 1 if m is not None else dev.action,
        "alarm": dev.alarm, "error": dev.error, "step": dev.step_no, "torque": dev.current,
        "limit": limit if dev.servo else 0, "servo": int(dev.servo), "homed": int(dev.homed),
        "inp": int(c.output_signals(dev)["INP"]), "pushing": int(dev.torque_reached),
    }


class Link(NamedTuple):
    port: str  # CP1..CP5
    station: int
    reply_us: int  # from the end of the request to the start of the answer
    timeout: int | None  # the PLC port's time-out, when this link sets it


BAUDS = ("9600", "19200", "38400", "57600", "115200")  # 0A00H 0-4 (5.8)
DEFAULT_REPLY = "2ms"  # [P] the manual gives no response time


def line_settings(dev: c.Xc100) -> LineSettings:
    """The XC100's RS-485 settings as of power-up (5.8 0A00H-0A04H)."""
    boot = dev.boot
    return LineSettings(int(BAUDS[boot[0x0A00]]), 7 if boot[0x0A01] else 8,
                        ("none", "even", "odd")[boot[0x0A02]], "rtu" if boot[0x0A04] else "ascii")


def _is_hex(text: str) -> bool:
    try:
        integer(text if text[:1] not in "+-" else "-", 16)  # no sign in a register name
    except ValueError:
        return False
    return True
