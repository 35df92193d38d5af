"""DABS (8-3 FNC 313): reading an absolute encoder's position, on the axis moves of targets/vs/positioning/moves.py."""

from __future__ import annotations

from mlctool.sim.state import Machine, s32
from mlctool.targets.vs.common import op_error, set_relay, state

# ------------------------------------------------------------ DABS (FNC 313)

ABS_DATA, ABS_SUM = 16, 3  # transfers of 2 bits: the 32-bit position, then a 6-bit checksum


def _abs_outputs(m: Machine, s, servo_on: int, mode: int, request: int) -> None:
    d1 = s.ops[1]
    for k, v in enumerate((servo_on, mode, request)):  # D1 SERVO ON, D1+1 ABSM, D1+2 ABSR
        d1.setbit(m, v, k)


def _abs_take(m: Machine, s, memo: dict) -> None:
    """ABST (S+2) On: the 2 bits on S (bit 0) and S+1 (bit 1) are the next transfer; the
    last one checks the sum and, when it holds, writes the position to D2."""
    bits = s.ops[0].bit(m, 0) | s.ops[0].bit(m, 1) << 1
    k = memo["k"]
    if k < ABS_DATA:
        memo["data"] |= bits << (2 * k)
        memo["sum"] += bits
    else:
        memo["check"] |= bits << (2 * (k - ABS_DATA))
    memo["k"] = k + 1
    if memo["k"] < ABS_DATA + ABS_SUM:
        return
    memo["done"] = True
    _abs_outputs(m, s, 1, 0, 0)
    if memo["check"] != memo["sum"] & 0x3F:
        return op_error(m, s, f"ABS checksum {memo['check']} != {memo['sum'] & 0x3F}")
    s.ops[2].set(m, s32(memo["data"]))
    memo["m9029"] = True
    set_relay(m, "done", True)


def dabs(m: Machine, s) -> None:
    """DABS S D1 D2 (FNC 313): reads a Mitsubishi absolute-encoder servo's position into D2
    (usually D9353:D9352). The page gives only the wiring (S ABS bit 0, bit 1, ready; D1 SERVO
    ON, ABS mode, ABS request) and "M9029 On one scan when read; the condition Off interrupts".
    DECISION: the handshake of the servo's ABS transfer (MR-J2S): SERVO ON and ABS mode On;
    per transfer the request On, the ready signal On = 2 bits valid, the request Off, ready
    Off; 16 transfers of the position (low bits first), 3 of the checksum (the low 6 bits of
    the sum of the 16 transfers); a wrong checksum is an operation error (D2 unchanged)."""
    memo = state(m, s, {})
    if memo.get("m9029"):  # On for one scan: the next execution turns it Off
        memo["m9029"] = False
        set_relay(m, "done", False)
    if not m.acc:
        if memo:
            _abs_outputs(m, s, 0, 0, 0)
            memo.clear()
        return
    if not memo:
        for ref in s.ops[:2]:  # S and D1 take 3 points each (the page)
            if ref.addr(m) + 2 > m.target.devices[ref.kind].hi:
                return op_error(m, s, f"{ref.text} takes 3 points, past the device range")
        memo.update(k=0, data=0, sum=0, check=0, done=False, m9029=False, ready=s.ops[0].bit(m, 2))
    if memo["done"]:
        return
    ready = s.ops[0].bit(m, 2)
    if ready and not memo["ready"]:
        _abs_take(m, s, memo)
    memo["ready"] = ready
    if not memo["done"]:
        _abs_outputs(m, s, 1, 1, 0 if ready else 1)


POS_ABS_ACTIONS = {"dabs": dabs}
