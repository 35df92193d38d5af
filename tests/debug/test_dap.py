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
    for line in ("step 99999999", "run #100001", "run 100000s", "goto 99999999"):  # pause is not read meanwhile
        out = client.request("evaluate", expression=line, context="repl")["result"]
        assert out == "error: at most 100000 at a time here (nothing can interrupt a move)", (line, out)
        client.event("stopped")

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
    """The same client over TCP: `mlc debug --dap-port N` in a subprocess."""

    def __init__(self):
        for _ in range(3):  # the free port may be taken in between: try another
            self.port = free_port()
            self.p = subprocess.Popen([*MLC_COMMAND, "debug", "--dap-port", str(self.port)],
                                      stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, cwd=CWD)
            self.timer = threading.Timer(60, self.p.kill)
            self.timer.start()
            line = self.p.stderr.readline().decode()
            if line.startswith(f"mlc debug: DAP on 127.0.0.1:{self.port}"):
                break
            self.timer.cancel()
            self.p.wait(30)
        else:
            pytest.fail(f"the DAP server did not start: {line}")
        self.sock = socket.create_connection(("127.0.0.1", self.port), timeout=30)
        self.r, self.w = self.sock.makefile("rb"), self.sock.makefile("wb")
        self.seq = 0
        self.seen = []

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
        c.event("initialized")
        c.request("launch", program="conveyor.il", stimulus="conveyor.stim", stopOnEntry=True)
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
