"""Cross-operand rules an instruction's table entry names in `constraints` (beyond the
ZRST pair rules of resolve.py), each from a manual page's note:

- "kn4": every bit-group operand is written K4 (VS CRC, 6-16: "Kn之n必須為 4") -> E207;
- "disjoint-blocks": the S1, S2 and D blocks of n elements (n a constant) do not overlap
  (VS BK+/BK-, 6-17: overlapping blocks are an operation error at run time) -> W240;
- "no-index-hhsc": an operand naming a hardware counter register (target.toml
  [hardware_counters]) is not index-modified (VS DHHCMV, 6-16) -> E209;
- "rows:TABLE:COUNT:WORDS[:width]": the operand TABLE holds COUNT (a constant operand) rows
  of WORDS registers (bits for a bit device; ":width" doubles word rows in the 32-bit form),
  all within its device (VS DHSCT S1 m rows of 3, 6-21; BK+ ... blocks of n, 6-17) -> E208;
- "latched:ROLE": the operand ROLE lies in a latched area of its device (devices.toml
  `latched = true`), else its value is lost at power-off (VS HOUR D1, 6-15) -> W241.

Program-wide ones ("unique-destination") are in check/blocks.py.
"""

from __future__ import annotations

from mlctool.syntax.operands import Operand
from mlctool.targetapi.model import InstrSpec, Target

_WORDS = ("D", "R", "T")  # plain word devices whose blocks are numbered contiguously


def constraint_problems(t: Target, spec: InstrSpec, ops: list[Operand], texts: list[str]
                        ) -> list[tuple[int, str, str]]:
    """(operand position, code, message) for each broken constraint of `spec`."""
    out: list[tuple[int, str, str]] = []
    if "kn4" in spec.constraints:
        for k, o in enumerate(ops):
            if o.is_group and o.digits != 4:
                out.append((k, "E207", f"{spec.mnemonic} takes bit groups as K4 only, not {texts[k]} "
                            f"({spec.section})"))
    if "disjoint-blocks" in spec.constraints and len(ops) >= 4:
        out += _overlaps(spec, ops, texts)
    if "no-index-hhsc" in spec.constraints:
        hw = t.settings.get("hardware_counters", {})
        regs = set(hw.get("mode_registers", ()))
        for key in ("value_registers", "set_registers"):
            regs.update(n + h for n in hw.get(key, ()) for h in (0, 1))
        for k, o in enumerate(ops):
            if o.kind == "D" and o.index and o.number in regs:
                out.append((k, "E209", f"{texts[k]}: a hardware counter register of {spec.mnemonic} "
                            f"cannot be index-modified ({spec.section})"))
    for c in spec.constraints:
        if c.startswith("latched:"):
            out += _not_latched(t, spec, ops, texts, c.split(":", 1)[1])
        elif c.startswith("rows:"):
            out += _rows_past_the_end(t, spec, ops, texts, *c.split(":")[1:])
    return out


def _rows_past_the_end(t: Target, spec: InstrSpec, ops: list[Operand], texts: list[str],
                       table: str, rows: str, words: str, width: str = "") -> list[tuple[int, str, str]]:
    roles = [o.role for o in spec.operands]
    if table not in roles or rows not in roles:
        return []
    k, r = roles.index(table), roles.index(rows)
    if k >= len(ops) or r >= len(ops):
        return []
    tab, count = ops[k], ops[r]
    dev = t.devices.get(tab.device) if not tab.is_const else None
    if dev is None or tab.index or tab.is_group or count.kind not in ("K", "H") or not isinstance(count.value, int):
        return []
    size = int(words) * (2 if width and spec.width == 32 and dev.kind != "bit" else 1)
    last = tab.number + count.value * size - 1
    if count.value < 1:
        return []
    what = "bits" if dev.kind == "bit" else "registers"
    if last <= dev.hi:
        gap = next((a for a in dev.areas if a.write == "absent" and a.lo <= last and tab.number <= a.hi), None)
        if gap is None:
            return []
        return [(k, "E205", f"{texts[k]}: {count.value} x {size} {what} would reach into "
                 f"{dev.name_of(gap.lo)}-{dev.name_of(gap.hi)}, which do not exist ({spec.section})")]
    return [(k, "E208", f"{texts[k]}: {count.value} x {size} {what} would occupy "
             f"{dev.name_of(tab.number)}-{dev.name_of(last)}, past {dev.name_of(dev.hi)} ({spec.section})")]


def _not_latched(t: Target, spec: InstrSpec, ops: list[Operand], texts: list[str], role: str
                 ) -> list[tuple[int, str, str]]:
    k = next((i for i, o in enumerate(spec.operands) if o.role == role), None)
    if k is None or k >= len(ops) or ops[k].is_const or ops[k].index or ops[k].is_group:
        return []
    dev = t.devices.get(ops[k].device)
    if dev is None or any(a.latched and a.lo <= ops[k].number <= a.hi for a in dev.areas):
        return []
    kept = ", ".join(f"{dev.name_of(a.lo)}-{dev.name_of(a.hi)}" for a in dev.areas if a.latched)
    return [(k, "W241", f"{spec.mnemonic} {role} = {texts[k]} is not latched: its value is cleared at "
             f"power-off and at STOP->RUN" + (f"; use a latched register ({kept})" if kept else "")
             + f" ({spec.section})")]


def _overlaps(spec: InstrSpec, ops: list[Operand], texts: list[str]) -> list[tuple[int, str, str]]:
    n = ops[3]
    if n.kind not in ("K", "H") or not isinstance(n.value, int) or n.value < 1:
        return []
    size = n.value * (2 if spec.width == 32 else 1)
    spans = {}
    for k in range(3):
        o = ops[k]
        if o.kind in _WORDS and not o.index:
            spans[k] = (o.kind, o.number, o.number + size - 1)
    for a, b in ((0, 2), (1, 2), (0, 1)):
        if a in spans and b in spans:
            (ka, la, ha), (kb, lb, hb) = spans[a], spans[b]
            if ka == kb and la <= hb and lb <= ha:
                return [(b, "W240", f"{spec.mnemonic}: the blocks {ka}{la}-{ka}{ha} ({texts[a]}) and "
                         f"{kb}{lb}-{kb}{hb} ({texts[b]}) overlap: an operation error at run time, "
                         f"the instruction is not executed ({spec.section})")]
    return []
