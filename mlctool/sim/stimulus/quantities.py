"""Times and frequencies as stimulus files, `mlc sim` options and device models write them
(150ms, 1.5s, 500us, 2min; 1kHz), and the error their readers raise (E601). Apart from
stimulus.py so that its helpers (serial_stim.py) need not import it."""

from __future__ import annotations

import re
from fractions import Fraction

from mlctool.limits import clip, long_number, too_long_message

_UNITS = {"us": 1, "ms": 1000, "s": 1_000_000, "min": 60_000_000}
_TIME = re.compile(r"(?P<num>[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?P<unit>us|ms|s|min)", re.IGNORECASE)
# The bounds of a run (docs/simulator.md "Bounds"), one pair for every way to ask for time:
# stimulus times (absolute and +relative), `run TIME`/`run #N`, `#N` scan numbers, --until,
# --scans, --scan-time, --duration. 10^12 us is about 11.6 days of virtual time; 10^9 scans
# are 10^7 s at the default 10 ms scan. Beyond either is surely a typo, and a CI run that must
# stop by wall-clock time has --max-wall.
MAX_TIME_US = 10**12
MAX_SCANS = 10**9
TIME_BOUND = "10^12 us (about 11.6 days)"


class StimError(ValueError):
    def __init__(self, message: str, col_offset: int = 0, code: str = "E601"):
        super().__init__(message)
        self.message = message
        self.col_offset = col_offset
        self.code = code


def parse_time(text: str) -> int:
    """'1.5s' -> 1500000 (microseconds). Raises StimError."""
    long = long_number(text)
    if long:  # --until, --duration and stimulus times (mlctool/limits.py)
        raise StimError(too_long_message(f"time {clip(text)!r}", len(long[0])))
    m = _TIME.fullmatch(text.strip())
    if not m:
        raise StimError(f"{clip(text)!r} is not a time (e.g. 150ms, 1.5s, 500us, 2min)")
    us = Fraction(m["num"]) * _UNITS[m["unit"].lower()]  # exact: 4.07s is 4070000 us
    if us.denominator != 1:
        raise StimError(f"{text!r} is not a whole number of microseconds")
    if us > MAX_TIME_US:
        raise StimError(f"{text!r} is past the bound of virtual time, {TIME_BOUND}")
    return int(us)


_FREQ = re.compile(r"(?P<num>[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?P<unit>hz|khz|mhz)", re.IGNORECASE)
_HZ = {"hz": 1, "khz": 1000, "mhz": 1_000_000}
MAX_HZ = 10_000_000


def parse_frequency(text: str) -> Fraction:
    """'1kHz' -> 1000 (Hz, exact). Raises StimError."""
    m = _FREQ.fullmatch(text.strip())
    if not m:
        raise StimError(f"{text!r} is not a frequency (e.g. 500Hz, 1kHz, 2.5kHz, 0Hz)")
    hz = Fraction(m["num"]) * _HZ[m["unit"].lower()]
    if hz > MAX_HZ:
        raise StimError(f"{text!r}: at most 10MHz")
    return hz
