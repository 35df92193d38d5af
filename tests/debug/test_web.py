"""`mlc debug --web`: the live ladder monitor's protocol, spoken by a WebSocket client to a
server on a free loopback port (in a thread, and once as `python -m mlctool` in a
subprocess): the initial state, force by toggle, a scan, release, junk that gets error
replies while the server goes on answering, a second tab that sees the same session, run and
pause, the page and the Host/Origin checks."""

from __future__ import annotations

import json
import signal
import socket
import subprocess
import threading
import time
import urllib.error
import urllib.request
from contextlib import ExitStack

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from websockets.exceptions import ConnectionClosed, InvalidStatus
from websockets.sync.client import connect

from mlctool.debug.load import load_session
from mlctool.debug.web import (
    COMMANDS,
    MAX_MESSAGE,
    MAX_QUEUE,
    MAX_TABLE,
    MAX_VALUE,
    Monitor,
    WebServer,
)
from mlctool.targets import load_target
from tests.conftest import MLC_COMMAND

# Y0 latches on X0 until X1; while Y0 is On, D0 counts scans; Y1 comes on past 3
PROGRAM = """LD X0
OR Y0
ANI X1
OUT Y0
LD Y0
ADD D0 K1 D0
LD> D0 K3
OUT Y1
END
"""
LATCH, COUNT, Y1_COIL = 3, 5, 7  # instruction indexes: OUT Y0, ADD, OUT Y1


@pytest.fixture
def program(tmp_path):
    path = tmp_path / "p.il"
    path.write_text(PROGRAM)
    return path


@pytest.fixture
def server(program):
    session = load_session([str(program)], None, load_target("nc5"))
    srv = WebServer(Monitor(session), 0)
    srv.start()
    yield srv
    srv.shutdown()


class Tab:
    """A WebSocket client: replies by id, the latest state, outputs."""

    def __init__(self, srv: WebServer, **kw):
        self.stack = ExitStack()
        self.ws = self.stack.enter_context(connect(srv.url.replace("http://", "ws://") + "ws", open_timeout=10, **kw))
        self.next_id = 0
        self.outputs: list[str] = []
        self.state = self.recv("state")

    def recv(self, kind: str | None = None) -> dict:
        while True:
            msg = json.loads(self.ws.recv(timeout=10))
            if msg["type"] == "state":
                self.state = msg
            elif msg["type"] == "output":
                self.outputs.append(msg["text"])
            if kind is None or msg["type"] == kind:
                return msg

    def request(self, cmd: str, **args) -> dict:
        """Send; the reply (or error) to it, then the state that follows it."""
        self.next_id += 1
        self.ws.send(json.dumps({"id": self.next_id, "cmd": cmd, **args}))
        return self.reply(self.next_id)

    def reply(self, msg_id) -> dict:
        while True:
            msg = self.recv()
            if msg["type"] in ("reply", "error") and msg["id"] == msg_id:
                if msg["type"] == "reply":
                    self.recv("state")
                return msg

    def raw(self, data) -> dict:
        self.ws.send(data)
        while True:
            msg = self.recv()
            if msg["type"] in ("reply", "error"):
                return msg

    def close(self):
        self.stack.close()


def test_force_scan_release_and_junk(server):
    tab = Tab(server)
    st = tab.state
    assert st["scan"] == 0 and st["pc"] is None and st["forced"] == {} and not st["running"]
    assert st["values"]["X0"] == "0" and st["values"]["D0"] == "0"
    assert LATCH not in st["on"] and 2 in st["on"]  # ANI X1 conducts (X1 Off), the coil is Off

    other = Tab(server)  # a second tab watches the same session
    r = tab.request("toggle", device="X0")
    assert r["ok"] and r["text"] == "forced X0=1"
    assert tab.state["forced"] == {"X0": "1"} and 0 in tab.state["on"]
    assert other.recv("state")["forced"] == {"X0": "1"}  # broadcast to every tab

    assert tab.request("scan")["text"] == "scan done: scan 1 (t=10ms), before the scan"
    st = tab.state
    assert st["scan"] == 1 and LATCH in st["on"] and st["values"]["Y0"] == "1" and st["values"]["D0"] == "1"
    assert other.recv("state")["scan"] == 1

    assert tab.request("release", device="X0")["text"] == "released X0"
    assert tab.state["forced"] == {}
    r = tab.request("force", device="X0", value="0")
    assert r["ok"] and tab.state["values"]["X0"] == "0"
    tab.request("release", device="X0")
    for _ in range(3):
        tab.request("scan")
    st = tab.state
    assert st["values"]["D0"] == "4" and Y1_COIL in st["on"] and LATCH in st["on"]  # latched
    assert st["values"]["Y1"] == "1"

    # junk: each gets an error reply, the connection and the server go on
    assert "not JSON" in tab.raw("{nope")["message"]
    assert "JSON object" in tab.raw("[1, 2]")["message"]
    assert "binary" in tab.raw(b"\x00\x01")["message"]
    assert "not JSON" in tab.raw("[" * 10_000)["message"]  # nesting past the parser's depth
    assert "unknown cmd" in tab.raw(json.dumps({"cmd": "rm -rf"}))["message"]
    assert "unknown cmd" in tab.raw(json.dumps({"id": 9}))["message"]
    assert "`id`" in tab.raw(json.dumps({"id": [1], "cmd": "state"}))["message"]
    assert "needs `device`" in tab.request("force", value=1)["message"]
    assert "'Q9': no device Q" in tab.request("toggle", device="Q9")["message"]
    assert "needs `value`" in tab.request("force", device="D0", value=None)["message"]
    assert tab.request("force", device="D0", value="K1e99")["type"] == "error"
    assert "not forced" in tab.request("release", device="X3")["message"]
    assert "not a bit" in tab.request("toggle", device="D0")["message"]
    assert "`scan`" in tab.request("goto", scan="3")["message"]
    # numbers: ASCII digits, at most 20 of them (#30.18: "internal error: ValueError")
    assert "scans go up to 1000000000" in tab.request("goto", scan=10**10)["message"]
    assert "numbers have at most 20" in tab.raw(json.dumps({"id": 5, "cmd": "goto", "scan": 10**30}))["message"]
    assert "numbers have at most 20" in tab.raw('{"cmd": "state", "id": ' + "7" * 5000 + "}")["message"]
    assert "'²': give a scan number" in tab.request("console", line="goto ²")["message"]
    assert "'99999999999999999999999…': give a scan number" in tab.request("console", line="goto " + "9" * 900)["message"]
    assert "'³': give a count" in tab.request("console", line="step ³")["message"]
    assert "no scan before scan 0" in tab.request("goto", scan=-1)["message"]
    assert "not available" in tab.request("console", line="save /tmp/x.stim")["message"]
    assert "unknown command" in tab.request("console", line="frobnicate")["message"]
    assert "`speed`" in tab.request("run", speed=-1)["message"]

    # still answering, state intact
    assert tab.request("state")["ok"] and tab.state["values"]["D0"] == "4"
    assert tab.request("step")["text"].startswith("stepped to scan 4 (t=40ms)")
    assert tab.state["pc"] == 1
    assert tab.request("back")["ok"] and tab.state["pc"] == 0
    assert tab.request("back-scan")["ok"] and tab.state["scan"] == 4 and tab.state["pc"] is None
    assert tab.request("goto", scan=1)["ok"] and tab.state["values"]["D0"] == "1"
    out = tab.request("console", line="print D0 Y0")
    assert out["text"] == "D0 = 1\nY0 = 1"
    assert tab.request("console", line='log 6 "count {D0}"')["ok"]  # a logpoint: its line in the reply
    assert tab.request("scan")["text"] == "count 1\nscan done: scan 2 (t=20ms), before the scan"
    tab.close()
    other.close()


# the device table: a symbol, an NC5 signal (M21000 cycle start) the program drives
TABLE_PROGRAM = """.define START X0
.define CYCLE M21000
LD START
OUT CYCLE
LD X1
ADD D5 K1 D5
END
"""


@pytest.fixture
def table_server(tmp_path):
    path = tmp_path / "t.il"
    path.write_text(TABLE_PROGRAM)
    srv = WebServer(Monitor(load_session([str(path)], None, load_target("nc5"))), 0)
    srv.start()
    yield srv
    srv.shutdown()


def test_the_device_table(table_server):
    tab, other = Tab(table_server), Tab(table_server)
    assert tab.state["table"] == []
    assert tab.request("table-add", device="CYCLE")["text"] == "added M21000"  # by its symbol
    assert tab.request("table-add", device="D5")["ok"]
    assert tab.request("table-add", device="x0")["text"] == "added X0"  # as the console spells it
    rows = tab.state["table"]
    assert rows == [
        {"device": "M21000", "symbol": "CYCLE", "signal": "M21000 - 程式啟動 cycle start, MLC->NC, channel 1, 5.3.2",
         "value": "0"},
        {"device": "D5", "symbol": "", "signal": "", "value": "0"},
        {"device": "X0", "symbol": "START", "signal": "", "value": "0"}]
    assert other.request("state")["ok"] and other.state["table"] == rows  # one table per session: every tab sees it
    other.close()

    # an edit of a row that is not forced: set once (`write`); the program may change it again
    r = tab.request("write", device="D5", value="K41")
    assert r["text"] == "wrote D5=41" and tab.state["table"][1]["value"] == "41" and tab.state["forced"] == {}
    tab.request("write", device="X1", value=1)
    tab.request("scan")
    assert tab.state["table"][1]["value"] == "42"  # ADD ran on the value written
    tab.request("write", device="START", value="1")
    tab.request("scan")
    assert tab.state["table"][0]["value"] == "1"  # OUT CYCLE followed X0
    # the program overwrites a one-shot write of its coil at the next scan, not a force
    tab.request("write", device="M21000", value=0)
    assert tab.state["table"][0]["value"] == "0"
    tab.request("scan")
    assert tab.state["table"][0]["value"] == "1"
    assert tab.request("force", device="M21000", value="0")["ok"] and tab.state["forced"] == {"M21000": "0"}
    tab.request("scan")
    assert tab.state["table"][0]["value"] == "0" and tab.state["forced"] == {"M21000": "0"}
    assert tab.request("console", line="save")["type"] == "error"  # (the console's refusals hold)
    tab.request("release", device="M21000")
    tab.request("scan")
    assert tab.state["table"][0]["value"] == "1"

    # refused, each with a sentence, the table unchanged
    assert tab.request("table-add", device="D5")["message"] == "D5 is in the table already"
    assert tab.request("table-remove", device="D6")["message"] == "D6 is not in the table"
    assert "'Q9': no device Q" in tab.request("table-add", device="Q9")["message"]
    assert "needs `device`" in tab.request("table-add", device=["D0"])["message"]
    assert "needs `device`" in tab.request("table-add")["message"]
    assert "too long" in tab.request("table-add", device="D" * 101)["message"]
    assert "needs `value`" in tab.request("write", device="D5")["message"]
    assert "needs `value`" in tab.request("write", device="D5", value=True)["message"]
    assert "needs `value`" in tab.request("write", device="D5", value={"K": 1})["message"]
    assert f"at most {MAX_VALUE} characters" in tab.request("write", device="D5", value="9" * 5000)["message"]
    assert "takes -32768..32767" in tab.request("write", device="D5", value="K99999")["message"]
    assert "not an integer" in tab.request("write", device="D5", value=1.5)["message"]
    assert "numbers have at most 20" in tab.raw('{"cmd": "write", "device": "D5", "value": ' + "9" * 21 + "}")["message"]
    assert "numbers have at most 20" in tab.raw('{"cmd": "table-add", "device": "D5", "x": ' + "9" * 99 + "}")["message"]
    assert [r["device"] for r in tab.state["table"]] == ["M21000", "D5", "X0"]
    assert tab.request("table-remove", device="START")["text"] == "removed X0"  # by symbol too
    for n in range(MAX_TABLE - 2):
        assert tab.request("table-add", device=f"D{100 + n}")["ok"]
    assert f"at most {MAX_TABLE} devices" in tab.request("table-add", device="D999")["message"]
    assert len(tab.state["table"]) == MAX_TABLE
    tab.close()


def test_a_table_edit_during_a_replay_is_refused_until_paused(table_server):
    """The session's rule: no action while it replays to another point (reverse-continue
    runs in batches that let this request in); after the Pause the edit is taken."""
    tab, other = Tab(table_server), Tab(table_server)
    tab.request("table-add", device="D5")
    tab.request("write", device="X1", value=1)
    tab.request("console", line="scan 5000")
    tab.request("console", line="break 6")  # the search goes instruction by instruction: ~0.3 s
    tab.next_id += 1
    tab.ws.send(json.dumps({"id": tab.next_id, "cmd": "console", "line": "reverse-continue"}))
    deadline = time.monotonic() + 10
    refused = None
    while refused is None and time.monotonic() < deadline:
        r = other.request("write", device="D5", value="7")
        if r["type"] == "error":
            refused = r
    assert refused is not None and "Pause it first" in refused["message"], refused
    other.request("pause")
    assert tab.reply(tab.next_id)["text"].startswith("interrupted: reverse-continue did not finish; still at scan 5000")
    assert other.request("write", device="D5", value="7")["ok"] and other.state["table"][0]["value"] == "7"
    tab.close()
    other.close()


def test_a_message_past_the_limit_closes_only_that_connection(server):
    tab = Tab(server)
    tab.ws.send("x" * (MAX_MESSAGE + 1))
    with pytest.raises(ConnectionClosed):
        tab.recv("reply")
    again = Tab(server)
    assert again.request("state")["ok"]
    again.close()


def test_run_until_a_condition_then_pause(server):
    tab = Tab(server)
    tab.request("toggle", device="X0")
    assert tab.request("console", line="break if D0 >= 50")["ok"]
    assert tab.request("console", line='log 6 "count {D0}"')["ok"]
    assert tab.request("run", speed=0)["ok"]
    deadline = time.monotonic() + 20
    while tab.state["running"] or tab.state["scan"] == 0:
        assert time.monotonic() < deadline
        tab.recv("state")
    st = tab.state
    assert "condition #1 (D0 >= 50) holds" in st["stop"] and st["values"]["D0"] == "50"
    # the logpoint's lines while running: sent to the tabs with the states, in order
    assert "\n".join(tab.outputs).split("\n") == [f"count {n}" for n in range(50)]
    tab.request("console", line="delete 1")
    tab.request("console", line="delete 2")
    assert tab.request("run", speed=1000)["ok"] and tab.state["running"]
    time.sleep(0.2)
    assert tab.request("pause")["ok"]
    st = tab.state
    assert not st["running"] and st["stop"].startswith("paused at scan") and st["scan"] > 50
    scan = st["scan"]
    time.sleep(0.15)
    assert tab.request("state")["ok"] and tab.state["scan"] == scan  # paused means stopped
    tab.close()


def get(url: str, host: str | None = None) -> tuple[int, str, str]:
    req = urllib.request.Request(url, headers={"Host": host} if host else {})
    try:
        with urllib.request.urlopen(req, timeout=10) as r:
            return r.status, r.headers.get("Content-Type"), r.read().decode()
    except urllib.error.HTTPError as e:
        return e.code, e.headers.get("Content-Type"), e.read().decode()


def test_page_and_the_loopback_checks(server):
    status, ctype, text = get(server.url)
    assert status == 200 and ctype == "text/html; charset=utf-8"
    assert text.count('<div class="rung"') == 3 and 'id="monitor"' in text and "new WebSocket" in text
    data = json.loads(text.split('<script type="application/json" id="monitor">')[1].split("</script>")[0])
    assert data["elements"]["0"] == {"kind": "contact", "bit": "X0", "values": []}
    assert data["elements"][str(COUNT)] == {"kind": "box", "bit": None, "values": ["D0"]}  # ADD D0 K1 D0: once
    assert get(server.url + "nothing")[0] == 404
    assert get(server.url, host=f"attacker.example:{server.port}")[0] == 403  # DNS rebinding
    with pytest.raises(InvalidStatus):  # another site's page may not drive the debugger
        with connect(server.url.replace("http://", "ws://") + "ws", origin="http://attacker.example",
                     open_timeout=10):
            pass
    tab = Tab(server, origin=f"http://localhost:{server.port}")
    assert tab.request("state")["ok"]
    tab.close()


def test_the_command_line_serves_until_interrupted(program):
    p = subprocess.Popen([*MLC_COMMAND, "debug", str(program), "--web"], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    timer = threading.Timer(60, p.kill)
    timer.start()
    try:
        line = p.stdout.readline()
        assert line.startswith("mlc debug: ladder monitor on http://127.0.0.1:"), line + p.stderr.read()
        url = line.split(" on ", 1)[1].split()[0]
        assert get(url)[0] == 200
        p.send_signal(signal.SIGINT)
        assert p.wait(30) == 0
    finally:
        timer.cancel()
        if p.poll() is None:
            p.kill()


def test_command_line_errors(program):
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        r = subprocess.run([*MLC_COMMAND, "debug", str(program), "--web", "--port", str(port)],
                           capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and f"cannot serve on 127.0.0.1:{port}" in r.stderr
    r = subprocess.run([*MLC_COMMAND, "debug", str(program), "--port", "8080"], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 2 and "--port is the --web monitor's port" in r.stderr
    r = subprocess.run([*MLC_COMMAND, "debug", "--dap", "--web"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "give one" in r.stderr


# -- hostile messages, straight to the request handler (no sockets) --------------------------

JSONISH = st.recursive(st.none() | st.booleans() | st.integers(-10**30, 10**30) | st.floats() | st.text(max_size=20),
                       lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=8), inner, max_size=3),
                       max_leaves=8)
ARG = st.one_of(JSONISH, st.sampled_from(["X0", "Y0", "D0", "T0:w", "K4M0", "Q9", "X0:f", "1", "K1e9", "H1G", ""]),
                st.integers(-3, 40))
LINES = st.sampled_from(["print D0", "break if D0 >", "watch Y0", "delete 1", "log 6 \"{D0\"", "back",
                         "goto 3", "rung", "diff 0 2", "save x.stim", "quit", "write D0=7", "step 2", "help", "",
                         "goto ²", "diff 0 99999999", "goto 99999999"])
MESSAGE = st.one_of(
    st.text(max_size=40),
    JSONISH.map(json.dumps),
    st.fixed_dictionaries({"cmd": st.sampled_from(COMMANDS + ("nope",))},
                          optional={"id": JSONISH, "device": ARG, "value": ARG, "scan": ARG,
                                    "speed": st.one_of(st.just(0), ARG), "line": st.one_of(LINES, ARG)}).map(json.dumps),
)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(messages=st.lists(MESSAGE, min_size=1, max_size=8))
def test_any_message_gets_a_reply_or_an_error_never_an_internal_one(program, messages):
    monitor = Monitor(load_session([str(program)], None, load_target("nc5")))
    done = threading.Event()

    def pause_every_half_second():  # a `goto 99999999` among the messages: Pause ends it
        while not done.wait(0.5):
            monitor.interrupt()

    threading.Thread(target=pause_every_half_second, daemon=True).start()
    try:
        for text in messages:
            reply, _ = monitor.handle_text(text)
            assert reply["type"] in ("reply", "error"), reply
            assert "internal error" not in reply.get("message", ""), (text, reply)
            json.dumps(monitor.state(), allow_nan=False)  # the state stays sendable
        monitor.pause()
        assert monitor.handle_text('{"cmd": "state"}')[0]["ok"]
    finally:
        done.set()
        monitor.close()


@pytest.mark.parametrize("line", ["step 99999999", "next 99999999", "run #99999999", "run 100000s"])
def test_a_huge_console_move_is_paused_by_another_tab(server, line):
    """A console move runs in batches that let the other tabs in: a Pause from a second
    connection ends it within a second, where it got to (the server never hangs)."""
    tab, other = Tab(server), Tab(server)
    tab.request("toggle", device="X0")
    tab.next_id += 1
    tab.ws.send(json.dumps({"id": tab.next_id, "cmd": "console", "line": line}))
    deadline = time.monotonic() + 10
    while tab.state["scan"] < 3:  # the move is under way: its progress reaches every tab
        assert time.monotonic() < deadline
        tab.recv("state")
    started = time.monotonic()
    assert other.request("pause")["ok"]
    reply = tab.reply(tab.next_id)
    assert time.monotonic() - started < 1.0
    assert reply["ok"] and reply["text"].startswith("interrupted at scan "), reply
    st = other.request("state") and other.state
    assert st["stop"].startswith("interrupted at scan ") and not st["running"]
    scan = st["scan"]
    assert int(st["values"]["D0"]) == scan or "step" in line  # a consistent machine: D0 counts the scans
    assert other.request("console", line="step")["ok"] and other.state["scan"] in (scan, scan + 1)
    # a move button from any tab ends a console move too (no two moves interleave); a logpoint
    # hit every scan of it: the reply keeps its first and last lines, the stop last
    assert other.request("console", line='log 6 "count {D0}"')["ok"]
    tab.next_id += 1
    tab.ws.send(json.dumps({"id": tab.next_id, "cmd": "console", "line": "scan 99999999"}))
    while tab.state["scan"] < scan + 2500:
        tab.recv("state")
    assert other.request("back")["ok"]
    lines = tab.reply(tab.next_id)["text"].split("\n")
    assert len(lines) == 2000 + 1 + 10 and lines[-1].startswith("interrupted at scan ")
    assert lines[0].startswith("count ") and lines[2000].endswith("more lines not shown)")
    tab.close()
    other.close()


# -- slow, silent and odd clients (#30.14, #30.18) ------------------------------------------------

class StuckConnection:
    """A tab's connection whose send never returns until its socket is shut down (a browser
    tab that stopped reading, its TCP window full)."""

    def __init__(self):
        self.released = threading.Event()
        self.sent = 0
        self.socket = self

    def send(self, text: str) -> None:
        self.sent += 1
        self.released.wait()
        raise OSError("connection cut")

    def shutdown(self, how) -> None:
        self.released.set()


class Recorder:
    def __init__(self):
        self.messages: list[dict] = []
        self.socket = None

    def send(self, text: str) -> None:
        self.messages.append(json.loads(text))


def test_a_tab_that_never_reads_stalls_no_other_and_is_let_go(program):
    """#30.14: every send went out on the caller's thread, so one tab that stopped reading held
    every broadcast (and the runner, and the other tabs' replies) once its socket was full."""
    monitor = Monitor(load_session([str(program)], None, load_target("nc5")))
    stuck, fine = StuckConnection(), Recorder()
    monitor.add_client(stuck)
    monitor.add_client(fine)
    rounds = MAX_QUEUE // 2 - 8  # messages to each tab: fewer than a queue holds
    try:
        done = threading.Event()

        def publish_many():
            for n in range(rounds):
                monitor.broadcast({"type": "output", "text": str(n)})  # not coalesced: each one queued
                monitor.publish()
            done.set()

        threading.Thread(target=publish_many, daemon=True).start()
        assert done.wait(10), "a tab that never reads held the broadcasts"
        deadline = time.monotonic() + 10
        while len(fine.messages) < 2 * rounds and time.monotonic() < deadline:
            time.sleep(0.01)
        assert [m["type"] for m in fine.messages] == ["output", "state"] * rounds  # all of them, in order
        assert [m["text"] for m in fine.messages[::2]] == [str(n) for n in range(rounds)]
        while stuck.sent < 1 and time.monotonic() < deadline:  # its sender thread is in its first send
            time.sleep(0.01)
        assert not stuck.released.is_set() and stuck in monitor.clients
        for _ in range(MAX_QUEUE):  # its queue fills: cut off
            monitor.send(stuck, {"type": "output", "text": "x"})
        assert stuck.released.is_set() and stuck.sent == 1
        while stuck in monitor.clients and time.monotonic() < deadline:
            time.sleep(0.01)
        assert stuck not in monitor.clients and fine in monitor.clients
    finally:
        monitor.close()


def test_queued_states_are_replaced_by_newer_ones(program):
    monitor = Monitor(load_session([str(program)], None, load_target("nc5")))
    stuck = StuckConnection()
    monitor.add_client(stuck)
    try:
        for _ in range(MAX_QUEUE * 4):  # a running machine's states: only the newest waits
            monitor.publish()
        time.sleep(0.05)
        assert not stuck.released.is_set() and len(monitor.clients[stuck].queue) == 1
    finally:
        monitor.close()


def raw_http(port: int, request: bytes) -> bytes:
    with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
        s.sendall(request)
        data = b""
        while chunk := s.recv(65536):
            data += chunk
        return data


@pytest.fixture
def web_log():
    """The monitor server's log lines (its websockets library's), as they would be printed."""
    import logging

    from mlctool.debug import web

    log = web._quiet_logger()
    lines: list[str] = []
    handler = logging.Handler(logging.ERROR)
    handler.emit = lambda record: lines.append(log.handlers[0].format(record))
    log.addHandler(handler)
    yield lines
    log.removeHandler(handler)


def test_two_host_or_origin_headers_get_a_400(server, web_log):
    """#30.18: two Host headers gave HTTP 500 and a traceback (refused, but not cleanly)."""
    host = f"127.0.0.1:{server.port}".encode()
    reply = raw_http(server.port, b"GET / HTTP/1.1\r\nHost: " + host + b"\r\nHost: evil.example\r\n\r\n")
    assert reply.startswith(b"HTTP/1.1 400 "), reply[:100]
    reply = raw_http(server.port, b"GET /ws HTTP/1.1\r\nHost: " + host + b"\r\nOrigin: http://" + host
                     + b"\r\nOrigin: http://evil.example\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                       b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n")
    assert reply.startswith(b"HTTP/1.1 400 "), reply[:100]
    assert get(server.url)[0] == 200 and web_log == []


def test_a_silent_tab_is_let_go_without_a_traceback(program, web_log):
    """#30.14: a traceback was printed when keepalive closed a tab that never read; now the tab
    is let go (its send stalled, or keepalive) with at most one line, the other tab runs on."""
    session = load_session([str(program)], None, load_target("nc5"))
    srv = WebServer(Monitor(session), 0, keepalive_s=0.3)
    srv.start()
    try:
        host = f"127.0.0.1:{srv.port}".encode()
        silent = socket.create_connection(("127.0.0.1", srv.port), timeout=10)  # upgrades, never reads
        silent.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        silent.sendall(b"GET /ws HTTP/1.1\r\nHost: " + host + b"\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                       b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n")
        tab = Tab(srv)
        tab.request("toggle", device="X0")
        assert tab.request("run", speed=0)["ok"]
        deadline = time.monotonic() + 1.5  # the silent tab is let go meanwhile; the other runs on
        while time.monotonic() < deadline:
            tab.recv("state")
        assert tab.request("pause")["ok"] and tab.state["scan"] > 100
        assert len(srv.monitor.clients) == 1
        silent.close()
        tab.close()
    finally:
        srv.shutdown()
    assert not [line for line in web_log if "Traceback" in line or "\n" in line], web_log


def test_pause_from_the_tab_whose_move_runs(server):
    """The tab's own Pause reached its move only after the move ended (one request at a time
    per connection): now the connection reads on while its request runs."""
    tab = Tab(server)
    tab.request("toggle", device="X0")
    for request in ({"cmd": "console", "line": "goto 100000000"}, {"cmd": "console", "line": "diff 0 99999999"},
                    {"cmd": "goto", "scan": 999999999}):
        tab.next_id += 1
        move = tab.next_id
        tab.ws.send(json.dumps({"id": move, **request}))
        time.sleep(0.3)
        started = time.monotonic()
        tab.next_id += 1
        tab.ws.send(json.dumps({"id": tab.next_id, "cmd": "pause"}))
        reply = tab.reply(move)
        assert time.monotonic() - started < 1.0 and reply["text"].startswith("interrupted"), reply
        assert tab.reply(tab.next_id)["ok"]
    assert tab.request("console", line="print X0")["text"] == "X0 = 1 (forced)"  # the session goes on
    tab.close()
