"""The XC100 Modbus register map (manual 004 8.2): which addresses exist, who may read or write
them, value ranges, and what a write does. Exception codes of 8.3: 02 address (not there, or
the wrong direction), 03 data (value, count or size).

Words travel big-endian; a 32-bit value occupies two addresses, high word first (8.4 example:
2000H = 0000H, 2001H = 0064H is 100). It must be written whole (one FC10) [A]; its halves
may be read alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from mlctool.devices.framing import ILLEGAL_ADDRESS, ILLEGAL_VALUE  # 8.3: the protocol's codes
from mlctool.devices.xc100 import controller as c
from mlctool.devices.xc100.tables import tables

MAX_WORDS = 60  # FC03/FC10 quantity: 8.5 prints up to 3CH; the RTU tables disagree [A]
UNLOCK_KEY = b"Lv01TyVg"  # 8.2 開放寫入指令: FC10 of these 8 bytes to 999BH
CONTROLLER_NAME = "XC100"
FIRMWARE = 0x0100  # 10F0H, HEX-ASCII: 100 = version 1.00


@dataclass(frozen=True, slots=True)
class Reg:
    base: int  # first address of the value
    words: int
    area: str  # status | param | action | point | save | key
    read: bool
    write: bool
    lo: int = 0
    hi: int = 0xFFFF
    name: str = ""
    values: tuple[int, ...] = ()


@cache
def register_map() -> dict[int, Reg]:
    """Every address -> the value it belongs to."""
    regs: dict[int, Reg] = {}

    def put(r: Reg) -> None:
        for a in range(r.base, r.base + r.words):
            regs[a] = r

    for a, w, name in ((0x1000, 1, "ActionStatus"), (0x1001, 1, "InpStatus"),
                       (0x1004, 1, "TrqLmtStatus"), (0x1005, 1, "AlarmStatus"),
                       (0x1006, 1, "MonSpeed"), (0x1007, 1, "MonCurrent"),
                       (0x1008, 2, "CmdNowPos"), (0x100A, 2, "EcdPos"), (0x100C, 1, "ServoStatus"),
                       (0x100D, 1, "ErrorStatus"), (0x100E, 1, "StepNo"), (0x1020, 1, "Outputs"),
                       (0x1040, 1, "Inputs"), (0x104F, 1, "ZPhase"), (0x10F0, 1, "FirmwareNo")):
        put(Reg(a, w, "status", True, False, name=name))
    for k in range(10):
        put(Reg(0x1021 + k, 1, "status", True, False, name=f"OUT{k + 1}"))
    for k in range(14):
        put(Reg(0x1041 + k, 1, "status", True, False, name=f"IN{k + 1}"))
    for k in range(50):
        put(Reg(0x1060 + k, 1, "status", True, False, name=f"AlarmList{k + 1:02d}"))
    # strings of up to 31 characters + NUL, two characters a word [A: 8.2 prints 1 word]
    put(Reg(0x10D0, 16, "status", True, False, name="MotorType"))
    put(Reg(0x10E0, 16, "status", True, False, name="Controller"))
    for p in tables().params:
        put(Reg(p.addr, p.words, "param", True, True, p.lo, p.hi, p.name))
    for a, w, lo, hi, name, values in (
            (0x2000, 2, -(1 << 31), (1 << 31) - 1, "INCamount", ()),
            (0x2002, 2, -(1 << 31), (1 << 31) - 1, "ABSamount", ()),
            (0x2005, 1, 0, 1, "TrqStopDir", ()),
            (0x2006, 2, -(1 << 31), (1 << 31) - 1, "PosAmount", ()),
            (0x2011, 1, 0, 1, "ServoOnOff", ()),
            (0x2014, 1, 0, 100, "MovSpeedSet", ()),
            (0x2040, 1, 0, 0x3FFF, "SimInputs", ())):
        put(Reg(a, w, "action", True, True, lo, hi, name, values))
    # 201EH executes a command: write-only [A]; 5 and 10 are 未開放
    put(Reg(0x201E, 1, "action", False, True, 0, 12, "MovType", (0, 1, 2, 3, 4, 6, 7, 8, 9, 11, 12)))
    for k in range(14):
        put(Reg(0x2041 + k, 1, "action", True, True, 0, 1, f"SimIN{k + 1}"))
    for n in range(128):
        for f in tables().fields:
            put(Reg(0x9000 + 0x10 * n + f.offset, f.words, "point", True, True, f.lo, f.hi,
                    f"P{n}.{f.name}", f.values))
    put(Reg(0x9999, 1, "save", False, True, 0, 1, "ParamSave"))
    put(Reg(0x999B, 4, "key", False, True, name="WriteUnlock"))
    return regs


def _s16(v: int) -> int:
    v &= 0xFFFF
    return v - 0x10000 if v >> 15 else v


def _s32(hi: int, lo: int) -> int:
    v = (hi & 0xFFFF) << 16 | (lo & 0xFFFF)
    return v - (1 << 32) if v >> 31 else v


def _split(value: int, words: int) -> list[int]:
    v = int(value) & ((1 << (16 * words)) - 1)
    return [(v >> (16 * (words - 1 - k))) & 0xFFFF for k in range(words)]


def _text(s: str, words: int) -> list[int]:
    raw = s.encode("ascii", "replace")[: 2 * words - 1].ljust(2 * words, b"\0")
    return [raw[2 * k] << 8 | raw[2 * k + 1] for k in range(words)]


# -- reading

def read_words(dev: c.Xc100, addr: int, count: int, motor: str = "XC100-SIM") -> list[int] | int:
    """FC03 -> the words, or an exception code (the lowest of the errors present, 8.3)."""
    regs = register_map()
    span = range(addr, min(addr + max(count, 0), 0x10000))
    bad_addr = addr + count > 0x10000 or any(a not in regs or not regs[a].read for a in span)
    if bad_addr:
        return ILLEGAL_ADDRESS
    if not 1 <= count <= MAX_WORDS:
        return ILLEGAL_VALUE
    out = []
    for a in span:
        r = regs[a]
        out.append(_value_words(dev, r, motor)[a - r.base])
    return out


def _value_words(dev: c.Xc100, r: Reg, motor: str) -> list[int]:
    if r.area == "param":
        return _split(dev.params[r.base], r.words)
    if r.area == "action":
        if r.base >= 0x2041:
            return [dev.sim_pins >> (r.base - 0x2041) & 1]
        if r.base == 0x2040:
            return [dev.sim_pins]
        return _split(dev.regs.get(r.base, 0), r.words)
    if r.area == "point":
        n, off = divmod(r.base - 0x9000, 0x10)
        f = next(f for f in tables().fields if f.offset == off)
        return _split(getattr(dev.points[n], f.name), r.words)
    return _split(_status(dev, r, motor), r.words) if r.words <= 2 else \
        _text(motor if r.base == 0x10D0 else CONTROLLER_NAME, r.words)


def _status(dev: c.Xc100, r: Reg, motor: str) -> int:
    a = r.base
    sig = c.output_signals(dev)
    if a == 0x1000:
        return 1 if dev.motion is not None else dev.action
    if a == 0x1001:
        return int(sig["INP"])
    if a == 0x1004:
        return int(dev.torque_reached)
    if a == 0x1005:
        return dev.alarm
    if a == 0x1006:
        return round(dev.vel / c.pulses_per_rev(dev) * 60)
    if a == 0x1007:
        return dev.current
    if a == 0x1008:
        return round(dev.cmd)
    if a == 0x100A:
        return round(dev.act)
    if a == 0x100C:
        return int(dev.servo)
    if a == 0x100D:
        return dev.error
    if a == 0x100E:
        return dev.step_no
    if a == 0x1020:
        return c.output_pins(dev)
    if 0x1021 <= a <= 0x102A:
        return c.output_pins(dev) >> (a - 0x1021) & 1
    if a == 0x1040:
        return c.effective_pins(dev) | int(c.z_phase(dev)) << 14
    if 0x1041 <= a <= 0x104E:
        return c.effective_pins(dev) >> (a - 0x1041) & 1
    if a == 0x104F:
        return int(c.z_phase(dev))
    if 0x1060 <= a <= 0x1091:
        k = a - 0x1060
        return dev.history[k] if k < len(dev.history) else 0
    if a == 0x10F0:
        return FIRMWARE
    raise KeyError(hex(a))  # pragma: no cover - register_map lists only the above


# -- writing

def write_words(dev: c.Xc100, addr: int, words: list[int]) -> int:
    """FC06/FC10 -> 0, or an exception code; nothing is written unless all of it is valid."""
    regs = register_map()
    span = range(addr, addr + len(words))
    if addr + len(words) > 0x10000 or any(a not in regs or not regs[a].write for a in span):
        return ILLEGAL_ADDRESS
    if not 1 <= len(words) <= MAX_WORDS:
        return ILLEGAL_VALUE
    values: list[tuple[Reg, int]] = []
    k = 0
    while k < len(words):
        r = regs[addr + k]
        if r.base != addr + k or k + r.words > len(words):
            return ILLEGAL_VALUE  # part of a multi-word value
        chunk = words[k:k + r.words]
        if r.area == "key":
            if bytes(b for w in chunk for b in (w >> 8, w & 0xFF)) != UNLOCK_KEY:
                return ILLEGAL_VALUE
            values.append((r, 0))
        else:
            v = _s32(*chunk) if r.words == 2 else (_s16(chunk[0]) if r.lo < 0 else chunk[0])
            if not (r.lo <= v <= r.hi) or (r.values and v not in r.values):
                if r.area == "param":  # 10.3 上下限錯誤: "在參數裡設定超出範圍的數值" [A]
                    dev.error = c.ERR_RANGE
                    dev.refused = f"{r.base:04X}H ({r.name}) = {v}: outside {r.lo}~{r.hi} (ch. 5)"
                return ILLEGAL_VALUE
            values.append((r, v))
        k += r.words
    if reason := line_settings_refused(dev, {r.base: v for r, v in values if r.area == "param"}):
        dev.error = c.ERR_RANGE
        dev.refused = reason
        return ILLEGAL_VALUE
    if any(r.area == "param" for r, _ in values) and not dev.unlocked:
        dev.error = 11  # 10.3 parameter write permission insufficient
        return ILLEGAL_VALUE
    for r, v in values:
        _apply(dev, r, v)
    return 0


def line_settings_refused(dev: c.Xc100, writing: dict[int, int]) -> str:
    """Why the RS-485 settings after this write are not a line the XC100 has ('' if they are).

    8.1's table: 資料長度 (data bits) "7、8 BIT" in ASCII mode but "8 BIT" in RTU mode, so
    DataSize 0A01H = 1 (7 bit) and Protocol 0A04H = 1 (RTU) together are refused like a value
    out of range (exception 03, ErrorStatus 2 上下限錯誤) whichever of the two is written
    last [A: the manual names no error for the pair]. 停止位元 (stop bits) "1 BIT": there is
    no parameter for them, so nothing here can set another count."""
    size = writing.get(0x0A01, dev.params[0x0A01])
    protocol = writing.get(0x0A04, dev.params[0x0A04])
    if size == 1 and protocol == 1:
        return ("0A01H DataSize = 1 (7 bit) with 0A04H Protocol = 1 (RTU): "
                "8.1 allows 8 data bits only in RTU mode")
    return ""


def _apply(dev: c.Xc100, r: Reg, v: int) -> None:
    if r.area == "key":
        dev.unlocked = True
    elif r.area == "param":
        if dev.motion is not None:
            dev.error = c.ERR_BUSY  # 10.3: parameters are not changed while operating
            return
        dev.params[r.base] = v
        p = tables().by_addr[r.base]
        if p.reboot:  # 5: "修改重新開機" o: the value acts after the next power-up
            dev.needs_reboot = True
            dev.error = c.ERR_REBOOT
    elif r.area == "point":
        n, off = divmod(r.base - 0x9000, 0x10)
        m = dev.motion
        if m is not None and m.kind == "point":
            dev.error = c.ERR_BUSY  # 10.3: program data set while the program runs
            return
        f = next(f for f in tables().fields if f.offset == off)
        setattr(dev.points[n], f.name, v)
    elif r.area == "save":
        if v == 0:
            dev.saved = dict(dev.params)  # 9999H = 0: keep the current parameters [A]
        else:
            dev.params = c.default_params()  # 9999H = 1: back to the defaults [A]
    elif r.base == 0x201E:
        c.command(dev, v)
    elif r.base == 0x2011:
        dev.regs[r.base] = v
        c.servo_command(dev, v)
    elif r.base == 0x2040:
        c.set_simulated_inputs(dev, v)
    elif r.base >= 0x2041:
        bit = 1 << (r.base - 0x2041)
        c.set_simulated_inputs(dev, (dev.sim_pins | bit) if v else (dev.sim_pins & ~bit))
    else:
        dev.regs[r.base] = v
