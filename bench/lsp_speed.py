"""`mlc lsp`: time from a didChange of a 10k-line file to its publishDiagnostics (goal 200 ms).

A real server process (python -m mlctool lsp) and a pygls client over stdio, as an editor
talks to it: open a generated 10k-line project module, then edit one line several times and
wait each time for the diagnostics of the new version. Prints the median and the worst of
the wall time (what the user waits) and of the server's CPU time per edit (Linux: from
/proc; steadier on a shared machine, where the wall time includes waiting for a core).
Run: .venv/bin/python bench/lsp_speed.py [LINES] [ROUNDS]
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import statistics
import sys
import tempfile
import time

from lsprotocol import types as lsp
from pygls.lsp.client import LanguageClient

sys.path.insert(0, os.path.dirname(__file__))
from gen import program  # noqa: E402

EDITS = 10


def ten_k_lines(lines: int) -> str:
    text = program(lines * 2)  # about two steps a line
    return "\n".join(text.split("\n")[:lines - 1]) + "\nEND\n"


def cpu_seconds(pid: int) -> float:
    """CPU time (user + system) of a process so far; 0.0 where /proc is not there."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


class Editor:
    """A server process (python -m mlctool lsp) and a pygls client, as an editor talks to it,
    on a temporary nc5 project of one generated module (`editor()` opens it)."""

    def __init__(self, client: LanguageClient, uri: str):
        self.client, self.uri = client, uri
        self.pid = 0
        self.arrived: dict[int, float] = {}  # version -> when its diagnostics arrived (perf_counter)
        self.waiting: dict[int, asyncio.Future] = {}

    def diagnostics(self, params: lsp.PublishDiagnosticsParams) -> None:
        if params.uri == self.uri and params.version is not None:
            self.arrived[params.version] = time.perf_counter()
            fut = self.waiting.pop(params.version, None)
            if fut is not None and not fut.done():
                fut.set_result(None)

    async def until_diagnostics(self, version: int, send) -> None:
        """send() (a notification making `version`), then wait for that version's diagnostics."""
        self.waiting[version] = fut = asyncio.get_running_loop().create_future()
        send()
        await asyncio.wait_for(fut, 60)

    async def insert(self, version: int, line: int, text: str) -> None:
        """Insert `text` at the start of `line` (the document becomes `version`) and wait for
        the diagnostics of that version."""
        await self.until_diagnostics(version, lambda: self.client.text_document_did_change(
            lsp.DidChangeTextDocumentParams(
                lsp.VersionedTextDocumentIdentifier(version, self.uri),
                [lsp.TextDocumentContentChangePartial(lsp.Range(lsp.Position(line, 0), lsp.Position(line, 0)),
                                                      text)])))


@contextlib.asynccontextmanager
async def editor(lines: int):
    """An Editor with the generated `lines`-line module open and its first diagnostics arrived."""
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "mlc.toml"), "w") as f:
            f.write('target = "nc5"\nsources = ["main.il"]\n')
        path = os.path.join(d, "main.il")
        text = ten_k_lines(lines)
        with open(path, "w") as f:
            f.write(text)
        client = LanguageClient("lsp-bench", "1")
        ed = Editor(client, "file://" + path)

        @client.feature(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def on_diagnostics(params: lsp.PublishDiagnosticsParams) -> None:  # (pygls takes no bound method)
            ed.diagnostics(params)

        await client.start_io(sys.executable, "-m", "mlctool", "lsp")
        await client.initialize_async(lsp.InitializeParams(capabilities=lsp.ClientCapabilities(),
                                                           root_uri="file://" + d))
        client.initialized(lsp.InitializedParams())
        await ed.until_diagnostics(1, lambda: client.text_document_did_open(
            lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(ed.uri, "il", 1, text))))
        ed.pid = client._server.pid  # pygls keeps the server process there
        yield ed
        await client.shutdown_async(None)
        client.exit(None)
        await client.stop()


async def measure(lines: int) -> tuple[list[float], list[float]]:
    times, cpu = [], []
    async with editor(lines) as ed:
        for version in range(2, EDITS + 2):
            # a different contact each time: the text really changes
            start, used = time.perf_counter(), cpu_seconds(ed.pid)
            await ed.insert(version, 5 + version, "; edited\n")
            times.append(ed.arrived[version] - start)
            cpu.append(cpu_seconds(ed.pid) - used)
    return times, cpu


def main() -> None:
    lines = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    for _ in range(rounds):
        times, cpu = asyncio.run(measure(lines))
        ms = [t * 1000 for t in times]
        cpu_ms = [t * 1000 for t in cpu]
        print(f"lsp didChange -> publishDiagnostics, {lines} lines, {len(ms)} edits: "
              f"median {statistics.median(ms):.0f} ms, worst {max(ms):.0f} ms (goal 200 ms); "
              f"server CPU per edit: median {statistics.median(cpu_ms):.0f} ms, worst {max(cpu_ms):.0f} ms")


if __name__ == "__main__":
    main()
