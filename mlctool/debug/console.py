"""The `mlc debug` console: one command per line over a DebugSession.

With a terminal, prompt-toolkit reads the lines (history, completion of commands, devices
and symbols); over a pipe a plain line reader does, so sessions can be scripted. A bad
command gets a message, never a traceback.
"""

from __future__ import annotations

import contextlib
import shlex
import signal
import sys
from collections.abc import Callable, Iterable

from mlctool.debug.session import BOUNDARY, DebugError, DebugSession, Interrupted, Stop
from mlctool.limits import clip, is_decimal
from mlctool.sim.stimulus.quantities import MAX_SCANS
from mlctool.sim.stimulus.stimulus import StimError, parse_time
from mlctool.targetapi.signals import device_signal

HELP = """commands:
  step [N]                  one instruction (N instructions)
  scan [N] | next [N]       to the end of this scan (N scans)
  run [TIME | #N | until EXPR]   run (TIME of virtual time, N scans, or until EXPR holds)
  continue                  run until a breakpoint, watch or condition fires
  break FILE:LINE | LINE | #STEP | P3 [if EXPR] [hits N]   stop before that instruction
  break if EXPR [hits N]    stop at a scan end where EXPR holds (D0 > 100 && Y0)
  log FILE:LINE "D0={D0}"   print the message when the instruction is reached
  watch DEV                 stop when DEV changes (a data breakpoint)
  breakpoints | delete ID   list / delete breakpoints, watches and logpoints
  print DEV...              values (bit, word, :d, :f; timers, counters with preset)
  display DEV... | undisplay   print these at every stop
  force DEV=V | release DEV held values (as the stimulus `force`)
  write DEV=V               set once (the program may overwrite it)
  back [scan]               one instruction (one scan) back in time
  reverse-continue          back to the previous breakpoint or watch hit
  goto SCAN                 to the start of scan SCAN
  diff A B                  devices that changed between scans A and B
  rung                      the current rung as a ladder with values
  where | save FILE.stim | help | quit"""

COMMANDS = ("step", "scan", "next", "run", "continue", "break", "log", "watch", "breakpoints",
            "delete", "print", "display", "undisplay", "force", "release", "write", "back",
            "reverse-continue", "goto", "diff", "rung", "where", "save", "help", "quit")
ALIASES = {"s": "step", "n": "next", "c": "continue", "p": "print", "b": "break", "q": "quit",
           "exit": "quit", "rc": "reverse-continue", "info": "breakpoints", "bt": "where"}


class Console:
    def __init__(self, session: DebugSession, out: Callable[[str], None]):
        self.s = session
        self.out = out
        self.displays: list[str] = []
        session.output = out
        self.saved: list[str] = []
        self.last_stop: Stop | None = None  # where the latest move ended
        self._ctrl_c: list | None = None  # the Ctrl-C presses not yet seen (ctrl_c_ends_moves)

    # one line -> False to quit
    def execute(self, line: str) -> bool:
        line = line.strip()
        if self._ctrl_c is not None:
            self._ctrl_c.clear()
        if not line or line.startswith("#"):
            return True
        word, _, rest = line.partition(" ")
        cmd = ALIASES.get(word.lower(), word.lower())
        if cmd == "quit":
            return False
        fn = getattr(self, "cmd_" + cmd.replace("-", "_"), None)
        if fn is None or cmd not in COMMANDS:
            from mlctool.suggest import closest

            near = closest(word, COMMANDS)
            self.out(f"error: unknown command {word!r}" + (f"; did you mean {near!r}?" if near else "")
                     + " (help lists the commands)")
            return True
        try:
            fn(rest.strip())
        except Interrupted as e:  # a move that says nothing itself (diff)
            self.out(str(e) or self.s.interrupted().text)
        except DebugError as e:
            self.out(f"error: {e}")
        except (StimError, ValueError) as e:
            self.out(f"error: {getattr(e, 'message', str(e))}")
        return True

    def report(self, stop: Stop) -> None:
        self.last_stop = stop
        self.out(stop.text)
        for name in self.displays:
            try:
                self.out("  " + self.s.describe(self.s.view(name)))
            except DebugError as e:
                self.out(f"  {name}: {e}")

    def _count(self, rest: str) -> int:
        if not rest:
            return 1
        if not is_decimal(rest) or not 1 <= int(rest) <= MAX_SCANS:
            raise DebugError(f"{clip(rest, 24)!r}: give a count from 1 to {MAX_SCANS}")
        return int(rest)

    def _repeat(self, rest: str, move: Callable[[], Stop]) -> None:
        """`move` N times; the session's poll hook between two (a Pause or Ctrl-C ends them)."""
        stop = None
        try:
            for i in range(self._count(rest)):
                if i and self.s.poll is not None:
                    self.s.poll()
                stop = move()
                if stop.reason != "step":  # a breakpoint, watch or condition on the way, a fault
                    break
        except Interrupted:
            stop = self.s.interrupted()
        self.report(stop)

    def cmd_step(self, rest: str) -> None:
        self._repeat(rest, self.s.step)

    def cmd_scan(self, rest: str) -> None:
        self._repeat(rest, self.s.step_scan)

    cmd_next = cmd_scan

    def cmd_run(self, rest: str) -> None:
        if not rest:
            self.report(self.s.run())
            return
        if rest.startswith("until "):
            self.report(self.s.run(until=self.s.expr(rest[6:])))
            return
        if rest.startswith("#"):
            self.report(self.s.run(scans=self._count(rest[1:])))
            return
        us = parse_time(rest)
        target_scan = -(-(self.s.time_us + us) // self.s.period)
        self.report(self.s.run(scans=max(1, target_scan - self.s.scan)))

    def cmd_continue(self, rest: str) -> None:
        self.report(self.s.run())

    def cmd_break(self, rest: str) -> None:
        if not rest:
            raise DebugError("break FILE:LINE | LINE | #STEP | P3 [if EXPR] [hits N], or break if EXPR")
        hits = ""
        if " hits " in f" {rest} ":
            rest, _, hits = f" {rest} ".rpartition(" hits ")
            rest = rest.strip()
        if rest.startswith("if "):
            b = self.s.add_condition(rest[3:], hits)
        else:
            spec, _, cond = rest.partition(" if ")
            b = self.s.add_line(spec.strip(), cond, hits)
        self.out(f"breakpoint {b.describe()}")

    def cmd_log(self, rest: str) -> None:
        try:
            parts = shlex.split(rest)
        except ValueError as e:
            raise DebugError(f"log: {e}") from None
        if len(parts) != 2:
            raise DebugError('log FILE:LINE "message with {DEV}"')
        b = self.s.add_line(parts[0], log=parts[1])
        self.out(f"logpoint {b.describe()}")

    def cmd_watch(self, rest: str) -> None:
        if not rest:
            raise DebugError("watch DEV")
        for name in rest.replace(",", " ").split():
            b = self.s.add_watch(name)
            self.out(f"watch {b.describe()} = {b.last}")

    def cmd_breakpoints(self, rest: str) -> None:
        if not self.s.breakpoints:
            self.out("no breakpoints")
        for b in self.s.breakpoints.values():
            self.out(b.describe())

    def cmd_delete(self, rest: str) -> None:
        if not rest:
            raise DebugError("delete ID (breakpoints lists them)")
        for part in rest.replace("#", "").split():
            if not part.isdigit():
                raise DebugError(f"{part!r} is not a breakpoint number")
            self.s.delete(int(part))
        self.out("deleted")

    def cmd_print(self, rest: str) -> None:
        if not rest:
            raise DebugError("print DEV... or print EXPR")
        names = rest.replace(",", " ").split()
        try:
            views = [self.s.view(n) for n in names]
        except DebugError:  # not a device list: an expression
            e = self.s.expr(rest)
            self.out(f"{rest} = {e.value(self.s.m)}")
            return
        for v in views:  # a signal of the target (NC5 special M/D) says what it is
            found = device_signal(self.s.target, v.kind, v.number) if v.view in ("bit", "w", "d") else None
            self.out(self.s.describe(v) + (f"  ; {found.text}" if found else ""))

    def cmd_display(self, rest: str) -> None:
        if not rest:
            self.out("displayed: " + (", ".join(self.displays) or "none"))
            return
        for name in rest.replace(",", " ").split():
            self.s.view(name)
            if name not in self.displays:
                self.displays.append(name)
        self.cmd_print(rest)

    def cmd_undisplay(self, rest: str) -> None:
        self.displays = [d for d in self.displays if rest and d not in rest.replace(",", " ").split()]
        self.out("displayed: " + (", ".join(self.displays) or "none"))

    def _assign(self, rest: str):
        name, eq, value = rest.partition("=")
        if not eq or not name.strip() or not value.strip():
            raise DebugError("give DEV=VALUE, e.g. X0=1 or D0=K100")
        view = self.s.view(name.strip())
        return view, self.s.value_for(view, value.strip())

    def cmd_force(self, rest: str) -> None:
        self._not_faulted()
        for item in rest.split() or [""]:
            view, value = self._assign(item)
            self.s.force(view, value)
            self.out(f"forced {view.name}={value}")

    def cmd_write(self, rest: str) -> None:
        self._not_faulted()
        for item in rest.split() or [""]:
            view, value = self._assign(item)
            self.s.write(view, value)
            self.out(f"wrote {view.name}={value}")

    def cmd_release(self, rest: str) -> None:
        self._not_faulted()
        if not rest:
            raise DebugError("release DEV")
        for name in rest.replace(",", " ").split():
            view = self.s.view(name)
            self.s.release(view)
            self.out(f"released {view.name}")

    def _not_faulted(self) -> None:
        if self.s.fault is not None:
            raise DebugError("the program faulted here: go back (back, goto) first")

    def cmd_back(self, rest: str) -> None:
        if rest == "scan":
            self.report(self.s.back_scan())
        elif not rest:
            self.report(self.s.back())
        else:
            raise DebugError("back or back scan")

    def cmd_reverse_continue(self, rest: str) -> None:
        self.report(self.s.reverse_continue())

    def cmd_goto(self, rest: str) -> None:
        if not rest:
            raise DebugError("goto SCAN (a scan number)")
        self.report(self.s.goto_scan(self.s.scan_number(rest)))

    def cmd_diff(self, rest: str) -> None:
        parts = rest.split()
        if len(parts) != 2:
            raise DebugError("diff SCAN_A SCAN_B")
        a, b = (self.s.scan_number(p) for p in parts)
        for k in (a, b):
            if self.s.fault_pos is not None and k > self.s.fault_pos[0]:
                raise DebugError(f"scan {k} is after the fault")
        changes = self.s.changed_between(a, b)
        if not changes:
            self.out(f"no device changed between scan {a} and scan {b}")
        for name, x, y in changes:
            self.out(f"{name}: {x or 0} -> {y or 0}")

    def cmd_where(self, rest: str) -> None:
        self.out(self.s.where())
        if self.s.sim.forces:
            self.out("forced: " + ", ".join(f"{v.name}={x}" for v, x in self.s.sim.forces.items()))

    def cmd_rung(self, rest: str) -> None:
        from mlctool.debug.rung import rung_text

        self.out(rung_text(self.s))

    def cmd_save(self, rest: str) -> None:
        from mlctool.debug.stimfile import save_stimulus

        self.out(save_stimulus(self.s, rest))

    def cmd_help(self, rest: str) -> None:
        self.out(HELP)

    @contextlib.contextmanager
    def ctrl_c_ends_moves(self):
        """Within the block, SIGINT (Ctrl-C) ends the move running (`step 99999999`, `goto N`,
        `diff 0 N`, `reverse-continue`) and comes back to the prompt, as in gdb, instead of
        ending the debugger: every long move looks at the poll hook between two scans (and
        every few thousand instructions inside one), so one Ctrl-C is enough; more of them,
        during the move or between two commands, change nothing more. Main thread only."""
        pressed = self._ctrl_c = []  # execute() empties it: a Ctrl-C between two commands is for none

        def poll() -> None:
            if pressed:
                pressed.clear()
                raise Interrupted

        previous = signal.signal(signal.SIGINT, lambda signum, frame: pressed.append(signum))
        self.s.poll = poll
        try:
            yield
        finally:
            self.s.poll = None
            self._ctrl_c = None
            signal.signal(signal.SIGINT, previous)

    # -- reading lines ------------------------------------------------------------------
    def run_lines(self, lines: Iterable[str]) -> None:
        """A script, one command a line: Ctrl-C ends the command running, not the session."""
        with self.ctrl_c_ends_moves():
            for line in lines:
                if not self.execute(line):
                    break

    def completions(self) -> list[str]:
        words = list(COMMANDS) + [v.name for v in self.s.program_views()] + list(self.s.symbols)
        return sorted(set(words))


def interactive(console: Console) -> None:
    """prompt-toolkit on a terminal; a plain line reader otherwise."""
    if not sys.stdin.isatty():
        console.run_lines(sys.stdin)
        return
    try:
        from prompt_toolkit import PromptSession
        from prompt_toolkit.completion import WordCompleter
        from prompt_toolkit.history import InMemoryHistory
    except ImportError:  # pragma: no cover - a dependency
        console.run_lines(sys.stdin)
        return
    session = PromptSession(history=InMemoryHistory(),
                            completer=WordCompleter(console.completions(), ignore_case=True, sentence=False))
    console.out(f"mlc debug: {console.s.where()} (help lists the commands)")
    with console.ctrl_c_ends_moves():
        while True:
            try:
                line = session.prompt("(mlc) ")
            except KeyboardInterrupt:  # Ctrl-C at the prompt: a new line, as in gdb
                continue
            except EOFError:
                break
            if not console.execute(line):
                break


__all__ = ["BOUNDARY", "Console", "interactive"]
