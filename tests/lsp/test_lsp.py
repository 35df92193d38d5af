"""`mlc lsp` end to end: a real server process and a pytest-lsp client, on a copy of
samples/project (two modules: conveyor.il CALLs P10/P11 exported by pickplace.il)."""

from __future__ import annotations

import asyncio
import re
import shutil
import sys
from pathlib import Path

import pytest

# a checkout whose .venv predates pygls/pytest-lsp (pyproject [test]) skips until reinstalled
pytest_lsp = pytest.importorskip("pytest_lsp")
from lsprotocol import types as lsp  # noqa: E402
from pytest_lsp import ClientServerConfig, LanguageClient  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest.fixture(scope="module")
def project(tmp_path_factory) -> Path:
    ws = tmp_path_factory.mktemp("lsp") / "project"
    shutil.copytree(ROOT / "samples" / "project", ws, ignore=shutil.ignore_patterns("build"))
    return ws


@pytest_lsp.fixture(scope="module", config=ClientServerConfig(
    server_command=[sys.executable, "-m", "mlctool", "lsp"]))
async def client(lsp_client: LanguageClient, project: Path):
    handlers = lsp_client.protocol.fm.features  # pytest-lsp's handler, and the version kept too
    keep = handlers[lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS]

    def diagnostics(params: lsp.PublishDiagnosticsParams) -> None:
        keep(params)
        _published[params.uri] = params.version

    handlers[lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = diagnostics

    result = await lsp_client.initialize_session(lsp.InitializeParams(
        capabilities=lsp.ClientCapabilities(), root_uri=project.as_uri()))
    _capabilities.append(result.capabilities)
    yield
    await lsp_client.shutdown_session()


def _uri(project: Path, name: str) -> str:
    return (project / "src" / name).as_uri()


_capabilities: list[lsp.ServerCapabilities] = []  # the server's answer to initialize
_versions: dict[str, int] = {}  # uri -> the version last sent
_published: dict[str, int | None] = {}  # uri -> the version of the diagnostics last received


async def _show(client: LanguageClient, uri: str, text: str) -> list[lsp.Diagnostic]:
    """Open (or replace) a document and wait for its diagnostics."""
    version = _versions.get(uri, 0) + 1
    _versions[uri] = version
    if version == 1:
        client.text_document_did_open(lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(uri, "il", version, text)))
    else:
        client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(version, uri), [lsp.TextDocumentContentChangeWholeDocument(text)]))
    for _ in range(3000):  # the server publishes every module of the project: this version's
        if _published.get(uri) == version:
            return list(client.diagnostics[uri])
        await asyncio.sleep(0.01)
    raise AssertionError(f"no diagnostics for version {version} of {uri} within 30 s")


def _text(project: Path, name: str) -> str:
    return (project / "src" / name).read_text()


def _line_of(text: str, needle: str) -> int:
    """The first line that starts with `needle` (0-based, as the protocol counts)."""
    return next(k for k, line in enumerate(text.split("\n")) if line.startswith(needle))


async def test_diagnostics_match_mlc_check(client: LanguageClient, project: Path):
    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    assert await _show(client, uri, text) == []  # the sample is clean, as `mlc check` says
    bad = text.replace("OUT     CONVEYOR", "OUTT    CONVEYOR")
    diags = await _show(client, uri, bad)
    assert [(d.code, d.range.start.line, d.severity) for d in diags] == [
        ("E201", _line_of(bad, "OUTT"), lsp.DiagnosticSeverity.Error)]
    assert "did you mean OUT" in diags[0].message
    await _show(client, uri, text)


async def test_an_exported_label_removed_shows_in_the_other_module(client: LanguageClient, project: Path):
    conveyor, pickplace = _uri(project, "conveyor.il"), _uri(project, "pickplace.il")
    await _show(client, conveyor, _text(project, "conveyor.il"))
    text = _text(project, "pickplace.il")
    await _show(client, pickplace, text.replace(".export P10 P11", ".export P11"))
    # the main module's CALL P10 has no target any more: published for conveyor.il too
    codes = {d.code for d in client.diagnostics[conveyor]}
    assert codes, "conveyor.il got no diagnostics after P10 stopped being exported"
    await _show(client, pickplace, text)
    assert not client.diagnostics[conveyor]


async def test_hover_instruction_device_and_symbol(client: LanguageClient, project: Path):
    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    await _show(client, uri, text)
    line = _line_of(text, "LD      START")
    h = await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(uri), lsp.Position(line, 1)))
    assert "2.2 LD" in h.contents.value and "Steps: 1~2" in h.contents.value and "`S`" in h.contents.value
    h = await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(uri), lsp.Position(line, 10)))
    value = h.contents.value
    assert "**START** = `X0`" in value and "on-board input" in value
    assert f"Read at: src/conveyor.il:{line + 1}" in value
    # a device written in the library and read in the main program: both named
    line = _line_of(text, "OUT     CONVEYOR")
    h = await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(uri), lsp.Position(line, 10)))
    assert f"Written at: src/conveyor.il:{line + 1}" in h.contents.value
    # a 32-bit instruction: both widths' steps, and what the manual says of its flags
    line = _line_of(text, "DADD")
    h = await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(uri), lsp.Position(line, 1)))
    assert "Steps: 8 (32-bit), 6 (16-bit ADD)" in h.contents.value and "no flags (旗標信號：無)" in h.contents.value


async def test_completion_mnemonics_with_snippets_and_operands(client: LanguageClient, project: Path):
    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il") + "DMO\n"
    await _show(client, uri, text)
    last = len(text.split("\n")) - 2
    got = await client.text_document_completion_async(lsp.CompletionParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(last, 3)))
    items = {i.label: i for i in got.items}
    assert items["DMOV"].insert_text == "DMOV ${1:S} ${2:D}"
    assert items["DMOV"].insert_text_format == lsp.InsertTextFormat.Snippet
    text = _text(project, "conveyor.il") + "LD      \n"
    await _show(client, uri, text)
    got = await client.text_document_completion_async(lsp.CompletionParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(last, 8)))
    labels = {i.label: i for i in got.items}
    assert {"START", "PICKED", "P10", "X", "D"} <= set(labels)
    assert "DMOV" not in labels  # an operand position offers no mnemonics
    await _show(client, uri, _text(project, "conveyor.il"))


async def test_definition_and_references_across_modules(client: LanguageClient, project: Path):
    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    await _show(client, uri, text)
    line = _line_of(text, "CALL    P10")
    got = await client.text_document_definition_async(lsp.DefinitionParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(line, 9)))
    lib = _text(project, "pickplace.il")
    assert got.uri == _uri(project, "pickplace.il") and got.range.start.line == _line_of(lib, "P10:")
    refs = await client.text_document_references_async(lsp.ReferenceParams(
        context=lsp.ReferenceContext(include_declaration=True), text_document=lsp.TextDocumentIdentifier(uri),
        position=lsp.Position(line, 9)))
    assert sorted((r.uri.rsplit("/", 1)[1], r.range.start.line) for r in refs) == sorted([
        ("conveyor.il", line), ("pickplace.il", _line_of(lib, "P10:")), ("pickplace.il", _line_of(lib, ".export"))])
    # a symbol: its .define in the same module
    use = _line_of(text, "OR      RUN")
    got = await client.text_document_definition_async(lsp.DefinitionParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(use, 9)))
    assert got.uri == uri and got.range.start.line == _line_of(text, ".define RUN")


async def test_rename_a_symbol_stays_in_its_module(client: LanguageClient, project: Path):
    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    await _show(client, uri, text)
    line = _line_of(text, ".define RUN")
    edit = await client.text_document_rename_async(lsp.RenameParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(line, 9), "LINE_RUN"))
    # pickplace.il has its own `.define RUN M0`: not this symbol
    assert set(edit.changes) == {uri}
    lines = {e.range.start.line for e in edit.changes[uri]}
    assert lines == {k for k, t in enumerate(text.split("\n")) if " RUN" in t.split(";")[0]}
    assert all(e.new_text == "LINE_RUN" for e in edit.changes[uri])
    with pytest.raises(Exception, match="reads as an operand"):
        await client.text_document_rename_async(lsp.RenameParams(
            lsp.TextDocumentIdentifier(uri), lsp.Position(line, 9), "M5"))


async def test_rename_an_exported_label_everywhere(client: LanguageClient, project: Path):
    uri = _uri(project, "pickplace.il")
    lib = _text(project, "pickplace.il")
    await _show(client, uri, lib)
    edit = await client.text_document_rename_async(lsp.RenameParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(_line_of(lib, "P11:"), 1), "P21"))
    assert set(edit.changes) == {uri, _uri(project, "conveyor.il")}
    assert len(edit.changes[_uri(project, "conveyor.il")]) == 1


async def test_formatting_is_mlc_fmt(client: LanguageClient, project: Path, tmp_path):
    from mlctool.fmt import format_source
    from mlctool.syntax.source import SourceText
    from mlctool.targetapi import load_target

    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    messy = text.replace("LD      START", "  ld START").replace("AND     GUARD", "and      GUARD")
    await _show(client, uri, messy)
    edits = await client.text_document_formatting_async(lsp.DocumentFormattingParams(
        lsp.TextDocumentIdentifier(uri), lsp.FormattingOptions(tab_size=8, insert_spaces=True)))
    expected, _ = format_source(SourceText("x.il", messy), load_target("nc5"))
    assert len(edits) == 1 and edits[0].new_text == expected == text
    await _show(client, uri, text)
    edits = await client.text_document_formatting_async(lsp.DocumentFormattingParams(
        lsp.TextDocumentIdentifier(uri), lsp.FormattingOptions(tab_size=8, insert_spaces=True)))
    assert not edits  # formatted already: nothing to change


async def test_code_actions_did_you_mean_and_noqa(client: LanguageClient, project: Path):
    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    bad = text.replace("OUT     CONVEYOR", "OUTT    CONVEYOR")
    diags = await _show(client, uri, bad)
    line = _line_of(bad, "OUTT")
    actions = await client.text_document_code_action_async(lsp.CodeActionParams(
        lsp.TextDocumentIdentifier(uri), lsp.Range(lsp.Position(line, 0), lsp.Position(line, 4)),
        lsp.CodeActionContext(diagnostics=diags)))
    fix = next(a for a in actions if a.title == "Replace with OUT")
    (edit,) = fix.edit.changes[uri]
    assert (edit.range.start.character, edit.range.end.character, edit.new_text) == (0, 4, "OUT")
    # a warning: two OUTs of one coil (W-code) can be silenced on its line
    warned = text.replace("OUT     Y7", "OUT     CONVEYOR")
    diags = await _show(client, uri, warned)
    warnings = [d for d in diags if d.severity == lsp.DiagnosticSeverity.Warning]
    assert warnings
    w = warnings[0]
    actions = await client.text_document_code_action_async(lsp.CodeActionParams(
        lsp.TextDocumentIdentifier(uri), w.range, lsp.CodeActionContext(diagnostics=[w])))
    noqa = next(a for a in actions if "noqa" in a.title)
    (edit,) = noqa.edit.changes[uri]
    assert edit.new_text == f"  ; mlc: noqa {w.code}"
    lines = warned.split("\n")
    k = edit.range.start.line
    lines[k] = lines[k][:edit.range.start.character] + edit.new_text + lines[k][edit.range.start.character:]
    after = await _show(client, uri, "\n".join(lines))
    assert not [d for d in after if d.code == w.code and d.range.start.line == k]
    await _show(client, uri, text)


async def test_document_symbols(client: LanguageClient, project: Path):
    uri = _uri(project, "pickplace.il")
    lib = _text(project, "pickplace.il")
    await _show(client, uri, lib)
    symbols = await client.text_document_document_symbol_async(lsp.DocumentSymbolParams(
        lsp.TextDocumentIdentifier(uri)))
    by_name = {s.name: s for s in symbols}
    assert {"P10", "P11", "STEP", "DONE"} <= set(by_name)
    assert by_name["P10"].kind == lsp.SymbolKind.Function
    rungs = [c.name for c in by_name["P10"].children]
    assert any(r.startswith("step 0: lower the gripper") for r in rungs), rungs


async def test_folding_and_step_address_hints(client: LanguageClient, project: Path):
    uri = _uri(project, "pickplace.il")
    lib = _text(project, "pickplace.il")
    await _show(client, uri, lib)
    folds = await client.text_document_folding_range_async(lsp.FoldingRangeParams(lsp.TextDocumentIdentifier(uri)))
    regions = {f.start_line: f.end_line for f in folds if f.kind == lsp.FoldingRangeKind.Region}
    p10, p11 = _line_of(lib, "P10:"), _line_of(lib, "P11:")
    lines = lib.split("\n")
    assert p10 in regions and p11 in regions
    assert lines[regions[p10]].startswith("SRET") and regions[p10] < p11
    assert any(f.kind == lsp.FoldingRangeKind.Comment and f.start_line == 0 for f in folds)
    hints = await client.text_document_inlay_hint_async(lsp.InlayHintParams(
        lsp.TextDocumentIdentifier(uri), lsp.Range(lsp.Position(0, 0), lsp.Position(len(lines), 0))))
    by_line = {h.position.line: h.label for h in hints}
    # the library's first instruction (the P10 label) at step 0; addresses grow with the code
    assert by_line[p10] == "0"
    addresses = [int(by_line[k]) for k in sorted(by_line)]
    assert addresses == sorted(addresses) and addresses[-1] > 10


async def test_a_module_changed_on_disk_is_read_again(client: LanguageClient, project: Path):
    conveyor = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    assert await _show(client, conveyor, text) == []
    lib = project / "src" / "pickplace.il"
    if _versions.pop(lib.as_uri(), None):  # an earlier test opened it: the disk counts once closed
        client.text_document_did_close(lsp.DidCloseTextDocumentParams(lsp.TextDocumentIdentifier(lib.as_uri())))
    before = lib.read_text()
    try:
        lib.write_text(before.replace(".export P10 P11", ".export P11"))  # not open in the editor
        client.workspace_did_change_watched_files(lsp.DidChangeWatchedFilesParams(
            [lsp.FileEvent(lib.as_uri(), lsp.FileChangeType.Changed)]))
        for _ in range(3000):
            if client.diagnostics.get(conveyor):
                break
            await asyncio.sleep(0.01)
        assert client.diagnostics[conveyor], "the CALL P10 of conveyor.il lost its label on disk"
    finally:
        lib.write_text(before)
        client.workspace_did_change_watched_files(lsp.DidChangeWatchedFilesParams(
            [lsp.FileEvent(lib.as_uri(), lsp.FileChangeType.Changed)]))


def _decode_tokens(data: list[int], legend: lsp.SemanticTokensLegend, text: str) -> list[tuple[int, str, str, set]]:
    """The protocol's five integers per token -> (line, word, type, modifiers)."""
    lines = text.split("\n")
    out, line, col = [], 0, 0
    for k in range(0, len(data), 5):
        dline, dcol, length, type_, mods = data[k:k + 5]
        line += dline
        col = col + dcol if dline == 0 else dcol
        names = {m for b, m in enumerate(legend.token_modifiers) if mods >> b & 1}
        out.append((line, lines[line][col:col + length], legend.token_types[type_], names))
    return out


async def test_semantic_tokens(client: LanguageClient, project: Path):
    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    await _show(client, uri, text)
    legend = _capabilities[-1].semantic_tokens_provider.legend
    got = await client.text_document_semantic_tokens_full_async(lsp.SemanticTokensParams(
        lsp.TextDocumentIdentifier(uri)))
    tokens = _decode_tokens(got.data, legend, text)
    by_line: dict[int, list] = {}
    for line, word, type_, mods in tokens:
        by_line.setdefault(line, []).append((word, type_, mods))
    # a .define: the directive, the symbol declared (as the input it names), the device, the comment
    assert by_line[_line_of(text, ".define START")] == [
        (".define", "macro", set()), ("START", "variable", {"bit", "input", "symbol", "declaration"}),
        ("X0", "variable", {"bit", "input"}), ("; start push button (normally open)", "comment", set())]
    assert by_line[_line_of(text, "TMR     T0 K5")] == [
        ("TMR", "keyword", set()), ("T0", "variable", {"timer"}), ("K5", "number", set())]
    assert by_line[_line_of(text, "CNT     BATCH K20")] == [
        ("CNT", "keyword", set()), ("BATCH", "variable", {"counter", "symbol"}), ("K20", "number", set())]
    assert by_line[_line_of(text, "MOV     PICKED D100")][1:] == [
        ("PICKED", "variable", {"word", "symbol"}), ("D100", "variable", {"word"})]
    assert by_line[_line_of(text, "CALL    P10")][1] == ("P10", "label", set())
    assert by_line[_line_of(text, "P1:")] == [("P1", "label", {"declaration"})]
    assert by_line[0] == [(text.split("\n")[0], "comment", set())]
    # in document order: no token goes back (the encoding is relative to the previous one)
    deltas = [(got.data[k], got.data[k + 1]) for k in range(5, len(got.data), 5)]
    assert all(d_line >= 0 and (d_line > 0 or d_col > 0) for d_line, d_col in deltas)


async def test_workspace_symbols_across_the_modules(client: LanguageClient, project: Path):
    got = await client.workspace_symbol_async(lsp.WorkspaceSymbolParams(query=""))
    where = {(s.name, s.location.uri.rsplit("/", 1)[1], s.kind) for s in got}
    conveyor, lib = _text(project, "conveyor.il"), _text(project, "pickplace.il")
    # subroutines (a CALL names them) in both modules, a CJ target, symbols of each module
    assert {("P10", "pickplace.il", lsp.SymbolKind.Function), ("P11", "pickplace.il", lsp.SymbolKind.Function),
            ("P1", "conveyor.il", lsp.SymbolKind.Function), ("P12", "pickplace.il", lsp.SymbolKind.Key),
            ("START", "conveyor.il", lsp.SymbolKind.Constant), ("STEP", "pickplace.il", lsp.SymbolKind.Constant),
            ("RUN", "conveyor.il", lsp.SymbolKind.Constant), ("RUN", "pickplace.il", lsp.SymbolKind.Constant)} <= where
    p10 = next(s for s in got if s.name == "P10")
    assert p10.location.range.start.line == _line_of(lib, "P10:")
    assert p10.container_name == "src/pickplace.il (subroutine)"
    start = next(s for s in got if s.name == "START")
    assert start.location.range.start == lsp.Position(_line_of(conveyor, ".define START"), 8)
    # a query keeps the names holding its letters in order, case ignored
    got = await client.workspace_symbol_async(lsp.WorkspaceSymbolParams(query="pkd"))
    assert sorted({s.name for s in got}) == ["PICKED"]
    assert len(got) == 2  # one .define in each module


VS_MAIN = """; main: count on C235, an interrupt at 100 counts (isr.il's IHC0)
EI
LD      M9000
DHSCS   K100 C235 IHC0
LD      X10
OUT     C235 K999
FEND

IX0P:
LD      M9000
OUT     Y1
IRET
END
"""
VS_ISR = """; interrupt routines of the project
.library
IHC0:
LD      M9000
OUT     Y0
IRET
"""


def _vs_project(tmp_path: Path) -> Path:
    """A VS project (interrupt pointers are the VS's): the routine of IHC0 in a library module,
    the DHSCS naming it in the main one."""
    ws = tmp_path / "vsproject"
    (ws / "src").mkdir(parents=True)
    (ws / "mlc.toml").write_text('target = "vs"\nsources = ["src/main.il", "src/isr.il"]\n')
    (ws / "src" / "main.il").write_text(VS_MAIN)
    (ws / "src" / "isr.il").write_text(VS_ISR)
    return ws


async def test_workspace_symbols_include_interrupt_routines(client: LanguageClient, tmp_path: Path):
    ws = _vs_project(tmp_path)
    uri = (ws / "src" / "main.il").as_uri()
    assert await _show(client, uri, VS_MAIN) == []
    got = await client.workspace_symbol_async(lsp.WorkspaceSymbolParams(query="i"))
    found = sorted((s.name, s.kind, s.location.uri.rsplit("/", 1)[1], s.location.range.start.line) for s in got
                   if "/vsproject/" in s.location.uri)
    assert found == [("IHC0", lsp.SymbolKind.Event, "isr.il", 2), ("IX0P", lsp.SymbolKind.Event, "main.il", 8)]
    client.text_document_did_close(lsp.DidCloseTextDocumentParams(lsp.TextDocumentIdentifier(uri)))


async def test_interrupt_pointer_definition_references_rename(client: LanguageClient, tmp_path: Path):
    ws = _vs_project(tmp_path)
    main, isr = (ws / "src" / "main.il").as_uri(), (ws / "src" / "isr.il").as_uri()
    assert await _show(client, main, VS_MAIN) == []
    assert await _show(client, isr, VS_ISR) == []
    use = lsp.Position(_line_of(VS_MAIN, "DHSCS"), 20)  # on IHC0, the DHSCS's D operand
    got = await client.text_document_definition_async(lsp.DefinitionParams(lsp.TextDocumentIdentifier(main), use))
    assert (got.uri, got.range.start.line, got.range.start.character) == (isr, 2, 0)  # across modules
    refs = await client.text_document_references_async(lsp.ReferenceParams(
        context=lsp.ReferenceContext(include_declaration=True), text_document=lsp.TextDocumentIdentifier(isr),
        position=lsp.Position(2, 1)))
    assert sorted((r.uri, r.range.start.line, r.range.start.character) for r in refs) == sorted(
        [(isr, 2, 0), (main, use.line, 18)])
    h = await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(main), use))
    assert "interrupt pointer, high-speed counter compare" in h.contents.value
    assert "Routine at: src/isr.il:3" in h.contents.value
    h = await client.text_document_hover_async(lsp.HoverParams(
        lsp.TextDocumentIdentifier(main), lsp.Position(_line_of(VS_MAIN, "IX0P:"), 1)))
    assert "input X0, rising edge" in h.contents.value and "M9050" in h.contents.value
    # rename: the routine's pointer and the DHSCS operand, in both modules; the result checks clean
    edit = await client.text_document_rename_async(lsp.RenameParams(lsp.TextDocumentIdentifier(main), use, "IHC3"))
    assert {u: len(e) for u, e in edit.changes.items()} == {main: 1, isr: 1}
    renamed_main, renamed_isr = _apply(VS_MAIN, edit.changes[main]), _apply(VS_ISR, edit.changes[isr])
    assert "DHSCS   K100 C235 IHC3\n" in renamed_main and "\nIHC3:\n" in renamed_isr
    await _show(client, isr, renamed_isr)
    assert await _show(client, main, renamed_main) == []
    await _show(client, isr, VS_ISR)
    await _show(client, main, VS_MAIN)
    for new, why in (("FOO", "not an interrupt pointer"), ("IX0P", "used already"), ("IX1P", "another kind")):
        with pytest.raises(Exception, match=why):
            await client.text_document_rename_async(lsp.RenameParams(lsp.TextDocumentIdentifier(main), use, new))
    symbols = await client.text_document_document_symbol_async(lsp.DocumentSymbolParams(lsp.TextDocumentIdentifier(main)))
    assert ("IX0P", lsp.SymbolKind.Event) in [(s.name, s.kind) for s in symbols]  # an interrupt routine
    ready = await client.text_document_prepare_rename_async(lsp.PrepareRenameParams(
        lsp.TextDocumentIdentifier(isr), lsp.Position(2, 2)))
    assert (ready.start.line, ready.start.character, ready.end.character) == (2, 0, 4)
    for uri in (main, isr):
        client.text_document_did_close(lsp.DidCloseTextDocumentParams(lsp.TextDocumentIdentifier(uri)))


def _apply(text: str, edits: list[lsp.TextEdit]) -> str:
    """A client's application of one document's edits (ranges of the original text)."""
    lines = text.split("\n")
    offsets = [0]
    for line in lines:
        offsets.append(offsets[-1] + len(line) + 1)

    def at(p: lsp.Position) -> int:
        return offsets[p.line] + p.character

    for e in sorted(edits, key=lambda e: at(e.range.start), reverse=True):
        text = text[:at(e.range.start)] + e.new_text + text[at(e.range.end):]
    return text


async def _actions(client: LanguageClient, uri: str, diags: list[lsp.Diagnostic], line: int) -> list[lsp.CodeAction]:
    return await client.text_document_code_action_async(lsp.CodeActionParams(
        lsp.TextDocumentIdentifier(uri), lsp.Range(lsp.Position(line, 0), lsp.Position(line, 4)),
        lsp.CodeActionContext(diagnostics=[d for d in diags if d.range.start.line == line])))


async def test_code_action_did_you_mean_applied_clears_the_error(client: LanguageClient, project: Path):
    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    bad = text.replace("OUT     CONVEYOR", "OUTT    CONVEYOR")
    diags = await _show(client, uri, bad)
    fix = next(a for a in await _actions(client, uri, diags, _line_of(bad, "OUTT")) if a.title == "Replace with OUT")
    assert fix.is_preferred and [d.code for d in fix.diagnostics] == ["E201"]
    assert await _show(client, uri, _apply(bad, fix.edit.changes[uri])) == []
    await _show(client, uri, text)


async def test_code_action_pulse_form_on_nc5(client: LanguageClient, project: Path):
    """MOVP on NC5 (no P forms, manual 3.2.4): rewritten to LDP/MOV, or with a PLS relay."""
    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    # the rung's condition is one contact: LDP RUN / MOV (preferred) or the PLS relay
    bad = text.replace("MOV     PICKED D100", "MOVP    PICKED D100")
    diags = await _show(client, uri, bad)
    line = _line_of(bad, "MOVP")
    assert [(d.code, d.range.start.line) for d in diags] == [("E201", line)]
    assert "no P (pulse) forms" in diags[0].message
    actions = {a.title: a for a in await _actions(client, uri, diags, line)}
    ldp = actions["Rewrite as LDP RUN / MOV (once per rising edge)"]
    assert ldp.is_preferred
    fixed = _apply(bad, ldp.edit.changes[uri])
    assert fixed == text.replace("LD      RUN\nMOV     PICKED D100", "LDP     RUN\nMOV     PICKED D100")
    assert await _show(client, uri, fixed) == []
    await _show(client, uri, bad)
    pls = next(a for t, a in actions.items() if t.startswith("Rewrite with a PLS relay"))
    fixed = _apply(bad, pls.edit.changes[uri])
    assert "LD      RUN\nPLS     M14999\nLD      M14999\nMOV     PICKED D100\n" in fixed  # M14999: top of the general M area, unused
    assert await _show(client, uri, fixed) == []
    # a condition of two contacts: only the PLS relay keeps the meaning
    bad = text.replace("LD      X4\nRST     BATCH", "LD      X4\nAND     RUN\nRSTP    BATCH")
    diags = await _show(client, uri, bad)
    line = _line_of(bad, "RSTP")
    titles = [a.title for a in await _actions(client, uri, diags, line)]
    assert titles == ["Rewrite with a PLS relay: PLS M14999 / LD M14999 / RST (M14999 is unused)"]
    (action,) = await _actions(client, uri, diags, line)
    assert await _show(client, uri, _apply(bad, action.edit.changes[uri])) == []
    # an output after it shares its condition: no rewrite (it would change that output too)
    bad = text.replace("LD      X4\nRST     BATCH", "LD      X4\nRSTP    BATCH\nOUT     Y5")
    diags = await _show(client, uri, bad)
    assert not await _actions(client, uri, diags, _line_of(bad, "RSTP"))
    await _show(client, uri, text)


_CLI_DIAGNOSTIC = re.compile(r"^(.+?):(\d+):(\d+): (error|warning)\[(\w+)\]: (.*)$", re.M)


async def test_stimulus_diagnostics_match_mlc_sim(client: LanguageClient, project: Path):
    from tests.conftest import run_mlc

    stim = project / "tests" / "pick_cycle.stim"
    uri = stim.as_uri()
    text = stim.read_text()
    assert await _show(client, uri, text) == []  # the sample's scenario is good
    typed = text + "4s expcet X0=1\n5s Q1=1\nmodel foo\n6s expect D10=99999\n7s X0 pulses 1kHz until 1s\n"
    diags = await _show(client, uri, typed)
    scratch = project / "scratch.stim"  # the same text, as `mlc sim --stimulus` reads it
    scratch.write_text(typed)
    try:
        cli = run_mlc("sim", "src/conveyor.il", "src/pickplace.il", "--stimulus", str(scratch), cwd=project)
    finally:
        scratch.unlink()
    assert cli.code == 2
    expected = {(int(m[2]) - 1, int(m[3]) - 1, m[5], m[6]) for m in _CLI_DIAGNOSTIC.finditer(cli.err + cli.out)}
    assert len(expected) == 5
    assert {(d.range.start.line, d.range.start.character, d.code, d.message) for d in diags} == expected
    await _show(client, uri, text)


async def test_stimulus_completion_and_hover(client: LanguageClient, project: Path):
    stim = project / "tests" / "pick_cycle.stim"
    uri = stim.as_uri()
    text = stim.read_text() + "4s \n"
    await _show(client, uri, text)
    last = len(text.split("\n")) - 2

    async def labels(line: int, col: int) -> set[str]:
        got = await client.text_document_completion_async(lsp.CompletionParams(
            lsp.TextDocumentIdentifier(uri), lsp.Position(line, col)))
        return {i.label for i in got.items}

    assert {"expect", "force", "release", "power-cycle", "X", "D", "C"} <= await labels(last, 3)
    assert "LD" not in await labels(last, 3)  # no IL mnemonics in a stimulus file
    assert "S" not in await labels(last, 3) and "A" in await labels(last, 3)  # NC5's devices, not the VS's
    assert await labels(last, 0) == {"scan", "run", "model", "port"}
    await _show(client, uri, text.replace("4s \n", "model \n"))
    assert await labels(last, 6) == {"conveyor", "nc5", "stepper", "vsplc", "xc100"}  # nc5: the target's own
    await _show(client, uri, text)
    line = _line_of(text, "1s      expect")
    h = await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(uri), lsp.Position(line, 9)))
    assert "check devices after the scan" in h.contents.value
    col = text.split("\n")[line].index("D10=0") + 1
    h = await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(uri), lsp.Position(line, col)))
    assert h.contents.value.startswith("**D10**: 16-bit word, values -32768..32767")
    lib = _text(project, "pickplace.il")
    assert f"Written at: src/pickplace.il:{_line_of(lib, 'MOV     K1 STEP') + 1}" in h.contents.value
    assert (h.range.start.character, h.range.end.character) == (col - 1, col + 2)
    # the IL features stay out of a stimulus file
    assert await client.text_document_definition_async(lsp.DefinitionParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(line, col))) is None
    await _show(client, uri, stim.read_text())


async def test_folding_of_step_ladder_blocks(client: LanguageClient, tmp_path: Path):
    """VS step ladder (2-11): each STL step folds to its last line before the next step or RET."""
    ws = tmp_path / "stl"
    ws.mkdir()
    (ws / "mlc.toml").write_text('target = "vs"\nsources = ["main.il"]\n')
    text = ("; a two-step sequence\nLD      M9002\nSET     S0\n\nSTL     S0\nLD      X0\nSET     S20\n\n"
            "STL     S20\nOUT     Y0\nLD      X1\nSET     S0\nRET\nEND\n")
    (ws / "main.il").write_text(text)
    uri = (ws / "main.il").as_uri()
    assert await _show(client, uri, text) == []
    folds = await client.text_document_folding_range_async(lsp.FoldingRangeParams(lsp.TextDocumentIdentifier(uri)))
    assert sorted((f.start_line, f.end_line) for f in folds if f.kind == lsp.FoldingRangeKind.Region) == [
        (_line_of(text, "STL     S0"), _line_of(text, "SET     S20")),
        (_line_of(text, "STL     S20"), _line_of(text, "RET") - 1)]
    client.text_document_did_close(lsp.DidCloseTextDocumentParams(lsp.TextDocumentIdentifier(uri)))


async def test_hover_on_a_diagnostic_explains_its_code(client: LanguageClient, project: Path):
    from mlctool.codes import CODES

    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il")
    bad = text.replace("OUT     CONVEYOR", "OUTT    CONVEYOR")
    await _show(client, uri, bad)
    h = await client.text_document_hover_async(lsp.HoverParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(_line_of(bad, "OUTT"), 1)))
    assert f"E201: {CODES['E201'].summary}" in h.contents.value  # `mlc explain E201`
    assert CODES["E201"].doc.strip().split("\n")[0] in h.contents.value
    await _show(client, uri, text)


async def test_stimulus_of_a_vs_project_has_the_vs_devices(client: LanguageClient, tmp_path: Path):
    ws = _vs_project(tmp_path)
    stim = ws / "tests" / "count.stim"  # a stimulus file of the VS project: the VS's devices
    stim.parent.mkdir()
    stim.write_text("0ms X10=1\n")
    assert await _show(client, stim.as_uri(), stim.read_text()) == []
    got = await client.text_document_completion_async(lsp.CompletionParams(
        lsp.TextDocumentIdentifier(stim.as_uri()), lsp.Position(0, 4)))
    assert {"S", "R", "X"} <= {i.label for i in got.items} and "A" not in {i.label for i in got.items}
    bad = await _show(client, stim.as_uri(), "0ms A0=1\n")  # NC5's A relays are no VS device
    assert [d.code for d in bad] == ["E602"]
    client.text_document_did_close(lsp.DidCloseTextDocumentParams(lsp.TextDocumentIdentifier(stim.as_uri())))


async def test_hover_and_completion_show_an_nc_signals_row(client: LanguageClient, project: Path):
    """The NC5's special M/D (targets/nc5/signals.tsv): hover on M21000 shows the manual's row,
    completion of `M210` offers M21000 with the same line (issue 27)."""
    uri = _uri(project, "conveyor.il")
    text = _text(project, "conveyor.il") + "LD      M21000\nLD      M210\n"
    await _show(client, uri, text)
    line = _line_of(text, "LD      M21000")
    h = await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(uri), lsp.Position(line, 10)))
    value = h.contents.value
    assert "**M21000 - 程式啟動 cycle start, MLC->NC, channel 1, 5.3.2**" in value
    assert "- access: R/W: the MLC writes it" in value and "- section: 5.3.2 (row of 5.2.1" in value
    got = await client.text_document_completion_async(lsp.CompletionParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(line + 1, 12)))
    items = {i.label: i for i in got.items}
    assert items["M21000"].detail == "M21000 - 程式啟動 cycle start, MLC->NC, channel 1, 5.3.2"
    assert "M21016" in items and "M22000" not in items  # one channel configured (mlc.toml: default 1)
    await _show(client, uri, _text(project, "conveyor.il"))
