"""`mlc debug --dap`: a DAP client speaking the protocol over stdio to a subprocess
(initialize, setBreakpoints, launch, configurationDone, continue, stackTrace, scopes,
variables, stepIn, stepBack, reverseContinue, setVariable, evaluate, setDataBreakpoints,
disconnect); malformed frames get error responses and the server carries on."""

from __future__ import annotations

import io
import json
import socket
import subprocess
import threading
import time

import pytest

from mlctool.debug.dap import FrameError, read_frame, write_frame
from tests.conftest import MLC_COMMAND, SAMPLES

CWD = SAMPLES / "nc5"


class Client:
    def __init__(self):
        self.p = subprocess.Popen([*MLC_COMMAND, "debug", "--dap"], stdin=subprocess.PIPE,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=CWD)
        self.seq = 0
        self.seen: list[dict] = []
        self.timer = threading.Timer(60, self.p.kill)  # a hung server fails the test, not the suite
        self.timer.start()

    def send(self, command: str, **arguments) -> int:
        self.seq += 1
        write_frame(self.p.stdin, {"seq": self.seq, "type": "request", "command": command,
                                   "arguments": arguments})
        return self.seq

    def raw(self, data: bytes) -> None:
        self.p.stdin.write(data)
        self.p.stdin.flush()

    def next(self) -> dict:
        msg = read_frame(self.p.stdout)
        assert msg is not None, self.p.stderr.read().decode()
        self.seen.append(msg)
        return msg

    def response(self, seq: int) -> dict:
        while True:
            msg = self.next()
            if msg["type"] == "response" and msg["request_seq"] == seq:
                return msg

    def request(self, command: str, **arguments) -> dict:
        r = self.response(self.send(command, **arguments))
        assert r["success"], r
        return r.get("body", {})

    def event(self, name: str) -> dict:
        while True:
            msg = self.next()
            if msg["type"] == "event" and msg["event"] == name:
                return msg.get("body", {})

    def close(self) -> int:
        try:
            self.p.stdin.close()
            return self.p.wait(30)
        finally:
            self.timer.cancel()


@pytest.fixture
def client():
    c = Client()
    yield c
    if c.p.poll() is None:
        c.p.kill()
    c.timer.cancel()


def test_a_debugging_session_over_stdio(client):
    caps = client.request("initialize", adapterID="mlc", linesStartAt1=True)
    assert caps["supportsStepBack"] and caps["supportsConditionalBreakpoints"] and caps["supportsLogPoints"]
    client.event("initialized")
    bps = client.request("setBreakpoints", source={"path": str(CWD / "conveyor.il")},
                         breakpoints=[{"line": 22, "hitCondition": "2"}])["breakpoints"]
    assert bps[0]["verified"] is False  # before launch: set when the program is loaded
    client.request("launch", program="conveyor.il", stimulus="conveyor.stim", stopOnEntry=True)
    client.request("configurationDone")
    assert client.event("stopped")["reason"] == "entry"

    client.request("continue", threadId=1)
    stop = client.event("stopped")
    assert stop["reason"] == "breakpoint" and stop["hitBreakpointIds"] == [1]
    frame = client.request("stackTrace", threadId=1)["stackFrames"][0]
    assert frame["line"] == 22 and frame["source"]["path"].endswith("conveyor.il")
    assert frame["name"] == "scan 1, step 6: LDP SENSOR"

    scopes = client.request("scopes", frameId=1)["scopes"]
    names = [s["name"] for s in scopes]
    assert names == ["Inputs", "Outputs", "Relays", "Words", "Timers", "Counters", "Watched", "Symbols"]
    outputs = client.request("variables", variablesReference=scopes[1]["variablesReference"])["variables"]
    assert {"name": "Y0", "value": "1"}.items() <= outputs[0].items()
    timers = client.request("variables", variablesReference=scopes[4]["variablesReference"])["variables"]
    assert timers[0]["value"].startswith("contact Off, value 0") and "preset 10" in timers[0]["value"]
    symbols = client.request("variables", variablesReference=scopes[7]["variablesReference"])["variables"]
    assert {"MOTOR", "START"} <= {v["name"] for v in symbols}

    client.request("stepBack", threadId=1)
    client.event("stopped")
    frame = client.request("stackTrace", threadId=1)["stackFrames"][0]
    assert frame["line"] == 20  # OUT RUNNING, the instruction before
    client.request("stepIn", threadId=1)
    client.event("stopped")
    assert client.request("stackTrace", threadId=1)["stackFrames"][0]["line"] == 22

    assert client.request("evaluate", expression="M0 && !X1", context="watch")["result"] == "1"
    r = client.response(client.send("evaluate", expression="D0 >", context="hover"))
    assert not r["success"] and "ends too early" in r["message"]
    client.request("setDataBreakpoints", breakpoints=[{"dataId": "M0"}])
    client.request("setBreakpoints", source={"path": str(CWD / "conveyor.il")}, breakpoints=[])
    assert client.request("setVariable", variablesReference=1, name="STOP", value="1")["value"] == "1"
    client.request("continue", threadId=1)
    stop = client.event("stopped")
    assert stop["reason"] == "data breakpoint" and "M0 changed 1 -> 0" in stop["text"], stop
    out = client.request("evaluate", expression="print M0 X1", context="repl")["result"]
    assert out == "M0 = 0\nX1 = 1 (forced)"  # STOP forced On dropped the run latch

    client.request("reverseContinue", threadId=1)
    stop = client.event("stopped")  # back to the end of scan 0, where the latch came on
    assert stop["reason"] == "data breakpoint" and "M0 changed 0 -> 1 at scan 1 (t=10ms), before the scan" in stop["text"], stop
    client.request("disconnect")
    assert client.close() == 0


def test_malformed_frames_get_error_responses(client):
    client.raw(b"Content-Length: 5\r\n\r\nnope!")
    r = client.next()
    assert r["type"] == "response" and not r["success"] and "not JSON" in r["message"]
    client.raw(b"garbage\r\n\r\n")
    r = client.next()
    assert not r["success"] and "not a header line" in r["message"]
    client.raw(b"Content-Length: 2\r\n\r\n[]")
    assert "not a JSON object" in client.next()["message"]
    r = client.response(client.send("frobnicate"))
    assert not r["success"] and "unsupported" in r["message"]
    r = client.response(client.send("continue"))
    assert not r["success"] and "launch" in r["message"]
    r = client.response(client.send("launch", program="missing.il"))
    assert not r["success"] and "missing.il" in r["message"]
    client.request("initialize", adapterID="mlc")  # still serving
    client.request("disconnect")
    assert client.close() == 0


def test_pause_ends_a_long_move_and_the_server_goes_on(client):
    """#30.10: `goto`, `diff 0 99999999` in the debug console and `continue` ran to their end
    while no request was read (the console's counts were capped at 100000 instead); now the
    requests are read meanwhile and `pause` ends the move within a second, where it got to."""
    client.request("initialize", adapterID="mlc")
    client.request("launch", program="conveyor.il", stimulus="conveyor.stim", stopOnEntry=True)
    client.request("configurationDone")
    client.event("stopped")
    for line, said in (("goto 99999999", "interrupted at scan "),
                       ("diff 0 99999999", "interrupted: diff 0 99999999 did not finish; still at scan "),
                       ("step 99999999", "interrupted at scan ")):
        seq = client.send("evaluate", expression=line, context="repl")
        client.event("continued")  # the editor shows the thread running: its Pause is enabled
        time.sleep(0.3)
        started = time.monotonic()
        pause = client.send("pause", threadId=1)
        out = client.response(seq)["body"]["result"]
        assert time.monotonic() - started < 1.0 and out.startswith(said), (line, out)
        assert client.event("stopped")["reason"] == "step"
        assert client.response(pause)["success"]  # and no second stopped event for it
    where = client.request("stackTrace", threadId=1)["stackFrames"][0]["name"]
    client.request("evaluate", expression="goto 1500", context="repl")  # past the stimulus's end
    client.event("stopped")
    client.request("continue", threadId=1)  # nothing fires: up to 100000 scans
    time.sleep(0.3)
    pause = client.send("pause", threadId=1)
    stop = client.event("stopped")
    assert stop["reason"] == "pause" and stop["text"].startswith("interrupted at scan "), stop
    assert client.response(pause)["success"]
    assert where.startswith("scan ")
    client.request("disconnect")
    assert client.close() == 0


def test_a_frame_nested_too_deeply_or_with_a_huge_number_gets_an_error_response(client):
    """#30.11: `"[" * 200000` ended the server (RecursionError, exit 2)."""
    for body in (b"[" * 200000, b'{"seq": ' + b"7" * 5000 + b"}", b'{"a": ' * 5000 + b"1" + b"}" * 5000):
        client.raw(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        r = client.next()
        assert r["type"] == "response" and not r["success"] and "malformed frame" in r["message"], r
    assert client.request("initialize", adapterID="mlc")["supportsStepBack"]  # still serving
    client.request("disconnect")
    assert client.close() == 0


def test_frame_reader_limits():
    with pytest.raises(FrameError):
        read_frame(io.BytesIO(b"Content-Length: 99999999999\r\n\r\n"))
    with pytest.raises(FrameError):
        read_frame(io.BytesIO(b"Content-Length: 10\r\n\r\n{}"))
    assert read_frame(io.BytesIO(b"")) is None
    buf = io.BytesIO()
    write_frame(buf, {"a": "é"})
    assert read_frame(io.BytesIO(buf.getvalue())) == {"a": "é"}
    assert json.loads(buf.getvalue().split(b"\r\n\r\n", 1)[1]) == {"a": "é"}


def test_launch_without_program_debugs_the_project():
    """The editor extension's default configuration names only a stimulus: the program is
    the project's (mlc.toml `sources`)."""
    c = Client()
    try:
        project = SAMPLES / "project"
        c.request("initialize", adapterID="mlc")
        c.request("launch", cwd=str(project), stimulus="tests/pick_cycle.stim")
        c.request("configurationDone")
        assert c.event("stopped")["reason"] == "entry"
        frame = c.request("stackTrace", threadId=1)["stackFrames"][0]
        assert frame["source"]["path"] == str(project / "src" / "conveyor.il")
        c.request("disconnect")
        assert c.close() == 0
    finally:
        if c.p.poll() is None:
            c.p.kill()
        c.timer.cancel()


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class PortClient(Client):
    """The same client over TCP: `mlc debug --dap-port N` in a subprocess; `token` is the one
    it printed."""

    def __init__(self, cwd=CWD):
        for _ in range(3):  # the free port may be taken in between: try another
            self.port = free_port()
            self.p = subprocess.Popen([*MLC_COMMAND, "debug", "--dap-port", str(self.port)],
                                      stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, cwd=cwd)
            self.timer = threading.Timer(60, self.p.kill)
            self.timer.start()
            line = self.p.stderr.readline().decode()
            if line.startswith(f"mlc debug: DAP on 127.0.0.1:{self.port}, token "):
                break
            self.timer.cancel()
            self.p.wait(30)
        else:
            pytest.fail(f"the DAP server did not start: {line}")
        self.token = line.split(", token ", 1)[1].split()[0]
        self.connect()

    def connect(self) -> None:
        self.sock = socket.create_connection(("127.0.0.1", self.port), timeout=30)
        self.r, self.w = self.sock.makefile("rb"), self.sock.makefile("wb")
        self.seq = 0
        self.seen = []

    def closed_by_server(self) -> bool:
        """Read on to the end: True when the server closed the connection (no frame is pending)."""
        try:
            while read_frame(self.r) is not None:
                pass
        except (FrameError, OSError):
            pass
        return True

    def send(self, command: str, **arguments) -> int:
        self.seq += 1
        write_frame(self.w, {"seq": self.seq, "type": "request", "command": command, "arguments": arguments})
        return self.seq

    def next(self) -> dict:
        msg = read_frame(self.r)
        assert msg is not None, "the server closed the connection"
        self.seen.append(msg)
        return msg

    def close(self) -> int:
        try:
            self.r.close()
            self.w.close()
            self.sock.close()
            return self.p.wait(30)
        finally:
            self.timer.cancel()


def test_a_debugging_session_over_a_tcp_port():
    c = PortClient()
    try:
        assert c.request("initialize", adapterID="mlc")["supportsStepBack"]
        c.request("launch", program="conveyor.il", stimulus="conveyor.stim", stopOnEntry=True, token=c.token)
        events = [m["event"] for m in c.seen if m["type"] == "event"]
        assert events == ["initialized"]  # on a port: once the launch gave the token, not before
        bps = c.request("setBreakpoints", source={"path": str(CWD / "conveyor.il")},
                        breakpoints=[{"line": 22}])["breakpoints"]
        assert bps == [{"id": 1, "verified": True, "line": 22}]
        c.request("configurationDone")
        assert c.event("stopped")["reason"] == "entry"
        c.request("continue", threadId=1)
        stop = c.event("stopped")
        assert stop["reason"] == "breakpoint" and stop["hitBreakpointIds"] == [1]
        assert c.request("stackTrace", threadId=1)["stackFrames"][0]["name"] == "scan 0, step 6: LDP SENSOR"
        c.request("disconnect")
        assert c.close() == 0  # one client: the server ends with it
    finally:
        if c.p.poll() is None:
            c.p.kill()
        c.timer.cancel()


def test_the_port_refuses_an_http_post_and_clients_without_the_token(tmp_path):
    """#30.1: a web page's `fetch(POST)` to the port had its body's DAP frames executed (a
    `save` could write ~/.bashrc), and any local client could drive the debugger. Now an HTTP
    request line closes the connection with nothing read further, and every request but
    initialize waits for a launch with the printed token: nothing is written, nothing runs."""
    (tmp_path / "p.il").write_text("LD X0\nOUT Y0\nEND\n")
    frames = io.BytesIO()
    for seq, (command, args) in enumerate([
            ("initialize", {"adapterID": "x"}),
            ("launch", {"program": "p.il", "cwd": str(tmp_path), "stopOnEntry": True}),
            ("evaluate", {"expression": "save pwned.stim", "context": "repl"})], 1):
        write_frame(frames, {"seq": seq, "type": "request", "command": command, "arguments": args})
    body = frames.getvalue()
    c = PortClient(cwd=tmp_path)
    try:
        c.sock.sendall(b"POST / HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nContent-Type: text/plain;charset=UTF-8\r\n"
                       b"Origin: http://attacker.example\r\nContent-Length: %d\r\n\r\n" % (c.port, len(body)) + body)
        try:  # the refusal, unless the close with the body unread reset the connection first
            r = read_frame(c.r)
        except ConnectionResetError:
            r = None
        assert r is None or (not r["success"] and r["message"].startswith("refused: not DAP")), r
        assert c.closed_by_server()
        c.connect()  # a DAP client without the token: initialize answers, launch closes
        assert c.request("initialize", adapterID="x")["supportsStepBack"]
        r = c.response(c.send("launch", program="p.il", cwd=str(tmp_path)))
        assert not r["success"] and "token" in r["message"]
        assert c.closed_by_server()
        for first in (("launch", {"program": "p.il", "cwd": str(tmp_path), "token": "guess"}),
                      ("evaluate", {"expression": "save pwned.stim", "context": "repl"}),
                      ("setBreakpoints", {"source": {"path": "p.il"}, "breakpoints": []})):
            c.connect()
            r = c.response(c.send(first[0], **first[1]))
            assert not r["success"] and r["message"].startswith("refused"), r
            assert c.closed_by_server()
        assert not (tmp_path / "pwned.stim").exists()
        c.connect()  # the token's holder: served, and its `save` stays in the session's folder
        c.request("initialize", adapterID="x")
        c.request("launch", program="p.il", cwd=str(tmp_path), token=c.token)
        c.request("configurationDone")
        c.event("stopped")
        out = c.request("evaluate", expression="save ../escape.stim", context="repl")["result"]
        assert out.startswith("error: save: ../escape.stim is outside"), out
        out = c.request("evaluate", expression="save p.il", context="repl")["result"]
        assert out.startswith("error: E606: save ") and "is the input" in out, out
        assert c.request("evaluate", expression="save t.stim", context="repl")["result"] == "wrote t.stim"
        c.request("disconnect")
        assert c.close() == 0
        assert not (tmp_path.parent / "escape.stim").exists() and (tmp_path / "p.il").read_text().startswith("LD X0")
        assert (tmp_path / "t.stim").read_text().startswith("# written by mlc debug")
        assert "Traceback" not in c.p.stderr.read().decode()
    finally:
        if c.p.poll() is None:
            c.p.kill()
        c.timer.cancel()


def test_a_taken_port_exits_2_with_e609():
    """#30.9: `--dap-port P` with P taken gave a traceback (exit 3)."""
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        r = subprocess.run([*MLC_COMMAND, "debug", "--dap-port", str(port)], capture_output=True, text=True,
                           timeout=60)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    assert f"error[E609]: cannot serve on 127.0.0.1:{port}: " in r.stderr, r.stderr


def test_a_connection_that_does_not_launch_in_time_is_closed(monkeypatch):
    """A client that connects and says nothing would hold the one-client port forever: it is
    closed after AUTH_TIMEOUT_S, and the next client (with the token) is served."""
    from mlctool.debug import dap

    monkeypatch.setattr(dap, "AUTH_TIMEOUT_S", 0.3)
    srv = dap.listen(0)
    port = srv.getsockname()[1]
    server = threading.Thread(target=dap.serve_port, args=(srv, "t" * 20, {}), daemon=True)
    server.start()
    with socket.create_connection(("127.0.0.1", port), timeout=10) as silent:
        started = time.monotonic()
        assert silent.recv(100) == b"" and time.monotonic() - started < 5  # closed by the server
    with socket.create_connection(("127.0.0.1", port), timeout=10) as s, s.makefile("rb") as r, \
            s.makefile("wb") as w:
        write_frame(w, {"seq": 1, "type": "request", "command": "launch",
                        "arguments": {"program": str(CWD / "conveyor.il"), "token": "t" * 20}})
        msgs = [read_frame(r), read_frame(r)]
        assert [m.get("event") or m["command"] for m in msgs] == ["initialized", "launch"] and msgs[1]["success"]
        write_frame(w, {"seq": 2, "type": "request", "command": "disconnect"})
        assert read_frame(r)["command"] == "disconnect"
    server.join(10)
    assert not server.is_alive()  # the launched session ended: so did the server
