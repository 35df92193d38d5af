"""What the two batch lane code generators share (bit-sliced lanes in mlctool/sim/campaign/batch.py,
numpy word lanes in mlctool/sim/campaign/word_lanes.py): the rung result and its blocks and stack as
generated statements, and which targets the lanes model."""

from __future__ import annotations

from mlctool.sim.decode import Program
from mlctool.targetapi.model import Target
from mlctool.targetapi.registry import simulation_of


class RungCodegen:
    """What both lane code generators share: the rung's result `a`, its ANB/ORB blocks and
    MPS stack (2.2), as generated statements. Subclasses say how a line is indented and how
    a lane word is inverted."""

    indent = ""

    def __init__(self, prog: Program):
        self.prog = prog
        self.slots: dict[tuple[str, int], int] = {}
        self.blocks: list[str] = []
        self.stack: list[str] = []
        self.tmp = 0

    def invert(self, x: str) -> str:
        raise NotImplementedError

    def edge_memory(self, i: int) -> str:
        """The expression reading step i's edge memory (2.2 LDP/LDF)."""
        raise NotImplementedError

    def contact(self, op: str, x: str, i: int, out: list[str]) -> str | None:
        """A bit contact's value as an expression (None: not a plain contact)."""
        if op == "contact":
            return x
        if op == "contact_not":
            return self.invert(x)
        if op in ("contact_rise", "contact_fall"):
            e = self._new("e")
            out.append(f"{self.indent}{e} = {self.edge_memory(i)}; E[{i}] = {x}")
            return f"({x} & {self.invert(e)})" if op == "contact_rise" else f"({e} & {self.invert(x)})"
        return None

    def coil(self, op: str, x: str, i: int, out: list[str]) -> None:
        """OUT/SET/RST/PLS/PLF of bit `x` driven by the rung result."""
        ind = self.indent
        if op == "out":
            out.append(f"{ind}{x} = a")
        elif op == "set":
            out.append(f"{ind}{x} = {x} | a")
        elif op == "rst":
            out.append(f"{ind}{x} = {x} & {self.invert('a')}")
        else:
            e = self._new("e")
            out.append(f"{ind}{e} = {self.edge_memory(i)}; E[{i}] = a")
            out.append(f"{ind}{x} = a & {self.invert(e)}" if op == "pls" else f"{ind}{x} = {e} & {self.invert('a')}")

    def _new(self, prefix: str) -> str:
        self.tmp += 1
        return f"{prefix}{self.tmp}"

    def combine(self, s, cls: str, contact: str, out: list[str]) -> list[str]:
        """A contact's value `contact` joins the rung result by the contact's class."""
        ind = self.indent
        if cls == "load":
            if s.new_rung:
                self.blocks.clear()
                self.stack.clear()
            else:
                k = self._new("k")
                out.append(f"{ind}{k} = a")
                self.blocks.append(k)
            out.append(f"{ind}a = {contact}")
        else:
            out.append(f"{ind}a = a {'&' if cls == 'and' else '|'} {contact}")
        return out

    def structure(self, op: str, out: list[str]) -> bool:
        """ANB/ORB/MPS/MRD/MPP/INV/NOP; False when `op` is none of them."""
        ind = self.indent
        if op in ("anb", "orb"):
            if self.blocks:
                out.append(f"{ind}a = {self.blocks.pop()} {'&' if op == 'anb' else '|'} a")
        elif op == "mps":
            k = self._new("p")
            out.append(f"{ind}{k} = a")
            self.stack.append(k)
        elif op == "mrd":
            if self.stack:
                out.append(f"{ind}a = {self.stack[-1]}")
        elif op == "mpp":
            if self.stack:
                out.append(f"{ind}a = {self.stack.pop()}")
        elif op == "inv":
            out.append(f"{ind}a = {self.invert('a')}")
        elif op != "nop":
            return False
        return True


def lanes_target(target: Target) -> bool:
    """Targets whose scans the lanes model: no system relays, no outputs-off relay (a Y read
    from outside is not the lane's bit), no simulation extension."""
    own = simulation_of(target)
    return (not target.settings.get("system_relays") and not target.settings.get("outputs_off")
            and own.before_scan is None and own.views is None)
