"""Vigor VS special relays a program writes (2-14-1, 2-14-2): M9034 all outputs off, and the
warning W608 for the ones whose function the simulator does not model
(targets/vs/unmodelled_specials.toml)."""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

import pytest

from mlctool.sim.run.run import Simulation
from mlctool.sim.run.unmodelled import unmodelled_writes
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targetapi.specials import unmodelled_specials
from vskit import VS, check_codes, image_of, run

ROOT = Path(__file__).resolve().parents[3]
TABLE = ROOT / "mlctool" / "targets" / "vs" / "unmodelled_specials.toml"
MANUAL = ROOT.parent / "shared" / "manuals" / "003_889c1621f09502b2.txt"
READING = ROOT.parent / "shared" / "notes" / "vs_reading.md"
OUTPUTS_OFF = "LD X0\nSET M9034\nLD X2\nRST M9034\nLD X1\nOUT Y0\nLD Y0\nOUT M0\n"


# ------------------------------------------------------------------ M9034 all outputs off

def test_m9034_turns_the_terminals_off_and_the_program_keeps_its_image():
    # 2-14-1 M9034 "PLC外部輸出全部OFF": Y0 reads Off from outside while M9034 is On; the
    # program's LD Y0 still sees its image (M0 follows it); M9034 Off: Y0 is back
    run(OUTPUTS_OFF,
        "0ms X1=1\n0ms expect Y0=1 M0=1\n"
        "10ms X0=1\n10ms expect Y0=0 M0=1 M9034=1 K4Y0=0\n"
        "20ms X0=0 X2=1\n20ms expect Y0=1 M0=1 M9034=0 K4Y0=1\n")


def test_m9034_in_the_trace_and_the_final_values():
    image = image_of(OUTPUTS_OFF + "END")
    st, sd = parse_stimulus_text("t.stim", "0ms X1=1\n20ms X0=1\n", VS)
    assert not sd
    r = Simulation(image, VS, st, [], 10_000, [], True).run(4)
    names = [v.name for v in r.views]
    y0, m0 = names.index("Y0"), names.index("M0")
    seen = [(t, names[i], v) for t, changes in r.trace for i, v in changes if i in (y0, m0)]
    assert seen == [(0, "Y0", 1), (0, "M0", 1), (20_000, "Y0", 0)]
    assert r.devices["Y0"] == 0 and r.devices["M0"] == 1 and r.devices["M9034"] == 1


def test_m9034_failed_expectation_says_why(mlc, tmp_path):
    # the program: M9034 set, Y0 driven; expecting Y0 On fails and names M9034
    (tmp_path / "sp.il").write_text("LD X0\nSET M9034\nLD X1\nOUT Y0\nEND\n", encoding="utf-8")
    (tmp_path / "sp.stim").write_text("0ms X1=1 X0=1\n20ms expect Y0=1\n", encoding="utf-8")
    r = mlc("sim", "--target", "vs", str(tmp_path / "sp.il"), "--stimulus", str(tmp_path / "sp.stim"),
            "--until", "30ms", "--json")
    assert r.code == 1, r.err
    [failure] = json.loads(r.out)["expectations"]["failures"]
    assert failure["actual"] == 0 and "M9034 is On" in failure["note"] and "2-14-1" in failure["note"]
    assert "E603" in r.err and "M9034 is On" in r.err
    assert "W608" not in r.err  # M9034 is modelled


def test_m9034_ref_y_in_an_interrupt_routine_puts_out_off():
    # REF Y0 K8 in a routine at 15 ms puts Y0 out at once (test_vs_sim_interrupts.py); with
    # M9034 On what goes out is Off
    image = image_of("LD M9000\nSET M9034\nRST Y0\nFEND\nIX0P:\nLD M9000\nSET Y0\nREF Y0 K8\n"
                     "IRET\nEND\n")
    st, sd = parse_stimulus_text("t.stim", "15ms X0=1\n", VS)
    assert not sd
    r = Simulation(image, VS, st, [], 10_000, [], True).run(4)
    y0 = [v.name for v in r.views].index("Y0")
    assert not [(t, v) for t, changes in r.trace for i, v in changes if i == y0 and v]


def test_m9034_is_cleared_by_a_power_cycle():
    run(OUTPUTS_OFF, "0ms X0=1 X1=1\n0ms expect Y0=0\n10ms X0=0\n20ms power-cycle\n"
                     "20ms expect M9034=0 Y0=1\n")


# ------------------------------------------------------------------ W608

def _warned(il: str) -> list[tuple[str, int]]:
    """(first word of the message, line) of each W608 the program gets."""
    image = image_of(il + "\nEND")
    assert image is not None
    return [(d.message.split()[0], d.span.line) for d in unmodelled_writes(image, VS)]


def test_unmodelled_writes_once_per_device_at_the_first_write():
    got = _warned("LD X0\nSET M9033\nOUT M9039\nMOV K50 D9039\nRST M9033\nDMOV K0 D9072\n"
                  "ZRST M9170 M9171\nMOV K3 K1M9076\nOUT D9000.3\nMOV K1 D9000")
    assert got == [("M9033", 2), ("M9039", 3), ("D9039", 4), ("D9072", 6), ("D9073", 6),
                   ("M9170", 7), ("M9171", 7), ("M9076", 8), ("M9077", 8), ("M9078", 8),
                   ("M9079", 8), ("D9000", 9)]


def test_no_warning_for_modelled_specials_or_reads():
    # M9024 BMOV direction, M9031/M9032 clear, M9040 transfer inhibit, D9013 clock: modelled;
    # reading an unmodelled one (LD M9170) is no write; an index register hides the device
    assert _warned("LD X0\nSET M9024\nOUT M9031\nRST M9032\nOUT M9040\nMOV K5 D9013\n"
                   "LD M9170\nOUT Y0\nMOV K1 D8990Z0") == []


def test_check_does_not_warn():
    # the program is not wrong (the simulator is limited): mlc check says nothing
    assert check_codes("LD X0\nSET M9033\nLD X1\nRST M9033\nMOV K50 D9039\nEND") == []


def test_w608_text_and_json_and_the_exit_code(mlc, tmp_path):
    il = tmp_path / "t.il"
    il.write_text("LD X0\nOUT M9039\nMOV K50 D9039\nLD M9000\nRST M9170\nOUT Y0\nEND\n", encoding="utf-8")
    stim = tmp_path / "t.stim"
    stim.write_text("0ms X0=1\n10ms expect Y0=1 M9039=1\n", encoding="utf-8")
    r = mlc("sim", "--target", "vs", str(il), "--stimulus", str(stim))
    assert r.code == 0, r.err  # a warning: the expectations decide
    lines = [x for x in r.err.splitlines() if "W608" in x]
    assert len(lines) == 3, r.err
    assert "M9039 (constant scan" in lines[0] and "2-14-1 M9039" in lines[0] and "does not model" in lines[0]
    assert "t.il:2:" in lines[0] and "t.il:3:" in lines[1] and "M9170" in lines[2]
    r = mlc("sim", "--target", "vs", str(il), "--stimulus", str(stim), "--json")
    assert r.code == 0, r.err
    warnings = json.loads(r.out)["warnings"]
    assert [(w["code"], w["line"], w["message"].split()[0]) for w in warnings] == \
        [("W608", 2, "M9039"), ("W608", 3, "D9039"), ("W608", 5, "M9170")]
    assert "2-14-2 D9039" in warnings[1]["message"] and warnings[1]["notes"][0].startswith("why:")


def test_no_w608_in_json_for_a_program_writing_modelled_specials_only(mlc, tmp_path):
    il = tmp_path / "t.il"
    il.write_text("LD X0\nOUT M9024\nLD X1\nOUT M9031\nEND\n", encoding="utf-8")
    r = mlc("sim", "--target", "vs", str(il), "--scans", "2", "--json")
    assert r.code == 0 and "W608" not in r.err and json.loads(r.out)["warnings"] == []


def test_mlc_test_warns_once_for_the_suite(mlc, tmp_path):
    (tmp_path / "mlc.toml").write_text('target = "vs"\nsources = ["main.il"]\ntests = ["tests/*.stim"]\n',
                                       encoding="utf-8")
    (tmp_path / "main.il").write_text("LD X0\nOUT M9033\nOUT Y0\nEND\n", encoding="utf-8")
    (tmp_path / "tests").mkdir()
    for name in ("a", "b"):
        (tmp_path / "tests" / f"{name}.stim").write_text("0ms X0=1\n10ms expect Y0=1\n", encoding="utf-8")
    r = mlc("test", str(tmp_path))
    assert r.code == 0, r.out + r.err
    assert r.err.count("W608") == 1 and "M9033" in r.err
    r = mlc("test", str(tmp_path), "--json")
    docs = json.loads(r.out)["scenarios"]
    assert [len(d["warnings"]) for d in docs.values()] == [1, 1]


# ------------------------------------------------------------------ the table

def _rows():
    return tomllib.loads(TABLE.read_text("utf-8"))["device"]


def _manual_section(lines: list[str], number: str) -> str:
    """The manual's text of section `number` (2-14-1 ...): from its heading to the next one."""
    heading = re.compile(r"^(?:<\|[^|]*\|>)?(\d+-\d+(?:-\d+)?)\s\s")
    starts = [(k, m[1]) for k, x in enumerate(lines) if (m := heading.match(x))]
    hits = [i for i, (_, n) in enumerate(starts) if n == number]
    assert hits, f"no heading {number} in the manual"
    i = hits[-1]  # the body, not the table of contents
    end = starts[i + 1][0] if i + 1 < len(starts) else len(lines)
    return "\n".join(lines[starts[i][0]:end])


def _devices(spec: str) -> list[str]:
    first, _, last = spec.partition("-")
    kind, lo, hi = first[0], int(first[1:]), int((last or first)[1:])
    return [f"{kind}{n}" for n in range(lo, hi + 1)]


@pytest.mark.skipif(not MANUAL.is_file(), reason=f"manual text not found at {MANUAL}")
def test_every_row_cites_a_section_of_the_manual_that_lists_its_devices():
    lines = MANUAL.read_text("utf-8").split("\n")
    reading = READING.read_text("utf-8") if READING.is_file() else ""
    for row in _rows():
        number = row["section"].split()[0]
        assert f"§{number.rsplit('-', 1)[0]}" in reading or not reading, row["section"]
        text = _manual_section(lines, number)
        for spec in row["devices"]:
            for device in _devices(spec):
                assert device in text, f"{device} is not in the manual's {number}"


def test_every_row_is_a_device_the_program_may_write():
    # not the read-only ■ ones (devices.toml `write = "system"`: W212), and a known section
    for row in _rows():
        assert row["section"].split()[0] in ("2-14-1", "2-14-2") and row["function"] and row["why"]
        for spec in row["devices"]:
            for device in _devices(spec):
                area = VS.devices[device[0]].area(int(device[1:]))
                assert area is not None and area.write == "ok", (device, area)
    # the loader reads every row, one entry per device or range
    assert len(unmodelled_specials("vs")) == sum(len(r["devices"]) for r in _rows())
    assert unmodelled_specials("nc5") == ()



def test_a_batch_warns_once_and_every_document_has_the_warnings(mlc, tmp_path):
    il = tmp_path / "t.il"
    il.write_text("LD X0\nOUT M9039\nOUT Y0\nEND\n", encoding="utf-8")
    for name in ("a", "b"):
        (tmp_path / f"{name}.stim").write_text("0ms X0=1\n10ms expect Y0=1\n", encoding="utf-8")
    pattern = str(tmp_path / "*.stim")
    r = mlc("sim", "--target", "vs", str(il), "--stimulus", pattern)
    assert r.code == 0 and r.err.count("W608") == 1, r.err
    r = mlc("sim", "--target", "vs", str(il), "--stimulus", pattern, "--json")
    docs = json.loads(r.out)["scenarios"]
    assert [[w["code"] for w in d["warnings"]] for d in docs.values()] == [["W608"], ["W608"]]
