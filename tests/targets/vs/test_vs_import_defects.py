"""Issue 29: import defects seen on real exports, each held by a test that failed before the fix."""

from __future__ import annotations

from conftest import run_mlc
from mlctool.imports import import_text
from mlctool.targetapi import load_target

VS = load_target("vs")


def _gx(rows: list[list[str]], cpu: str = "FXCPU FX3U/FX3UC", info: str = "PLC Information:") -> str:
    head = f'"MAIN"\n"{info}"\t"{cpu}"\n' \
        '"Step Number"\t"Line Statement"\t"Instruction"\t"I/O(Device)"\t"Blank"\t"PI Statement"\t"Note"\n'
    return head + "".join("\t".join(f'"{c}"' for c in (r + [""] * 7)[:7]) + "\n" for r in rows)


def test_w107_quotes_the_row_as_the_export_writes_it():
    """Before: `LD M9002` (the mapped device) and `OUT T0` without its K10 continuation."""
    text = _gx([["0", "", "LD", "M8002"], ["2", "", "OUT", "T0"], ["", "", "", "K10"], ["3", "", "END"]])
    out, _, diags = import_text("g.csv", text, VS)
    said = [d.message for d in diags if d.code == "W107"]
    assert said == ["row 4: LD M8002 is 2 steps in the export (step 0 to 2), 1 by target vs's step convention",
                    "row 5: OUT T0 K10 is 1 steps in the export (step 2 to 3), 3 by target vs's step convention"]
    assert "LD M9002" in out


MODBUS_RUNG = [["0", "", "LD", "M8411"], ["3", "", "MOV", "H1097"], ["", "", "", "D8400"], ["8", "", "MOV", "K1"],
               ["", "", "", "D8401"], ["13", "", "END"]]


def test_fx3u_modbus_slave_setup_is_refused_by_import_as_by_check(tmp_path):
    """Before: W910 and exit 0 for M8411, then `mlc check` E205: the two disagreed."""
    out, _, diags = import_text("m.csv", _gx(MODBUS_RUNG), VS)
    assert out is None and [d.code for d in diags if d.severity == "error"] == ["E911"]
    e911 = next(d for d in diags if d.code == "E911")
    assert "M8411" in e911.message and "E205" in e911.message
    assert any("MODBUS Slave" in n and "7-3-5" in n for n in e911.notes)
    (tmp_path / "m.csv").write_text(_gx(MODBUS_RUNG), "utf-16")
    r = run_mlc("import", "m.csv", "-o", "m.il", cwd=tmp_path)
    assert r.code == 1 and "E911" in r.err and not (tmp_path / "m.il").exists()
    (tmp_path / "h.il").write_text("LD M8411\nMOV H1097 D8400\nEND\n", "utf-8")
    r = run_mlc("check", "--target", "vs", "h.il", cwd=tmp_path)
    assert r.code == 1 and "E205" in r.err and "M8411" in r.err
    # a special the VS has as an ordinary register (D8400) is still kept with W910
    out, _, diags = import_text("d.csv", _gx([["0", "", "LD", "X000"], ["1", "", "MOV", "K1"], ["", "", "", "D8400"],
                                              ["6", "", "END"]]), VS)
    assert out is not None and "W910" in [d.code for d in diags]


def test_fx_drvi_is_the_vs_drvr_and_d8140_the_vs_pulse_count():
    """Before: E907 `DDRVI` ("did you mean DDVIT?") and W910 for D8140 (no counterpart)."""
    text = _gx([["0", "", "LD", "X000"], ["1", "", "DDRVI", "K1000"], ["", "", "", "K500"], ["", "", "", "Y000"],
                ["", "", "", "Y004"], ["18", "", "LD", "X001"], ["19", "", "DRVI", "D10"], ["", "", "", "D20"],
                ["", "", "", "Y001"], ["", "", "", "Y005"], ["28", "", "LD", "M8000"], ["29", "", "DMOV", "D8140"],
                ["", "", "", "D100"], ["38", "", "DMOV", "D8142"], ["", "", "", "D102"], ["47", "", "END"]])
    out, _, diags = import_text("p.csv", text, VS)
    assert out is not None, [d.message for d in diags]
    assert sorted(d.code for d in diags) == ["N910", "N910", "N911"], [d.message for d in diags]
    lines = out.splitlines()
    assert "DDRVR K1000 K500 Y0 Y4" in lines and "DRVR D10 D20 Y1 Y5" in lines
    assert "DMOV D9352 D100" in lines and "DMOV D9372 D102" in lines
    assert "DDRVI -> DDRVR, DRVI -> DRVR" in next(d.message for d in diags if d.code == "N911")


DELTA_ROWS = {"stepped": "0,LD,X0,,\n1,TMR,T0,K10,\n5,LD,T0,,\n6,OUT,Y0,,\n7,END,,,\n",
              "plain": "LD,X0\nTMR,T0,K10\nLD,T0\nOUT,Y0\nEND\n"}


def test_headerless_delta_rows_are_read_never_a_1_byte_file(tmp_path):
    """Before: `--from delta` on rows without the header wrote "\\n" with exit 0; without
    --from, `0,LD,X0,,` read as GX rows (E907 'X0') and `LD,X0` as plain IL (TMR unmapped)."""
    for name, rows in DELTA_ROWS.items():
        (tmp_path / f"{name}.csv").write_text(rows, "ascii")
        for fmt in (["--from", "delta"], []):
            r = run_mlc("import", "--target", "vs", *fmt, f"{name}.csv", "-o", f"{name}.il", cwd=tmp_path)
            assert r.code == 0, r.err
            assert (tmp_path / f"{name}.il").read_text("utf-8").endswith("LD X0\nOUT T0 K10\nLD T0\nOUT Y0\nEND\n")
    # a file with no instruction row is an error: nothing written
    (tmp_path / "empty.csv").write_text("Step,Instruction,Operand1,Operand2,Operand3\n", "ascii")
    r = run_mlc("import", "--from", "delta", "empty.csv", "-o", "empty.il", cwd=tmp_path)
    assert r.code == 2 and "E912" in r.err and not (tmp_path / "empty.il").exists()


def test_check_names_the_vs_instruction_for_a_delta_tmr(tmp_path):
    """Before: E201 TMR 'did you mean TTMR?' (a teaching timer)."""
    (tmp_path / "d.il").write_text(DELTA_ROWS["plain"], "ascii")
    r = run_mlc("check", "--target", "vs", "d.il", cwd=tmp_path)
    assert r.code == 1 and "TMR is Delta DVP's; target vs writes it OUT" in r.err and "TTMR" not in r.err


def test_octal_x_one_rule_for_the_program_and_its_comments(tmp_path):
    """Before: the program row X058 passed through (exit 0, `mlc check` failing later) while the
    comment row X058 aborted the import with E907: one rule now, E913 for both."""
    (tmp_path / "p.csv").write_text(_gx([["0", "", "LD", "X058"], ["1", "", "OUT", "Y000"], ["2", "", "END"]]),
                                    "utf-16")
    (tmp_path / "c.csv").write_text('"COMMENT"\n"Device Name"\t"Comment"\n"X5B"\t"a"\n', "utf-16")
    (tmp_path / "good.csv").write_text('"COMMENT"\n"Device Name"\t"Comment"\n"X010"\t"a"\n', "utf-16")
    r = run_mlc("import", "p.csv", "-o", "p.il", cwd=tmp_path)
    assert r.code == 1 and "E913" in r.err and "'X058': X devices are numbered in octal" in r.err
    r = run_mlc("import", "--comments", "c.csv", "p.csv", cwd=tmp_path)
    assert r.code == 1 and "E913" in r.err and "X5B" in r.err
    fixed = _gx([["0", "", "LD", "X010"], ["1", "", "OUT", "Y000"], ["2", "", "END"]])
    (tmp_path / "p.csv").write_text(fixed, "utf-16")
    r = run_mlc("import", "--comments", "good.csv", "p.csv", cwd=tmp_path)
    assert r.code == 0 and "LD X10 ; X10 a" in r.out


def test_an_l_series_export_is_refused_saying_what_to_do(tmp_path):
    """Before: "PC情報: LCPU L26-BT" imported with exit 0, hexadecimal X62 written as the octal
    VS input X62 (another input)."""
    rows = [["0", "", "LD", "X62"], ["1", "", "OUT", "Y70"], ["2", "", "LD", "SM400"], ["3", "", "END"]]
    (tmp_path / "l.csv").write_text(_gx(rows, "LCPU L26-BT", "PC情報:"), "utf-16")
    r = run_mlc("import", "l.csv", "-o", "l.il", cwd=tmp_path)
    assert r.code == 2 and "E910" in r.err and "LCPU L26-BT" in r.err and "hexadecimal" in r.err
    assert "rewrite the program" in r.err and not (tmp_path / "l.il").exists()
    for cpu in ("QCPU(Q mode) Q06UDH", "RCPU R04"):
        out, _, diags = import_text("q.csv", _gx(rows, cpu), VS)
        assert out is None and [d.code for d in diags] == ["E910"]
    # GX Developer's one-cell form, an FX CPU: read as ever; an FX5 or an unknown name: W911
    fx = _gx([["0", "", "LD", "X000"], ["1", "", "OUT", "Y000"], ["2", "", "END"]])
    assert import_text("f.csv", fx.replace('"PLC Information:"\t"FXCPU FX3U/FX3UC"', '"PLC Type:FX2N(C)"'),
                       VS)[2] == []
    out, _, diags = import_text("f.csv", fx.replace("FXCPU FX3U/FX3UC", "FX5UCPU"), VS)
    assert out is not None and [d.code for d in diags] == ["W911"]


def test_the_dialect_of_origin_decides_w217(tmp_path):
    """Before: an FX program's M1000 (an ordinary relay, here set by an HMI) was W217 "Delta
    special" after import; the import now writes `.dialect fx` and the checker reads it."""
    text = _gx([["0", "", "LD", "M1000"], ["1", "", "OUT", "Y000"], ["2", "", "LD", "M8005"], ["4", "", "OUT", "Y001"],
                ["5", "", "END"]])
    (tmp_path / "p.csv").write_text(text, "utf-16")
    r = run_mlc("import", "p.csv", "-o", "p.il", cwd=tmp_path)
    il = (tmp_path / "p.il").read_text("utf-8")
    assert r.code == 0 and il.startswith(".dialect fx\n"), r.err
    r = run_mlc("check", "--target", "vs", "p.il", cwd=tmp_path)
    assert "M1000" not in r.err and "W217" in r.err and "M8005" in r.err  # the FX special still warned
    # the same lines without the directive: M1000 taken for Delta's RUN monitor
    (tmp_path / "bare.il").write_text(il.removeprefix(".dialect fx\n"), "utf-8")
    r = run_mlc("check", "--target", "vs", "bare.il", cwd=tmp_path)
    assert "W217" in r.err and "M1000" in r.err
    (tmp_path / "bad.il").write_text(".dialect s7\nLD X0\nOUT Y0\nEND\n", "utf-8")
    r = run_mlc("check", "--target", "vs", "bad.il", cwd=tmp_path)
    assert r.code == 1 and "E105" in r.err and "dvp, fx" in r.err


def test_a_vendor_project_file_is_refused_saying_what_to_do(tmp_path):
    """Binary project files no public description reads reliably: E914, never a guess. A
    GX Works2 .gxw (or any compound file) goes to the project reader, which refuses a damaged
    one with E915 (tests/test_gxw.py), a GX Developer .wpg to its reader, which refuses one
    without its signature with E932 (tests/test_wpg.py), a WinProladder .pdw / .ldr to its
    reader, which refuses a damaged one with E923 (tests/test_winproladder.py)."""
    for name in ("p.dvp", "p.isp", "p.gx3"):
        (tmp_path / name).write_bytes(b"\x00\x01\x02\x03LD X0")
        r = run_mlc("import", name, "-o", "p.il", cwd=tmp_path)
        assert r.code == 2 and "E914" in r.err and "offset 0" in r.err and "export" in r.err, (name, r.err)
        assert not (tmp_path / "p.il").exists()
    (tmp_path / "p.wpg").write_bytes(b"\x00\x01\x02\x03LD X0" + bytes(0x40))
    r = run_mlc("import", "p.wpg", "-o", "p.il", cwd=tmp_path)
    assert r.code == 2 and "E932" in r.err and "offset 0" in r.err and "CSV" in r.err and not (tmp_path / "p.il").exists()
    for name in ("p.pdw", "p.ldr"):
        (tmp_path / name).write_bytes(b"\x00\x01\x02\x03LD X0")
        r = run_mlc("import", name, "-o", "p.il", cwd=tmp_path)
        assert r.code == 2 and "E923" in r.err and "offset 0" in r.err and not (tmp_path / "p.il").exists()
    (tmp_path / "p.gxw").write_bytes(b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1" + bytes(504))
    (tmp_path / "p.bin").write_bytes(b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1" + bytes(504))  # by its header too
    for name in ("p.gxw", "p.bin"):
        r = run_mlc("import", name, "-o", "p.il", cwd=tmp_path)
        assert r.code == 2 and "E915" in r.err and "CSV" in r.err, (name, r.err)
        assert not (tmp_path / "p.il").exists()
