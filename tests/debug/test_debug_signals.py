"""The debugger names the NC5's signals (targets/nc5/signals.tsv) through the generic hook
targetapi.signals.device_signal: console `print`, DAP variables, the web monitor's ladder."""

from __future__ import annotations

import io
import json

import pytest

from mlctool.debug.console import Console
from mlctool.debug.dap import SCOPES, DapServer
from mlctool.debug.load import load_session
from mlctool.debug.web import Monitor
from mlctool.targetapi import load_target

PROGRAM = "LD X0\nOUT M21000\nLD M31016\nOUT Y1\nMOV K3 D21000\nEND\n"


@pytest.fixture
def session(tmp_path):
    path = tmp_path / "nc.il"
    path.write_text(PROGRAM, "utf-8")
    stim = tmp_path / "nc.stim"
    stim.write_text("0ms X0=1\nrun 50ms\n", "utf-8")
    s = load_session([str(path)], str(stim), load_target("nc5"))
    s.run(scans=2)
    return s


def test_console_print_says_what_a_signal_is(session):
    out: list[str] = []
    Console(session, out.append).execute("print M21000 D21000 Y1")
    assert out == ["M21000 = 1  ; 程式啟動 cycle start, MLC->NC, channel 1, 5.3.2",
                   "D21000 = 0  ; NC 模式切換 NC mode select, MLC->NC, channel 1, 5.3.1", "Y1 = 0"]


def test_dap_variables_carry_the_row_in_their_type(session):
    writer = io.BytesIO()
    server = DapServer(io.BytesIO(), writer)
    server.session = session
    relays = 1 + SCOPES.index("Relays")
    server.handle({"seq": 1, "type": "request", "command": "variables", "arguments": {"variablesReference": relays}})
    body = writer.getvalue().split(b"\r\n\r\n", 1)[1]
    variables = {v["name"]: v for v in json.loads(body)["body"]["variables"]}
    assert variables["M21000"]["value"] == "1"  # the value stays the value (setVariable reads it)
    assert variables["M21000"]["type"] == "bit - M21000 - 程式啟動 cycle start, MLC->NC, channel 1, 5.3.2"
    assert variables["M31016"]["type"].startswith("bit - M31016 - 程序執行中 program running, NC->MLC")


def test_the_web_monitor_ladder_names_the_signals(session):
    page = Monitor(session).page()
    assert "程式啟動" in page and "程序執行中" in page
    assert "M21000 - 程式啟動 cycle start, MLC-&gt;NC, channel 1, 5.3.2" in page
