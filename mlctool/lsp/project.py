"""The editor's view of a project: the mlc.toml above a file, the open buffers checked
together with the project's other sources, and an index of names and their uses.

Paths are absolute here (editors speak in URIs); the checker gets them as they are, so its
diagnostics name the same paths. A file outside any project, or not among its `sources`, is
checked together with the project's sources (or alone) with the project's settings.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from mlctool.check import CheckMemo, CheckResult, check_texts
from mlctool.config import Config, load_config
from mlctool.diagnostics import Diagnostic, MlcError, Span, diag
from mlctool.syntax.parser import ParsedFile, parse
from mlctool.syntax.source import SourceText, read_source, source_encoding
from mlctool.syntax.statements import Statement, Word
from mlctool.targetapi import Target, load_target

LABEL = re.compile(r"P[0-9]+", re.IGNORECASE)


@dataclass
class Project:
    """One mlc.toml (or none: `root` is None) with its target and sources."""

    root: Path | None
    config: Config
    target: Target | None
    sources: list[str]  # absolute paths of the IL sources, in mlc.toml order
    problems: list[Diagnostic] = field(default_factory=list)  # mlc.toml itself is wrong

    def files_with(self, path: str) -> list[str]:
        return self.sources if path in self.sources else [*self.sources, path]


@dataclass(slots=True)
class Place:
    path: str
    line: int  # 1-based
    col: int  # 1-based
    end_col: int
    text: str


@dataclass
class Index:
    """Names of the files of one check: where each is defined and used."""

    parsed: dict[str, ParsedFile]
    defines: dict[str, dict[str, Place]]  # file -> SYMBOL (upper) -> its .define name
    define_values: dict[str, dict[str, str]]  # file -> SYMBOL -> operand text
    labels: dict[str, dict[str, Place]]  # file -> P10 / NAME (upper) -> its definition
    exports: dict[str, set[str]]  # file -> exported label names (upper)
    uses: dict[str, list[Place]]  # file -> every operand word

    def statement_at(self, path: str, line: int) -> Statement | None:
        parsed = self.parsed.get(path)
        if parsed is None:
            return None
        for st in parsed.statements:  # statements are in line order; files are small enough
            if st.line == line:
                return st
        return None


def _index(parsed_files: list[ParsedFile]) -> Index:
    idx = Index({}, {}, {}, {}, {}, {})
    for pf in parsed_files:
        path = pf.path
        idx.parsed[path] = pf
        defines: dict[str, Place] = {}
        values: dict[str, str] = {}
        labels: dict[str, Place] = {}
        exports: set[str] = set()
        uses: list[Place] = []
        for st in pf.statements:
            name = st.name
            if st.kind == "directive":
                directive = name.text.lower()
                if directive == ".define" and len(st.operands) >= 2:
                    sym, val = st.operands[0], st.operands[1]
                    defines.setdefault(sym.text.upper(), _place(path, st.line, sym))
                    values.setdefault(sym.text.upper(), val.text)
                    uses.append(_place(path, st.line, val))
                elif directive == ".export":
                    exports.update(w.text.upper() for w in st.operands)
                    uses.extend(_place(path, st.line, w) for w in st.operands)
                continue
            if st.kind == "label" or (LABEL.fullmatch(name.text) and not st.operands):
                labels.setdefault(name.text.upper(), _place(path, st.line, name))
                continue
            uses.extend(_place(path, st.line, w) for w in st.operands)
        idx.defines[path], idx.define_values[path] = defines, values
        idx.labels[path], idx.exports[path], idx.uses[path] = labels, exports, uses
    return idx


def _place(path: str, line: int, w: Word) -> Place:
    return Place(path, line, w.col, w.end_col, w.text)


@dataclass
class Analysis:
    """One check of a project's files (the open buffers as they are now) and its index."""

    project: Project
    result: CheckResult
    sources: dict[str, SourceText]
    _index: Index | None = None
    memo: CheckMemo | None = None  # the workspace's: lines parsed before are not parsed again

    @property
    def index(self) -> Index:
        """Parsed on first use: diagnostics as you type need only the check."""
        if self._index is None:
            from mlctool.check.labels import restrict_names

            target = self.project.target
            memo = self.memo
            files = [parse(src, memo=memo.lines(src) if memo else None) for src in self.sources.values()]
            if target is not None:
                files = [restrict_names(pf, target) for pf in files]
            self._index = _index(files)
        return self._index

    def diagnostics_of(self, path: str) -> list[Diagnostic]:
        return [d for d in self.result.diagnostics if d.file == path]


class Workspace:
    """Open buffers (path -> text) and the projects they belong to."""

    def __init__(self) -> None:
        self.buffers: dict[str, str] = {}
        self._projects: dict[str, Project] = {}
        self._analyses: dict[str, Analysis] = {}  # file -> its latest analysis (still valid)
        # what the checks learnt about the files' lines: an edit re-reads the lines it changed
        # and re-runs the rules over the whole program (check.CheckMemo)
        self.memo = CheckMemo()

    # ---------------------------------------------------------------- buffers
    def open(self, path: str, text: str) -> None:
        self.buffers[path] = text
        self._forget(path)

    def close(self, path: str) -> None:
        self.buffers.pop(path, None)
        self.memo.forget(path)
        self._forget(path)

    def reload(self) -> None:
        """An mlc.toml changed: every project is read again."""
        self._projects.clear()
        self._analyses.clear()
        self.memo = CheckMemo()

    def _forget(self, path: str) -> None:
        """An edit invalidates every analysis that read the file (the project's modules)."""
        for k in [k for k, a in self._analyses.items() if path in a.sources or k == path]:
            del self._analyses[k]

    # ---------------------------------------------------------------- projects
    def project_of(self, path: str) -> Project:
        folder = str(Path(path).parent)
        project = self._projects.get(folder)
        if project is None:
            project = self._projects[folder] = _load_project(Path(folder))
        return project

    def analysis(self, path: str) -> Analysis:
        found = self._analyses.get(path)
        if found is not None:
            return found
        project = self.project_of(path)
        sources: dict[str, SourceText] = {}
        problems = list(project.problems)
        encoding, bad = source_encoding(project.config)
        problems += bad
        for p in project.files_with(path):
            text = self.buffers.get(p)
            if text is not None:
                sources[p] = SourceText(p, _normalised(text))
                continue
            src, found_diags = read_source(p, encoding)
            problems += found_diags
            if src is not None:
                sources[p] = src
        if project.target is None:
            result = CheckResult([], problems, {}, list(sources.values()))
        else:
            result = check_texts(list(sources.values()), project.target, project.config, initial=problems,
                                 memo=self.memo)
        analysis = Analysis(project, result, sources, memo=self.memo)
        for p in sources:  # every module of the check shares it until one of them changes
            self._analyses[p] = analysis
        self._analyses[path] = analysis
        return analysis


def _normalised(text: str) -> str:
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    return text if text.endswith("\n") else text + "\n"


def _load_project(folder: Path) -> Project:
    problems: list[Diagnostic] = []
    try:
        config = load_config(start=folder)
    except MlcError as e:
        config = Config()
        problems += e.diagnostics
    target = None
    try:
        target = load_target(config.target or "nc5", str(config.data["model"]).upper()
                             if config.data.get("model") else None)
    except Exception as e:  # an unknown target or model: said at mlc.toml, nothing else checked
        file = str(config.file) if config.file else "mlc.toml"
        problems.append(diag(file, Span.at(1), "E110", f"mlc.toml: {e}"))
    sources: list[str] = []
    if config.root is not None:
        listed = config.data.get("sources")
        if isinstance(listed, list):
            for s in listed:
                if isinstance(s, str) and s.lower().endswith(".il"):
                    sources.append(str((config.root / s).resolve()))
    return Project(config.root, config, target, sources, problems)
