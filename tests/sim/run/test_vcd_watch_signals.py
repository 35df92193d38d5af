"""`mlc sim` names the NC5's signals (targets/nc5/signals.tsv) where a run is looked at: VCD
aliases under mlc.signals (sim/run/vcd.py) and the `--watch` lines (cli/sim.py), through the
generic hook targetapi.signals.device_signal."""

from __future__ import annotations

from conftest import run_mlc

PROGRAM = "LD X0\nOUT M21000\nLD M31016\nOUT Y1\nMOV K3 D21000\nDMOV K5 D21014\nEND\n"


def _run(tmp_path, *args):
    (tmp_path / "nc.il").write_text(PROGRAM, "utf-8")
    (tmp_path / "nc.stim").write_text("0ms X0=1\nrun 30ms\n", "utf-8")
    return run_mlc("sim", "--target", "nc5", "nc.il", "--stimulus", "nc.stim", *args, cwd=tmp_path)


def test_watch_lines_say_what_a_signal_is(tmp_path):
    r = _run(tmp_path, "--watch", "M21000,D21000,D21014:d,Y1")
    assert r.code == 0, r.err
    lines = r.out.splitlines()
    assert "M21000 = 1  ; 程式啟動 cycle start, MLC->NC, channel 1, 5.3.2" in lines
    assert "D21000 = 0  ; NC 模式切換 NC mode select, MLC->NC, channel 1, 5.3.1" in lines
    assert "D21014:d = 0  ; 增量寸動移動量倍率 (32-bit) incremental jog amount, MLC->NC, 32-bit, channel 1, 5.3.5" \
        in lines
    assert "Y1 = 0" in lines


def test_vcd_aliases_name_the_signals(tmp_path):
    r = _run(tmp_path, "--vcd", "nc.vcd")
    assert r.code == 0, r.err
    text = (tmp_path / "nc.vcd").read_text("utf-8")
    scope = text[text.index("$scope module signals $end"):]
    for name in ("M21000_cycle_start", "M31016_program_running", "D21000_NC_mode_select"):
        assert f" {name} $end" in scope, name
    # an alias is the same variable: the identifier code of M21000 and of its alias agree
    ids = {line.split()[4]: line.split()[3] for line in text.splitlines() if line.startswith("$var")}
    assert ids["M21000"] == ids["M21000_cycle_start"]
