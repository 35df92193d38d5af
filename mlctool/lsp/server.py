"""The pygls wiring of `mlc lsp`: protocol messages <-> mlctool/lsp/features.py.

Positions: the protocol's are 0-based, mlctool's 1-based. Columns are counted in code points
(IL sources are ASCII or CJK of the basic plane, where UTF-16 units are the same count).
"""

from __future__ import annotations

from urllib.parse import unquote, urlparse

from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path

from mlctool import __version__
from mlctool.diagnostics import Diagnostic
from mlctool.lsp import features, stim
from mlctool.lsp.project import Analysis, Place, Workspace

SEVERITY = {"error": lsp.DiagnosticSeverity.Error, "warning": lsp.DiagnosticSeverity.Warning,
            "note": lsp.DiagnosticSeverity.Information}
SYMBOL_KIND = {"label": lsp.SymbolKind.Function, "interrupt": lsp.SymbolKind.Event, "define": lsp.SymbolKind.Constant,
               "rung": lsp.SymbolKind.Event}
COMPLETION_KIND = {"instruction": lsp.CompletionItemKind.Function, "device": lsp.CompletionItemKind.Variable,
                   "symbol": lsp.CompletionItemKind.Constant, "label": lsp.CompletionItemKind.Reference}
IL_SUFFIXES = (".il",)


def path_of(uri: str) -> str:
    parsed = urlparse(uri)
    return unquote(parsed.path) if parsed.scheme == "file" else uri


def uri_of(path: str) -> str:
    return from_fs_path(path) or path


def _range(line: int, col: int, end_line: int, end_col: int) -> lsp.Range:
    return lsp.Range(lsp.Position(max(line - 1, 0), max(col - 1, 0)),
                     lsp.Position(max(end_line - 1, 0), max(end_col - 1, 0)))


def _place_range(p: Place) -> lsp.Range:
    return _range(p.line, p.col, p.line, p.end_col)


def to_lsp(d: Diagnostic) -> lsp.Diagnostic:
    s = d.span
    message = d.message + "".join(f"\n{n}" for n in d.notes)
    return lsp.Diagnostic(_range(s.line, s.col, s.end_line, s.end_col), message,
                          severity=SEVERITY.get(d.severity, lsp.DiagnosticSeverity.Information),
                          code=d.code, source="mlc")


class MlcServer(LanguageServer):
    def __init__(self) -> None:
        super().__init__("mlc", __version__)
        self.projects = Workspace()
        self.published: dict[str, set[str]] = {}  # project root -> uris given diagnostics

    def analysis(self, uri: str) -> Analysis:
        return self.projects.analysis(path_of(uri))

    def publish(self, uri: str) -> None:
        """Diagnostics of every module checked with the file (an exported label that changed
        changes the other modules' diagnostics too)."""
        a = self.analysis(uri)
        by_file: dict[str, list[lsp.Diagnostic]] = {p: [] for p in a.sources}
        for d in a.result.diagnostics:
            by_file.setdefault(d.file, []).append(to_lsp(d))
        key = str(a.project.root)
        uris = set()
        own = path_of(uri)  # the edited file last: a client waiting for it has all the others
        for path, diags in sorted(by_file.items(), key=lambda kv: kv[0] == own):
            u = uri_of(path) if path.startswith("/") else path
            uris.add(u)
            version = None
            doc = self.workspace.text_documents.get(u)
            if doc is not None:
                version = doc.version
            self.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(u, diags, version))
        for stale in self.published.get(key, set()) - uris:
            self.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(stale, []))
        self.published[key] = uris


    def publish_stim(self, uri: str) -> None:
        """A stimulus file's diagnostics, as `mlc sim --stimulus` gives them, against the
        target of the mlc.toml above it."""
        path = path_of(uri)
        doc = self.workspace.get_text_document(uri)
        project = self.projects.project_of(path)
        diags = [] if project.target is None else stim.diagnostics(path, _normalised(doc.source), project.target)
        self.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
            uri, [to_lsp(d) for d in diags], doc.version))

    def publish_all(self) -> None:
        """Every open file's diagnostics anew (the projects were read again)."""
        for open_uri in list(self.workspace.text_documents):
            if _is_il(open_uri):
                self.publish(open_uri)
            elif _is_stim(open_uri):
                self.publish_stim(open_uri)


server = MlcServer()


def _is_il(uri: str) -> bool:
    return not uri.lower().endswith((".stim", ".toml"))


def _is_stim(uri: str) -> bool:
    return uri.lower().endswith(".stim")


def _normalised(text: str) -> str:
    return text.replace("\r\n", "\n").replace("\r", "\n")


@server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: MlcServer, params: lsp.DidOpenTextDocumentParams) -> None:
    uri = params.text_document.uri
    if _is_stim(uri):
        ls.publish_stim(uri)
    if not _is_il(uri):
        return
    ls.projects.open(path_of(uri), params.text_document.text)
    ls.publish(uri)


@server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: MlcServer, params: lsp.DidChangeTextDocumentParams) -> None:
    uri = params.text_document.uri
    if _is_stim(uri):
        ls.publish_stim(uri)
    if not _is_il(uri):
        return
    ls.projects.open(path_of(uri), ls.workspace.get_text_document(uri).source)
    ls.publish(uri)


@server.feature(lsp.TEXT_DOCUMENT_DID_SAVE)
def did_save(ls: MlcServer, params: lsp.DidSaveTextDocumentParams) -> None:
    uri = params.text_document.uri
    if uri.endswith("mlc.toml"):  # settings changed: every project is read again
        ls.projects.reload()
        ls.publish_all()


@server.feature(lsp.WORKSPACE_DID_CHANGE_WATCHED_FILES)
def watched_files_changed(ls: MlcServer, params: lsp.DidChangeWatchedFilesParams) -> None:
    """mlc.toml or a module changed on disk (a git checkout, another editor): read the
    projects again and publish the open files' diagnostics anew."""
    ls.projects.reload()
    ls.publish_all()


@server.feature(lsp.TEXT_DOCUMENT_DID_CLOSE)
def did_close(ls: MlcServer, params: lsp.DidCloseTextDocumentParams) -> None:
    uri = params.text_document.uri
    if _is_il(uri):
        ls.projects.close(path_of(uri))  # the file on disk counts again
    elif _is_stim(uri):  # nothing checks a closed stimulus file: its diagnostics go with it
        ls.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(uri, []))


@server.feature(lsp.TEXT_DOCUMENT_HOVER)
def hover(ls: MlcServer, params: lsp.HoverParams) -> lsp.Hover | None:
    if _is_stim(params.text_document.uri):
        return _stim_hover(ls, params)
    if not _is_il(params.text_document.uri):
        return None
    path = path_of(params.text_document.uri)
    a = ls.analysis(params.text_document.uri)
    line, col = params.position.line + 1, params.position.character + 1
    found = features.hover(a, path, line, col)
    explained = [features.explain(d.code) for d in a.diagnostics_of(path)
                 if d.span.line <= line <= d.span.end_line and d.span.col <= col <= d.span.end_col]
    parts = ([found[0]] if found else []) + [e for e in explained if e]
    if not parts:
        return None
    rng = _place_range(found[1]) if found else None
    return lsp.Hover(lsp.MarkupContent(lsp.MarkupKind.Markdown, "\n\n---\n\n".join(parts)), rng)


def _line_text(ls: MlcServer, uri: str, line: int) -> str:
    doc = ls.workspace.get_text_document(uri)
    return doc.lines[line].rstrip("\r\n") if line < len(doc.lines) else ""


def _stim_hover(ls: MlcServer, params: lsp.HoverParams) -> lsp.Hover | None:
    """A keyword's form, a device's view and kind, and where the project's program writes and
    reads it."""
    uri = params.text_document.uri
    project = ls.projects.project_of(path_of(uri))
    if project.target is None:
        return None
    line = params.position.line
    found = stim.hover(_line_text(ls, uri, line), params.position.character + 1, project.target)
    if found is None:
        return None
    text, first, end, device = found
    if device is not None and project.sources:
        text += "\n\n" + "\n\n".join(features.device_use_lines(ls.projects.analysis(project.sources[0]), device))
    return lsp.Hover(lsp.MarkupContent(lsp.MarkupKind.Markdown, text), _range(line + 1, first, line + 1, end))


STIM_COMPLETION_KIND = {"keyword": lsp.CompletionItemKind.Keyword, "device": lsp.CompletionItemKind.Variable,
                        "model": lsp.CompletionItemKind.Class}


@server.feature(lsp.TEXT_DOCUMENT_COMPLETION, lsp.CompletionOptions(trigger_characters=[" "]))
def completion(ls: MlcServer, params: lsp.CompletionParams) -> lsp.CompletionList:
    uri = params.text_document.uri
    line = params.position.line
    text = _line_text(ls, uri, line)
    if _is_stim(uri):
        target = ls.projects.project_of(path_of(uri)).target
        found = stim.completions(text, params.position.character + 1, target) if target else []
        return lsp.CompletionList(is_incomplete=False, items=[
            lsp.CompletionItem(c.label, kind=STIM_COMPLETION_KIND[c.kind], detail=c.detail) for c in found])
    if not _is_il(uri):
        return lsp.CompletionList(is_incomplete=False, items=[])
    a = ls.analysis(uri)
    items = []
    for c in features.completions(a, path_of(uri), line + 1, params.position.character + 1, text):
        item = lsp.CompletionItem(c.label, kind=COMPLETION_KIND[c.kind], detail=c.detail)
        if c.snippet:
            item.insert_text = c.snippet
            item.insert_text_format = lsp.InsertTextFormat.Snippet
        items.append(item)
    return lsp.CompletionList(is_incomplete=False, items=items)


@server.feature(lsp.TEXT_DOCUMENT_DEFINITION)
def definition(ls: MlcServer, params: lsp.DefinitionParams) -> lsp.Location | None:
    if not _is_il(params.text_document.uri):  # a .stim file: stimulus features only
        return None
    a = ls.analysis(params.text_document.uri)
    p = features.definition(a, path_of(params.text_document.uri), params.position.line + 1,
                            params.position.character + 1)
    return lsp.Location(uri_of(p.path), _place_range(p)) if p else None


@server.feature(lsp.TEXT_DOCUMENT_REFERENCES)
def references(ls: MlcServer, params: lsp.ReferenceParams) -> list[lsp.Location]:
    if not _is_il(params.text_document.uri):  # a .stim file: stimulus features only
        return []
    a = ls.analysis(params.text_document.uri)
    found = features.references(a, path_of(params.text_document.uri), params.position.line + 1,
                                params.position.character + 1, params.context.include_declaration)
    return [lsp.Location(uri_of(p.path), _place_range(p)) for p in found]


@server.feature(lsp.TEXT_DOCUMENT_PREPARE_RENAME)
def prepare_rename(ls: MlcServer, params: lsp.PrepareRenameParams) -> lsp.Range | None:
    if not _is_il(params.text_document.uri):  # a .stim file: stimulus features only
        return None
    a = ls.analysis(params.text_document.uri)
    path = path_of(params.text_document.uri)
    line, col = params.position.line + 1, params.position.character + 1
    pointer = features.interrupt_at(a, path, line, col) is not None  # renamed to another pointer
    if not pointer and features.rename_check(a, path, line, col, "X_RENAMED_") is not None:
        return None
    found = features.word_at(a, path, line, col)
    return _place_range(found.place) if found else None


@server.feature(lsp.TEXT_DOCUMENT_RENAME)
def rename(ls: MlcServer, params: lsp.RenameParams) -> lsp.WorkspaceEdit:
    if not _is_il(params.text_document.uri):  # a .stim file: stimulus features only
        return lsp.WorkspaceEdit(changes={})
    a = ls.analysis(params.text_document.uri)
    path = path_of(params.text_document.uri)
    line, col = params.position.line + 1, params.position.character + 1
    why = features.rename_check(a, path, line, col, params.new_name)
    if why is not None:
        raise ValueError(why)  # pygls answers with an error response carrying the message
    changes: dict[str, list[lsp.TextEdit]] = {}
    for p in features.references(a, path, line, col):
        changes.setdefault(uri_of(p.path), []).append(lsp.TextEdit(_place_range(p), params.new_name))
    return lsp.WorkspaceEdit(changes=changes)


@server.feature(lsp.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
def document_symbol(ls: MlcServer, params: lsp.DocumentSymbolParams) -> list[lsp.DocumentSymbol]:
    if not _is_il(params.text_document.uri):  # a .stim file: stimulus features only
        return []
    a = ls.analysis(params.text_document.uri)

    def convert(s: features.Symbol) -> lsp.DocumentSymbol:
        return lsp.DocumentSymbol(
            s.name, SYMBOL_KIND[s.kind], _range(s.line, 1, s.end_line, 1 if s.end_line > s.line else s.end_col),
            _range(s.line, s.col, s.line, s.end_col), children=[convert(c) for c in s.children or []])

    return [convert(s) for s in features.document_symbols(a, path_of(params.text_document.uri))]


@server.feature(lsp.TEXT_DOCUMENT_FORMATTING)
def formatting(ls: MlcServer, params: lsp.DocumentFormattingParams) -> list[lsp.TextEdit]:
    if not _is_il(params.text_document.uri):  # a .stim file: stimulus features only
        return []
    a = ls.analysis(params.text_document.uri)
    path = path_of(params.text_document.uri)
    new = features.formatted(a, path)
    if new is None:
        return []
    doc = ls.workspace.get_text_document(params.text_document.uri)
    end = len(doc.lines)
    return [lsp.TextEdit(lsp.Range(lsp.Position(0, 0), lsp.Position(end, 0)), new)]


@server.feature(lsp.TEXT_DOCUMENT_CODE_ACTION,
                lsp.CodeActionOptions(code_action_kinds=[lsp.CodeActionKind.QuickFix]))
def code_action(ls: MlcServer, params: lsp.CodeActionParams) -> list[lsp.CodeAction]:
    if not _is_il(params.text_document.uri):  # a .stim file: stimulus features only
        return []
    uri = params.text_document.uri
    path = path_of(uri)
    a = ls.analysis(uri)
    first, last = params.range.start.line + 1, params.range.end.line + 1
    diags = [d for d in a.diagnostics_of(path) if first <= d.span.line <= last]
    lines = a.sources[path].text.split("\n") if path in a.sources else []
    out = []
    for fix in features.fixes(a, path, diags, lines):
        edits = [lsp.TextEdit(_range(e.line, e.col, e.end_line, e.end_col), e.new_text) for e in fix.edits]
        related = [to_lsp(d) for d in diags if d.code == fix.code and d.span.line == fix.line]
        out.append(lsp.CodeAction(fix.title, kind=lsp.CodeActionKind.QuickFix, diagnostics=related,
                                  is_preferred=fix.preferred or None,
                                  edit=lsp.WorkspaceEdit(changes={uri: edits})))
    return out


@server.feature(lsp.TEXT_DOCUMENT_FOLDING_RANGE)
def folding_range(ls: MlcServer, params: lsp.FoldingRangeParams) -> list[lsp.FoldingRange]:
    if not _is_il(params.text_document.uri):  # a .stim file: stimulus features only
        return []
    a = ls.analysis(params.text_document.uri)
    kinds = {"region": lsp.FoldingRangeKind.Region, "comment": lsp.FoldingRangeKind.Comment}
    return [lsp.FoldingRange(first - 1, last - 1, kind=kinds[kind])
            for first, last, kind in features.folding_ranges(a, path_of(params.text_document.uri))]


@server.feature(lsp.TEXT_DOCUMENT_INLAY_HINT)
def inlay_hint(ls: MlcServer, params: lsp.InlayHintParams) -> list[lsp.InlayHint]:
    """The step address of each instruction, before it (as `mlc fmt --steps renumber` would
    write it)."""
    if not _is_il(params.text_document.uri):  # a .stim file: stimulus features only
        return []
    a = ls.analysis(params.text_document.uri)
    found = features.step_addresses(a, path_of(params.text_document.uri), params.range.start.line + 1,
                                    params.range.end.line + 1)
    return [lsp.InlayHint(lsp.Position(line - 1, 0), f"{addr}", padding_right=True) for line, addr in found]


WORKSPACE_SYMBOL_KIND = {"subroutine": lsp.SymbolKind.Function, "label": lsp.SymbolKind.Key,
                         "interrupt": lsp.SymbolKind.Event, "define": lsp.SymbolKind.Constant}


def _project_analyses(ls: MlcServer) -> list[Analysis]:
    """One analysis per project the editor shows: the mlc.toml of each workspace folder (and
    of its subfolders two levels down), and the project of each open IL file."""
    from pathlib import Path

    roots = [path_of(f.uri) for f in ls.workspace.folders.values()]
    if not roots and ls.workspace.root_path:
        roots = [ls.workspace.root_path]
    starts: list[str] = []
    for root in roots:
        base = Path(root)
        for depth in ("", "*/", "*/*/"):
            for toml in sorted(base.glob(depth + "mlc.toml")):
                if not any(part.startswith(".") or part == "node_modules" for part in toml.relative_to(base).parts):
                    sources = ls.projects.project_of(str(toml)).sources
                    if sources:
                        starts.append(sources[0])
    starts += [path_of(u) for u in ls.workspace.text_documents if _is_il(u)]
    seen: dict[int, Analysis] = {}
    for path in starts:
        a = ls.projects.analysis(path)
        seen.setdefault(id(a), a)
    return list(seen.values())


@server.feature(lsp.WORKSPACE_SYMBOL)
def workspace_symbol(ls: MlcServer, params: lsp.WorkspaceSymbolParams) -> list[lsp.WorkspaceSymbol]:
    found: dict[tuple, lsp.WorkspaceSymbol] = {}
    for a in _project_analyses(ls):
        for s in features.workspace_symbols(a, params.query):
            p = s.place
            key = (p.path, p.line, p.col, s.name)
            if key not in found:
                found[key] = lsp.WorkspaceSymbol(
                    name=s.name, kind=WORKSPACE_SYMBOL_KIND[s.kind],
                    location=lsp.Location(uri_of(p.path), _place_range(p)), container_name=f"{s.module} ({s.kind})")
    return list(found.values())


SEMANTIC_LEGEND = lsp.SemanticTokensLegend(token_types=list(features.TOKEN_TYPES),
                                           token_modifiers=list(features.TOKEN_MODIFIERS))


@server.feature(lsp.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, SEMANTIC_LEGEND)
def semantic_tokens_full(ls: MlcServer, params: lsp.SemanticTokensParams) -> lsp.SemanticTokens:
    """The whole document, encoded as the protocol asks: five integers per token (line and
    start relative to the previous token, length, type index, modifier bits)."""
    uri = params.text_document.uri
    if not _is_il(uri):
        return lsp.SemanticTokens(data=[])
    a = ls.analysis(uri)
    types = {t: k for k, t in enumerate(features.TOKEN_TYPES)}
    bits = {m: 1 << k for k, m in enumerate(features.TOKEN_MODIFIERS)}
    masks: dict[tuple[str, ...], int] = {}  # a file has few distinct modifier sets
    data: list[int] = []
    prev_line, prev_col = 0, 0
    for t in features.semantic_tokens(a, path_of(uri)):
        line, col = t.line - 1, t.col - 1
        mask = masks.get(t.modifiers)
        if mask is None:
            mask = masks[t.modifiers] = sum(bits[m] for m in set(t.modifiers))
        data += [line - prev_line, col - prev_col if line == prev_line else col, t.length, types[t.type], mask]
        prev_line, prev_col = line, col
    return lsp.SemanticTokens(data=data)


def main() -> None:
    server.start_io()
