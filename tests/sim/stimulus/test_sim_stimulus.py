"""Stimulus files: syntax, diagnostics with line/column, the time rule, forces, ranges."""

from __future__ import annotations

import pytest

from mlctool.sim.stimulus.stimulus import parse_stimulus_text, parse_time
from simkit import NC5, passed, simulate


def diags_of(text: str):
    _, diags = parse_stimulus_text("s.stim", text, NC5)
    return [(d.code, d.span.line, d.span.col) for d in diags]


def test_full_syntax_parses():
    st, diags = parse_stimulus_text("s.stim", """
# comment
scan 10ms                       # scan period
0ms     X0=1                    # inputs
150ms   X0=0 X1=1
1.5s    D100=25 K4M0=H00FF
#250    X2=1
+10ms   X3=on
2s      expect Y0=1 D0=30 T0=1
2.5s    expect D10:d=70000 D20:f=1.5 D0!=3 D1=-5..5 D2:h=HFFFF
3s      power-cycle
3s      force X5=1
4s      release X5
4s      expect alarm MLC_ARITH_ERROR
500us   C64:d=-1 T0:w=65535 C3:w=7 V0:d=100000
run 4s
""", NC5)
    assert diags == []
    assert st.scan_us == 10_000 and st.run_time_us == 4_000_000
    kinds = [e.kind for e in st.events]
    assert kinds == ["set", "set", "set", "set", "set", "expect", "expect", "power", "force",
                     "release", "alarm", "set"]
    assert st.events[3].scan == 250 and st.events[4].time_us == 1_510_000
    assert st.events[2].assigns[1][1] == 0xFF


@pytest.mark.parametrize("text,code,line,col", [
    ("0ms X0=2", "E601", 1, 5),
    ("0ms Q0=1", "E602", 1, 5),
    ("0ms D0:q=1", "E602", 1, 5),
    ("\n12 X0=1", "E601", 2, 1),
    ("0ms expect", "E601", 1, 5),
    ("0ms D0=1.5", "E601", 1, 5),
    ("0ms D0=40000", "E601", 1, 5),
    ("0ms X0=1 bogus", "E601", 1, 10),
    ("scan 0ms", "E601", 1, 6),
    ("run 4", "E601", 1, 5),
    ("1s expect D0=5..1", "E601", 1, 11),
    ("0ms T0:d=1", "E602", 1, 5),
    ("0ms C3:d=1", "E602", 1, 5),
    ("0ms X600=1", "E602", 1, 5),
    ("0ms expect alarm", "E601", 1, 12),
])
def test_errors_have_code_line_and_column(text, code, line, col):
    assert diags_of(text)[:1] == [(code, line, col)]


def test_time_units():
    assert [parse_time(t) for t in ("500us", "1.5ms", "2s", "1min", ".5s")] == \
        [500, 1500, 2_000_000, 60_000_000, 500_000]


def test_event_applies_before_first_scan_at_or_after_its_time():
    # 25 ms lies between scans 2 (20 ms) and 3 (30 ms): X0 is seen by scan 3 only
    r = simulate("LD X0\nINC D0\nEND", "25ms X0=1\n20ms expect D0=0\n25ms expect D0=1\n"
                 "40ms expect D0=2\n#5 expect D0=3")
    assert passed(r)


def test_force_holds_against_the_program_until_release():
    r = simulate("LD X0\nOUT Y0\nEND", "0ms force Y0=1\n10ms expect Y0=1\n20ms release Y0\n"
                 "20ms expect Y0=0")
    assert passed(r)


def test_failed_expectation_reports_device_values_and_writer():
    r = simulate("LD X0\nMOV K30 D0\nEND", "0ms X0=1\n1s expect D0=31 D1=0")
    [f] = r.failed
    assert (f.device, f.expected, f.actual, f.scan, f.time_us) == ("D0", "31", 30, 100, 1_000_000)
    assert f.writer.endswith("t.il:2: MOV K30 D0")


def test_expectation_after_the_run_fails():
    r = simulate("LD X0\nOUT Y0\nEND", "1s expect Y0=0\nrun 500ms")
    assert r.scans == 50 and len(r.failed) == 1 and "run ended" in r.failed[0].actual


def test_float_and_range_expectations():
    r = simulate("LD X0\nFDIV F1 F3 D0\nEND", "0ms X0=1\n0ms expect D0:f=0.33333334 "
                 "D0:f=0.333..0.334 D0:f!=0.5")
    assert passed(r)


def test_decimal_times_are_exact():
    from mlctool.sim.stimulus.stimulus import StimError, parse_time

    assert parse_time("4.07s") == 4_070_000  # float arithmetic would give 4069999.9999...
    assert parse_time("0.29s") == 290_000
    assert parse_time("1.001ms") == 1001
    with pytest.raises(StimError):
        parse_time("1.0000001s")


@pytest.mark.parametrize("line, col, hint", [
    ("sacn 10ms", 1, "did you mean `scan`?"),
    ("rnu 1s", 1, "did you mean `run`?"),
    ("10ms expcet Y0=1", 6, "did you mean `expect`?"),
    ("20ms focre X0=1", 6, "did you mean `force`?"),
    ("30ms relase X0", 6, "did you mean `release`?"),
    ("40ms power-cyle", 6, "did you mean `power-cycle`?"),
    ("50ms X0 puls 1kHz", 9, "did you mean `pulses`?"),
])
def test_mistyped_keywords_name_the_nearest(line, col, hint):
    """Issue 14 §3: a mistyped stimulus keyword gets the nearest one."""
    _, diags = parse_stimulus_text("s.stim", line + "\n", NC5)
    assert len(diags) == 1 and diags[0].code == "E601" and diags[0].span.col == col
    assert diags[0].message.endswith(hint), diags[0].message


def test_no_hint_when_nothing_is_near():
    _, diags = parse_stimulus_text("s.stim", "70ms zzz\nqqq 1s\n", NC5)
    assert [d.span.line for d in diags] == [1, 2] and not any("did you mean" in d.message for d in diags)


# lines the set-line fast path (`#250 X0=1`, `100ms X0=1`) reads, and look-alikes it must leave
# to the full parser: bad names, values, times, signals, comments, blanks, extra items
_FAST_LINES = ["#0 X0=1", "#250 M5=0", "  #7\tm5=1  ", "10ms X1=1", "1.5s Y0=0", "100us D0=25",
               "10ms D0=H00FF", "#3 K4M0=H00FF", "#3 X9=1", "#3 M99999=1", "#3 M5=2", "#3 Q5=1",
               "10xs X0=1", "#1 X0=1 # comment", "#1 X0=1 X1=0", "#99999999999 X0=1", "#999999999 X0=1",
               "0.0000001s X0=1", "10ms X0==1", "10ms =1", "10ms XC1.pos=1", "#2 D0:f=1.5",
               "#2 D0=1.5", "+10ms X0=1", "5ms X0=on", "#1 expect=1", "# comment only", "",
               "#1 X0=" + "1" * 30, "10ms M" + "9" * 25 + "=1", "\u00a0#1 X0=1", "#1 X0=1\u00a0",
               "run #1000", "run #0", " run #5", "run\t#7\t", "RUN #5", "run #999999999", "run #1000 # note",
               "run #12 X0=1", "run #", "run 10ms", "run #00012", "run #" + "9" * 30]


def _parsed(text: str, cache=None):
    st, diags = parse_stimulus_text("s.stim", text, NC5, cache)
    events = [(e.scan, e.time_us, e.kind, e.line, e.col, e.text, e.assigns, e.checks) for e in st.events]
    return events + [(st.run_scans, st.run_time_us, st.scan_us)], \
        [(d.code, d.span.line, d.span.col, d.message) for d in diags]


def test_set_line_fast_path_reads_as_the_full_parser(monkeypatch):
    """Every line above, alone and all together in random orders, gives the same events and
    diagnostics with the fast path as without it (a pattern that never matches)."""
    import random
    import re

    from mlctool.sim.stimulus import stimulus

    rnd = random.Random(3)
    texts = list(_FAST_LINES) + ["\n".join(rnd.sample(_FAST_LINES, len(_FAST_LINES))) for _ in range(20)]
    fast = [_parsed(t) for t in texts]
    shared = stimulus.NameCache(NC5)  # the inline path: items read by an earlier file of a batch
    fast_shared = [_parsed(t, shared) for t in texts]
    monkeypatch.setattr(stimulus, "_LINES", re.compile(r"^()()()().*$", re.M))  # no line is a set line
    monkeypatch.setattr(stimulus, "_RUN_SCANS", re.compile(r"(?!)"))  # nor a plain `run #N`
    full = [_parsed(t) for t in texts]
    assert fast == full and fast_shared == full
    assert any(events for events, _ in fast) and any(diags for _, diags in fast)


def test_name_cache_shared_by_files_changes_nothing():
    """A NameCache carried from file to file (a batch) gives each file the events and the
    diagnostics it gets alone; a failed name is not remembered as a success."""
    from mlctool.sim.stimulus.stimulus import NameCache

    texts = ["#1 M5=1\n#2 m5=0\n10ms expect M5=0", "#1 M99999=1\n#2 M5=1", "#1 M99999=1\n#1 X0=1 M5=0",
             "#4 D0=7\n#5 D0=70000"]
    cache = NameCache(NC5)
    assert [_parsed(t, cache) for t in texts] == [_parsed(t) for t in texts]
    assert [_parsed(t, cache) for t in texts] == [_parsed(t) for t in texts]  # now all cached
    assert "M99999" not in cache.views and "M5" in cache.views
