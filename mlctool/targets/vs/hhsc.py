"""Hardware high-speed counters HHSC1/HHSC2 (manual 2-15-4) and DHHCMV (6-16 FNC 189).

Each counter has a circuit (count, mode, set value) and its special registers (target.toml
`[hardware_counters]`: mode D9224/D9225, present value D9227:D9226 / D9229:D9228, set value
D9231:D9230 / D9233:D9232, direction relays M9196/M9197 On = down). The system writes the
mode and set value registers to the circuit and reads its count into the present value
registers at END. DECISION: the simulator's scans are instantaneous at their start, so
that END refresh is done before the next scan: the mode written in scan k counts from
scan k's time on, and the present value registers in scan k+1 hold the count as of its
start time (as inputs are read then). Modes (2-15-4 table): 0 off, 1 1-phase up (X0), 2
1-phase with direction input (X0 counts, X1 On = down; DECISION: the page's figure is
lost, On = down like M9196), 3 2-phase (U X0, D X1), 4/5/6 A/B phase x1/x2/x4 (X0 A,
X1 B; from the stimulus's A/B pairs `X0/X1 pulses 1kHz`); HHSC2 on X3/X4. Another mode
number counts nothing. RST does not clear them: DHHCMV writes the circuit at once.
A count that reaches the set value requests IHHC1/IHHC2 at its time (_set_value_reached).
"""

from __future__ import annotations

from mlctool.check.interrupts import source_pointer
from mlctool.sim.hardware.pulses import count as count_edges
from mlctool.sim.hardware.pulses import quadrature_count, time_of_count
from mlctool.sim.operands import WordRef
from mlctool.sim.state import Machine, s32


def _table(m: Machine):
    return m.target.settings.get("hardware_counters")


def _circuits(m: Machine) -> list[dict]:
    t = _table(m)
    return m.hsc.setdefault("hardware", [{"count": 0, "mode": 0, "set": 0, "levels": {}}
                                         for _ in t["mode_registers"]])


def _get32(m: Machine, reg: int) -> int:
    d = m.words["D"]
    return s32(d[reg] | (d[reg + 1] << 16))


def _put32(m: Machine, reg: int, v: int) -> None:
    d = m.words["D"]
    d[reg], d[reg + 1] = v & 0xFFFF, (v >> 16) & 0xFFFF


def _pins(t: dict, unit: int) -> list[tuple[str, int]]:
    return [(p[0], int(p[1:], 8)) for p in t["inputs"][unit]]


def _net(m: Machine, mode: int, pins, was: dict, after: int, upto: int) -> int:
    first, second = pins
    if mode == 1:
        return count_edges(m, *first, after, upto)
    if mode == 2:  # the direction input's level as the previous scan saw it holds over the interval
        return (-1 if was.get(second) else 1) * count_edges(m, *first, after, upto)
    if mode == 3:
        return count_edges(m, *first, after, upto) - count_edges(m, *second, after, upto)
    if mode in (4, 5, 6):
        return quadrature_count(m, first, second, {4: 1, 5: 2, 6: 4}[mode], after, upto)
    return 0


def catch_up_hardware(m: Machine) -> None:
    """Before a scan: the registers written since the last END go to the circuits, the
    circuits count (last, now], the counts go to the present value registers."""
    t = _table(m)
    if not t:
        return
    last = m.hsc.get("hw_last_us", -1)
    m.hsc["hw_last_us"] = m.now_us
    for unit, hw in enumerate(_circuits(m)):
        pins = _pins(t, unit)
        hw["mode"] = m.words["D"][t["mode_registers"][unit]]
        hw["set"] = _get32(m, t["set_registers"][unit])
        net = _net(m, hw["mode"], pins, hw["levels"], last, m.now_us)
        if net:
            _set_value_reached(m, unit, hw, pins, net, last)
            hw["count"] = s32(hw["count"] + net)
            m.bits["M"][t["direction_relays"][unit]] = 1 if net < 0 else 0
        hw["levels"] = {pins[1]: m.bits[pins[1][0]][pins[1][1]]}
        _put32(m, t["value_registers"][unit], hw["count"])


def _set_value_reached(m: Machine, unit: int, hw: dict, pins, net: int, last: int) -> None:
    """Present value = set value during this interval's counting (2-15-4): IHHC1/IHHC2 is
    requested at the time of the count that reaches it (M9062/M9063 disable, in the queue).
    DECISION: judged on the interval's net count (2-phase and A/B counts that go back and
    forth within one interval are taken as their net); a count written by DHHCMV or a set
    value written equal to the count requests nothing (no count reached it)."""
    steps = (hw["set"] - hw["count"]) * (1 if net > 0 else -1)
    if not 1 <= steps <= abs(net):
        return
    number = source_pointer(m.target, "hardware", unit)
    if number is None:
        return
    levels = hw["levels"]
    at = time_of_count(lambda t: _net(m, hw["mode"], pins, levels, last, t), last, m.now_us, steps)
    m.hsc.setdefault("irq", []).append((at, number))


def _which(m: Machine, ref, key: str) -> int | None:
    """The counter whose `key` register (value/set) the operand names, else None."""
    t = _table(m)
    if not t or not isinstance(ref, WordRef) or ref.kind != "D":
        return None
    a = ref.addr(m)
    regs = t[key]
    return regs.index(a) if a in regs else None


def dhhcmv(m: Machine, s) -> None:
    """DHHCMV S D (FNC 189, 32-bit only): S a present value register: the circuit's count is
    read into it and moved to D; D a present value or set value register: S goes to it and
    into the circuit at once. DECISION: with neither an HHSC register it is a plain 32-bit
    move (the page defines only the register cases)."""
    if not m.acc:
        return
    src, dst = s.ops
    read = _which(m, src, "value_registers")
    if read is not None:
        hw = _circuits(m)[read]
        _put32(m, _table(m)["value_registers"][read], hw["count"])
        dst.set(m, hw["count"])
        return
    v = s32(src.get(m))
    for key, field in (("value_registers", "count"), ("set_registers", "set")):
        unit = _which(m, dst, key)
        if unit is not None:
            _circuits(m)[unit][field] = v
            dst.set(m, v)
            return
    dst.set(m, v)
