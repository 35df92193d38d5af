"""`mlc debug --web`: the live ladder monitor (docs/debug.md "Live ladder monitor").

The page is `mlc ladder`'s (ladder/html.py, the same renderer) plus a control bar and a
script; it is served on 127.0.0.1 with a WebSocket at `/ws` that carries JSON messages both
ways. The server is a thin front end over one DebugSession: every request (step, scan, back,
force, write, ...) is a call on the session under one lock, and after each one the new state
(the lit elements, device values, forces, the device table, where the machine is) goes to
every connected tab. `run` is the
session's own `run(scans=N)` called every tick (50 ms) for the scans that virtual time owes
wall-clock time at the chosen speed; a breakpoint, watch or fault ends it.

Contacts, coils and STL state boxes are lit by the rule the simulation report uses
(ladder/lighting.py, docs/ladder.md "Lighting"), with the devices' values where the machine
stopped. Instruction boxes show their operands' values above them.

The device table (docs/debug.md "Device table"), as a PLC tool's device monitor: one per
session (every tab shows and edits the same rows, at most MAX_TABLE), each row a device
added by name or symbol with its value, whether it is forced, and its signal's description
(targetapi/signals.py). An edit is the console's `write` (set once), or `force` on a forced
row; both are the session's logged actions, refused while it replays ("Pause it first").

Hostile input: every message is parsed and checked; anything wrong gets an `error` reply and
the connection and the server go on. Messages over MAX_MESSAGE bytes close that connection
(WebSocket code 1009), never the server. Requests whose Host or Origin is not this server's
loopback address are refused (a web page elsewhere cannot drive the debugger).

Slow tabs: every tab has its own sender thread and a queue of at most MAX_QUEUE messages (a
state waiting to be sent is replaced by a newer one), so a tab that stops reading holds up
nobody else; when its queue is full, or a send to it has waited KEEPALIVE_S, it is
disconnected. Every move (the buttons, `goto`, a console line) runs with the session's poll
hook: every MAX_BATCH_S the lock is let go (the other tabs' requests are served, all tabs see
the progress) and a Pause ends the move. A connection reads on while its request runs (a
worker serves them in order), so the Pause of the tab whose move runs reaches it too.
"""

from __future__ import annotations

import json
import logging
import queue
import socket
import sys
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from http import HTTPStatus

from mlctool.debug.console import ALIASES, Console
from mlctool.debug.session import BOUNDARY, DebugError, DebugSession, Interrupted, Stop, _fmt, _time
from mlctool.ladder.document import RungView, image_sheet
from mlctool.ladder.html import page, sheets_body
from mlctool.ladder.lighting import lamps, lit
from mlctool.limits import MAX_DIGITS
from mlctool.sim.state import DeviceView, NameError_, parse_device_name
from mlctool.sim.stimulus.quantities import MAX_SCANS
from mlctool.sim.stimulus.stimulus import StimError
from mlctool.targetapi.signals import describe_device

MAX_MESSAGE = 64 * 1024
TICK_S = 0.05  # a running machine's state goes out at most this often
MAX_SPEED = 0  # `run` speed 0: as fast as the engine goes
MAX_BATCH_S = 0.04  # at speed 0, scans run between two looks at the clock
MAX_PENDING = 200  # output lines sent a tick while running
MAX_REPLY_LINES = 2000  # output lines in the reply to one request
KEEPALIVE_S = 20  # a tab that answers no ping, or takes no message, for this long is let go
MAX_QUEUE = 256  # messages waiting for one tab; past it the tab is disconnected (it stopped reading)
# console lines the page may send: not `save` (it writes files) nor `quit`
CONSOLE_REFUSED = ("save", "quit")
MAX_TABLE = 64  # rows of the device table (one table per session, every tab sees it)
MAX_VALUE = 100  # characters of a value typed into the table (K10, H0F, -1.5e3 ...)
COMMANDS = ("state", "step", "scan", "back", "back-scan", "goto", "run", "pause", "force", "release",
            "toggle", "write", "table-add", "table-remove", "console")


class RequestError(ValueError):
    pass


class Tab:
    """A connected tab: its messages go out from a thread of its own, through a bounded queue,
    so a tab that never reads blocks nothing but that thread (module doc)."""

    def __init__(self, conn, gone: Callable[[object], None], stall_s: float):
        self.conn = conn
        self.gone = gone  # told once when this tab is dropped
        self.queue: deque[tuple[str, str]] = deque()  # (type, JSON text)
        self.cond = threading.Condition()
        self.closed = False
        # a send blocked stall_s: the tab is gone (keepalive cannot tell: its ping waits behind it)
        self.stall_s = stall_s
        self.sending_since: float | None = None
        threading.Thread(target=self._pump, name="mlc-monitor-tab", daemon=True).start()

    def put(self, msg: dict) -> None:
        text = json.dumps(msg, separators=(",", ":"))
        kind = msg.get("type", "")
        with self.cond:
            if self.closed:
                return
            if self.sending_since is not None and time.monotonic() - self.sending_since > self.stall_s:
                self._drop()
                return
            if kind == "state" and self.queue and self.queue[-1][0] == "state":
                self.queue[-1] = (kind, text)  # not sent yet: the newer state says all of it
            elif len(self.queue) >= MAX_QUEUE:
                self._drop()
                return
            else:
                self.queue.append((kind, text))
            self.cond.notify()

    def _pump(self) -> None:
        while True:
            with self.cond:
                while not self.queue and not self.closed:
                    self.cond.wait()
                if self.closed:
                    return
                _, text = self.queue.popleft()
                self.sending_since = time.monotonic()
            try:
                self.conn.send(text)
            except Exception:  # noqa: BLE001 - a closed tab: dropped, the others go on
                with self.cond:
                    self._drop()
                return
            self.sending_since = None

    def close(self) -> None:
        with self.cond:
            self._drop()

    def _drop(self) -> None:
        """(Holding cond.) Stop sending and cut the connection: a send blocked on a full
        socket returns, and the tab's receiving side ends (its client sees the close)."""
        if self.closed:
            return
        self.closed = True
        self.queue.clear()
        self.cond.notify_all()
        sock = getattr(self.conn, "socket", None)
        if sock is not None:
            try:
                sock.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
        threading.Thread(target=self.gone, args=(self.conn,), daemon=True).start()


@dataclass
class Element:
    """A drawn element (`g.el[data-i]`) and what the monitor shows on it."""
    index: int
    kind: str  # contact | compare | step | coil | box
    values: list[DeviceView] = field(default_factory=list)  # shown below a box or comparison
    bit: DeviceView | None = None  # the device a click forces (contacts and coils)


@dataclass
class Row:
    """A row of the device table: the device, a symbol naming it, what the target's signal
    table says it is (NC5 special M/D: `M21000 - 程式啟動 cycle start, MLC->NC ...`)."""
    view: DeviceView
    symbol: str
    signal: str


def _read(view: DeviceView, m) -> str:
    try:
        return _fmt(view.read(m))
    except (IndexError, KeyError, ValueError):
        return "?"


def _view(text: str, target, width: int, box: bool) -> DeviceView | None:
    """An operand's view for display: words of 32-bit instructions as :d, timers and
    counters in boxes as their value (a contact shows their contact)."""
    try:
        view = parse_device_name(text, target)
        if box and view.kind in ("T", "C") and view.view == "bit":
            return parse_device_name(text + ":w", target)
        if width == 32 and view.view == "w" and view.kind not in ("T", "C"):
            return parse_device_name(text + ":d", target)
        return view
    except NameError_:
        return None  # constants (K10), pointers (P3), indexed operands


def elements_of(session: DebugSession, sheet) -> dict[int, Element]:
    out: dict[int, Element] = {}
    target = session.target

    def add(index: int, kind: str) -> None:
        ins = session.steps[index].ins
        views = [_view(str(op), target, ins.spec.width, kind == "box") for op in ins.operands]
        views = list({v.name: v for v in views if v is not None}.values())  # ADD D0 K1 D0: D0 once
        el = Element(index, kind)
        if kind in ("contact", "coil", "step") and views and views[0].view == "bit":
            el.bit = views[0]
        if kind in ("compare", "box"):
            el.values = views
        out[index] = el

    for it in sheet.items:
        if isinstance(it, RungView):
            for c in it.grid.cells:
                if c.index >= 0 and c.kind in ("contact", "compare", "step"):
                    add(c.index, c.kind)
            for o in it.grid.outputs:
                if o.kind in ("coil", "box"):
                    add(o.index, o.kind)
        elif it.row.ins.spec.cls != "label":
            add(it.row.index, "box")
    return out


class Monitor:
    """The session, its lock, the connected clients and the runner."""

    def __init__(self, session: DebugSession, title: str = ""):
        self.s = session
        self.lock = threading.RLock()
        self.clients: dict[object, Tab] = {}
        self.clients_lock = threading.Lock()
        self.sheet = image_sheet(session.image, getattr(session, "lines", {}) or {}, session.target)
        self.title = title or f"Monitor: {self.sheet.path}"
        self.elements = elements_of(session, self.sheet)
        self.lamps = lamps(self.sheet)
        self.shown: dict[str, DeviceView] = {}
        self.table: dict[str, Row] = {}  # the device table, in the order rows were added
        for el in self.elements.values():
            for v in ([el.bit] if el.bit else []) + el.values:
                self.shown.setdefault(v.name, v)
        self.stop_text = f"at {session.where()}"
        self.running = False
        self.speed = 1.0
        self._runner: threading.Thread | None = None
        self._generation = 0
        self._local = threading.local()  # .collect: the output of the request this thread serves
        self._pending: list[str] = []  # output while running (logpoints): sent with the next state
        self._dropped = 0
        self.console = Console(session, self._output)
        self.closed = threading.Event()
        self._move_lock = threading.Lock()  # held by the console move in flight
        self._moves_lock = threading.Lock()
        self._moves = 0  # bumped by each pause: a console move started before it ends
        self._run_interrupted = False  # a run ended by interrupt(): its pause request says "paused at"
        self._move_generation = 0
        self._polled = 0.0

    # -- state --------------------------------------------------------------------------
    def state(self) -> dict:
        s = self.s
        with self.lock:
            m = s.m
            values = {name: _read(view, m) for name, view in self.shown.items()}
            return {
                "type": "state", "scan": s.scan, "time": _time(s.time_us), "where": s.where(),
                "pc": s.pc if s.n != BOUNDARY else None, "running": self.running,
                "speed": self.speed, "stop": self.stop_text,
                "fault": s.fault.message if s.fault is not None else None,
                "on": lit(self.lamps, s.steps, m),  # the report's rule (ladder/lighting.py)
                "values": values,
                "forced": {v.name: _fmt(value) for v, value in s.sim.forces.items()},
                "table": [{"device": name, "symbol": row.symbol, "signal": row.signal, "value": _read(row.view, m)}
                          for name, row in self.table.items()],
            }

    def page(self) -> str:
        data = {"elements": {str(i): {"kind": el.kind, "bit": el.bit.name if el.bit else None,
                                      "values": [v.name for v in el.values]}
                             for i, el in sorted(self.elements.items())}}
        body = (sheets_body([self.sheet])
                + f'\n<script type="application/json" id="monitor">{_json_script(data)}</script>')
        return page(self.title, body, MONITOR_STYLE, MONITOR_SCRIPT, CONTROLS)

    # -- clients --------------------------------------------------------------------------
    def add_client(self, conn, stall_s: float = KEEPALIVE_S) -> None:
        with self.clients_lock:
            self.clients[conn] = Tab(conn, self.remove_client, stall_s)

    def remove_client(self, conn) -> None:
        with self.clients_lock:
            tab = self.clients.pop(conn, None)
        if tab is not None:
            tab.close()

    def send(self, conn, msg: dict) -> None:
        """Queue `msg` for one tab (never waits for it to read)."""
        with self.clients_lock:
            tab = self.clients.get(conn)
        if tab is not None:
            tab.put(msg)

    def broadcast(self, msg: dict) -> None:
        with self.clients_lock:
            tabs = list(self.clients.values())
        for tab in tabs:
            tab.put(msg)

    def _output(self, text: str) -> None:
        """Console output, logpoints and failed expects: into the reply to the request that
        caused them; while running, to every tab with the next state (at most MAX_PENDING
        lines a tick: a logpoint hit every scan cannot flood the page)."""
        collect = getattr(self._local, "collect", None)
        if collect is not None:  # a long console move with a logpoint: a reply of bounded size
            if len(collect) < MAX_REPLY_LINES:
                collect.append(text)
            else:  # the last lines are kept: they say where the move stopped
                self._local.overflow += 1
                self._local.tail.append(text)
        elif len(self._pending) < MAX_PENDING:
            self._pending.append(text)
        else:
            self._dropped += 1

    def publish(self) -> None:
        """The pending output, then the state, to every tab."""
        with self.lock:
            lines, self._pending = self._pending, []
            if self._dropped:
                lines.append(f"({self._dropped} more lines not shown)")
                self._dropped = 0
            state = self.state()
        if lines:
            self.broadcast({"type": "output", "text": "\n".join(lines)})
        self.broadcast(state)

    # -- requests -------------------------------------------------------------------------
    def handle_text(self, text) -> tuple[dict, bool]:
        """One message -> (reply, whether the state changed). Never raises."""
        msg_id = None
        try:
            if not isinstance(text, str):
                raise RequestError("send JSON text, not binary messages")
            try:
                msg = json.loads(text, parse_int=_bounded_int)
            except (json.JSONDecodeError, RecursionError) as e:
                raise RequestError(f"not JSON: {e}") from None
            if not isinstance(msg, dict):
                raise RequestError("a message is a JSON object with a `cmd`")
            msg_id = msg.get("id")
            if not (msg_id is None or (isinstance(msg_id, int) and not isinstance(msg_id, bool))
                    or isinstance(msg_id, str) and len(msg_id) <= 100):
                msg_id = None
                raise RequestError("`id` must be an integer or a short string")
            cmd = msg.get("cmd")
            if cmd not in COMMANDS:
                raise RequestError(f"unknown cmd {str(cmd)[:40]!r}: one of {', '.join(COMMANDS)}")
            self._local.collect, self._local.overflow, self._local.tail = [], 0, deque(maxlen=10)
            try:
                text_out, changed = getattr(self, "cmd_" + cmd.replace("-", "_"))(msg)
                lines = self._local.collect + ([text_out] if text_out else [])
                tail = list(self._local.tail)
                if tail:
                    lines[MAX_REPLY_LINES:] = [f"({self._local.overflow - len(tail)} more lines not shown)", *tail]
            finally:
                self._local.collect = None
            reply = {"type": "reply", "id": msg_id, "ok": True}
            if lines:
                reply["text"] = "\n".join(lines)
            return reply, changed
        except (RequestError, DebugError) as e:
            return {"type": "error", "id": msg_id, "message": str(e)}, False
        except StimError as e:
            return {"type": "error", "id": msg_id, "message": e.message}, False
        except Exception as e:  # noqa: BLE001 - a bug: an error reply, not a dead monitor
            return {"type": "error", "id": msg_id, "message": f"internal error: {type(e).__name__}: {e}"}, False

    def _arg(self, msg: dict, name: str, kind=str):
        v = msg.get(name)
        if not isinstance(v, kind) or isinstance(v, bool):
            raise RequestError(f"`{msg['cmd']}` needs `{name}` ({'a string' if kind is str else 'a number'})")
        return v

    def _device(self, msg: dict) -> DeviceView:
        name = self._arg(msg, "device")
        if len(name) > 100:
            raise RequestError("`device`: too long")
        return self.s.view(name)

    def _stopped(self, stop: Stop) -> tuple[str, bool]:
        self.stop_text = stop.text
        return stop.text, True

    def cmd_state(self, msg):
        return "", False  # the caller sends the state to this client

    def cmd_step(self, msg):
        return self._stopped(self._move(self.s.step))

    def cmd_scan(self, msg):
        return self._stopped(self._move(self.s.step_scan))

    def cmd_back(self, msg):
        return self._stopped(self._move(self.s.back))

    def cmd_back_scan(self, msg):
        return self._stopped(self._move(self.s.back_scan))

    def cmd_goto(self, msg):
        k = self._arg(msg, "scan", int)
        if k < 0:
            raise RequestError("there is no scan before scan 0")
        if k > MAX_SCANS:
            raise RequestError(f"`goto`: scans go up to {MAX_SCANS}")
        return self._stopped(self._move(lambda: self.s.goto_scan(k)))

    def _move(self, move: Callable[[], Stop | None]) -> Stop | None:
        """One move at a time: a run or a move in flight ends first; this one runs in batches
        (the poll hook, `_poll`), between which the lock is let go and a Pause or any later
        move from any tab ends it where it is (as Ctrl-C does in gdb)."""
        generation = self.pause()
        with self._move_lock, self.lock:
            self._move_generation, self._polled = generation, time.perf_counter()
            self.s.poll = self._poll
            try:
                return move()
            finally:
                self.s.poll = None

    def cmd_force(self, msg):
        return self._set(msg, self.s.force, "forced")

    def cmd_release(self, msg):
        with self.lock:
            view = self._device(msg)
            self.s.release(view)
            return f"released {view.name}", True

    def cmd_write(self, msg):
        """The device table's edit of a device that is not forced: a one-shot set, as the
        console's `write` (the program may change it again; docs/debug.md "Device table")."""
        return self._set(msg, self.s.write, "wrote")

    def _set(self, msg: dict, action: Callable[[DeviceView, int | float], None], done: str):
        """`device` set to `value` by `action` (the session's force or write). `value`: a
        number, or a string as the console takes it (1, K10, H0F, -1.5)."""
        with self.lock:
            view = self._device(msg)
            value = msg.get("value")
            if isinstance(value, bool) or not isinstance(value, (int, float, str)):
                raise RequestError(f"`{msg['cmd']}` needs `value` (a number or a string such as \"K10\")")
            if isinstance(value, str) and len(value) > MAX_VALUE:
                raise RequestError(f"`value`: at most {MAX_VALUE} characters")
            v = self.s.value_for(view, str(value))
            action(view, v)
            return f"{done} {view.name}={_fmt(v)}", True

    def cmd_table_add(self, msg):
        with self.lock:
            text = self._arg(msg, "device").strip()
            view = self._device(msg)
            if view.name in self.table:
                raise RequestError(f"{view.name} is in the table already")
            if len(self.table) >= MAX_TABLE:
                raise RequestError(f"the table holds at most {MAX_TABLE} devices: remove one first")
            self.table[view.name] = Row(view, self._symbol_of(text, view), self._signal_of(view))
            return f"added {view.name}", True

    def cmd_table_remove(self, msg):
        with self.lock:
            view = self._device(msg)
            if self.table.pop(view.name, None) is None:
                raise RequestError(f"{view.name} is not in the table")
            return f"removed {view.name}", True

    def _symbol_of(self, typed: str, view: DeviceView) -> str:
        """The symbol the row was added by, else the first (sorted) symbol naming the device."""
        symbols = self.s.symbols
        if typed in symbols:
            return typed
        return next((name for name in sorted(symbols) if str(symbols[name]).upper() == view.name), "")

    def _signal_of(self, view: DeviceView) -> str:
        if view.view not in ("bit", "w", "d"):
            return ""
        return describe_device(self.s.target, view.kind, view.number) or ""

    def cmd_toggle(self, msg):
        """A click on a contact or coil: force its bit to the other value."""
        with self.lock:
            view = self._device(msg)
            if view.view != "bit":
                raise RequestError(f"{view.name} is not a bit: force it with a value")
            v = 0 if view.read(self.s.m) else 1
            self.s.force(view, v)
            return f"forced {view.name}={v}", True

    def cmd_console(self, msg):
        line = self._arg(msg, "line")
        if len(line) > 1000 or "\n" in line:
            raise RequestError("`line`: one console command of at most 1000 characters")
        word, _, rest = line.strip().partition(" ")
        word = ALIASES.get(word.lower(), word.lower())
        if word in CONSOLE_REFUSED:
            raise RequestError(f"`{word}` is not available from the page (use the terminal console)")
        self.console.last_stop = None
        self._move(lambda: self.console.execute(line))
        out = self._local.collect
        if len(out) == 1 and out[0].startswith("error: "):
            raise RequestError(out[0][len("error: "):])
        if self.console.last_stop is not None:  # a move said where it stopped
            self.stop_text = self.console.last_stop.text
        return "", True

    def _poll(self) -> None:
        """The session's poll hook during a console move (the lock held once, by this thread)."""
        if self._moves != self._move_generation:
            raise Interrupted
        if time.perf_counter() - self._polled < MAX_BATCH_S:
            return
        self.stop_text = "running a console command (Pause ends it)"
        self.lock.release()
        try:
            self.publish()
            time.sleep(0.002)  # let the requests waiting for the lock in
        finally:
            self.lock.acquire()
        self._polled = time.perf_counter()
        if self._moves != self._move_generation:
            raise Interrupted

    # -- running --------------------------------------------------------------------------
    def cmd_run(self, msg):
        speed = msg.get("speed", 1)
        if isinstance(speed, bool) or not isinstance(speed, (int, float)) or not 0 <= speed <= 1e6:
            raise RequestError("`speed`: a number, 1 = real time, 0 = as fast as possible")
        self._end_move()  # a console move in flight ends: one move at a time
        with self.lock:
            self.s._need_running()
            self.speed = float(speed)
            if self.running:
                return "", True
            self.running = True
            self.stop_text = "running"
            self._generation += 1  # a runner of an earlier run still ending (pause timed out) stops
            self._runner = threading.Thread(target=self._run, args=(self._generation,), name="mlc-monitor-run",
                                            daemon=True)
            self._runner.start()
        return "", True

    def cmd_pause(self, msg):
        was, self._run_interrupted = self.running or self._run_interrupted, False
        self.pause()
        with self.lock:
            if was:
                self.stop_text = f"paused at {self.s.where()}"
        return "", True

    def pause(self) -> int:
        """Stop the runner and end a console move in flight; the new move generation."""
        runner = self._runner
        self.running = False
        if runner is not None and runner is not threading.current_thread():
            runner.join(5)  # it ends at its next tick
        self._runner = None
        return self._end_move()

    def interrupt(self) -> None:
        """End the run and the move in flight at their next batch, without waiting for them
        (a Pause as it arrives: the request itself follows in its turn)."""
        self._run_interrupted = self._run_interrupted or self.running
        self.running = False
        with self._moves_lock:
            self._moves += 1

    def _end_move(self) -> int:
        with self._moves_lock:
            self._moves += 1
            generation = self._moves
        if self._move_lock.acquire(timeout=5):  # the move sees the new generation at its next batch
            self._move_lock.release()
        return generation

    def _run(self, generation: int) -> None:
        """Scans as virtual time owes wall time (speed x); the state out every tick."""
        speed, start_wall, start_scan, batch = None, 0.0, 0, 1
        while self.running and not self.closed.is_set():
            tick = time.perf_counter()
            with self.lock:
                if not self.running or generation != self._generation:
                    break
                s = self.s
                if self.speed != speed:  # started, or the speed changed: time counts from now
                    speed, start_wall, start_scan = self.speed, tick, s.scan
                if self.speed == MAX_SPEED:
                    n = batch
                else:
                    due = start_scan + int((tick - start_wall) * 1e6 * self.speed / s.period)
                    n = min(due - s.scan, 100_000)
                    if n > 10_000:  # the engine cannot keep up: fall behind, not flood
                        start_wall, start_scan = tick, s.scan
                stop = s.run(scans=n) if n > 0 else None
                if stop is not None and stop.reason != "step":
                    self.running = False
                    self.stop_text = stop.text
            self.publish()
            spent = time.perf_counter() - tick
            if self.speed == MAX_SPEED:
                batch = max(1, min(batch * 2, 100_000)) if spent < MAX_BATCH_S / 2 else max(1, batch // 2)
                time.sleep(0.002)  # let requests in
            else:
                time.sleep(max(0.0, TICK_S - spent))

    def close(self) -> None:
        self.closed.set()
        self.pause()


def _is_pause(message) -> bool:
    try:
        msg = json.loads(message, parse_int=_bounded_int) if isinstance(message, str) and "pause" in message else None
    except (ValueError, RecursionError):
        return False
    return isinstance(msg, dict) and msg.get("cmd") == "pause"


def _quiet_logger() -> logging.Logger:
    """The websockets library's log: one line on stderr for what it reports as an error (a
    tab's connection that failed, a keepalive ping that timed out), never a traceback."""
    log = logging.getLogger("mlctool.debug.web")
    if not log.handlers:
        handler = logging.StreamHandler(sys.stderr)
        handler.setFormatter(_OneLine("mlc debug: web monitor: %(message)s"))
        handler.setLevel(logging.ERROR)
        log.addHandler(handler)
        log.propagate = False
    return log


class _OneLine(logging.Formatter):
    def format(self, record: logging.LogRecord) -> str:
        text = record.getMessage()
        if record.exc_info and record.exc_info[1] is not None:
            e = record.exc_info[1]
            text += f" ({type(e).__name__}: {e})"
        return self._fmt % {"message": text}


def _bounded_int(text: str) -> int:
    """JSON integers as the page sends them: at most MAX_DIGITS digits (Python refuses to
    convert more than 4300, with a ValueError that is no message for a user)."""
    if len(text.lstrip("-")) > MAX_DIGITS:
        raise RequestError(f"a number of {len(text.lstrip('-'))} digits: numbers have at most {MAX_DIGITS}")
    return int(text)


def _json_script(data) -> str:
    """JSON inside a <script> element: `</` cannot end it early."""
    return json.dumps(data, separators=(",", ":")).replace("</", "<\\/")


# -- the server -------------------------------------------------------------------------------

class WebServer:
    """The HTTP page at `/` and the WebSocket at `/ws` (the `websockets` package, imported
    here only: `mlc --help` and the other commands never load it)."""

    def __init__(self, monitor: Monitor, port: int = 0, keepalive_s: float = KEEPALIVE_S):
        from websockets.sync.server import serve

        self.monitor = monitor
        self.keepalive_s = keepalive_s
        # a tab that answers no ping for keepalive_s is closed (a browser that went to sleep)
        self.server = serve(self._serve_ws, "127.0.0.1", port, process_request=self._http,
                            max_size=MAX_MESSAGE, compression=None, logger=_quiet_logger(),
                            ping_interval=keepalive_s, ping_timeout=keepalive_s)
        self.port = self.server.socket.getsockname()[1]
        self.url = f"http://127.0.0.1:{self.port}/"
        self._page: bytes | None = None

    def _allowed_hosts(self) -> set[str]:
        return {f"127.0.0.1:{self.port}", f"localhost:{self.port}"}

    def _http(self, conn, request):
        from websockets.datastructures import Headers
        from websockets.http11 import Response

        def respond(status: HTTPStatus, body: bytes, ctype: str = "text/plain; charset=utf-8"):
            headers = Headers([("Content-Type", ctype), ("Content-Length", str(len(body))),
                               ("Cache-Control", "no-store"), ("Connection", "close")])
            return Response(status.value, status.phrase, headers, body)

        hosts, origins = request.headers.get_all("Host"), request.headers.get_all("Origin")
        if len(hosts) != 1 or len(origins) > 1:  # which one would the browser have meant?
            return respond(HTTPStatus.BAD_REQUEST, b"bad request: one Host header, at most one Origin\n")
        if hosts[0] not in self._allowed_hosts():  # DNS rebinding: only our own address
            return respond(HTTPStatus.FORBIDDEN, b"forbidden: wrong Host\n")
        path = request.path.split("?", 1)[0]
        if path == "/ws":
            if origins and origins[0] not in {"http://" + h for h in self._allowed_hosts()}:
                return respond(HTTPStatus.FORBIDDEN, b"forbidden: another site's page\n")
            return None  # the WebSocket handshake goes on
        if path == "/":
            if self._page is None:
                self._page = self.monitor.page().encode("utf-8")
            return respond(HTTPStatus.OK, self._page, "text/html; charset=utf-8")
        if path == "/favicon.ico":
            return respond(HTTPStatus.NO_CONTENT, b"")
        return respond(HTTPStatus.NOT_FOUND, b"not found\n")

    def _serve_ws(self, conn) -> None:
        from websockets.exceptions import ConnectionClosed

        mon = self.monitor
        mon.add_client(conn, self.keepalive_s)
        # requests are served in order by a worker, so that this thread goes on reading: a
        # Pause from the tab whose own move runs (its `goto`, its console line) reaches it
        inbox: queue.Queue = queue.Queue()
        threading.Thread(target=self._work, args=(conn, inbox), name="mlc-monitor-requests", daemon=True).start()
        try:
            mon.send(conn, mon.state())
            for message in conn:
                if inbox.qsize() >= MAX_QUEUE:
                    mon.send(conn, {"type": "error", "id": None,
                                    "message": f"more than {MAX_QUEUE} requests waiting: this one is dropped"})
                    continue
                if _is_pause(message):
                    mon.interrupt()  # now; then in its turn, which replies
                inbox.put(message)
        except ConnectionClosed:
            pass
        finally:
            inbox.put(None)
            mon.remove_client(conn)

    def _work(self, conn, inbox: queue.Queue) -> None:
        mon = self.monitor
        while (message := inbox.get()) is not None:
            reply, changed = mon.handle_text(message)
            mon.send(conn, reply)
            if changed:
                mon.publish()
            elif reply.get("ok"):
                mon.send(conn, mon.state())

    def serve_forever(self) -> None:
        self.server.serve_forever()

    def start(self) -> threading.Thread:
        """Serve in a thread (tests)."""
        t = threading.Thread(target=self.serve_forever, name="mlc-monitor", daemon=True)
        t.start()
        return t

    def shutdown(self) -> None:
        self.monitor.close()
        self.server.shutdown()


CONTROLS = """
<span id="controls">
<button id="b-run" type="button" title="run in real time (at the chosen speed)">Run</button>
<select id="speed" aria-label="speed"><option value="1">1&times;</option><option value="10">10&times;</option>
<option value="100">100&times;</option><option value="0">max</option></select>
<button id="b-pause" type="button">Pause</button>
<button id="b-step" type="button" title="one instruction">Step</button>
<button id="b-scan" type="button" title="to the end of the scan">Scan</button>
<button id="b-back" type="button" title="one instruction back">Back</button>
<button id="b-backscan" type="button" title="back to the start of the scan">Back scan</button>
</span>
<span id="where" class="mon">connecting...</span>
""".strip()

MONITOR_STYLE = """
#controls button{font-size:13px}
.mon{font-family:monospace;font-size:12px}
#bar{padding:4px 16px;background:#fff;border-bottom:1px solid #ddd;font-size:13px;display:flex;gap:16px;flex-wrap:wrap}
#bar .err{color:#b00020}
#forced button{font-size:11px;margin-left:4px}
#cmd{font-family:monospace;width:22em}
#out{margin:0;padding:2px 16px;max-height:8em;overflow:auto;font-size:12px;background:#f4f4f4;white-space:pre-wrap}
.lad .el.click{cursor:pointer}
.lad rect.hit{fill:transparent;stroke:none}
.lad .el.forced text{fill:#d35400;font-weight:bold}
.lad .el.cur{filter:drop-shadow(0 0 3px #1f4fbf)}
.lad .el.cur .sym,.lad .el.cur .box{stroke:#1f4fbf}
.lad text.val{font-size:10px;fill:#1f4f9f}
#out:empty{display:none}
body.off main{opacity:.5}
#devices{position:fixed;right:8px;bottom:8px;z-index:3;background:#fff;border:1px solid #bbb;
box-shadow:0 2px 8px rgba(0,0,0,.15);font-size:12px;max-height:45vh;max-width:60vw;overflow:auto;padding:4px 8px}
#devices form{display:flex;gap:4px;align-items:center}
#devices b{margin-right:4px}
#add-dev{font-family:monospace;width:16em}
#devtable{border-collapse:collapse;margin-top:4px}
#devtable th,#devtable td{border:1px solid #ddd;padding:1px 6px;text-align:left;vertical-align:middle}
#devtable th{background:#f4f4f4;font-weight:normal}
#devtable input.val{font-family:monospace;width:8em}
#devtable tr.forced td,#devtable tr.forced input.val{color:#d35400;font-weight:bold}
#devtable td.sig{color:#555;max-width:28em;overflow:hidden;text-overflow:ellipsis;white-space:nowrap}
#devtable.empty{display:none}
main{padding-bottom:45vh}
""".strip()

# The page's side: `data` says which device each element shows; a state message lights the
# elements by the lighting rule, writes values and marks forces, and fills the device table.
# A click on a contact or coil forces its device to the other value; shift-click (or the
# list's release button) releases it. In the table, Enter in a value sets it once (`write`),
# or forces it on a row whose force box is ticked; ticking the box forces the value shown.
MONITOR_SCRIPT = r"""
(function(){
  var data=JSON.parse(document.getElementById('monitor').textContent);
  var SVG='http://www.w3.org/2000/svg';
  var header=document.querySelector('header'), bar=document.createElement('div');
  bar.id='bar';
  bar.innerHTML='<span id="stop" class="mon"></span><span id="forced">forced: <i>none</i></span>'+
    '<span><input id="cmd" placeholder="console: break if D0 &gt; 3, watch Y0, print D0" aria-label="console command"></span>';
  header.parentNode.insertBefore(bar,header.nextSibling);
  var out=document.createElement('pre'); out.id='out'; bar.parentNode.insertBefore(out,bar.nextSibling);
  var where=document.getElementById('where'), stopEl=document.getElementById('stop');
  var forcedEl=document.getElementById('forced'), cmd=document.getElementById('cmd');
  // the device table: a panel of its own (docked bottom right), rows kept across states so
  // that a value being typed is not overwritten by the next state
  var panel=document.createElement('section'); panel.id='devices';
  panel.innerHTML='<form id="add"><b>Devices</b><input id="add-dev" placeholder="device or symbol: D0, X0, M21000" '+
    'aria-label="device to add"><button type="submit">Add</button></form><table id="devtable" class="empty"><thead><tr>'+
    '<th>device</th><th>symbol</th><th title="Enter sets it once; on a forced row, forces the new value">value</th>'+
    '<th title="held until released">force</th><th>signal</th><th></th></tr></thead><tbody></tbody></table>';
  document.body.appendChild(panel);
  var devtable=document.getElementById('devtable'), tbody=devtable.querySelector('tbody'), rows={}, last=null;
  var addDev=document.getElementById('add-dev');
  function newRow(r){
    var tr=document.createElement('tr'); tr.setAttribute('data-device',r.device);
    function cell(text,cls){ var td=document.createElement('td'); td.textContent=text; if(cls) td.className=cls;
      tr.appendChild(td); return td; }
    cell(r.device,'mon'); cell(r.symbol,'mon');
    var input=document.createElement('input'); input.className='val'; input.setAttribute('aria-label','value of '+r.device);
    cell('').appendChild(input);
    var box=document.createElement('input'); box.type='checkbox'; box.setAttribute('aria-label','force '+r.device);
    cell('').appendChild(box);
    var sig=cell(r.signal,'sig'); sig.title=r.signal;
    var del=document.createElement('button'); del.type='button'; del.textContent='remove';
    cell('').appendChild(del);
    input.addEventListener('keydown',function(ev){
      if(ev.key==='Enter'&&input.value.trim()){  // set once; a forced row: force the new value
        send({cmd:box.checked?'force':'write',device:r.device,value:input.value.trim()}); input.blur();
      } else if(ev.key==='Escape'){ input.value=input.getAttribute('data-value'); input.blur(); }
    });
    box.addEventListener('change',function(){
      if(box.checked) send({cmd:'force',device:r.device,value:input.value.trim()});
      else send({cmd:'release',device:r.device});
    });
    del.addEventListener('click',function(){ send({cmd:'table-remove',device:r.device}); });
    tbody.appendChild(tr);
    return {tr:tr,input:input,box:box};
  }
  function showTable(st){
    var keep={};
    st.table.forEach(function(r){
      keep[r.device]=1;
      var row=rows[r.device]||(rows[r.device]=newRow(r)), forced=st.forced.hasOwnProperty(r.device);
      row.tr.classList.toggle('forced',forced);
      row.box.checked=forced;
      row.input.setAttribute('data-value',r.value);
      if(document.activeElement!==row.input) row.input.value=r.value;
    });
    Object.keys(rows).forEach(function(n){ if(!keep[n]){ tbody.removeChild(rows[n].tr); delete rows[n]; } });
    devtable.classList.toggle('empty',!st.table.length);
  }
  document.getElementById('add').addEventListener('submit',function(ev){
    ev.preventDefault();
    if(addDev.value.trim()){ send({cmd:'table-add',device:addDev.value.trim()}); addDev.value=''; }
  });
  var els={}, vals={};
  Array.prototype.forEach.call(document.querySelectorAll('.el[data-i]'),function(g){
    var i=g.getAttribute('data-i'), d=data.elements[i];
    if(!d) return;
    (els[i]=els[i]||[]).push(g);
    var b=g.getBBox();
    if(d.bit){  // the whole box takes the click, not only the drawn strokes
      g.classList.add('click'); g.setAttribute('data-bit',d.bit);
      var hit=document.createElementNS(SVG,'rect');
      hit.setAttribute('class','hit'); hit.setAttribute('x',b.x); hit.setAttribute('y',b.y);
      hit.setAttribute('width',b.width); hit.setAttribute('height',b.height);
      g.insertBefore(hit,g.firstChild);
      var tip=g.querySelector('title');
      if(tip) tip.textContent+='\nclick: force '+d.bit+' to the other value; shift-click: release';
    }
    if(d.values.length){  // above the box: below it is its symbol line, then the next row
      var box=g.querySelector('rect.box'), bb=box?box.getBBox():b, t=document.createElementNS(SVG,'text');
      t.setAttribute('class','val'); t.setAttribute('x',bb.x+bb.width/2); t.setAttribute('y',bb.y-4);
      t.setAttribute('text-anchor','middle'); g.appendChild(t); vals[i]=t;
    }
  });
  var ws=null, nextId=1, pending={};
  function log(text,cls){
    var line=document.createElement('div'); line.textContent=text; if(cls) line.className=cls;
    out.appendChild(line); out.scrollTop=out.scrollHeight;
    while(out.childNodes.length>200) out.removeChild(out.firstChild);
  }
  function send(o){
    if(!ws||ws.readyState!==1){ log('not connected','err'); return; }
    o.id=nextId++; pending[o.id]=o.cmd; ws.send(JSON.stringify(o));
  }
  function show(st){
    var on={}; st.on.forEach(function(i){ on[i]=1; });
    Object.keys(els).forEach(function(i){
      var d=data.elements[i];
      els[i].forEach(function(g){
        g.classList.toggle('on',!!on[i]);
        g.classList.toggle('cur',st.pc!==null&&+i===st.pc);
        g.classList.toggle('forced',!!(d.bit&&st.forced.hasOwnProperty(d.bit)));
      });
      if(vals[i]) vals[i].textContent=d.values.map(function(n){ return n+'='+st.values[n]; }).join('  ');
    });
    where.textContent=(st.running?'running: ':'')+st.where;
    stopEl.textContent=st.fault?('fault: '+st.fault):st.stop;
    stopEl.className='mon'+(st.fault?' err':'');
    var names=Object.keys(st.forced).sort();
    forcedEl.innerHTML='forced: '+(names.length?'':'<i>none</i>');
    names.forEach(function(n){
      var s=document.createElement('span'); s.textContent=' '+n+'='+st.forced[n];
      var b=document.createElement('button'); b.type='button'; b.textContent='release';
      b.setAttribute('data-release',n);
      b.addEventListener('click',function(){ send({cmd:'release',device:n}); });
      s.appendChild(b); forcedEl.appendChild(s);
    });
    if(st.pc!==null&&els[st.pc]&&!st.running){
      var r=els[st.pc][0].getBoundingClientRect();
      if(r.top<80||r.bottom>window.innerHeight) els[st.pc][0].scrollIntoView({block:'center'});
    }
    showTable(st);
    last=st;
    document.body.setAttribute('data-scan',st.scan);
  }
  function connect(){
    ws=new WebSocket((location.protocol==='https:'?'wss://':'ws://')+location.host+'/ws');
    ws.onopen=function(){ document.body.classList.remove('off'); };
    ws.onmessage=function(ev){
      var msg=JSON.parse(ev.data);
      if(msg.type==='state') show(msg);
      else if(msg.type==='output') log(msg.text);
      else if(msg.type==='error'){  // a refused edit: the table shows the state again
        log('error: '+msg.message,'err'); delete pending[msg.id]; if(last) showTable(last);
      }
      else if(msg.type==='reply'){ if(msg.text) log(msg.text); delete pending[msg.id]; }
    };
    ws.onclose=function(){ document.body.classList.add('off'); where.textContent='disconnected (is mlc debug --web still running?)'; };
  }
  document.querySelector('main').addEventListener('click',function(ev){
    var g=ev.target.closest&&ev.target.closest('.el.click');
    if(!g) return;
    var dev=g.getAttribute('data-bit');
    if(ev.shiftKey) send({cmd:'release',device:dev}); else send({cmd:'toggle',device:dev});
  });
  var speed=document.getElementById('speed');
  document.getElementById('b-run').addEventListener('click',function(){ send({cmd:'run',speed:+speed.value}); });
  speed.addEventListener('change',function(){ if(/^running/.test(where.textContent)) send({cmd:'run',speed:+speed.value}); });
  document.getElementById('b-pause').addEventListener('click',function(){ send({cmd:'pause'}); });
  document.getElementById('b-step').addEventListener('click',function(){ send({cmd:'step'}); });
  document.getElementById('b-scan').addEventListener('click',function(){ send({cmd:'scan'}); });
  document.getElementById('b-back').addEventListener('click',function(){ send({cmd:'back'}); });
  document.getElementById('b-backscan').addEventListener('click',function(){ send({cmd:'back-scan'}); });
  cmd.addEventListener('keydown',function(ev){
    if(ev.key==='Enter'&&cmd.value.trim()){ log('> '+cmd.value); send({cmd:'console',line:cmd.value}); cmd.value=''; }
  });
  connect();
})();
""".strip()


def serve(server: WebServer, announce=print) -> None:
    """`mlc debug --web`: serve until interrupted (Ctrl-C)."""
    announce(f"mlc debug: ladder monitor on {server.url} (Ctrl-C stops)")
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        server.shutdown()


__all__ = ["Monitor", "WebServer", "serve"]
