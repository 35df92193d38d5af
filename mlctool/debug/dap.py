"""`mlc debug --dap`: the Debug Adapter Protocol over a DebugSession (docs/debug.md).

The framing is DAP's own: `Content-Length: N` header lines, a blank line, N bytes of JSON.
One thread (the PLC), one frame (the instruction about to execute); stepIn = one instruction,
next = one scan, stepBack / reverseContinue travel back in time. A frame that cannot be read
(no length, bad JSON, nested too deeply, not an object) gets an error response; a failing
request gets an error response with the message; the server never ends on them.

Requests are read by a thread of their own while the main thread executes them one at a
time, so a `pause` (or the client leaving) reaches a long move (continue, goto, a console
`step 99999999`): the session's poll hook sees it between two scans and the move ends there.

On a TCP port (`--dap-port`) anything on the machine can connect, a web page in a browser
too (a `fetch` POST carries DAP frames in its body). So there the server refuses what is not
DAP: a line that is not a header (an HTTP request line) closes the connection with nothing
read further, and every request but `initialize` and `disconnect` waits for a `launch` that
carries the session's token (generated at start and printed, or MLC_DAP_TOKEN); a launch
without it, or any other request first, closes the connection. docs/reliability.md, Threat
model.
"""

from __future__ import annotations

import hmac
import io
import json
import os
import queue
import secrets
import socket
import sys
import threading
from pathlib import Path
from typing import BinaryIO

from mlctool.debug.session import BOUNDARY, DebugError, DebugSession, Interrupted, Stop
from mlctool.limits import MAX_DIGITS
from mlctool.sim.stimulus.stimulus import StimError
from mlctool.targetapi.signals import device_signal

THREAD = 1
MAX_FRAME = 16 * 1024 * 1024
MAX_HEADER_LINES = 32
TOKEN_ENV = "MLC_DAP_TOKEN"
MIN_TOKEN = 16  # characters of a token given in MLC_DAP_TOKEN
AUTH_TIMEOUT_S = 30  # a connection that has not launched with the token by then is closed
CONSOLE_MOVES = ("step", "scan", "next", "run", "continue", "back", "reverse-continue", "goto", "diff")
SCOPES = ("Inputs", "Outputs", "Relays", "Words", "Timers", "Counters", "Watched", "Symbols")
_STOP_REASONS = {"breakpoint": "breakpoint", "watch": "data breakpoint", "condition": "breakpoint",
                 "step": "step", "entry": "entry", "fault": "exception", "goto": "goto",
                 "end": "pause", "pause": "pause"}


class FrameError(ValueError):
    """A frame that cannot be read. `framing`: not even DAP's framing (a header that is not
    one: an HTTP request line, say), as opposed to a well-framed body that is bad JSON."""

    def __init__(self, message: str, framing: bool = True):
        super().__init__(message)
        self.framing = framing


def read_frame(stream: BinaryIO) -> dict | None:
    """One message; None at the end of the stream; FrameError for a frame that is not DAP."""
    length = None
    lines = 0
    while True:
        line = stream.readline(65536)
        if not line:
            if lines:
                raise FrameError("the stream ended inside a header")
            return None
        lines += 1
        text = line.decode("ascii", "replace").strip()
        if not text:
            if length is None:
                raise FrameError("a frame without a Content-Length header")
            break
        name, colon, value = text.partition(":")
        if not colon or " " in name.strip():
            _skip_header(stream)
            raise FrameError(f"not a header line: {text[:60]!r}")
        if lines > MAX_HEADER_LINES:
            _skip_header(stream)
            raise FrameError(f"more than {MAX_HEADER_LINES} header lines")
        if name.strip().lower() == "content-length":
            value = value.strip()
            if not (value.isascii() and value.isdigit()) or len(value) > MAX_DIGITS or int(value) > MAX_FRAME:
                raise FrameError(f"bad Content-Length {value[:20]!r}")
            length = int(value)
    body = stream.read(length)
    if len(body) < length:
        raise FrameError("the stream ended inside a frame")
    try:
        msg = json.loads(body.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise FrameError(f"the frame is not JSON: {e}", framing=False) from None
    except RecursionError:  # "[" * 200000: the parser's depth bound (the recursion limit)
        raise FrameError("the frame's JSON nests too deeply", framing=False) from None
    except ValueError as e:  # an integer of more than 4300 digits
        raise FrameError(f"the frame's JSON cannot be read: {str(e)[:80]}", framing=False) from None
    if not isinstance(msg, dict):
        raise FrameError("the frame is not a JSON object", framing=False)
    return msg


def _skip_header(stream: BinaryIO) -> None:
    """After a bad header line: drop the rest of that header, up to its blank line."""
    while True:
        line = stream.readline(65536)
        if not line or not line.strip():
            return


def write_frame(stream: BinaryIO, msg: dict) -> None:
    body = json.dumps(msg, separators=(",", ":")).encode("utf-8")
    stream.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
    stream.flush()


class RequestError(Exception):
    pass


class Refused(Exception):
    """The connection is closed: it is not DAP, or not the token's holder (TCP port only)."""


class DapServer:
    def __init__(self, reader: BinaryIO, writer: BinaryIO, defaults: dict | None = None,
                 token: str | None = None):
        self.reader, self.writer = reader, writer
        self.defaults = defaults or {}
        # on a TCP port: the session's token, which the launch request must carry
        self.token = token
        self.authenticated = token is None
        self.seq = 0
        self.session: DebugSession | None = None
        self.pending: dict[str, list[dict]] = {}  # setBreakpoints before launch: path -> breakpoints
        self.pending_data: list[dict] = []
        self.stop_on_entry = True
        self.running = True
        self.lines_of: dict[str, str] = {}
        self.inbox: queue.Queue = queue.Queue()  # ("msg", dict) | ("bad", FrameError) | ("end", None)
        # pause requests read (by the reader thread) and handled (by the main thread): a move
        # in progress ends at its next poll while a pause is pending, or the client has gone
        self.pauses_read = 0
        self.pauses_handled = 0
        self.leaving = False
        self.pause_ended_a_move = False

    # -- transport ---------------------------------------------------------------------
    def send(self, msg: dict) -> None:
        self.seq += 1
        msg["seq"] = self.seq
        write_frame(self.writer, msg)

    def event(self, name: str, body: dict | None = None) -> None:
        self.send({"type": "event", "event": name, **({"body": body} if body is not None else {})})

    def respond(self, req: dict, body: dict | None = None, error: str | None = None) -> None:
        msg = {"type": "response", "request_seq": req.get("seq", 0) if isinstance(req.get("seq"), int) else 0,
               "command": str(req.get("command", "")), "success": error is None}
        if error is not None:
            msg["message"] = error
            msg["body"] = {"error": {"id": 1, "format": error, "showUser": True}}
        elif body is not None:
            msg["body"] = body
        self.send(msg)

    def output(self, text: str, category: str = "console") -> None:
        self.event("output", {"category": category, "output": text + "\n"})

    def serve(self) -> None:
        """Until disconnect or the end of the stream; Refused (TCP port) when the client is
        not let in."""
        threading.Thread(target=self._read, name="mlc-dap-reader", daemon=True).start()
        while self.running:
            kind, item = self.inbox.get()
            if kind == "end":
                break
            if kind == "bad":
                if self.token is not None and (item.framing or not self.authenticated):
                    self.respond({"seq": 0, "command": "unknown"}, error=f"refused: not DAP ({item})")
                    raise Refused(str(item))
                self.respond({"seq": 0, "command": "unknown"}, error=f"malformed frame: {item}")
                continue
            self.handle(item)

    def _read(self) -> None:
        """The reader thread: every frame into the inbox; pauses counted as they arrive."""
        try:
            while True:
                try:
                    msg = read_frame(self.reader)
                except FrameError as e:
                    self.inbox.put(("bad", e))
                    if self.token is not None and (e.framing or not self.authenticated):
                        break  # not read further: the main thread closes the connection
                    continue
                if msg is None:
                    break
                if msg.get("type") == "request" and msg.get("command") == "pause":
                    self.pauses_read += 1
                elif msg.get("type") == "request" and msg.get("command") == "disconnect":
                    self.leaving = True
                self.inbox.put(("msg", msg))
        except (OSError, ValueError):  # the connection reset, or closed under the reader
            pass
        self.leaving = True
        self.inbox.put(("end", None))

    def _poll(self) -> None:
        """The session's poll hook: a pending pause, or the client gone, ends the move."""
        if self.pauses_read > self.pauses_handled or self.leaving:
            self.pause_ended_a_move = self.pauses_read > self.pauses_handled
            raise Interrupted

    def handle(self, msg: dict) -> None:
        if msg.get("type") != "request" or not isinstance(msg.get("command"), str):
            if not self.authenticated:
                raise Refused("not a request")
            self.respond(msg, error="expected a request with a command")
            return
        if not self.authenticated and msg["command"] not in ("initialize", "launch", "disconnect"):
            self.respond(msg, error=f"refused: `{msg['command'][:40]}` before a launch with the session's token")
            raise Refused("no token")
        fn = getattr(self, "on_" + msg["command"], None)
        if fn is None:
            self.respond(msg, error=f"unsupported request {msg['command']!r}")
            return
        args = msg.get("arguments") or {}
        if not isinstance(args, dict):
            self.respond(msg, error="arguments must be an object")
            return
        try:
            fn(msg, args)
        except Refused:
            raise
        except (RequestError, DebugError, StimError) as e:
            self.respond(msg, error=getattr(e, "message", None) or str(e))
        except Exception as e:  # a bug: an error response, not a dead debugger
            self.respond(msg, error=f"internal error: {type(e).__name__}: {e}")

    def need(self) -> DebugSession:
        if self.session is None:
            raise RequestError("no program: send launch first")
        return self.session

    # -- lifecycle ----------------------------------------------------------------------
    def on_initialize(self, req, args) -> None:
        self.respond(req, {
            "supportsConfigurationDoneRequest": True, "supportsConditionalBreakpoints": True,
            "supportsHitConditionalBreakpoints": True, "supportsLogPoints": True,
            "supportsDataBreakpoints": True, "supportsStepBack": True, "supportsSetVariable": True,
            "supportsEvaluateForHovers": True, "supportsTerminateRequest": True,
            "supportsGotoTargetsRequest": False, "supportsRestartRequest": False,
        })
        if self.authenticated:  # else after the launch that carries the token
            self.event("initialized")

    def on_launch(self, req, args) -> None:
        from mlctool.config import load_config
        from mlctool.debug.load import LoadError, load_session
        from mlctool.targets import load_target

        if not self.authenticated:
            given = args.get("token")
            if not isinstance(given, str) or not hmac.compare_digest(given.encode(), self.token.encode()):
                self.respond(req, error="refused: this server needs the session's token (launch argument "
                                        "`token`, printed when `mlc debug --dap-port` started)")
                raise Refused("a launch without the token")
            self.authenticated = True
            self.event("initialized")
        program = args.get("program")
        if isinstance(program, str):
            program = [program]
        cwd = args.get("cwd") if isinstance(args.get("cwd"), str) else os.getcwd()
        config = self.defaults.get("config")
        if config is None or (not program and config.root is None):
            try:
                config = load_config(Path(cwd))
            except Exception:  # noqa: BLE001 - an unreadable mlc.toml: defaults
                config = None
        if not program and config is not None and config.root is not None:
            # no program: the project's sources (mlc.toml `sources`), as the editor extension asks
            program = [str(config.root / p) for p in config.data.get("sources") or []]
        if not program or not all(isinstance(p, str) for p in program):
            raise RequestError("launch needs `program`: a file or a list of files (or an mlc.toml "
                               "with `sources`)")
        program = [os.path.join(cwd, p) for p in program]
        stim = args.get("stimulus")
        if stim is not None and not isinstance(stim, str):
            raise RequestError("`stimulus` must be a path")
        stim = os.path.join(cwd, stim) if stim else None
        data = config.data if config is not None else {}  # mlc.toml
        name = args.get("target") or self.defaults.get("target") or getattr(config, "target", None) or "nc5"
        model = args.get("model") or self.defaults.get("model") or data.get("model")
        try:
            target = load_target(str(name), str(model).upper() if model else None)
        except Exception as e:  # noqa: BLE001 - an unknown target or model: the client is told
            raise RequestError(f"target {name}: {getattr(e, 'message', None) or e}") from None
        try:
            self.session = load_session(program, stim, target, config, self.defaults.get("scanTime"),
                                        args.get("engine") or self.defaults.get("engine"),
                                        self.defaults.get("checkpointEvery", 100), cwd=cwd)
        except LoadError as e:
            raise RequestError("the program cannot be simulated: " + str(e)) from None
        self.session.output = self.output
        self.session.poll = self._poll
        self.stop_on_entry = args.get("stopOnEntry", True) is not False
        for path, bps in self.pending.items():
            self._set_line_breakpoints(path, bps, announce=True)
        if self.pending_data:
            self._set_data_breakpoints(self.pending_data)
        self.respond(req)

    def on_configurationDone(self, req, args) -> None:
        self.respond(req)
        if self.session is None:
            return
        if self.stop_on_entry:
            self.stopped(Stop("entry", f"at {self.session.where()}"))
        else:
            self.stopped(self.session.run())

    def on_disconnect(self, req, args) -> None:
        self.respond(req)
        self.running = False

    def on_terminate(self, req, args) -> None:
        self.respond(req)
        self.event("terminated")

    def on_threads(self, req, args) -> None:
        self.respond(req, {"threads": [{"id": THREAD, "name": "PLC scan"}]})

    def on_setExceptionBreakpoints(self, req, args) -> None:
        self.respond(req, {"breakpoints": []})

    # -- breakpoints ----------------------------------------------------------------------
    def on_setBreakpoints(self, req, args) -> None:
        source = args.get("source") or {}
        path = source.get("path") or source.get("name")
        if not isinstance(path, str):
            raise RequestError("setBreakpoints needs source.path")
        bps = args.get("breakpoints")
        if bps is None:
            bps = [{"line": n} for n in args.get("lines") or []]
        if not isinstance(bps, list) or not all(isinstance(b, dict) for b in bps):
            raise RequestError("breakpoints must be a list of objects")
        if self.session is None:
            self.pending[path] = bps
            self.respond(req, {"breakpoints": [{"verified": False, "line": b.get("line"),
                                                "message": "set when the program is launched"} for b in bps]})
            return
        self.respond(req, {"breakpoints": self._set_line_breakpoints(path, bps)})

    def _set_line_breakpoints(self, path: str, bps: list[dict], announce: bool = False) -> list[dict]:
        s = self.need()
        s.clear_lines(self._source_file(path))
        out = []
        for b in bps:
            line = b.get("line")
            try:
                if not isinstance(line, int):
                    raise DebugError("a breakpoint needs a line number")
                bp = s.add_line(f"{self._source_file(path)}:{line}", b.get("condition") or "",
                                b.get("hitCondition") or "", b.get("logMessage") or "")
                where_line = int(bp.where.rsplit(":", 1)[1])
                out.append({"id": bp.id, "verified": True, "line": where_line})
            except DebugError as e:
                out.append({"verified": False, "line": line, "message": str(e)})
        if announce:
            for item in out:
                if "id" in item:
                    self.event("breakpoint", {"reason": "changed", "breakpoint": item})
        return out

    def _source_file(self, path: str) -> str:
        """The program's name for a client's path (the client sends absolute paths)."""
        s = self.need()
        files = {st.ins.file for st in s.steps}
        real = os.path.realpath(path)
        for f in files:
            if os.path.realpath(f) == real:
                return f
        base = os.path.basename(path)
        for f in sorted(files):
            if os.path.basename(f) == base:
                return f
        return path

    def on_dataBreakpointInfo(self, req, args) -> None:
        name = args.get("name")
        s = self.need()
        try:
            view = s.view(str(name))
        except DebugError as e:
            self.respond(req, {"dataId": None, "description": str(e)})
            return
        self.respond(req, {"dataId": view.name, "description": f"{view.name} changes",
                           "accessTypes": ["write"], "canPersist": True})

    def on_setDataBreakpoints(self, req, args) -> None:
        bps = args.get("breakpoints") or []
        if not isinstance(bps, list) or not all(isinstance(b, dict) for b in bps):
            raise RequestError("breakpoints must be a list of objects")
        if self.session is None:
            self.pending_data = bps
            self.respond(req, {"breakpoints": [{"verified": False} for _ in bps]})
            return
        self.respond(req, {"breakpoints": self._set_data_breakpoints(bps)})

    def _set_data_breakpoints(self, bps: list[dict]) -> list[dict]:
        s = self.need()
        for b in [b for b in s.breakpoints.values() if b.kind in ("watch", "cond")]:
            del s.breakpoints[b.id]
        out = []
        for b in bps:
            try:
                data = str(b.get("dataId") or "")
                if data.startswith("if "):  # a condition: `if D0 > 100`
                    bp = s.add_condition(data[3:], b.get("hitCondition") or "")
                else:
                    bp = s.add_watch(data, b.get("hitCondition") or "")
                out.append({"id": bp.id, "verified": True})
            except DebugError as e:
                out.append({"verified": False, "message": str(e)})
        return out

    # -- running --------------------------------------------------------------------------
    def stopped(self, stop: Stop) -> None:
        body = {"reason": _STOP_REASONS.get(stop.reason, "pause"), "description": stop.text,
                "threadId": THREAD, "allThreadsStopped": True, "text": stop.text}
        if stop.breakpoints:
            body["hitBreakpointIds"] = stop.breakpoints
        self.event("stopped", body)

    def _go(self, req, action) -> None:
        s = self.need()
        self.respond(req, {"allThreadsContinued": True} if req["command"] == "continue" else None)
        try:
            stop = action(s)
        except DebugError as e:
            self.output(f"error: {e}", "stderr")
            stop = Stop("pause", str(e))
        self.stopped(stop)

    def on_continue(self, req, args) -> None:
        self._go(req, lambda s: s.run())

    def on_next(self, req, args) -> None:
        self._go(req, lambda s: s.step_scan())

    def on_stepIn(self, req, args) -> None:
        self._go(req, lambda s: s.step())

    def on_stepOut(self, req, args) -> None:
        self._go(req, lambda s: s.step_scan())

    def on_stepBack(self, req, args) -> None:
        self._go(req, lambda s: s.back())

    def on_reverseContinue(self, req, args) -> None:
        self._go(req, lambda s: s.reverse_continue())

    def on_pause(self, req, args) -> None:
        self.pauses_handled += 1
        self.respond(req)
        if self.pause_ended_a_move:  # the move it ended said where it stopped
            self.pause_ended_a_move = False
        elif self.session is not None:  # it came when no move ran: the machine is stopped already
            self.stopped(Stop("pause", f"paused at {self.session.where()}"))

    # -- looking ------------------------------------------------------------------------
    def on_stackTrace(self, req, args) -> None:
        s = self.need()
        step = s.current_step() or (s.steps[0] if s.steps else None)
        frame = {"id": 1, "name": f"scan {s.scan}" + ("" if s.n == BOUNDARY else f", step {step.ins.addr}"),
                 "line": 0, "column": 0}
        if step is not None:
            ins = step.ins
            frame.update({"name": frame["name"] + f": {' '.join((ins.mnemonic, *ins.texts))}",
                          "line": ins.line, "column": ins.col or 1,
                          "source": {"name": os.path.basename(ins.file), "path": os.path.abspath(ins.file)}})
        self.respond(req, {"stackFrames": [frame], "totalFrames": 1})

    def on_scopes(self, req, args) -> None:
        self.need()
        self.respond(req, {"scopes": [{"name": name, "variablesReference": i + 1, "expensive": False}
                                      for i, name in enumerate(SCOPES)]})

    def _scope_views(self, ref: int):
        s = self.need()
        if not 1 <= ref <= len(SCOPES):
            raise RequestError(f"no variables {ref}")
        scope = SCOPES[ref - 1]
        views = s.program_views()
        if scope == "Inputs":
            return [v for v in views if v.kind == "X" and v.view == "bit"]
        if scope == "Outputs":
            return [v for v in views if v.kind == "Y" and v.view == "bit"]
        if scope == "Relays":
            return [v for v in views if v.view == "bit" and v.kind not in "XYTC"]
        if scope == "Words":
            return [v for v in views if v.view != "bit" and v.kind not in "TC"]
        if scope == "Timers":
            return [v for v in views if v.kind == "T" and v.view == "bit"]
        if scope == "Counters":
            return [v for v in views if v.kind == "C" and v.view == "bit"]
        if scope == "Watched":
            return [b.view for b in s.breakpoints.values() if b.kind == "watch"]
        return [(name, s.view(text)) for name, text in sorted(s.symbols.items()) if _is_device(s, text)]

    def on_variables(self, req, args) -> None:
        s = self.need()
        ref = args.get("variablesReference")
        if not isinstance(ref, int):
            raise RequestError("variables needs variablesReference")
        out = []
        for item in self._scope_views(ref):
            name, view = item if isinstance(item, tuple) else (item.name, item)
            value = s.describe(view).split(" = ", 1)[-1] if view.kind not in "TC" or view.view != "bit" \
                else s.describe(view).split(": ", 1)[-1]
            # a signal of the target (NC5 special M/D): its row in the type, which clients show on hover
            found = device_signal(s.target, view.kind, view.number) if view.view in ("bit", "w", "d") else None
            out.append({"name": name, "value": value, "variablesReference": 0, "evaluateName": view.name,
                        "type": view.view + (f" - {found.describe()}" if found else "")})
        self.respond(req, {"variables": out})

    def on_setVariable(self, req, args) -> None:
        s = self.need()
        name, value = args.get("name"), args.get("value")
        if not isinstance(name, str) or not isinstance(value, str):
            raise RequestError("setVariable needs name and value")
        view = s.view(s.symbols.get(name, name))
        v = s.value_for(view, value)
        s.force(view, v)
        self.output(f"forced {view.name}={v} (release it with `release {view.name}` in the debug console)")
        self.respond(req, {"value": str(view.read(s.m))})

    def on_evaluate(self, req, args) -> None:
        s = self.need()
        text = args.get("expression")
        if not isinstance(text, str):
            raise RequestError("evaluate needs an expression")
        try:
            e = s.expr(text)
            self.respond(req, {"result": str(e.value(s.m)), "variablesReference": 0})
            return
        except DebugError as first:
            if args.get("context") != "repl":
                raise
            error = first
        # in the debug console, the console's commands work too (force, release, back, rung ...)
        from mlctool.debug.console import ALIASES, COMMANDS, Console

        word = text.strip().split(" ", 1)[0].lower()
        word = ALIASES.get(word, word)
        if word not in COMMANDS:
            raise error
        lines: list[str] = []
        console = Console(s, lines.append)
        if word in CONSOLE_MOVES:  # the client shows the thread running: its Pause ends the move
            self.event("continued", {"threadId": THREAD, "allThreadsContinued": True})
        console.execute(text)
        s.output = self.output
        self.respond(req, {"result": "\n".join(lines), "variablesReference": 0})
        if word in CONSOLE_MOVES:
            self.stopped(Stop("step", lines[-1] if lines else s.where()))


def _is_device(s: DebugSession, text: str) -> bool:
    try:
        s.view(text)
        return True
    except DebugError:
        return False


def serve_stdio(defaults: dict | None = None) -> None:
    """DAP on stdin/stdout; anything else printed goes to stderr (stdout carries frames only).
    The reader thread reads a reader of its own over standard input's file descriptor: one
    still waiting in sys.stdin's when the session ends would abort the interpreter's exit."""
    out = sys.stdout.buffer
    sys.stdout = sys.stderr
    try:
        DapServer(open(os.dup(sys.stdin.fileno()), "rb"), out, defaults).serve()
    finally:
        sys.stdout = sys.__stdout__


def session_token() -> str:
    """MLC_DAP_TOKEN (a launcher's choice, at least MIN_TOKEN characters), else a new one."""
    given = os.environ.get(TOKEN_ENV)
    if given is None:
        return secrets.token_urlsafe(24)
    if len(given) < MIN_TOKEN or not given.isascii() or not given.isprintable():
        raise ValueError(f"{TOKEN_ENV}: give at least {MIN_TOKEN} printable ASCII characters")
    return given


def listen(port: int) -> socket.socket:
    """The listening socket on 127.0.0.1:port (OSError when it is taken: the caller says so)."""
    return socket.create_server(("127.0.0.1", port))


def serve_port(srv: socket.socket, token: str, defaults: dict | None = None) -> None:
    """DAP on a listening socket, one client: connections are taken in turn until one
    launches with the token; when that one ends, so does the server. The others (not DAP,
    no token, silent for AUTH_TIMEOUT_S) are closed and wait for nothing."""
    with srv:
        port = srv.getsockname()[1]
        print(f"mlc debug: DAP on 127.0.0.1:{port}, token {token} (the launch request gives it as `token`)",
              file=sys.stderr, flush=True)
        while True:
            conn, _ = srv.accept()
            server = None
            with conn, conn.makefile("rb") as r, conn.makefile("wb") as w:
                server = DapServer(r, w, defaults, token)
                timer = threading.Timer(AUTH_TIMEOUT_S, _close_unless, (server, conn))
                timer.daemon = True
                timer.start()
                try:
                    server.serve()
                except Refused:
                    pass
                except OSError:  # the client went away mid-reply
                    pass
                finally:
                    timer.cancel()
                    try:
                        conn.shutdown(socket.SHUT_RDWR)
                    except OSError:
                        pass
            if server.authenticated:
                return


def _close_unless(server: DapServer, conn: socket.socket) -> None:
    if not server.authenticated:  # the reader sees the end; the connection is closed
        try:
            conn.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass


__all__ = ["DapServer", "FrameError", "Refused", "io", "listen", "read_frame", "serve_port", "serve_stdio",
           "session_token", "write_frame"]
