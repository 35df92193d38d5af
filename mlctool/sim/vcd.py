"""Waveforms: IEEE 1364 VCD written with pyvcd, and a GTKWave save file beside it.

Bits are 1-bit wires, 16-bit words and timer/counter values 16-bit vectors, 32-bit views
32-bit vectors (raw two's-complement patterns), floats `real`. Time unit 1 us; each scan's
results are dumped at the scan's start time. No date header, so equal runs give equal bytes.
"""

from __future__ import annotations

import io
import os

from vcd import VCDWriter

from mlctool.program import Image
from mlctool.sim.run import RunResult
from mlctool.sim.state import DeviceView, NameError_, parse_device_name
from mlctool.targets.model import Target

SCOPE = "mlc"


def signal_name(view: DeviceView) -> str:
    """VCD identifiers: `T0:w` -> `T0_w` (':' is not portable in VCD names)."""
    return view.name.replace(":", "_")


def _raw(view: DeviceView, value):
    if view.is_float:
        return float(value)
    return int(value) & ((1 << view.width) - 1)


def to_vcd(r: RunResult, image: Image, target: Target) -> str:
    buf = io.StringIO()
    writer = VCDWriter(buf, timescale="1 us", date="", comment="mlc sim (virtual time)",
                       version="mlctool")
    variables = []
    for v in r.views:
        if v.is_float:
            variables.append(writer.register_var(SCOPE, signal_name(v), "real", init=0.0))
        else:
            variables.append(writer.register_var(SCOPE, signal_name(v), "wire", size=v.width, init=0))
    by_name = {v.name: k for k, v in enumerate(r.views)}
    for sym, text in sorted(image.symbols.items()):
        view = _symbol_view(text, target)
        if view is not None and view.name in by_name:
            writer.register_alias(SCOPE + ".symbols", sym, variables[by_name[view.name]])
    for t, changes in r.trace:
        for k, value in changes:
            writer.change(variables[k], t, _raw(r.views[k], value))
    writer.close(r.time_us)
    return buf.getvalue()


def _symbol_view(text: str, target: Target) -> DeviceView | None:
    try:
        return parse_device_name(text, target)
    except NameError_:
        return None


def to_gtkw(vcd_path: str, views: list[DeviceView]) -> str:
    """A GTKWave save file showing `views` (decimal, signed where the view is signed)."""
    lines = ["[*] mlctool sim", f'[dumpfile] "{os.path.basename(vcd_path)}"', "[timestart] 0",
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
