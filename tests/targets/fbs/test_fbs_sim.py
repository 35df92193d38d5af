"""`mlc sim --target fbs`: FUN140-143 on the simulator's clock, axis registers in PLC memory."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

from test_fbs_cli import mlc

from mlctool.asm import program_from_paths
from mlctool.sim.run.run import Simulation, plan_scans
from mlctool.sim.state import parse_device_name
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targetapi import load_target
from mlctool.targets.fbs.files import table_preload

FBS = load_target("fbs")
SAMPLES = Path(__file__).resolve().parents[3] / "samples" / "fbs"

from fbskit import AXIS, PARAMS  # noqa: E402


def run(il: str, stim: str, tables: dict[str, str], trace: bool = False):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "t.il")
        Path(path).write_text(il.strip() + "\n", "utf-8")
        image, diags, _ = program_from_paths([path], FBS)
        assert image is not None, [d.message for d in diags]
        preload = []
        for sr, text in tables.items():
            pos = os.path.join(tmp, f"{sr}.{'mpos' if ' LIN' in text else 'pos'}")
            Path(pos).write_text(text, "utf-8")
            table, problems = table_preload(f"{sr}={pos}")
            assert table is not None, [d.message for d in problems]
            preload.append(table)
    st, sdiags = parse_stimulus_text("t.stim", stim, FBS)
    assert not sdiags, [d.message for d in sdiags]
    n = plan_scans(st, st.scan_us or 10_000, None, None)
    return Simulation(image, FBS, st, [], st.scan_us or 10_000, [], trace, preload=preload).run(n)


def ok(r) -> bool:
    assert r.fault is None, r.fault
    assert not r.failed, [(f.line, f.device, f.expected, f.actual) for f in r.failed]
    assert not r.alarms
    return True


def test_exact_pulse_count_flags_and_registers():
    table = "001 SPD 10000\n DRV ADR,+,12345,Ps\n MEND\n"
    stim = """scan 10ms
    0ms M0=1
    50ms expect M1992=0 R2100=1 R2101:h=H1001 Y0=1 Y1=0 M20=1 R4080:d=10000
    2s expect R4088:d=12345 R4072:d=0 M1992=1 M1996=1 R4064=1 R2101:h=H4001 R4060=0 M20=0"""
    assert ok(run(AXIS, stim, {"R5000": table}))


def test_pause_resumes_the_unfinished_pulses_and_abort_restarts_at_step_1():
    table = "001 SPD 1000\n DRV ADR,+,3000,Ps\n GOTO NEXT\n002 SPD 1000\n DRV ADR,+,500,Ps\n MEND\n"
    stim = """scan 10ms
    0ms M0=1
    1s M10=1
    1.5s expect R4080:d=0 R4088:d=500..1000 R2101:h=H1102
    2s M10=0
    6s expect R4088:d=3500 M1996=1
    6.5s M11=1
    6.6s expect M1992=1 R2100=0"""
    assert ok(run(AXIS, stim, {"R5000": table}))


def test_en_off_stops_at_once_and_m1991_decelerates():
    table = "001 SPD 50000\n DRV ADR,+,0,Ps\n MEND\n"  # ADR 0: continuous (WR+1 b10)
    stim = """scan 10ms
    0ms M0=1
    490ms expect R2101:h=H1401
    500ms M0=0
    510ms expect R4080:d=0 M1992=1"""
    assert ok(run(AXIS, stim, {"R5000": table}))
    stim = """scan 10ms
    0ms M0=1 M1991=1
    500ms M0=0
    510ms expect R4080:d=40000..49999 M1992=0
    700ms expect R4080:d=0 M1992=1"""
    assert ok(run(AXIS, stim, {"R5000": table}))  # P8 100 ms to 100 kHz: 50 kHz in 50 ms


def test_r4056_makes_spd_changes_take_effect_at_once():
    table = "001 SPD R100\n DRV ADR,+,0,Ps\n MEND\n"
    base = """scan 10ms
    0ms R100:d=2000 M0=1
    300ms R100:d=4000
    600ms expect R4080:d={}"""
    assert ok(run(AXIS, base.format(2000), {"R5000": table}))
    assert ok(run(AXIS, "0ms R4056=H5A\n" + base.format(4000), {"R5000": table}))


def test_homing_md0_then_table_on_shared_axis_and_pscnv():
    il = PARAMS + """
LD M0
LD M10
LD M11
HSPSO K0 R5000 R2100
LD M1996
AND M0
RST M0
SET M2
LD M2
LD M10
LD M11
HSPSO K0 R5100 R2110
LD M2
PSCNV K0 D10
END
"""
    home = "001 SPD 5000\n DRVZ MD0\n MEND\n"
    move = "001 SPD 5000\n DRV ABS, ,2500,Ut\n MEND\n"
    stim = """scan 10ms
    0ms M0=1
    100ms expect Y1=1 Y0=0
    300ms X4=1
    400ms X4=0
    500ms expect M2=1 R2110=1
    2s expect R4088:d=2500 D10:d=2500 M1996=1 R2100=1 R2110=1"""
    assert ok(run(il, stim, {"R5000": home, "R5100": move}))


def test_errors_go_to_r4060_and_the_err_flag():
    bad_speed = "001 SPD 200000\n DRV ADR,+,100,Ps\n MEND\n"  # above P4: error 37
    stim = "scan 10ms\n0ms M0=1\n50ms expect R4060=37 R2101:h=H2001 M1992=1"
    assert ok(run(AXIS, stim, {"R5000": bad_speed}))
    stim = "scan 10ms\n0ms M0=1\n50ms expect R4060=34"  # no table at R5000
    assert ok(run(AXIS, stim, {}))
    stim = "scan 10ms\n0ms M0=1\n50ms expect R4060=2"  # P1 = 0
    assert ok(run(AXIS.replace("MOV K2000 R2001", "MOV K0 R2001"), stim,
                  {"R5000": "001 SPD 1000\n DRV ADR,+,1,Ps\n MEND\n"}))


def test_mpara_result_is_its_err_output():
    """11.6 FUN141 note 4: "當參數值有錯誤時，輸出指示〝ERR〞ON，且錯誤代碼會出現在錯誤碼暫存器"
    (a wrong parameter value turns the ERR output On); note 3: it runs whatever EN is."""
    il = PARAMS.replace("MPARA K0 R2000", "MPARA K0 R2000\nOUT M30") + """
LD M1
MOV K0 R2001
END
"""
    # the table is fine: ERR Off although EN (M1924) is On only in the first scan
    stim = "scan 10ms\n0ms expect M30=0\n50ms expect M30=0 R4060=0\n60ms M1=1\n100ms expect M30=1 R4060=2"
    assert ok(run(il, stim, {}))
    # EN Off for good: still executed, ERR On for P1 = 0
    bad = il.replace("LD M1924\nMPARA", "LD M2\nMPARA").replace("LD M1\n", "LD M1924\n")
    assert ok(run(bad, "scan 10ms\n50ms expect M30=1 R4060=2", {}))


def test_cli_sample_with_vcd_of_the_axis(tmp_path):
    vcd = tmp_path / "axis.vcd"
    r = mlc("sim", "--target", "fbs", str(SAMPLES / "home_and_run.il"),
            "--table", f"R5000={SAMPLES / 'home.pos'}", "--table", f"R5100={SAMPLES / 'run.pos'}",
            "--stimulus", str(SAMPLES / "home_and_run.stim"), "--vcd", str(vcd))
    assert r.returncode == 0, r.stdout + r.stderr
    text = vcd.read_text()
    for name in ("R4088_d", "R4080_d", "R4072_d", "R4064", "R2110", "Y0", "Y1"):
        assert f" {name} $end" in text
    # position as a 32-bit vector: the homing run went negative before the zero point
    assert "b11111111" in text


def test_cli_table_usage_errors_without_traceback(tmp_path):
    il = str(SAMPLES / "home_and_run.il")
    for spec in (str(SAMPLES / "home.pos"), f"R4000={SAMPLES / 'home.pos'}", "R5000=x.txt"):
        r = mlc("sim", "--target", "fbs", il, "--table", spec, "--scans", "1")
        assert r.returncode == 2 and "Traceback" not in r.stderr and "--table" in r.stderr, r.stderr
    bad = tmp_path / "bad.pos"
    bad.write_text("001 SPD 0\n DRV ADR,+,1,Ps\n MEND\n", "utf-8")
    r = mlc("sim", "--target", "fbs", il, "--table", f"R5000={bad}", "--scans", "1")
    assert r.returncode == 2 and "F031" in r.stderr and "Traceback" not in r.stderr
    r = mlc("sim", il, "--table", f"R5000={bad}", "--scans", "1")  # nc5: no tables
    assert r.returncode == 2 and "Traceback" not in r.stderr


def test_image_tables_load_at_their_sr(tmp_path):
    img = tmp_path / "run.json"
    r = mlc("build", str(SAMPLES / "run.pos"), "-o", str(img), "--sr", "R5100")
    assert r.returncode == 0, r.stderr
    table, problems = table_preload(str(img))
    assert not problems and table[:2] == ("R", 5100) and table[2][0] == 0xA55A
    assert parse_device_name("R4088:d", FBS).width == 32


def test_mhspo_manual_example_linear_interpolation():
    """FUN147 format example: 4 axes 500/400/300/200 Ut (P3 = 3: 1 Ut = 1 Ps) at 5 kHz line
    speed, then Ps0/Ps1 from DD100/DD200, then Ps2/Ps3 from DR300/DR400 in Ps, WAIT X0.
    The group holds its axes (M1992-M1995 Off) until its run ends, waits included."""
    il = PARAMS.replace("MPARA K0 R2000", "MPARA K0 R2000\nMPARA K1 R2000\nMPARA K2 R2000\n"
                        "MPARA K3 R2000") + """
LD M0
LD M10
LD M11
MHSPO K0 R5000 R2200
OUT M20
END
"""
    text = (SAMPLES / "man_interpolation.mpos").read_text("utf-8")
    stim = """scan 10ms
    0ms R1000:d=5000 D100:d=100 D200:d=-300 R500=10 R1002:d=1000 R300:d=50 R400:d=-50 M0=1
    50ms expect M1992=0 M1993=0 M1994=0 M1995=0 M20=1 R2200=1 R4068:d=4000..5000
    1s expect R4088:d=500 R4090:d=400 R4092:d=300 R4094:d=200 M1992=0 R2201:h=H4203 D4062=1
    1.25s expect R4088:d=600 R4090:d=100 R4092:d=300 R2200=2 D4062=2
    2.6s expect R4088:d=600 R4090:d=100 R4092:d=350 R4094:d=150 R2200=3 M20=0
    3s X0=1
    3.1s expect R2200=1 M20=1
    """
    assert ok(run(il, stim, {"R5000": text}))


def test_mhspo_waits_for_an_axis_fun140_holds():
    il = AXIS.replace("END", "LD M1\nLD M12\nLD M13\nMHSPO K0 R5100 R2200\nEND")
    stim = """scan 10ms
    0ms M0=1
    100ms M1=1
    200ms expect R4088:d=100..1000 R4090:d=0 R2200=0
    2.5s expect R4088:d=2000 R4090:d=1000
    """
    tables = {"R5000": "001 SPD 1000\n DRV ADR,+,1000,Ps\n MEND\n",
              "R5100": "001 SPD 1000\n LIN ADR,1000,1000, , ,Ps\n MEND\n"}
    assert ok(run(il, stim, tables))


def test_cli_tables_with_a_batch_of_scenarios_match_single_runs(tmp_path):
    """--table with a stimulus pattern: every scenario starts with the tables loaded, and its
    JSON document is the one a single run gives (the second scenario ends after step 1)."""
    stim = (SAMPLES / "home_and_run.stim").read_text()
    (tmp_path / "a.stim").write_text(stim)
    (tmp_path / "b.stim").write_text(stim.split("5.6s")[0] + "run 3.4s\n")  # step 1 only
    args = ["sim", "--target", "fbs", str(SAMPLES / "home_and_run.il"),
            "--table", f"R5000={SAMPLES / 'home.pos'}", "--table", f"R5100={SAMPLES / 'run.pos'}"]
    batch = mlc(*args, "--stimulus", str(tmp_path / "*.stim"), "--json")
    assert batch.returncode == 0, batch.stdout + batch.stderr
    docs = json.loads(batch.stdout)["scenarios"]
    for name in ("a.stim", "b.stim"):
        one = mlc(*args, "--stimulus", str(tmp_path / name), "--json")
        assert one.returncode == 0, one.stdout + one.stderr
        assert docs[str(tmp_path / name)] == json.loads(one.stdout)
    without = mlc("sim", "--target", "fbs", str(SAMPLES / "home_and_run.il"),
                  "--stimulus", str(tmp_path / "*.stim"))
    assert without.returncode == 1  # no tables: the axis never moves, the expectations fail


def test_a_table_written_at_run_time_is_checked_when_fun140_executes():
    """11.6 error list, "執行 FUN140 與 執行 FUN147 時 可能之錯誤碼": 41 "DRVC 內不允許 ABS 定址",
    42 "DRVC 不可銜接 DRVZ 命令"; a table the program MOVs into place gets the build's codes."""
    from dataclasses import replace

    from mlctool.targets.fbs.lang import parse_program
    from mlctool.targets.fbs.model import Motion, Val, tables
    from mlctool.targets.fbs.table import encode

    text = "001 SPD 1000\n DRVC ADR,+,100,Ps\n GOTO NEXT\n002 SPD 1000\n DRV ADR,+,50,Ps\n MEND\n"
    good, diags = parse_program("t.pos", text, tables().dialects["hspso"])
    assert not diags
    for follow, code in ((Motion("DRV", "ABS", "", (Val("K", 50),), "Ps"), 41), (Motion("DRVZ", mode=0), 42)):
        bad = replace(good, steps=(good.steps[0], replace(good.steps[1], motion=follow)))
        movs = "".join(f"MOV K{w - 65536 if w > 32767 else w} R{5000 + i}\n" for i, w in enumerate(encode(bad)))
        il = AXIS.replace("MPARA K0 R2000\n", "MPARA K0 R2000\nLD M1924\n" + movs)
        stim = f"scan 10ms\n20ms M0=1\n100ms expect R4060={code} R4088:d=0 M1992=1"
        assert ok(run(il, stim, {}))
    movs = "".join(f"MOV K{w - 65536 if w > 32767 else w} R{5000 + i}\n" for i, w in enumerate(encode(good)))
    il = AXIS.replace("MPARA K0 R2000\n", "MPARA K0 R2000\nLD M1924\n" + movs)
    assert ok(run(il, "scan 10ms\n20ms M0=1\n2s expect R4060=0 R4088:d=150", {}))


def test_a_table_written_at_run_time_is_checked_when_fun147_executes():
    """11.6 error list, "執行 FUN140 與 執行 FUN147 時 可能之錯誤碼": 33 "行程設定值錯誤",
    34 "不合法定位程式"; a FUN147 table the program MOVs into place gets the build's codes
    (F033 every axis blank, F034 GOTO beyond the last step) in D4060+Gp when FUN147 executes,
    before any axis moves (the GOTO used to be found only after step 1 had run)."""
    from dataclasses import replace

    from mlctool.targets.fbs.lang import parse_program
    from mlctool.targets.fbs.model import BLANK, Val, tables
    from mlctool.targets.fbs.table import encode

    text = "001 SPD 1000\n LIN ADR,1000,500, , ,Ps\n MEND\n"
    good, diags = parse_program("t.mpos", text, tables().dialects["mhspo"])
    assert not diags
    step = good.steps[0]
    blank = replace(step.motion, travel=(BLANK,) * 4)
    cases = ((replace(step, motion=blank), 33), (replace(step, goto=Val("K", 2), mend=False), 34))

    def il_writing(program):
        movs = "".join(f"MOV K{w - 65536 if w > 32767 else w} R{5100 + i}\n" for i, w in enumerate(encode(program)))
        return AXIS.replace("END", "LD M1924\n" + movs + "LD M1\nLD M12\nLD M13\nMHSPO K0 R5100 R2200\nEND")

    tables_ = {"R5000": "001 SPD 1000\n DRV ADR,+,0,Ps\n MEND\n"}
    for bad_step, code in cases:
        stim = f"scan 10ms\n100ms M1=1\n2s expect D4060={code} R4088:d=0 R4090:d=0"
        assert ok(run(il_writing(replace(good, steps=(bad_step,))), stim, tables_))
    stim = "scan 10ms\n100ms M1=1\n2s expect D4060=0 R4088:d=1000 R4090:d=500"
    assert ok(run(il_writing(good), stim, tables_))


def test_mlc_toml_pulse_modes_set_the_axes_output_mode(tmp_path):
    """11.6: "務必設定 Pulse Output 之工作模式（不設定時，Y0～Y7 當作一般輸出）為 U/D，P/R 或 A/B
    等三種模式之一" — "P/R 模式：Y0 送出脈波。Y1 送出方向信號；ON=上數，OFF=下數" and
    "U/D 模式：Y0 送出上數脈波。Y1 送出下數脈波". The mode is a project setting (mlc.toml
    `pulse_modes`, Ps0 first); while Ps0 pulses forward, Y1 is On in P/R and Off in U/D."""
    from conftest import run_mlc

    (tmp_path / "t.il").write_text(AXIS.strip() + "\n", "utf-8")
    (tmp_path / "t.pos").write_text("001 SPD 1000\n DRV ADR,+,2000,Ps\n MEND\n", "utf-8")

    def sim(toml: str, expect: str):
        (tmp_path / "mlc.toml").write_text('target = "fbs"\n' + toml, "utf-8")
        (tmp_path / "t.stim").write_text(f"scan 10ms\n0ms M0=1\n500ms expect {expect}\n", "utf-8")
        return run_mlc("sim", "t.il", "--table", "R5000=t.pos", "--stimulus", "t.stim", cwd=tmp_path)

    r = sim('pulse_modes = ["P/R"]\n', "Y0=1 Y1=1")
    assert r.code == 0, r.out + r.err
    r = sim("", "Y0=1 Y1=0")  # the packaged default: U/D
    assert r.code == 0, r.out + r.err
    r = sim('pulse_modes = ["U/D", "P/R"]\n', "Y0=1 Y1=0")
    assert r.code == 0, r.out + r.err
    assert sim('pulse_modes = ["P/R"]\n', "Y0=1 Y1=0").code == 1  # the expectation can fail
    r = sim('pulse_modes = ["PR"]\n', "Y0=1")
    assert r.code == 2 and "E110" in r.err and "pulse_modes" in r.err and "Traceback" not in r.err


# FUN147 takes U/D or A/B axes only (11.6, FUN147: "務必設定 Pulse Output 之工作模式 ... 為 U/D 或
# A/B 等二種模式之一"); the manual names no error code: E236 in `mlc check`, an alarm in `mlc sim`.
MHSPO_IL = PARAMS.replace("MPARA K0 R2000", "MPARA K0 R2000\nMPARA K1 R2000") + """
LD M0
LD M10
LD M11
MHSPO K0 R5100 R2200
OUT M20
END
"""
MHSPO_TABLE = {"R5100": "001 SPD 1000\n LIN ADR,1000,500, , ,Ps\n MEND\n"}


def test_mhspo_on_a_p_r_axis_from_the_stimulus_does_not_start_and_raises_an_alarm(tmp_path):
    """`model stepper axis=1 mode=P/R`: the group's LIN drives Ps1, so FUN147 does not start
    (no pulses, ACT Off, no error code) and the alarm OPERATION_ERROR is raised; U/D and A/B
    run it, and an axis the LIN does not drive (ADR 0) may be P/R."""
    from conftest import run_mlc

    (tmp_path / "t.il").write_text(MHSPO_IL.strip() + "\n", "utf-8")
    (tmp_path / "mlc.toml").write_text('target = "fbs"\n', "utf-8")

    def sim(mode: str, lin: str, expect: str):
        (tmp_path / "t.mpos").write_text(f"001 SPD 1000\n LIN ADR,{lin}, , ,Ps\n MEND\n", "utf-8")
        (tmp_path / "t.stim").write_text(f"scan 10ms\nmodel stepper axis=1 mode={mode}\n0ms M0=1\n"
                                         f"{expect}\n", "utf-8")
        return run_mlc("sim", "t.il", "--table", "R5100=t.mpos", "--stimulus", "t.stim", cwd=tmp_path)

    for mode in ("U/D", "A/B"):
        r = sim(mode, "1000,500", "2s expect R4088:d=1000 R4090:d=500")
        assert r.code == 0, r.out + r.err
    r = sim("P/R", "1000,0", "2s expect R4088:d=1000 R4090:d=0")
    assert r.code == 0, r.out + r.err
    r = sim("P/R", "1000,500", "500ms expect alarm OPERATION_ERROR\n"
            "500ms expect R4088:d=0 R4090:d=0 M20=0 D4060=0 R2201=0")
    assert r.code == 0, r.out + r.err
    r = sim("P/R", "1000,500", "500ms expect R4088:d=0")
    assert r.code == 1 and "E604" in r.err and "Ps1" in r.err and "P/R" in r.err, r.out + r.err


def test_mhspo_p_r_alarm_through_the_cli_is_e604_at_the_fun147_line(tmp_path):
    from conftest import run_mlc

    (tmp_path / "t.il").write_text(MHSPO_IL.strip() + "\n", "utf-8")
    (tmp_path / "t.mpos").write_text(MHSPO_TABLE["R5100"], "utf-8")
    (tmp_path / "mlc.toml").write_text('target = "fbs"\n', "utf-8")
    line = MHSPO_IL.strip().split("\n").index("MHSPO K0 R5100 R2200") + 1
    for extra, code in (("500ms expect M20=0\n", 1), ("500ms expect alarm OPERATION_ERROR\n", 0)):
        (tmp_path / "t.stim").write_text("scan 10ms\nmodel stepper axis=0 mode=P/R\n0ms M0=1\n" + extra, "utf-8")
        r = run_mlc("sim", "t.il", "--table", "R5100=t.mpos", "--stimulus", "t.stim", cwd=tmp_path)
        assert r.code == code, r.out + r.err
        if code:
            assert "E604" in r.err and f"t.il:{line}" in r.err and "Traceback" not in r.err
