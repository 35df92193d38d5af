"""The live status view of `mlc device serve xc100`: position, state, signals, last requests.

Drawn with rich on a terminal (a few times a second); elsewhere one line at start, so logs
and tests stay quiet.
"""

from __future__ import annotations

import sys

from rich.console import Console, Group
from rich.live import Live
from rich.table import Table

from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.tables import tables

REFRESH_TICKS = 10
STATES = {0: "stopped", 1: "moving", 2: "abnormal stop"}


def render(devices: dict[int, c.Xc100], title: str) -> Group:
    parts = [f"[bold]{title}[/bold]  (Ctrl-C stops)"]
    for station, dev in devices.items():
        if len(devices) > 1:
            parts.append(f"[bold]station {station}[/bold]")
        parts.extend(_render_one(dev))
    return Group(*parts)


def _mm(value: float) -> str:
    """A length to 0.01 mm; a value that rounds to zero is 0.00, not -0.00."""
    return f"{round(value, 2) + 0.0:9.2f}"


def _render_one(dev: c.Xc100) -> list:
    mm = c.pulses_per_mm(dev)
    t = tables()
    state = Table.grid(padding=(0, 2))
    state.add_column(style="bold")
    state.add_column()
    m = dev.motion
    doing = "idle" if m is None else f"{m.kind}" + (f" P{m.point}" if m.point >= 0 else "")
    rows = [
        ("position", f"{_mm(dev.act / mm)} mm  ({round(dev.act)} pulses, command {round(dev.cmd)})"),
        ("speed", f"{_mm(dev.vel / mm)} mm/s"),
        ("state", f"{STATES.get(1 if m else dev.action)} ({doing}), step {dev.step_no}"),
        ("servo", ("ON" if dev.servo else "OFF") + ("   homed" if dev.homed else "   not homed")),
        ("alarm", f"{dev.alarm} {t.alarms[dev.alarm][0]} (ERR LED {c.led_blinks(dev)} blinks)"
         if dev.alarm else "none"),
        ("error", f"{dev.error} {t.errors.get(dev.error, '')}"),
        ("line", line_text(dev)),
        ("inputs", " ".join(f"IN{k + 1}" for k in range(14) if c.effective_pins(dev) >> k & 1) or "-"),
        ("outputs", " ".join(name for name, on in c.output_signals(dev).items() if on) or "-"),
    ]
    if dev.refused:
        rows.append(("refused", dev.refused))
    for k, v in rows:
        state.add_row(k, v)
    reqs = Table(title="last requests", show_header=False, box=None)
    for line in dev.requests[-6:] or ["(none yet)"]:
        reqs.add_row(line)
    return [state, reqs]


BAUDS = (9600, 19200, 38400, 57600, 115200)  # 0A00H 0-4 (5.8)


def line_text(dev: c.Xc100) -> str:
    """The RS-485 settings of 0A00H-0A04H as of power-up (5.8, 8.1: 1 stop bit always)."""
    b = dev.boot
    text = (f"{BAUDS[b[0x0A00]]} {7 if b[0x0A01] else 8}-{'NEO'[b[0x0A02]]}-1 "
            f"{'RTU' if b[0x0A04] else 'ASCII'} (0A00H-0A04H as of power-up)")
    if any(dev.params[a] != b[a] for a in range(0x0A00, 0x0A05) if a != 0x0A03):
        text += ", changed: acts after the next power-up"
    return text


class StatusView:
    def __init__(self, devices: dict[int, c.Xc100], title: str):
        self.devices = devices
        self.title = title
        self.ticks = 0
        self.console = Console(stderr=True)
        self.live: Live | None = None

    def __enter__(self) -> StatusView:
        return self

    def ready(self) -> None:
        """The link is open: start drawing (or say so once)."""
        if sys.stderr.isatty():
            self.live = Live(render(self.devices, self.title), console=self.console,
                             auto_refresh=False, transient=False)
            self.live.__enter__()
        else:
            print(f"serving {self.title}", file=sys.stderr, flush=True)

    def tick(self) -> None:
        self.ticks += 1
        if self.live is not None and self.ticks % REFRESH_TICKS == 0:
            self.live.update(render(self.devices, self.title), refresh=True)

    def close(self) -> None:
        if self.live is not None:
            self.live.__exit__(None, None, None)
            self.live = None

    def __exit__(self, *exc) -> None:
        self.close()
