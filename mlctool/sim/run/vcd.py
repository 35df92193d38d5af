"""Waveforms: IEEE 1364 VCD written with pyvcd, and a GTKWave save file beside it.

Bits are 1-bit wires, 16-bit words and timer/counter values 16-bit vectors, 32-bit views
32-bit vectors (raw two's-complement patterns), floats `real`. Time unit 1 us; each scan's
results are dumped at the scan's start time (outputs an interrupt routine's REF put out
between scans at the routine's time). No date header, so equal runs give equal bytes.
"""

from __future__ import annotations

import io
import os
from typing import IO

from vcd import VCDWriter

from mlctool.fileio import open_input
from mlctool.program import Image
from mlctool.sim.run.run import RunResult
from mlctool.sim.state import DeviceView, NameError_, parse_device_name
from mlctool.targetapi.model import Target
from mlctool.targetapi.signals import device_signal

SCOPE = "mlc"


def signal_name(view: DeviceView) -> str:
    """VCD identifiers: `T0:w` -> `T0_w` (':' is not portable in VCD names)."""
    return view.name.replace(":", "_")


def _raw(view: DeviceView, value):
    if view.is_float:
        return float(value)
    return int(value) & ((1 << view.width) - 1)


class VcdStream:
    """A VCD written as the run goes (Simulation.trace_sink): pyvcd keeps one value per
    variable, so memory does not grow with the number of changes."""

    def __init__(self, out: IO[str], views: list[DeviceView], image: Image, target: Target,
                 timescale: str = "1 us"):
        self.writer = VCDWriter(out, timescale=timescale, date="", comment="mlc sim (virtual time)",
                                version="mlctool")
        self.views = views
        self.variables = []
        for v in views:
            if v.is_float:
                self.variables.append(self.writer.register_var(SCOPE, signal_name(v), "real", init=0.0))
            else:
                self.variables.append(self.writer.register_var(SCOPE, signal_name(v), "wire", size=v.width,
                                                               init=0))
        self.by_name = {v.name: k for k, v in enumerate(views)}
        for sym, text in sorted(image.symbols.items()):
            view = _symbol_view(text, target)
            if view is not None and view.name in self.by_name:
                self.writer.register_alias(SCOPE + ".symbols", sym, self.variables[self.by_name[view.name]])
        # the target's signals (NC5 special M/D) under their names too: mlc.signals.M21000_cycle_start
        for k, v in enumerate(views):
            found = device_signal(target, v.kind, v.number) if v.view in ("bit", "w", "d") else None
            if found is not None and not found.high:
                self.writer.register_alias(SCOPE + ".signals", found.identifier, self.variables[k])

    def add(self, t: int, changes: list[tuple[int, int | float]]) -> None:
        for k, value in changes:
            self.writer.change(self.variables[k], t, _raw(self.views[k], value))

    def close(self, end_time: int) -> None:
        self.writer.close(end_time)


def to_vcd(r: RunResult, image: Image, target: Target) -> str:
    """The VCD of a run whose trace was kept (RunResult.trace)."""
    buf = io.StringIO()
    window = r.pin_window  # --pulse-window: 1 ns time unit, pulse pins as pulse trains inside it
    stream = VcdStream(buf, r.views, image, target, "1 ns" if window else "1 us")
    if window is None:
        for t, changes in r.trace:
            stream.add(t, changes)
        stream.close(r.time_us)
        return buf.getvalue()
    for t, k, value in _with_pulses(r, window, stream.by_name):
        stream.writer.change(stream.variables[k], t, _raw(r.views[k], value))
    stream.close(r.time_us * 1000)
    return buf.getvalue()


def _with_pulses(r: RunResult, window, by_name: dict[str, int]):
    """(t ns, view index, value) in time order: the per-scan values, except the pulse pins
    inside the window, where the recorded edges replace them; at the window's end the pins
    take their per-scan level again."""
    pins = {by_name[f"{kind}{n}"] for kind, n in window.pins if f"{kind}{n}" in by_name}
    out = []
    for t_us, changes in r.trace:
        t = t_us * 1000
        for k, value in changes:
            if not (k in pins and window.inside(t)):
                out.append((t, 0, k, value))
    for t, kind, n, value in window.edges:
        k = by_name.get(f"{kind}{n}")
        if k is not None:
            out.append((t, 1, k, value))
    for k in pins:  # back to the per-scan level at the window's end
        out.append((window.to_ns, 2, k, _level_at(r, k, window.to_ns)))
    out.sort(key=lambda e: (e[0], e[1]))
    return [(t, k, v) for t, _, k, v in out]


def _level_at(r: RunResult, k: int, t_ns: int):
    value = 0
    for t_us, changes in r.trace:
        if t_us * 1000 > t_ns:
            break
        for j, v in changes:
            if j == k:
                value = v
    return value


def _symbol_view(text: str, target: Target) -> DeviceView | None:
    try:
        return parse_device_name(text, target)
    except NameError_:
        return None


GTKW_HEADER = "[*] mlctool sim"  # the first line of every save file mlc sim writes


def gtkw_path(vcd_path: str) -> str:
    return os.path.splitext(vcd_path)[0] + ".gtkw"


def gtkw_is_ours(path: str) -> bool:
    """True when `path` is missing or was written by mlc sim (its first line is GTKW_HEADER):
    mlc sim replaces only its own save file; a user's, with their own view, is kept."""
    try:
        with open_input(path, note=False) as f:  # a peek at an output, not an input
            first = f.readline(len(GTKW_HEADER) + 2)
    except FileNotFoundError:
        return True
    except OSError:
        return False
    return first.rstrip(b"\r\n") == GTKW_HEADER.encode()


def to_gtkw(vcd_path: str, views: list[DeviceView]) -> str:
    """A GTKWave save file showing `views` (decimal, signed where the view is signed)."""
    lines = [GTKW_HEADER, f'[dumpfile] "{os.path.basename(vcd_path)}"', "[timestart] 0",
             "[treeopen] mlc.", "[sst_expanded] 1"]
    for v in views:
        name = f"{SCOPE}.{signal_name(v)}"
        if v.width == 1:
            lines += ["@28", name]
        elif v.is_float:
            lines += ["@10024", name]  # real
        else:
            signed = v.kind in "DVZ" and v.view in ("w", "d") or (v.kind == "C" and v.view == "d")
            lines += ["@424" if signed else "@24", f"{name}[{v.width - 1}:0]"]
    return "\n".join(lines) + "\n"
