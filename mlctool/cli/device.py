"""`mlc device serve`: a device model as a real Modbus device (docs/xc100.md).

Exit 0 after Ctrl-C / SIGTERM or --duration; 2 on bad options (E801) or a link that cannot
be opened (E802).
"""

from __future__ import annotations

import asyncio
import math
import re
import signal
import sys

import click

from mlctool.cli import main_group
from mlctool.cli.common import Integer, examples
from mlctool.diagnostics import MlcError, Span, diag
from mlctool.limits import clip, real
from mlctool.sim.stimulus.stimulus import StimError, parse_time

LOOPBACK = {"127.0.0.1", "localhost"}
BAUDS = ("9600", "19200", "38400", "57600", "115200")


def _fail(code: str, message: str) -> MlcError:
    return MlcError(diag("<command line>", Span.at(1), code, message))


def parse_tcp(text: str) -> tuple[str, int]:
    host, sep, port = text.rpartition(":")
    # ASCII digits only (isdigit() takes "²"), and few enough for int() (mlctool/limits.py)
    if not sep or not re.fullmatch(r"[0-9]{1,5}", port) or not 0 < int(port) < 65536:
        raise _fail("E801", f"--tcp {clip(text, 60)!r}: expected HOST:PORT, e.g. 127.0.0.1:5020")
    if host not in LOOPBACK:
        raise _fail("E801", f"--tcp {text!r}: only loopback (127.0.0.1, localhost) is served")
    return "127.0.0.1", int(port)


class FiniteRange(click.FloatRange):
    """A float range that also refuses nan and inf (FloatRange lets nan through: every
    comparison with nan is false; issue 21 #17)."""

    def convert(self, value, param, ctx):
        if isinstance(value, str):  # ASCII digits (mlctool/limits.py; float() takes "٣" as 3)
            try:
                real(value.strip(), finite=False)
            except ValueError as e:
                self.fail(str(e), param, ctx)
        number = super().convert(value, param, ctx)
        if not math.isfinite(number):
            self.fail(f"{value!r} is not a finite number", param, ctx)
        return number


@main_group.group("device", epilog=examples(
    "mlc device serve xc100 --tcp 127.0.0.1:5020",
    "mlc device serve xc100 --serial /dev/ttyUSB0 --rtu --station 2",
))
def device_group() -> None:
    """Device models as real devices on a Modbus link."""


@device_group.command("serve", epilog=examples(
    "mlc device serve xc100 --tcp 127.0.0.1:5020",
    "mlc device serve xc100 --serial /dev/ttyUSB0 --rtu --station 2 --baud 38400",
    "mlc device serve xc100 --tcp 127.0.0.1:5020 --duration 10s   # stops by itself",
))
@click.argument("kind", type=click.Choice(["xc100"]))
@click.option("--tcp", metavar="HOST:PORT", help="serve over TCP on loopback")
@click.option("--serial", metavar="PATH", help="serve on a serial device (or pseudo-terminal)")
@click.option("--framing", type=click.Choice(["ascii", "rtu", "tcp"]), default=None,
              help="ascii (the XC100's factory setting, 0A04H = 0; the default) or rtu frames, "
                   "on the serial line or tunnelled over TCP (serial servers); tcp = Modbus TCP "
                   "(MBAP header, unit id = station) for HMIs and SCADA")
@click.option("--ascii", "ascii_flag", is_flag=True, help="same as --framing ascii")
@click.option("--rtu", "rtu_flag", is_flag=True, help="same as --framing rtu")
@click.option("--station", type=Integer(1, 16), multiple=True, show_default="1",
              help="Modbus station = rotary switch CH + 1 (8.2); repeat it for several devices "
                   "on one line, each its own model")
@click.option("--baud", type=click.Choice(BAUDS), default="19200", show_default=True)
@click.option("--duration", metavar="TIME", default=None, help="stop by itself after TIME")
@click.option("--unlocked", is_flag=True,
              help="accept parameter writes without the 8.2 write-unlock frame first")
@click.option("--lead", type=FiniteRange(0.1, 100), default=10.0, show_default=True,
              help="cylinder lead, mm per motor revolution")
@click.option("--stroke", type=FiniteRange(1, 10000), default=300.0, show_default=True,
              help="mechanical stroke, mm")
def serve_cmd(kind, tcp, serial, framing, ascii_flag, rtu_flag, station, baud, duration,
              unlocked, lead, stroke):
    """Run device KIND as a Modbus server, with a live status view, until Ctrl-C."""
    if (tcp is None) == (serial is None):
        raise _fail("E801", "give exactly one of --tcp HOST:PORT and --serial PATH")
    chosen = {f for f, on in (("ascii", ascii_flag), ("rtu", rtu_flag), (framing, framing)) if on}
    if len(chosen) > 1:
        raise _fail("E801", f"framings {' and '.join(sorted(chosen))} given: choose one")
    framing = chosen.pop() if chosen else "ascii"
    if framing == "tcp" and serial is not None:
        raise _fail("E801", "--framing tcp is Modbus TCP: it needs --tcp (a serial line takes "
                            "ascii or rtu)")
    stations = station or (1,)
    if len(set(stations)) != len(stations):
        raise _fail("E801", f"--station {stations}: a station number may be used once on a line")
    if serial is not None and not serial.strip():
        raise _fail("E801", "--serial '': give the serial device, e.g. /dev/ttyUSB0 or COM3")
    address = parse_tcp(tcp) if tcp is not None else None  # --tcp "" is a bad address, not no address
    seconds = None
    if duration is not None:
        try:
            seconds = parse_time(duration) / 1e6
        except StimError as e:
            raise _fail("E801", f"--duration: {e.message}") from None
    from mlctool.devices.xc100 import controller as c

    devices = {}
    for st in sorted(stations):
        devices[st] = c.new_xc100(lead_mm=lead, stroke_mm=stroke, start_mm=stroke / 6)
        devices[st].unlocked = unlocked
    link = f"tcp {address[0]}:{address[1]}" if address else f"serial {serial} {baud} 8-N-1"
    code = asyncio.run(_serve(devices, framing, address, serial, int(baud), seconds, link))
    sys.exit(code)


async def _serve(devices, framing, address, serial, baud, seconds, link) -> int:
    from mlctool.devices.xc100.server import make_server, run_device
    from mlctool.devices.xc100.status import StatusView

    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for sig in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(sig, stop.set)
    try:
        server = make_server(devices, framing, tcp=address, serial=serial, baudrate=baud)
        names = ", ".join(str(st) for st in devices)
        kind = "Modbus TCP" if framing == "tcp" else framing.upper()
        title = f"XC100 station{'s' if len(devices) > 1 else ''} {names}, {kind}, {link}"
        view = StatusView(devices, title)
        with view:
            try:
                await run_device(server, seconds, on_tick=view.tick, stop=stop, on_ready=view.ready)
            except (OSError, RuntimeError) as e:
                view.close()
                from mlctool.cli.common import show

                show([diag("<command line>", Span.at(1), "E802", f"cannot open {link}: {e}")], {})
                return 2
    finally:
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.remove_signal_handler(sig)
    from mlctool.devices.xc100.controller import pulses_per_mm

    where = ", ".join(f"station {st} at {dev.act / pulses_per_mm(dev):.2f} mm"
                      for st, dev in devices.items())
    click.echo(f"stopped: {link}, {server.line.requests} requests from {server.accepted} "
               f"connections; {where}", err=True)
    return 0
