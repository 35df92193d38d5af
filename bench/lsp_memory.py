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
import time

from lsprotocol import types as lsp

sys.path.insert(0, os.path.dirname(__file__))
from lsp_speed import editor  # noqa: E402

GOAL_MB = 20
WARM = 10  # edits before the first reading: the memo and the caches filled


def rss_mb(pid: int) -> float:
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS")


async def measure(lines: int, edits: int) -> tuple[float, float, float]:
    first = 0.0
    async with editor(lines) as ed:
        started = time.perf_counter()
        for version in range(2, edits + 2):
            await ed.insert(version, 5 + version % 1000, f"; edit {version}\n")
            await ed.client.text_document_semantic_tokens_full_async(
                lsp.SemanticTokensParams(lsp.TextDocumentIdentifier(ed.uri)))
            if version == WARM + 1:
                first = rss_mb(ed.pid)
        last = rss_mb(ed.pid)
        seconds = time.perf_counter() - started
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
