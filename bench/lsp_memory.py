"""`mlc lsp`: memory over many edits of a 10k-line file (issue 30.12; goal: 1,000 edits grow
the server by less than 20 MB).

A real server process (python -m mlctool lsp) and a pygls client over stdio, as in
bench/lsp_speed.py: open a generated 10k-line module, then edit it EDITS times (a comment
line inserted, a different place each time), waiting each time for the diagnostics of the
new version and asking for the semantic tokens, as an editor does. Prints the server's
resident memory (Linux: /proc) after the first 10 edits and at the end. Before the fix the
checks froze every analysis (gc.freeze) and the server grew about 1.4 MB an edit.
Run: .venv/bin/python bench/lsp_memory.py [LINES] [EDITS]   (about 5 minutes for 1,000)
"""

from __future__ import annotations

import asyncio
import os
import sys
import tempfile
import time

from lsprotocol import types as lsp
from pygls.lsp.client import LanguageClient

sys.path.insert(0, os.path.dirname(__file__))
from lsp_speed import ten_k_lines  # noqa: E402

GOAL_MB = 20
WARM = 10  # edits before the first reading: the memo and the caches filled


def rss_mb(pid: int) -> float:
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS")


async def measure(lines: int, edits: int) -> tuple[float, float, float]:
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "mlc.toml"), "w") as f:
            f.write('target = "nc5"\nsources = ["main.il"]\n')
        path = os.path.join(d, "main.il")
        text = ten_k_lines(lines)
        with open(path, "w") as f:
            f.write(text)
        uri = "file://" + path
        client = LanguageClient("lsp-bench", "1")
        waiting: dict[int, asyncio.Future] = {}

        @client.feature(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def on_diagnostics(params: lsp.PublishDiagnosticsParams) -> None:
            fut = waiting.pop(params.version, None) if params.uri == uri else None
            if fut is not None and not fut.done():
                fut.set_result(None)

        await client.start_io(sys.executable, "-m", "mlctool", "lsp")
        await client.initialize_async(lsp.InitializeParams(capabilities=lsp.ClientCapabilities(),
                                                           root_uri="file://" + d))
        client.initialized(lsp.InitializedParams())
        loop = asyncio.get_running_loop()
        waiting[1] = loop.create_future()
        client.text_document_did_open(lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(uri, "il", 1, text)))
        await asyncio.wait_for(waiting[1], 60)
        pid = client._server.pid  # pygls keeps the server process there
        first = 0.0
        started = time.perf_counter()
        for version in range(2, edits + 2):
            line = 5 + version % 1000
            waiting[version] = fut = loop.create_future()
            client.text_document_did_change(lsp.DidChangeTextDocumentParams(
                lsp.VersionedTextDocumentIdentifier(version, uri),
                [lsp.TextDocumentContentChangePartial(
                    lsp.Range(lsp.Position(line, 0), lsp.Position(line, 0)), f"; edit {version}\n")]))
            await asyncio.wait_for(fut, 60)
            await client.text_document_semantic_tokens_full_async(
                lsp.SemanticTokensParams(lsp.TextDocumentIdentifier(uri)))
            if version == WARM + 1:
                first = rss_mb(pid)
        last = rss_mb(pid)
        seconds = time.perf_counter() - started
        await client.shutdown_async(None)
        client.exit(None)
        await client.stop()
        return first, last, seconds


def main() -> None:
    lines = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
    edits = int(sys.argv[2]) if len(sys.argv) > 2 else 1_000
    first, last, seconds = asyncio.run(measure(lines, edits))
    grown = last - first
    print(f"lsp memory, {lines} lines, {edits} edits ({seconds:.0f} s): server RSS {first:.0f} MB after "
          f"{WARM} edits, {last:.0f} MB at the end: {grown:+.1f} MB (goal under {GOAL_MB} MB) "
          f"{'ok' if grown < GOAL_MB else 'MISSED'}")


if __name__ == "__main__":
    main()
