"""`mlc lsp` memory stays flat over edits (issue 30.12): a check that froze the objects
alive (gc.freeze after every check) kept every earlier analysis's reference cycles from the
collector, 1.4 MB an edit of a 10k-line file (58 -> 472 MB after 300 edits).

The test drives the editor's view as the server does on every didChange (mlctool/lsp/
server.py: Workspace.open with the new text, the analysis, its diagnostics, the semantic
tokens the editor asks for next) over 20 edits of a 1,000-line file, and counts the memory
blocks Python holds after a full collection (sys.getallocatedblocks: exact and free, where
tracemalloc made the test 40 times slower; a full collection does not reach frozen objects,
so the leak shows through it). Before the fix: 2,700 blocks more an edit; now about one
(CheckMemo keeps each new line's text). The acceptance figure in bytes (1,000 edits of a
10k-line file under 20 MB) is measured on a real server by bench/lsp_memory.py."""

from __future__ import annotations

import gc
import sys

from mlctool.lsp import features
from mlctool.lsp.project import Workspace


def program(lines: int) -> list[str]:
    """A valid nc5 program of about `lines` lines: rungs of contacts, coils, moves and timers."""
    out: list[str] = []
    k = 0
    while len(out) < lines - 1:
        out += [f"LD X{k % 256}", f"AND M{k % 1000}", f"OUT Y{k % 256}", f"MOV K{k} D{k % 1000}",
                f"LDP M{(k + 7) % 1000}", f"TMR T{k % 256} K{k % 100 + 1}"]
        k += 1
    return out + ["END"]


def edits(workspace: Workspace, path: str, lines: list[str], n: int, first: int = 0) -> None:
    for k in range(first, first + n):
        text = list(lines)
        text.insert(5 + k % 100, f"; edit {k}")  # a different line each time: the text really changes
        workspace.open(path, "\n".join(text) + "\n")
        a = workspace.analysis(path)
        assert not a.result.errors
        assert a.diagnostics_of(path) is not None
        assert features.semantic_tokens(a, path)


def test_memory_stays_flat_over_edits(tmp_path):
    (tmp_path / "mlc.toml").write_text('target = "nc5"\n')
    path = str(tmp_path / "big.il")
    lines = program(1000)
    (tmp_path / "big.il").write_text("\n".join(lines) + "\n")
    workspace = Workspace()
    edits(workspace, path, lines, 5)  # warm: the memo and the caches filled
    gc.collect()
    before = sys.getallocatedblocks()
    edits(workspace, path, lines, 20, first=5)
    gc.collect()
    grown = sys.getallocatedblocks() - before
    assert grown < 20 * 10, f"{grown} memory blocks more after 20 edits of a 1,000-line file"
