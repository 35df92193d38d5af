"""The one rule by which the simulation report (`mlc sim --report`, `mlc test`'s failure
pages) and the live monitor (`mlc debug --web`) light a ladder (docs/ladder.md, "Lighting").

Both look at the devices, as a PLC's monitor mode does: the report at the end of each scan,
the monitor wherever the machine stopped.

- A contact is lit when its condition holds with the devices' values: LD/AND/OR when its
  device is On, LDI/ANI/ORI when it is Off, a comparison when it holds. An edge contact
  (LDP/LDF and their AND/OR forms) is lit when its device is On: the one-scan pulse of an
  edge is not a value a sample of the devices can show.
- An STL state box is lit when its step is active (its S device On).
- A coil (OUT/SET/RST of a bit) is lit when its device is On, except in a step that is not
  active: there it is not lit, whatever its device (another, active step may drive the same
  device).
- An instruction box is never lit: whether its input was On is not in the devices (the
  monitor shows its operands' values under it).
"""

from __future__ import annotations

from dataclasses import dataclass

from mlctool.ladder.document import RungView, Sheet
from mlctool.sim import semantics
from mlctool.sim.state import Machine, SimFault

EDGE_CONTACTS = ("contact_rise", "contact_fall")


@dataclass(frozen=True, slots=True)
class Lamp:
    """An element that can be lit: instruction index, kind, and for a coil in a step ladder
    step the indices of the step's state boxes (steps joined by several STL: all of them)."""

    index: int
    kind: str  # contact | compare | step | coil
    steps: tuple[int, ...] = ()


def lamps(sheet: Sheet) -> list[Lamp]:
    out: list[Lamp] = []
    for it in sheet.items:
        if not isinstance(it, RungView):
            continue
        boxes = tuple(c.index for c in it.grid.cells if c.kind == "step")
        out += [Lamp(c.index, c.kind) for c in it.grid.cells if c.kind in ("contact", "compare", "step")]
        out += [Lamp(o.index, "coil", boxes) for o in it.grid.outputs if o.kind == "coil"]
    return out


def lit(lamps: list[Lamp], steps: list, m: Machine) -> list[int]:
    """The indices of the lamps lit on machine `m` (`steps`: the decoded program's steps)."""
    return [lamp.index for lamp in lamps if _lit(lamp, steps, m)]


def _on(steps: list, index: int, m: Machine) -> bool:
    return bool(steps[index].ops[0].bit(m))


def _lit(lamp: Lamp, steps: list, m: Machine) -> bool:
    s = steps[lamp.index]
    op = s.ins.spec.op
    try:
        if lamp.kind == "contact" and op in EDGE_CONTACTS or lamp.kind == "step":
            return _on(steps, lamp.index, m)
        if lamp.kind in ("contact", "compare"):
            contact = semantics.CONTACTS.get(op)
            return contact is not None and bool(contact(m, s))
        return _on(steps, lamp.index, m) and all(_on(steps, k, m) for k in lamp.steps)
    except (SimFault, IndexError):  # an indexed operand out of range now: shown unlit
        return False
