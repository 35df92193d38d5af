"""`rung`: the rung around the current instruction as a terminal ladder (mlc ladder --term),
then its instructions with the live value of every device operand and whether each contact
conducts now (power flow); `▶` marks the instruction about to execute."""

from __future__ import annotations

from rich.console import Console as RichConsole

from mlctool.debug.session import DebugSession
from mlctool.ladder.document import RungView, build_sheet, instr_text
from mlctool.ladder.term import item_text, text_layout
from mlctool.sim.state import NameError_, parse_device_name

_CONTACTS = {"LD": False, "AND": False, "OR": False, "LDI": True, "ANI": True, "ORI": True}


def _sheet(s: DebugSession):
    sheet = getattr(s, "_rung_sheet", None)
    if sheet is None:
        sheet = s._rung_sheet = build_sheet(s.image.modules[0][0] if s.image.modules else "<program>",
                                            list(s.image.instrs), getattr(s, "lines", {}) or {}, s.target)
    return sheet


def item_range(it) -> range:
    if isinstance(it, RungView):
        return range(it.rung.start, it.rung.stop)
    return range(it.row.index, it.row.index + 1)


def rung_at(s: DebugSession, index: int):
    sheet = _sheet(s)
    for it in sheet.items:
        if index in item_range(it):
            return sheet, it
    return sheet, None


def operand_values(s: DebugSession, index: int) -> list[tuple[str, int | float | None]]:
    ins = s.steps[index].ins
    out = []
    for op in ins.operands:
        text = str(op)
        try:
            view = parse_device_name(text, s.target)
        except NameError_:
            continue  # constants (K10), pointers (P3), indexed operands
        try:
            out.append((view.name, view.read(s.m)))
        except (IndexError, KeyError):
            out.append((view.name, None))
    return out


def conducts(s: DebugSession, index: int) -> bool | None:
    """A plain contact's power flow now (its own value, inverted for LDI/ANI/ORI)."""
    ins = s.steps[index].ins
    inverted = _CONTACTS.get(ins.mnemonic)
    if inverted is None:
        return None
    values = operand_values(s, index)
    if len(values) != 1 or values[0][1] is None:
        return None
    return bool(values[0][1]) != inverted


def rung_text(s: DebugSession) -> str:
    index = s.pc if s.n >= 0 else 0
    if not s.steps:
        return "the program is empty"
    sheet, it = rung_at(s, index)
    if it is None:
        return "no rung here"
    console = RichConsole(width=200, no_color=True, highlight=False, record=True, file=_Null())
    console.print(item_text(sheet, it, text_layout([sheet], 200)), end="")
    art = "\n".join(line.rstrip() for line in console.export_text().splitlines())
    rows = [s.where(), art.rstrip("\n")]
    if s.n >= 0 and not s.m.bus:  # mid-scan on a dead rail: closed contacts light no coil
        rows.append(" rail Off (an MC block whose condition is Off, or a step that is not active):"
                    " no rung here has power, whatever its contacts (VS 3-6, 4-1-3)")
    for i in item_range(it):
        ins = s.steps[i].ins
        mark = "▶" if s.n >= 0 and i == s.pc else " "
        vals = "  ".join(f"{n}={v}" for n, v in operand_values(s, i))
        flow = conducts(s, i)
        power = "" if flow is None else ("  conducts" if flow else "  open")
        rows.append(f" {mark} {ins.line:>5}  {instr_text(ins):<24} {vals}{power}".rstrip())
    return "\n".join(rows)


class _Null:
    def write(self, text: str) -> int:
        return len(text)

    def flush(self) -> None:
        pass
