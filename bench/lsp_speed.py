"""`mlc lsp`: time from a didChange of a 10k-line file to its publishDiagnostics (goal 200 ms).

A real server process (python -m mlctool lsp) and a pygls client over stdio, as an editor
talks to it: open a generated 10k-line project module, then edit one line several times and
wait each time for the diagnostics of the new version. Prints the median and the worst.
Run: .venv/bin/python bench/lsp_speed.py [LINES]
"""

from __future__ import annotations

import asyncio
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


async def measure(lines: int) -> list[float]:
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "mlc.toml"), "w") as f:
            f.write('target = "nc5"\nsources = ["main.il"]\n')
        path = os.path.join(d, "main.il")
        text = ten_k_lines(lines)
        with open(path, "w") as f:
            f.write(text)
        uri = "file://" + path
        client = LanguageClient("lsp-bench", "1")
        arrived: dict[int, float] = {}
        waiting: dict[int, asyncio.Future] = {}

        @client.feature(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def on_diagnostics(params: lsp.PublishDiagnosticsParams) -> None:
            if params.uri == uri and params.version is not None:
                arrived[params.version] = time.perf_counter()
                fut = waiting.pop(params.version, None)
                if fut is not None and not fut.done():
                    fut.set_result(None)

        await client.start_io(sys.executable, "-m", "mlctool", "lsp")
        await client.initialize_async(lsp.InitializeParams(capabilities=lsp.ClientCapabilities(),
                                                           root_uri="file://" + d))
        client.initialized(lsp.InitializedParams())
        loop = asyncio.get_running_loop()
        waiting[1] = loop.create_future()
        client.text_document_did_open(lsp.DidOpenTextDocumentParams(
            lsp.TextDocumentItem(uri, "il", 1, text)))
        await asyncio.wait_for(waiting[1], 60)
        times = []
        for version in range(2, EDITS + 2):
            line = 5 + version  # a different contact each time: the text really changes
            waiting[version] = loop.create_future()
            fut = waiting[version]
            start = time.perf_counter()
            client.text_document_did_change(lsp.DidChangeTextDocumentParams(
                lsp.VersionedTextDocumentIdentifier(version, uri),
                [lsp.TextDocumentContentChangePartial(
                    lsp.Range(lsp.Position(line, 0), lsp.Position(line, 0)), "; edited\n")]))
            await asyncio.wait_for(fut, 60)
            times.append(arrived[version] - start)
        await client.shutdown_async(None)
        client.exit(None)
        await client.stop()
        return times


def main() -> None:
    lines = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
    times = asyncio.run(measure(lines))
    ms = [t * 1000 for t in times]
    print(f"lsp didChange -> publishDiagnostics, {lines} lines, {len(ms)} edits: "
          f"median {statistics.median(ms):.0f} ms, worst {max(ms):.0f} ms (goal 200 ms)")


if __name__ == "__main__":
    main()
