"""Real-time clock instructions on a virtual calendar (manual 6-14, FNC 160-167).

The calendar never reads the wall clock: it starts at target.toml `rtc.epoch` (VS:
2000-01-01 00:00:00, a Saturday) at virtual time 0 and advances with the virtual time. The
registers D9013-D9019 (second, minute, hour, day, month, year, weekday) are refreshed
before every scan; a value written to them from outside the program since the last refresh
(a stimulus line `0ms D9018=2024 D9017=5 ...`) sets the calendar, as TWR does.
"""

from __future__ import annotations

import datetime as dt

from mlctool.sim import semantics as base
from mlctool.sim.state import Machine, put_words
from mlctool.targets.vs.common import op_error, read_block, set_flags, write_block

_KEY = "rtc"  # Machine.fx_state entry: (calendar at base_us, base_us, registers last written)


def _settings(m: Machine):
    return m.target.settings.get("rtc")


def _now(m: Machine) -> dt.datetime:
    cal = m.fx_state.get(_KEY)
    if cal is None:
        epoch = dt.datetime.fromisoformat(_settings(m)["epoch"])
        cal = m.fx_state[_KEY] = (epoch, 0, None)
    start, base_us, _ = cal
    return start + dt.timedelta(seconds=(m.now_us - base_us) // 1_000_000)


def _set(m: Machine, when: dt.datetime) -> None:
    m.fx_state[_KEY] = (when, m.now_us - m.now_us % 1_000_000, None)


def _fields(when: dt.datetime) -> list[int]:
    """second, minute, hour, day, month, year, weekday (0 = Sunday): D9013-D9019 order."""
    return [when.second, when.minute, when.hour, when.day, when.month, when.year,
            (when.weekday() + 1) % 7]


def _date(year, month, day, hour, minute, second) -> dt.datetime | None:
    try:
        if not 2000 <= year <= 2099:
            return None
        return dt.datetime(year, month, day, hour, minute, second)
    except ValueError:
        return None


def refresh(m: Machine) -> None:
    """Before each scan: registers written from outside set the calendar, then the current
    time is written to them."""
    cfg = _settings(m)
    if not cfg:
        return
    first = cfg["registers"]
    words = m.words["D"]
    now = _now(m)
    current = [words[first + k] for k in range(7)]
    last = m.fx_state[_KEY][2]
    if last is not None and current != last:
        sec, mi, hr, day, mon, year, _ = current
        when = _date(year, mon, day, hr, mi, sec)
        if when is not None:
            _set(m, when)
            now = when
    values = _fields(now)
    put_words(words, first, values)
    start, base_us, _ = m.fx_state[_KEY]
    m.fx_state[_KEY] = (start, base_us, values)


@base._on
def trd(m: Machine, s) -> None:
    """TRD D: year, month, day, hour, minute, second, weekday into D..D+6 (FNC 166; the FX
    order, D+6 the weekday 0-6 as the TWR page says)."""
    sec, mi, hr, day, mon, year, wd = _fields(_now(m))
    write_block(m, s.ops[0], [year, mon, day, hr, mi, sec, wd], 16)


@base._on
def twr(m: Machine, s) -> None:
    """TWR S: sets the calendar from S..S+6 (same order as TRD); a field out of range is an
    operation error (FNC 167)."""
    year, mon, day, hr, mi, sec, wd = read_block(m, s.ops[0], 7, 16)
    when = _date(year, mon, day, hr, mi, sec)
    if when is None or not 0 <= wd <= 6:
        op_error(m, s, f"{year}-{mon}-{day} {hr}:{mi}:{sec} weekday {wd} is not a valid time")
        return
    _set(m, when)
    if _settings(m):
        refresh(m)


def _hms(values) -> int | None:
    h, mi, sec = values
    if not (0 <= h <= 23 and 0 <= mi <= 59 and 0 <= sec <= 59):
        return None
    return h * 3600 + mi * 60 + sec


def _three(m: Machine, ref) -> int | None:
    return _hms(read_block(m, ref, 3, 16))


@base._on
def tcmp(m: Machine, s) -> None:
    """TCMP S1 S2 S3 S D: D = (S1:S2:S3) > (S..S+2), D+1 equal, D+2 less (FNC 160)."""
    ref = _hms([r.get(m) for r in s.ops[:3]])
    t = _three(m, s.ops[3])
    if ref is None or t is None:
        op_error(m, s, "a time value is out of range")
        return
    for k, on in enumerate((ref > t, ref == t, ref < t)):
        s.ops[4].setbit(m, on, k)


@base._on
def tzcp(m: Machine, s) -> None:
    """TZCP S1 S2 S D: D = S < S1, D+1 = S1 <= S <= S2, D+2 = S > S2; S1 > S2 uses S1 as both
    limits (FNC 161)."""
    lo, hi, t = (_three(m, r) for r in s.ops[:3])
    if lo is None or hi is None or t is None:
        op_error(m, s, "a time value is out of range")
        return
    hi = max(hi, lo) if lo > hi else hi
    for k, on in enumerate((t < lo, lo <= t <= hi, t > hi)):
        s.ops[3].setbit(m, on, k)


def _time_arith(sign: int):
    """TADD/TSUB S1 S2 D: times of day added/subtracted modulo 24 h; past 24 h M9022, below
    0 M9021, 0:00:00 M9020 (FNC 162/163)."""
    @base._on
    def run(m: Machine, s) -> None:
        a, b = _three(m, s.ops[0]), _three(m, s.ops[1])
        if a is None or b is None:
            op_error(m, s, "a time value is out of range")
            return
        r = a + sign * b
        t = r % 86400
        write_block(m, s.ops[2], [t // 3600, t // 60 % 60, t % 60], 16)
        set_flags(m, zero=t == 0, carry=r >= 86400, borrow=r < 0)
    return run


@base._on
def htos(m: Machine, s) -> None:
    """HTOS S D: hours, minutes, seconds -> seconds; hours 0-4 (16-bit), 0-32767 (32-bit)."""
    h, mi, sec = read_block(m, s.ops[0], 3, 16)
    top = 32767 if s.width == 32 else 4
    if not (0 <= h <= top and 0 <= mi <= 59 and 0 <= sec <= 59):
        op_error(m, s, f"{h}:{mi}:{sec} is out of range")
        return
    s.ops[1].set(m, h * 3600 + mi * 60 + sec)


@base._on
def stoh(m: Machine, s) -> None:
    """STOH S D: seconds -> hours, minutes, seconds in D..D+2 (S 0-32767 / 0-117,964,799)."""
    v = s.ops[0].get(m)
    top = 117_964_799 if s.width == 32 else 32767
    if not 0 <= v <= top:
        op_error(m, s, f"{v} s is out of range")
        return
    write_block(m, s.ops[1], [v // 3600, v // 60 % 60, v % 60], 16)


CLOCK_ACTIONS = {
    "trd": trd, "twr": twr, "tcmp": tcmp, "tzcp": tzcp, "tadd": _time_arith(1),
    "tsub": _time_arith(-1), "htos": htos, "stoh": stoh,
}
