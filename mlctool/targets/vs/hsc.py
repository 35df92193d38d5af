"""Software high-speed counters C235-C255 and their compare instructions (manual 2-7, 6-7
FNC 53 DHSCS, 54 DHSCR, 55 DHSZ, 56 SPD) on the stimulus's pulse trains (sim/hardware/pulses.py).

Which counters count which input is data: target.toml `[high_speed_counters]` (`inputs`:
counter -> input; `counters`: the whole range, so one without an input assignment is a
run-time fault naming it, never a silent count of its rung). A high-speed counter counts the
rising edges of its input between scans while its coil (OUT C235 K..) was On at its last
execution, up or down by its direction relay M9235... as of that execution, past the preset both ways (contact
On at value >= preset, judged at each count).

Counting is analytic: the edges of a scan interval are counted, never stepped. Compare
points of DHSCS/DHSCR (active while their condition was On at their last execution) act at
the edge that makes the value equal to S1, in time order within the interval (the time of
edge k of a train is t0 + k/f): DHSCS sets D (Y at once, not at END) or, with an interrupt
pointer IHC0-IHC7 as D (6-7), requests that routine at the edge's time through the
interrupt queue (targets/vs/interrupts.py; M9061 disables), DHSCR resets D (the
counter itself: value 0, contact Off, counting goes on from 0). DHSZ judges the zone after
the counts of the interval. Writing a counter (DMOV) compares nothing (2-7, 6-7).
"""

from __future__ import annotations

from mlctool.sim.hardware.pulses import count as count_edges
from mlctool.sim.hardware.pulses import quadrature_count, time_of_count
from mlctool.sim.operands import CounterRef
from mlctool.sim.state import Machine, SimFault, s32
from mlctool.targets.vs.common import op_error, special, write_block
from mlctool.targets.vs.hhsc import catch_up_hardware, dhhcmv
from mlctool.targets.vs.routines import counter

MAX_COMPARES = 8  # DHSCS/DHSCR/DHSZ/DHSCT executed together (6-7)


def _table(m: Machine):
    return m.target.settings.get("high_speed_counters")


def _counters(m: Machine) -> dict:
    return m.hsc.setdefault("counters", {})


def _compares(m: Machine) -> dict:
    return m.hsc.setdefault("compares", {})


def _may_compare(m: Machine, s, points: dict, n: int) -> bool:
    """DHSCS/DHSCR/DHSZ/DHSCT: C n must be a high-speed counter, and at most MAX_COMPARES
    compare points are active at once (6-7, 6-21); else an operation error."""
    if not is_high_speed(m, n):
        op_error(m, s, f"C{n} is not a high-speed counter")
        return False
    if s.index not in points and len(points) >= MAX_COMPARES:
        op_error(m, s, f"more than {MAX_COMPARES} high-speed compares active at once")
        return False
    return True


def is_high_speed(m: Machine, n: int) -> bool:
    t = _table(m)
    return bool(t) and t["counters"][0] <= n <= t["counters"][1]


def _input(name: str | None) -> tuple[str, int] | None:
    return None if name is None else (name[0], int(name[1:], 8))


def _wiring(m: Machine, n: int) -> dict | None:
    """The counter's inputs from the table (2-7-1, mode 1): 1-phase `inputs` (U/D), 2-phase
    `two_phase` [U, D], A/B `ab_phase` [A, B]; optional hardware `reset` and `start` inputs."""
    t = _table(m)
    key = str(n)
    for kind, table in (("one", "inputs"), ("two", "two_phase"), ("ab", "ab_phase")):
        pins = t.get(table, {}).get(key)
        if pins is not None:
            pins = [pins] if isinstance(pins, str) else pins
            return {"kind": kind, "pins": [_input(p) for p in pins],
                    "reset": _input(t.get("reset", {}).get(key)),
                    "start": _input(t.get("start", {}).get(key))}
    return None


def coil(m: Machine, s, n: int) -> None:
    """OUT C235 K..: enables counting of the input's pulses (2-7 "software start")."""
    wiring = _wiring(m, n)
    if wiring is None:
        raise SimFault(f"C{n}: the input assignment of this high-speed counter is not simulated")
    c = _counters(m).setdefault(n, {})
    # the state the program leaves counts the pulses until its next execution: enable,
    # preset and the direction relay as of now (a relay changed later acts from then on)
    c.update(wiring, on=bool(m.acc), preset=s.ops[1].get(m), direction=_direction(m, n))
    c.setdefault("levels", _levels(m, c))


def _levels(m: Machine, c: dict) -> dict:
    """The hardware reset/start inputs as this scan sees them: they hold until the next scan."""
    return {pin: m.bits[pin[0]][pin[1]] for pin in (c["reset"], c["start"]) if pin}


def _direction(m: Machine, n: int) -> int:
    base_relay = m.target.settings.get("counter_direction_base")
    k = n - m.c32_lo
    if base_relay is None or k >= m.target.settings.get("counter_direction_count", 0):
        return 1
    return -1 if m.bits["M"][base_relay + k] else 1


def _net(m: Machine, c: dict, after: int, upto: int) -> int:
    """Signed counts of the interval: 1-phase by the direction relay, 2-phase U minus D,
    A/B phase x1 from the stimulus's A/B pairs (pulses.Quadrature)."""
    pins = c["pins"]
    if c["kind"] == "one":
        return c["direction"] * count_edges(m, *pins[0], after, upto)
    if c["kind"] == "two":
        return count_edges(m, *pins[0], after, upto) - count_edges(m, *pins[1], after, upto)
    return quadrature_count(m, pins[0], pins[1], 1, after, upto)


def catch_up(m: Machine) -> None:
    """Before a scan: the counts since the previous scan (edges in (last, now]). The hardware
    start input gates and the reset input holds the counter at 0 by the level the previous
    scan saw (DECISION: input levels change at scan starts, 2-7-1 examples); a reset input
    On now clears after the interval's counts (value 0, contact Off)."""
    m.hsc["irq"] = []  # interrupt requests of this interval (IHC, IHHC), taken by the queue
    catch_up_hardware(m)
    if not _table(m):
        return
    if m.hsc.pop("table_done", False):  # M9162 was On for the scan after the last row
        m.bits["M"][special(m, "hsct_done")] = 0
    last = m.hsc.get("last_us", -1)
    m.hsc["last_us"] = m.now_us
    monitor = m.target.settings.get("counter_direction_base")
    for n, c in sorted(_counters(m).items()):
        was = c["levels"]
        gated = (c["start"] is not None and not was.get(c["start"])) or \
            (c["reset"] is not None and was.get(c["reset"]))
        if c["on"] and not gated:
            net = _net(m, c, last, m.now_us)
            if net:
                _count(m, n, c, abs(net), 1 if net > 0 else -1,
                       lambda k, c=c: time_of_count(lambda t: _net(m, c, last, t), last, m.now_us, k))
                if c["kind"] != "one" and monitor is not None:  # M9246-M9255: On = counting down
                    m.bits["M"][monitor + n - m.c32_lo] = 1 if net < 0 else 0
        if c["reset"] is not None and m.bits[c["reset"][0]][c["reset"][1]]:
            m.cval[n] = 0
            m.bits["C"][n] = 0
        c["levels"] = _levels(m, c)


def _interrupt(m: Machine, dest, at_us: int) -> None:
    """DHSCS ... IHCn: the compare requests the interrupt at the count's time; the interrupt
    queue (targets/vs/interrupts.py) serves it before the next scan, in time order with the others."""
    m.hsc.setdefault("irq", []).append((at_us, dest.num))


def _count(m: Machine, n: int, c: dict, total: int, d: int, time_of=None) -> None:
    """`time_of(k)`: the time of the interval's k-th count (for interrupt requests)."""
    points = [(idx, p) for idx, p in sorted(_compares(m).items()) if p["counter"] == n]
    v = s32(m.cval[n])
    # whole cycles may be skipped only when nothing but the counter's state depends on them
    tables = any(p["kind"] == "table" or (p["kind"] == "set" and p["dest"].kind == "I") for _, p in points)
    whole, done = total, 0
    seen_reset = None  # remaining count at the last self-reset: the cycle repeats after it
    while total:
        hit = None
        for _idx, p in points:
            if p["kind"] in ("set", "reset", "table"):
                target = p["rows"][p["row"]][0] if p["kind"] == "table" else p["value"]
                steps = (target - v) * d
                if 1 <= steps <= total and (hit is None or steps < hit[0]):
                    hit = (steps, p)
        if hit is None:
            v = s32(v + d * total)
            total = 0
            break
        steps, p = hit
        v = s32(v + d * steps)
        total -= steps
        done = whole - total
        m.bits["C"][n] = 1 if v >= c["preset"] else 0
        if p["kind"] == "table":
            _table_row_reached(m, p)
        elif p["kind"] == "set" and p["dest"].kind == "I":
            _interrupt(m, p["dest"], time_of(done) if time_of else m.now_us)
        elif p["kind"] == "set":
            p["dest"].setbit(m, 1)
        elif isinstance(p["dest"], CounterRef) and p["dest"].addr(m) == n:
            v = 0  # self-reset: value 0, contact Off (6-7 DHSCR)
            m.bits["C"][n] = 0
            # whole cycles leave the same state only without a DHSCT table's row to advance
            if seen_reset is not None and seen_reset > total and not tables:
                total %= seen_reset - total  # whole cycles leave the same state
            seen_reset = total
        else:
            p["dest"].setbit(m, 0)
    m.cval[n] = v
    m.bits["C"][n] = 1 if v >= c["preset"] else 0
    for _, p in points:
        if p["kind"] == "zone":
            lo, hi = p["value"]
            for k, on in enumerate((v < lo, lo <= v <= hi, v > hi)):
                p["dest"].setbit(m, on, k)


def _register(kind: str):
    """DHSCS/DHSCR/DHSZ: the compare point is active while the condition is On."""
    def run(m: Machine, s) -> None:
        points = _compares(m)
        if not m.acc:
            points.pop(s.index, None)
            return
        ops = s.ops
        counter = ops[-2]
        n = counter.addr(m)
        if not _may_compare(m, s, points, n):
            return
        value = (ops[0].get(m), ops[1].get(m)) if kind == "zone" else ops[0].get(m)
        points[s.index] = {"kind": kind, "value": value, "counter": n, "dest": ops[-1]}
    return run


# ------------------------------------------------------------------ DHSCT (6-21 FNC 280)

def _table_row_reached(m: Machine, p: dict) -> None:
    """The row's output state goes to D..D+n-1 at once, D9162 counts the row; after the last
    row D9162 is 0 again, M9162 On for one scan and the table starts over from row 1."""
    rows = p["rows"]
    state_word = rows[p["row"]][1]
    for k in range(p["bits"]):
        p["dest"].setbit(m, bool((state_word >> k) & 1), k)
    p["row"] += 1
    if p["row"] == len(rows):
        p["row"] = 0
        done = special(m, "hsct_done")
        if done is not None:
            m.bits["M"][done] = 1
            m.hsc["table_done"] = True  # catch_up turns it Off before the next scan
    row_register = special(m, "hsct_row")
    if row_register is not None:
        m.words["D"][row_register] = p["row"]


def dhsct(m: Machine, s) -> None:
    """DHSCT S1 m S2 D n: a table of m rows from S1 (compare value S1+3k+1:S1+3k, output state
    S1+3k+2) against the counter S2, row by row; a compare point like DHSCS (active while the
    condition is On, one of the 8). The rows are read at each execution (DECISION: a row
    changed while counting applies from the next execution); the row reached is the
    simulator's, shown in D9162. Off: stops, D9162 = 0, the outputs keep their states."""
    points = _compares(m)
    row_register = special(m, "hsct_row")
    if not m.acc:
        if points.pop(s.index, None) is not None and row_register is not None:
            m.words["D"][row_register] = 0
        return
    table, rows_ref, counter, dest, bits_ref = s.ops
    rows, bits, n = rows_ref.get(m), bits_ref.get(m), counter.addr(m)
    if not (1 <= rows <= 16 and 1 <= bits <= 16):
        op_error(m, s, f"m = {rows}, n = {bits}: both must be 1-16")
        return
    if not _may_compare(m, s, points, n):
        return
    words = m.words[table.kind]
    a = table.addr(m)
    if a + 3 * rows > len(words):
        op_error(m, s, f"a table of {rows} rows from {table.kind}{a} runs past the device range")
        return
    entries = [(s32(words[a + 3 * k] | words[a + 3 * k + 1] << 16), words[a + 3 * k + 2])
               for k in range(rows)]
    p = points.setdefault(s.index, {"kind": "table", "row": 0})
    p.update(rows=entries, counter=n, dest=dest, bits=bits, row=p["row"] % rows)


def spd(m: Machine, s) -> None:
    """SPD S1 S2 D (FNC 56): the pulses of input S1 counted over windows of S2 ms: D = the
    count of the last complete window, D+1 the count so far in this one, D+2 the ms left.
    DECISION: windows start at the execution that finds the condition On after Off, and
    follow each other without gaps (remainders carried); Off stops the measurement, D keeps."""
    memo = m.hsc.setdefault("spd", {})
    if not m.acc:
        memo.pop(s.index, None)
        return
    src, window_ref, dst = s.ops
    ms = window_ref.get(m)
    if ms < 1:
        op_error(m, s, f"S2 = {ms} ms: the window must be at least 1 ms")
        return
    kind, number = src.kind, src.addr(m)
    start = memo.setdefault(s.index, m.now_us)
    span = ms * 1000
    while m.now_us - start >= span:
        dst.set(m, count_edges(m, kind, number, start, start + span))
        start += span
    memo[s.index] = start
    # D+1 the count so far, D+2 the ms left: the block of three written as one (a counter
    # or index register as D too; past the device's end a fault)
    write_block(m, dst, [dst.get(m), count_edges(m, kind, number, start, m.now_us),
                         (start + span - m.now_us) // 1000], s.width)


def counter_coil(m: Machine, s) -> None:
    """OUT C: high-speed counters by the table, every other counter by routines.counter."""
    n = s.ops[0].addr(m)
    if is_high_speed(m, n):
        coil(m, s, n)
    else:
        counter(m, s)  # the VS counter rules of 2-6 (routines.py), not the engine's cnt


HSC_ACTIONS = {
    "cnt": counter_coil, "dhscs": _register("set"), "dhscr": _register("reset"),
    "dhsz": _register("zone"), "dhsct": dhsct, "spd": spd, "dhhcmv": dhhcmv,
}
