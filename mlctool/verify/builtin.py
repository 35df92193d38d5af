"""Built-in checks worth proving on every program, opt-in (`mlc verify --check NAME`, mlc.toml
`[verify] checks = [...]`): each is a set of ordinary properties made from the program.

- `no-chatter`: with every input constant (chosen at the first scan, kept), no output (Y the
  program writes) changes in two scans running (`stable Yn for 2 scans`). A blinker driven
  by a timer or a clock relay breaks it by design.
- `timers-finish`: every timer the program runs can reach its contact (`reachable Tn`).
- `stl-exit`: every step relay an STL instruction opens can be entered and then left (a
  witness: the step On after some scan, Off after a later one).
"""

from __future__ import annotations

from mlctool.program import Image
from mlctool.sim.decode import program_devices
from mlctool.sim.scan import load_program
from mlctool.sim.state import DeviceView
from mlctool.targetapi.model import Target
from mlctool.verify.props import Atom, Input, Property, Props

CHECKS = ("no-chatter", "timers-finish", "stl-exit")


def check_props(image: Image, target: Target, name: str, path: str, line: int) -> Props:
    """The properties of built-in check `name`, at `path`:`line` (where the check was asked for)."""
    prog = load_program(image, target)
    props = Props(path, [])

    def prop(kind: str, view: DeviceView, text: str, scans: int = 0) -> Property:
        return Property(kind, line, 1, text, f"{name} {view.name}", Atom(view, "bit", None, view.name, 1),
                        scans=scans)

    if name == "no-chatter":
        written = sorted({s.ops[0].num for s in prog.steps if s.ins.spec.op in ("out", "set", "rst", "pls", "plf")
                          and s.ins.operands and s.ins.operands[0].device == "Y" and s.ops[0].ix is None})
        for n in written:
            view = DeviceView("Y", n, "bit", radix=target.devices["Y"].radix)
            props.properties.append(prop("stable", view, f"stable {view.name} for 2 scans (inputs constant)", 2))
        for v in program_devices(prog):
            dev = target.devices.get(v.kind)
            if v.view == "bit" and dev is not None and dev.input:
                props.inputs[v] = Input(v, (0, 1), constant=True, line=line)
    elif name == "timers-finish":
        timers = sorted({s.ops[0].num for s in prog.steps if s.ins.spec.op == "tmr" and s.ops[0].ix is None})
        for n in timers:
            view = DeviceView("T", n, "bit")
            props.properties.append(prop("reachable", view, f"reachable {view.name}"))
    elif name == "stl-exit":
        steps = sorted({s.ops[0].num for s in prog.steps if s.ins.spec.op == "stl" and s.ops})
        for n in steps:
            view = DeviceView("S", n, "bit", radix=target.devices["S"].radix)
            props.properties.append(prop("left", view, f"{view.name} entered and left"))
    return props
