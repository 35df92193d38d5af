"""Vigor VS LINK (6-10 FNC 89, EASY LINK) and CPUL (FNC 87, CPU Link) with peer PLC stations
`model vsplc link=CP1 station=k` whose devices the stimulus sets and checks (`CP1#1.D0`);
tables as `.table Qn LINK|CPUL ...` rows (docs/vs.md "LINK and CPUL")."""

from __future__ import annotations

import pytest

from mlctool.check import check_texts
from mlctool.sim.run.run import Simulation, build_models, plan_scans
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.syntax.source import decode
from vskit import VS, image_of


def run(il: str, stim: str) -> None:
    """vskit.run with the stimulus's device models attached (the peer stations)."""
    image = image_of(il + "\nEND")
    assert image is not None
    st, diags = parse_stimulus_text("t.stim", stim, VS)
    models, mdiags = build_models(st, VS)
    assert not diags and not mdiags, [(d.code, d.message) for d in diags + mdiags]
    r = Simulation(image, VS, st, models, 10_000, [], False).run(plan_scans(st, 10_000, None, None))
    assert r.fault is None, r.fault
    assert not r.failed, [(f.line, f.device, f.expected, f.actual) for f in r.failed]
    assert not r.alarms, [(a.name, a.message) for a in r.alarms]

PEERS = "model vsplc link=CP1 station=1\nmodel vsplc link=CP1 station=2\n"

# the LINK page's table: read D0-D9 of station 1 into D0-D9, write D10-D14 to its D10-D14,
# read D0-D9 of station 2 into D20-D29, write D30-D34 to its D10-D14, write D40-D59 to every
# slave (255); M1 disables rows 1-2, M2 row 3, row 4 has no disable contact
LINK_TABLE = """
.table Q0 LINK K0 K1 D0 D0 K10 M1
.table Q0 LINK K1 K1 D10 D10 K5 M1
.table Q0 LINK K0 K2 D20 D0 K10 M2
.table Q0 LINK K1 K2 D30 D10 K5
.table Q0 LINK K1 K255 D40 D40 K20
"""
LINK_PROGRAM = LINK_TABLE + "LD X20\nLINK Q0 D100 K1\nLD M9104\nINC D200\n"


def test_link_the_pages_table_with_two_slaves():
    # row 1 at 19200: request 11 x 11 bits (6.3 ms), the peer's 10 ms, the answer with 20
    # bytes (17.8 ms): complete at 34.1 ms, taken by the LINK of the scan at 40 ms
    run(LINK_PROGRAM, PEERS + "0ms X20=1 CP1#1.D0=11 CP1#1.D9=19 CP1#2.D0=21 D10=100 D14=104 "
                              "D30=300 D34=304 D40=400 D59=459\n"
                              "30ms expect D0=0 D101=1\n40ms expect D0=11 D9=19 D101=2 D200=0\n"
                              "1s expect D20=21 CP1#1.D10=100 CP1#1.D14=104 CP1#2.D10=300 CP1#2.D14=304 "
                              "CP1#1.D40=400 CP1#2.D59=459 CP1#1.D30=0 D100=0 M9103=0 D200=1..20\n")


def test_link_done_relay_once_per_pass_and_disable_contacts():
    # M1/M2 On: rows 4 and 5 only. Row 4 (write 5 words to station 2): request with 10
    # bytes 12.0 ms, the peer's 10 ms, answer 6.3 ms = 28.3 ms, taken at 30 ms; row 5
    # (broadcast 20 words, no answer): 29.2 ms, taken at 60 ms: the pass is done, M9104 On
    # for that one scan; the next pass ends at 120 ms
    run(LINK_PROGRAM, PEERS + "0ms X20=1 M1=1 M2=1 D30=7 D40=9\n20ms expect M9104=0 D200=0 CP1#2.D10=0\n"
                              "30ms expect M9104=0 CP1#2.D10=7 CP1#1.D40=0 D101=5\n"
                              "60ms expect M9104=1 D200=1 CP1#1.D40=9 CP1#2.D40=9 CP1#1.D10=0\n"
                              "70ms expect M9104=0 D200=1\n110ms expect D200=1\n120ms expect M9104=1 D200=2\n")


def test_link_time_out_without_the_slave_and_the_device_error():
    # no station 3: no answer 500 ms after the 6.3 ms request -> 0AH, station 3 in the high byte
    run(".table Q1 LINK K0 K3 D0 D0 K1\nLD X20\nLINK Q1 D100 K1\n",
        "0ms X20=1\n500ms expect D100=0 M9103=0\n510ms expect D100:h=H030A M9103=1\n")
    # DECISION: a word block paired with a bit block is status 4 (the page's "對象元件錯誤")
    run(".table Q1 LINK K0 K1 D0 M0 K8\nLD X20\nLINK Q1 D100 K1\n",
        PEERS + "0ms X20=1 CP1#1.M0=1\n1s expect D100:h=H0104 M9103=1 D0=0\n")


def test_link_condition_off_stops_and_a_new_start_clears_the_work_area():
    run(LINK_TABLE + "LD X20\nLINK Q0 D100 K1\n",
        "0ms X20=1\n20ms X20=0\n1s expect D100=0 M9103=0\n1s X20=1\n2s expect D100:h=H010A M9103=1\n")


# the 7-3-7 example: 38400 bps, station 0 shares D0-D9, station 1 M0-M7, station 2 D10: rows
# of 8.9, 3.46 and 3.74 ms, a pass of 16.1 ms
CPUL_PROGRAM = """
.table Q2 CPUL K0 D0 K10 M10
.table Q2 CPUL K1 M0 K8 M10
.table Q2 CPUL K2 D10 K1
LD X20
CPUL Q2 D100 K1
"""
CPUL_PORT = ("port CP1 baud=38400 station=0\nmodel vsplc link=CP1 station=1 baud=38400\n"
             "model vsplc link=CP1 station=2 baud=38400\n")


def test_cpul_the_manuals_three_rows_in_real_time():
    run(CPUL_PROGRAM, CPUL_PORT + "0ms X20=1 D0=5 D9=9 CP1#1.M0=1 CP1#1.M7=1 CP1#2.D10=77\n"
                                  "10ms expect CP1#1.D0=5 CP1#2.D9=9 M0=0 D10=0\n"
                                  "20ms D0=6\n"
                                  "20ms expect M0=1 M7=1 CP1#2.M0=1 CP1#2.M7=1 D10=77 CP1#1.D10=77 "
                                  "CP1#1.D0=5 D100=0\n"
                                  "30ms expect CP1#1.D0=6 CP1#2.D0=6\n")


def test_cpul_missing_station_times_out_and_disable_contact():
    # station 2 absent: 0AH with station 2 after its row time and the 500 ms time-out; M10
    # disables rows 1-2, so D0 is no longer shared
    run(CPUL_PROGRAM, "port CP1 baud=38400\nmodel vsplc link=CP1 station=1 baud=38400\n"
                      "0ms X20=1 M10=1 D0=5\n500ms expect D100=0\n510ms expect D100:h=H020A\n"
                      "1s expect CP1#1.D0=0\n")


def _codes(il: str) -> list[str]:
    src, _ = decode("t.il", il.encode())
    return [d.code for d in check_texts([src], VS).diagnostics if d.severity == "error"]


@pytest.mark.parametrize("row, code", [
    (".table Q0 LINK K0 K255 D0 D0 K1", "E206"),  # station 255 writes only
    (".table Q0 LINK K2 K1 D0 D0 K1", "E206"),    # command K0 read / K1 write
    (".table Q0 LINK K0 K1 D9505 D0 K10", "E206"),  # the block passes the device range
    (".table Q0 CPUL K255 D0 K1", "E206"),        # stations 0-254
    (".table Q0 CPUL K1 X0 K8", "E204"),          # X is not shared (7-3-7)
])
def test_table_rows_are_checked(row, code):
    assert code in _codes(f"{row}\nLD X0\nEND\n")


@pytest.mark.parametrize("line, message", [
    ("0ms CP9#1.D0=1", "ports are"),
    ("0ms CP1#300.D0=1", "0-254"),
    ("0ms CP1#1.T0=1", "peer stations show"),
    ("0ms CP1#1.M0:h=1", "no view"),
    ("0ms CP1#1.Y8=1", "octal"),
])
def test_bad_peer_names_are_e602(line, message):
    _, diags = parse_stimulus_text("t.stim", line + "\n", VS)
    assert [(d.code, d.span.line) for d in diags] == [("E602", 1)] and message in diags[0].message
