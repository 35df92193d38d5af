"""Screenshots for docs/editor.md, made from real answers (CI runs this: .ci/run).

    python tools/editor_screenshots.py OUT_DIR

Into OUT_DIR (created; nothing else is touched):
- ladder.html, ladder.png: what "mlc: show ladder" on src/conveyor.il of samples/project puts
  in its webview (`mlc ladder` of the project's sources, `--title conveyor.il`), in headless
  chromium.
- editor.html, editor.png: samples/project/src/conveyor.il with one typo (SETT) and one coil
  written twice, as `mlc lsp` answers for it: the colours are its semantic tokens, the
  squiggles and the problems list its published diagnostics, the box its hover on START.

Without chromium (/usr/bin/chromium, Debian's package) the HTML is written and the PNGs are
not: the script says so and exits 0. The sample is copied to a temporary folder first.
"""

from __future__ import annotations

import asyncio
import html
import os
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "project"
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-dev-shm-usage", "--hide-scrollbars"]
TYPO = ("SET     PICKING", "SETT    PICKING")  # an unknown instruction (E201, did you mean SET)
TWICE = ("OUT     Y7", "OUT     CONVEYOR")  # the conveyor coil written twice (a warning)
HOVER_ON = "LD      START"  # hover on START of this line
SHOWN_LINES = (16, 50)  # the part of the file drawn (1-based, inclusive)
COLOURS = {"keyword": "#569cd6", "macro": "#c586c0", "variable": "#9cdcfe", "number": "#b5cea8",
           "string": "#ce9178", "label": "#dcdcaa", "comment": "#6a9955"}


def browser() -> str | None:
    return next((p for p in map(shutil.which, ("chromium", "chromium-browser")) if p), None)


def screenshot(exe: str, page: Path, png: Path, size: str, home: Path) -> None:
    r = subprocess.run([exe, *FLAGS, f"--user-data-dir={home / ('profile-' + png.stem)}", f"--screenshot={png}",
                        f"--window-size={size}", page.resolve().as_uri()],
                       capture_output=True, text=True, timeout=120, env={**os.environ, "HOME": str(home)})
    if r.returncode != 0 or not png.exists() or png.read_bytes()[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"error: chromium made no screenshot of {page}: {r.stderr[-1000:]}")


async def server_answers(project: Path, text: str) -> dict:
    """What `mlc lsp` says about conveyor.il holding `text`: diagnostics, semantic tokens, hover."""
    from lsprotocol import types as lsp
    from pygls.lsp.client import LanguageClient

    client = LanguageClient("screenshots", "1")
    published: asyncio.Queue = asyncio.Queue()
    uri = (project / "src" / "conveyor.il").as_uri()

    @client.feature(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def diagnostics(params: lsp.PublishDiagnosticsParams) -> None:
        if params.uri == uri:
            published.put_nowait(params.diagnostics)

    await client.start_io(sys.executable, "-m", "mlctool", "lsp")
    try:
        init = await client.initialize_async(lsp.InitializeParams(
            capabilities=lsp.ClientCapabilities(), root_uri=project.as_uri()))
        client.initialized(lsp.InitializedParams())
        client.text_document_did_open(lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(uri, "il", 1, text)))
        diags = await asyncio.wait_for(published.get(), 60)
        doc = lsp.TextDocumentIdentifier(uri)
        tokens = await client.text_document_semantic_tokens_full_async(lsp.SemanticTokensParams(doc))
        line = next(k for k, t in enumerate(text.split("\n")) if t.startswith(HOVER_ON))
        hover = await client.text_document_hover_async(lsp.HoverParams(doc, lsp.Position(line, 9)))
        await client.shutdown_async(None)
        client.exit(None)
    finally:
        await client.stop()
    return {"diagnostics": diags, "tokens": tokens.data, "legend": init.capabilities.semantic_tokens_provider.legend,
            "hover": hover, "hover_line": line}


def _markdown(text: str) -> str:
    """The little markdown mlc's hovers use: paragraphs, **bold**, `code`, - items."""
    out = []
    for para in text.split("\n\n"):
        if para.strip() == "---":
            out.append("<hr>")
            continue
        p = html.escape(para)
        p = re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", p)
        p = re.sub(r"`(.+?)`", r"<code>\1</code>", p)
        out.append(f"<p>{p}</p>")
    return "".join(out)


def editor_html(text: str, answers: dict, project: Path) -> str:
    """The editor's view: `project`'s (temporary) folder is dropped from the messages."""
    lines = text.split("\n")
    legend = answers["legend"]
    spans: dict[int, list[tuple[int, int, str]]] = {}  # line -> (start, end, css colour)
    line = col = 0
    data = answers["tokens"]
    for k in range(0, len(data), 5):
        dline, dcol, length, type_, _mods = data[k:k + 5]
        line += dline
        col = col + dcol if dline == 0 else dcol
        spans.setdefault(line, []).append((col, col + length, COLOURS.get(legend.token_types[type_], "#d4d4d4")))
    squiggles: dict[int, list[tuple[int, int, int]]] = {}
    for d in answers["diagnostics"]:
        squiggles.setdefault(d.range.start.line, []).append((d.range.start.character, d.range.end.character,
                                                             d.severity))
    first, last = SHOWN_LINES
    rows = []
    for n in range(first - 1, min(last, len(lines))):
        raw = lines[n]
        marks = ["#d4d4d4"] * len(raw)
        for start, end, colour in spans.get(n, []):
            marks[start:end] = [colour] * (end - start)
        under = [0] * len(raw)
        for start, end, severity in squiggles.get(n, []):
            under[start:max(end, start + 1)] = [severity] * (max(end, start + 1) - start)
        cells, k = [], 0
        while k < len(raw):
            j = k
            while j < len(raw) and marks[j] == marks[k] and under[j] == under[k]:
                j += 1
            cls = {1: ' class="err"', 2: ' class="warn"'}.get(under[k], "")
            cells.append(f'<span style="color:{marks[k]}"{cls}>{html.escape(raw[k:j])}</span>')
            k = j
        rows.append(f'<div class="row"><span class="no">{n + 1}</span><span class="code">{"".join(cells)}</span></div>')
        if n == answers["hover_line"] and answers["hover"] is not None:
            rows.append(f'<div class="hover">{_markdown(answers["hover"].contents.value)}</div>')
    severity = {1: "error", 2: "warning", 3: "info", 4: "hint"}
    problems = "".join(
        f'<div class="problem {severity[d.severity]}"><b>{severity[d.severity]}</b> [{html.escape(str(d.code))}] '
        f'{html.escape(d.message.splitlines()[0].replace(str(project) + "/", ""))} <span class="at">conveyor.il:{d.range.start.line + 1}:'
        f'{d.range.start.character + 1}</span></div>' for d in answers["diagnostics"])
    return f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>conveyor.il in an editor, as mlc lsp answers</title>
<style>
body {{ margin: 0; background: #1e1e1e; color: #d4d4d4; font: 14px/1.45 "DejaVu Sans Mono", monospace; }}
.tab {{ background: #252526; padding: 6px 14px; color: #fff; border-bottom: 1px solid #333; }}
.row {{ white-space: pre; }}
.no {{ display: inline-block; width: 3.5em; color: #858585; text-align: right; padding-right: 1.2em; }}
.err {{ text-decoration: underline wavy #f14c4c; }}
.warn {{ text-decoration: underline wavy #cca700; }}
.hover {{ margin: 2px 0 4px 9em; max-width: 640px; background: #252526; border: 1px solid #454545;
         padding: 2px 10px; font: 13px/1.4 sans-serif; white-space: normal; }}
.hover p {{ margin: 5px 0; }} .hover code {{ font-family: monospace; color: #ce9178; }}
.panel {{ border-top: 1px solid #444; margin-top: 8px; padding: 6px 14px; font: 13px/1.5 sans-serif; }}
.problem.error b {{ color: #f14c4c; }} .problem.warning b {{ color: #cca700; }} .at {{ color: #858585; }}
</style></head><body>
<div class="tab">conveyor.il (lines {first}-{last})</div>
{"".join(rows)}
<div class="panel"><b>PROBLEMS</b>{problems}</div>
</body></html>
"""


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__.strip().split("\n\n")[1], file=sys.stderr)
        return 2
    out = Path(argv[0])
    out.mkdir(parents=True, exist_ok=True)
    exe = browser()
    with tempfile.TemporaryDirectory(prefix="mlc-shots-") as scratch:
        project = Path(scratch) / "project"
        shutil.copytree(SAMPLE, project, ignore=shutil.ignore_patterns("build"))
        ladder = out / "ladder.html"
        # as the extension's ladderFiles(): conveyor.il is one of the project's sources, so all of them
        sources = tomllib.loads((project / "mlc.toml").read_text("utf-8"))["sources"]
        r = subprocess.run([sys.executable, "-m", "mlctool", "ladder", *sources, "-o", str(ladder.resolve()),
                            "--title", "conveyor.il"], cwd=project, capture_output=True, text=True, timeout=120)
        if r.returncode != 0:
            raise SystemExit(f"error: mlc ladder failed: {r.stderr}")
        text = (project / "src" / "conveyor.il").read_text("utf-8").replace(*TYPO).replace(*TWICE)
        answers = asyncio.run(server_answers(project, text))
        page = out / "editor.html"
        page.write_text(editor_html(text, answers, project), "utf-8")
        if exe is None:
            print("note: chromium is not installed: HTML written, no screenshots", file=sys.stderr)
            return 0
        screenshot(exe, ladder, out / "ladder.png", "1200,900", Path(scratch))
        screenshot(exe, page, out / "editor.png", "1100,1050", Path(scratch))
    print(f"wrote {out}/ladder.png, {out}/editor.png")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
