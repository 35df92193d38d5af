"""Stimulus lines for the PLC's serial ports (docs/stimulus.md "Serial ports"):

    port CP1 baud=9600 data=8 parity=none start=H02 end=H03 timeout=100ms station=0
    20ms CP1 receive H02 "AB12" 13 H03

`port` gives the PLC's port settings, as Ladder Master S's project port settings do (Vigor VS
7-3-8 Non Protocol: data 7/8 bits, parity, start and end characters "none or any data",
time-out; 7-3-7 the station number). `CPn receive` sends bytes to the PLC from the line's time
on, one character time each (sim/hardware/seriallink.py Port.deliver). Errors are StimError (E601).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from mlctool.limits import integer, is_decimal
from mlctool.sim.hardware.seriallink import PORT_NAMES, LineSettings
from mlctool.sim.stimulus.quantities import StimError, parse_time

BAUDS = (300, 600, 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200)  # 7-3-8


@dataclass(frozen=True, slots=True)
class PortSpec:
    name: str  # CP1..CP5
    settings: LineSettings
    timeout_us: int | None
    start: int | None
    end: int | None
    station: int
    line: int

    def apply(self, port) -> None:
        port.configure(self.settings, self.timeout_us)
        port.start, port.end, port.station = self.start, self.end, self.station


def port_name(text: str, offset: int) -> str:
    name = text.upper()
    if name not in PORT_NAMES:
        raise StimError(f"{text!r}: ports are {', '.join(PORT_NAMES)}", offset)
    return name


def _byte(text: str, offset: int, what: str) -> int:
    u = text.upper()
    try:
        v = integer(u[1:], 16) if u.startswith("H") else integer(u[1:] if u.startswith("K") else u)
    except ValueError:
        raise StimError(f"{what} {text!r}: expected a byte (H41, K65 or 65)", offset) from None
    if not 0 <= v <= 255:
        raise StimError(f"{what} {text!r}: a byte is 0-255", offset)
    return v


def parse_port(toks: list[tuple[str, int]]) -> PortSpec:
    """`port CPn key=value ...` (toks: the whole line)."""
    if len(toks) < 2:
        raise StimError("expected `port CPn [baud=19200] [data=8] [parity=none] [start=H02] [end=H03] "
                        "[timeout=100ms] [station=0]`", 0)
    name = port_name(toks[1][0], 1)
    values: dict = {"baud": 19200, "data": 8, "parity": "none", "start": None, "end": None,
                    "timeout": None, "station": 0}
    for k, (t, _) in enumerate(toks[2:], 2):
        key, _, value = t.partition("=")
        key = key.lower()
        if key not in values or not value:
            raise StimError(f"{t!r}: port settings are {', '.join(f'{x}=' for x in values)}", k)
        if key == "baud":
            if not is_decimal(value) or int(value) not in BAUDS:
                raise StimError(f"baud {value!r}: one of {', '.join(map(str, BAUDS))} (7-3-8)", k)
            values[key] = int(value)
        elif key == "data":
            if value not in ("7", "8"):
                raise StimError(f"data {value!r}: 7 or 8 bits (7-3-8)", k)
            values[key] = int(value)
        elif key == "parity":
            if value.lower() not in ("none", "even", "odd"):
                raise StimError(f"parity {value!r}: none, even or odd (7-3-8)", k)
            values[key] = value.lower()
        elif key in ("start", "end"):
            values[key] = None if value.lower() == "none" else _byte(value, k, key)
        elif key == "timeout":
            try:
                values[key] = parse_time(value)
            except StimError as e:
                raise StimError(e.message, k) from None
            if values[key] <= 0:
                raise StimError("timeout must be longer than 0", k)
        else:
            if not is_decimal(value) or not 0 <= int(value) <= 254:
                raise StimError(f"station {value!r}: 0-254 (7-3-7)", k)
            values[key] = int(value)
    settings = LineSettings(values["baud"], values["data"], values["parity"])
    return PortSpec(name, settings, values["timeout"], values["start"], values["end"], values["station"], 0)


_STRING = re.compile(r'"([^"]*)"')


def parse_receive(toks: list[tuple[str, int]], off: int) -> tuple[str, bytes]:
    """`CPn receive ITEM ...` (toks from CPn; off = its token offset in the line): ITEM is a
    byte (H41, K65, 65) or a "text" without spaces (its ASCII codes)."""
    name = port_name(toks[0][0], off)
    if len(toks) < 3:
        raise StimError('expected `CPn receive BYTE|"TEXT" ...`, e.g. CP1 receive H02 "AB" H03', off + 1)
    data = bytearray()
    for k, (t, _) in enumerate(toks[2:], off + 2):
        m = _STRING.fullmatch(t)
        if m:
            try:
                data += m[1].encode("ascii")
            except UnicodeEncodeError:
                raise StimError(f"{t}: text is ASCII; write other bytes as H..", k) from None
        elif t.startswith('"'):
            raise StimError(f"{t}: a text item has no spaces; write a space as H20", k)
        else:
            data.append(_byte(t, k, "byte"))
    return name, bytes(data)
