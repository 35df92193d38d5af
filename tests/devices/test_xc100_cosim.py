"""Modbus-master co-simulation (issue 10): a Vigor VS program's MBUS (manual 003 6-13 FNC 149)
talking to the XC100 model (manual 004 ch. 8) over the simulator's serial link on virtual
time. The frames on the line are the manual's; a wrong station times out; exception answers
set the error relay and status; `.table` rows are checked."""

from __future__ import annotations

import os
import subprocess
import tempfile
from pathlib import Path

from conftest import MLC_COMMAND
from mlctool.asm import program_from_paths
from mlctool.check import check_texts
from mlctool.devices.xc100.registers import read_words
from mlctool.sim.hardware import seriallink
from mlctool.sim.run.run import Simulation, build_models, plan_scans
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.syntax.source import decode
from mlctool.targetapi import load_target

ROOT = Path(__file__).resolve().parents[2]
VS = load_target("vs")

# The manual's frames (004 8.4 RTU, 8.5 ASCII): read ActionStatus, write 201EH = 3 (homing),
# write 2000H-2001H = 100 (INCamount, high word first).
TABLE = """
.table Q0 MBUS H03 K1 D0  H1000 K1
.table Q0 MBUS H06 K1 D10 H201E K1
.table Q0 MBUS H10 K1 D20 H2000 K2
LD   M9000
MOV  K3 D10
MOV  K100 D21
LD   X20
MBUS Q0 D100 K1
"""
RTU_FRAMES = ["01 03 10 00 00 01 80 CA", "01 06 20 1E 00 03 A2 0D",
              "01 10 20 00 00 02 04 00 00 00 64 6B 85"]
ASCII_FRAMES = [":010310000001EB\r\n", ":0106201E0003B8\r\n", ":011020000002040000006465\r\n"]


def simulate(il: str, stim: str, model: str = "VS3"):
    target = load_target("vs", model)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "t.il")
        Path(path).write_text(il.strip() + "\nEND\n", encoding="utf-8")
        image, diags, _ = program_from_paths([path], target)
    assert image is not None, [(d.code, d.message) for d in diags]
    st, sd = parse_stimulus_text("t.stim", stim, target)
    assert not sd, [(d.code, d.message) for d in sd]
    models, md = build_models(st, target)
    assert not md, [(d.code, d.message) for d in md]
    sim = Simulation(image, target, st, models, 10_000, [], False)
    result = sim.run(plan_scans(st, 10_000, None, None))
    assert result.fault is None, result.fault
    return sim, result, models


def test_frames_on_the_line_are_the_manuals_rtu():
    sim, r, (xc,) = simulate(TABLE, "model xc100 link=CP1 station=1 protocol=rtu\n0ms X20=1\nrun 100ms\n")
    line = seriallink.port(sim.m, "CP1")
    sent = [ex.request.hex(" ").upper() for ex in line.exchanges[:3]]
    assert sent == RTU_FRAMES
    replies = [ex.reply.hex(" ").upper() for ex in line.exchanges[:3]]
    assert replies[1] == RTU_FRAMES[1]  # 8.4: the write is echoed
    assert replies[2] == "01 10 20 00 00 02 4A 08"  # echo of address and count (8.4), pymodbus CRC
    assert r.devices["D100"] == 0
    assert read_words(xc.dev, 0x2000, 2) == [0, 100]  # INCamount written whole
    assert xc.dev.motion is not None and xc.dev.motion.kind == "home"  # 201EH = 3 started homing


def test_ascii_frames_timing_and_done_relay():
    sim, r, _ = simulate(TABLE + "LD M9104\nOUT M0\nLD M9104\nINC D50\n",
                         "model xc100 link=CP1 station=1 baud=9600\n0ms X20=1\n"
                         "300ms expect D0=0..1 D100=0 D50=2..30\nrun 310ms\n")
    line = seriallink.port(sim.m, "CP1")
    assert [ex.request.decode() for ex in line.exchanges[:3]] == ASCII_FRAMES
    # 8.5 read: 17 characters of 10 bits at 9600 baud = 17.71 ms on the line
    first = line.exchanges[0]
    assert first.arrive_us - first.sent_us == 17_709
    # the answer ":01030200 01 F9"-style frame comes 2 ms (reply delay) plus its own time later
    assert first.reply_us == first.arrive_us + 2_000 + line.settings.char_us(len(first.reply))
    # D0: ActionStatus read; D50 counts the scans M9104 was On, one per table pass
    assert not r.failed, [(f.device, f.expected, f.actual) for f in r.failed]
    # a new pass starts (row 1 sent again) in the scan the previous one completed: one
    # scan of M9104 per completed pass
    passes = sum(1 for ex in line.exchanges if ex.request[3:5] == b"03") - 1
    assert passes >= 2 and sim.m.words["D"][50] == passes


def test_wrong_station_times_out():
    sim, r, _ = simulate(TABLE.replace("K1 D0", "K2 D0"),
                         "model xc100 link=CP1 station=1 protocol=rtu timeout=100ms\n"
                         "0ms X20=1\n90ms expect M9103=0\n130ms expect M9103=1 D100=H020A\nrun 150ms\n")
    first = seriallink.port(sim.m, "CP1").exchanges[0]
    assert first.reply is None
    assert not r.failed, [(f.device, f.expected, f.actual) for f in r.failed]


def test_exception_answers_set_the_error_relay_and_status():
    il = """
.table Q1 MBUS H06 K1 D10 H2014 K1
.table Q2 MBUS H03 K1 D0 H1002 K1
.table Q3 MBUS H06 K1 D10 H1000 K1
LD M9000
MOV K101 D10
LD X0
MBUS Q1 D100 K1
LD X1
MBUS Q2 D110 K2
LD X2
MBUS Q3 D120 K3
"""
    stim = ("model xc100 link=CP1 station=1 protocol=rtu\n"
            "model xc100 link=CP2 station=1 protocol=rtu\n"
            "model xc100 link=CP3 station=1 protocol=rtu\n"
            "0ms X0=1 X1=1 X2=1\n100ms expect M9103=1 M9113=1 M9123=1\n"
            "100ms expect D100=H0102 D110=H0104 D120=H0104\nrun 110ms\n")
    sim, r, _ = simulate(il, stim)
    assert not r.failed, [(f.device, f.expected, f.actual) for f in r.failed]
    # speed 101 % is exception 03 (status 2), a gap in the status map 02 (status 4)
    assert seriallink.port(sim.m, "CP1").exchanges[0].reply.hex(" ").upper().startswith("01 86 03")
    assert seriallink.port(sim.m, "CP2").exchanges[0].reply.hex(" ").upper().startswith("01 83 02")


def test_stopping_and_disable_contact():
    il = TABLE.replace("H10 K1 D20 H2000 K2", "H10 K1 D20 H2000 K2 M5")
    sim, r, _ = simulate(il, "model xc100 link=CP1 protocol=rtu\n0ms force M5=1\n0ms X20=1\n"
                            "200ms X20=0\n400ms expect M9104=0 D101=2\nrun 410ms\n")
    line = seriallink.port(sim.m, "CP1")
    assert all(ex.request[1] != 0x10 for ex in line.exchanges)  # row 3 disabled
    assert line.master is None and max(ex.sent_us for ex in line.exchanges) < 200_000
    assert not r.failed, [(f.device, f.expected, f.actual) for f in r.failed]


def test_table_rows_are_checked():
    def errs(il):
        src, _ = decode("t.il", il.encode())
        return [d.code for d in check_texts([src], VS).diagnostics if d.severity == "error"]
    assert errs(".define XC Q3\n.table XC MBUS H03 K1 D0 H1000 K10 M1\nLD X0\nMBUS XC D100 K1\nEND\n") == []
    assert errs(".table Q0 MBUS H03 K0 D0 K0 K1\nEND\n") == ["E206"]  # a broadcast read
    assert errs(".table Q0 MBUS H06 K1 D0 K0 K2\nEND\n") == ["E206"]  # FC06 writes one word
    assert errs(".table Q0 MBUS H05 K1 D0 K0 K1\nEND\n") == ["E206"]
    assert errs(".table Q32 MBUS H03 K1 D0 K0 K1\nEND\n") == ["E105"]
    assert errs(".table Q0 MBUS H03 K1 X0 K0 K1\nEND\n") == ["E204"]
    assert errs(".table Q0 MBUS H03 K1\nEND\n") == ["E105"]
    nc5 = load_target("nc5")
    src, _ = decode("t.il", b".table Q0 MBUS H03 K1 D0 K0 K1\nEND\n")
    assert [d.code for d in check_texts([src], nc5).diagnostics] == ["E105"]


def test_bad_link_keys_are_diagnostics():
    for line, word in [("model xc100 link=CP9", "CP1"), ("model xc100 link=CP1 station=17", "1-16"),
                       ("model xc100 station=2 out1=X0", "link=CPn"), ("model xc100 link=CP1 baud=1200", "0A00H")]:
        st, _ = parse_stimulus_text("t.stim", line + "\n", VS)
        models, diags = build_models(st, VS)
        assert [d.code for d in diags] == ["E601"] and word in diags[0].message


def test_port_beyond_the_model_is_a_fault():
    # the checker refuses CP3 on VS1 (E206, 6-13 MBUS n per model); an image linked for VS3
    # and run as VS1 meets the simulator's own guard
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "t.il")
        Path(path).write_text(".table Q0 MBUS H03 K1 D0 K0 K1\nLD X0\nMBUS Q0 D100 K3\nEND\n")
        refused, diags, _ = program_from_paths([path], load_target("vs", "VS1"))
        assert refused is None and "E206" in [d.code for d in diags]
        image, _, _ = program_from_paths([path], load_target("vs", "VS3"))
    st, _ = parse_stimulus_text("t.stim", "0ms X0=1\nrun 20ms\n", VS)
    r = Simulation(image, load_target("vs", "VS1"), st, [], 10_000, [], False).run(2)
    assert r.fault is not None and "CP3" in r.fault.message


def test_sample_passes_mlc_sim():
    with tempfile.TemporaryDirectory() as tmp:
        vcd = os.path.join(tmp, "out.vcd")
        cmd = MLC_COMMAND
        p = subprocess.run([*cmd, "sim", "--target", "vs",
                            str(ROOT / "samples/vs/xc100_modbus.il"), "--stimulus",
                            str(ROOT / "samples/vs/xc100_modbus.stim"), "--vcd", vcd],
                           capture_output=True, text=True, timeout=60)
        assert p.returncode == 0, p.stdout + p.stderr
        text = Path(vcd).read_text()
        assert "XC1.pos" in text and "XC1.torque" in text  # the model's own signals (name=XC1)
