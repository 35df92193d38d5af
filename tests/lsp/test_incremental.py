"""The language server's analysis after an edit (mlctool/lsp/project.py with check.CheckMemo:
lines seen before are neither parsed nor resolved again) gives exactly the diagnostics of a
fresh `mlc check` of the same texts, after every one of many random edits (issue 18: fresh
diagnostics within 200 ms of an edit of a 10k-line file, bench/lsp_speed.py)."""

from __future__ import annotations

import importlib
import random
from pathlib import Path

import pytest
from progen import random_edit, random_program

from mlctool.check import CheckMemo, check_texts
from mlctool.config import load_config
from mlctool.lsp.project import Workspace
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target

# (target, model, mlc.toml extra lines): named labels (vs) and project symbols change what
# a line resolves to, so they are among the cases
PROJECTS = [
    ("nc5", None, ""),
    ("nc5", None, '[symbols]\nSTART = "X3"\nLOOP = "M7"\n'),
    ("vs", None, ""),
    ("vs", "VS1", 'capacity = 4000\n'),
    ("fbs", None, ""),
]


def _fresh(paths: list[str], texts: dict[str, str], root: Path):
    """What `mlc check` says of the texts: a check without any memo."""
    config = load_config(start=root)
    model = config.data.get("model")
    target = load_target(config.target, str(model) if model else None)
    return check_texts([SourceText(p, texts[p]) for p in paths], target, config).diagnostics


@pytest.mark.parametrize(("name", "model", "extra"), PROJECTS)
def test_incremental_analysis_equals_a_fresh_check(tmp_path, name, model, extra):
    rnd = random.Random(f"{name}{model}{extra}")
    target = load_target(name, model)
    (tmp_path / "mlc.toml").write_text(f'target = "{name}"\n' + (f'model = "{model}"\n' if model else "")
                                       + 'sources = ["main.il", "lib.il"]\n' + extra)
    paths = [str((tmp_path / f).resolve()) for f in ("main.il", "lib.il")]
    lines = {p: random_program(rnd, target, rnd.randint(150, 300)) for p in paths}
    lines[paths[1]][:0] = [".library", ".export P1"]
    ws = Workspace()
    for p in paths:
        ws.open(p, "\n".join(lines[p]) + "\n")
    ws.analysis(paths[0])
    compared = 0
    for _ in range(60):
        edited = rnd.choice(paths)
        lines[edited] = random_edit(rnd, target, lines[edited])
        texts = {p: "\n".join(lines[p]) + "\n" for p in paths}
        ws.open(edited, texts[edited])
        got = ws.analysis(rnd.choice(paths)).result.diagnostics
        assert got == _fresh(paths, texts, tmp_path)
        compared += len(got)
    assert compared > 100  # the programs are full of findings: the comparison compares something


def test_memo_is_used_between_edits(tmp_path):
    """An edit of one line parses and resolves that line only: the memo really carries over."""
    resolver = importlib.import_module("mlctool.check.resolve")  # the module (check.resolve is its function)
    (tmp_path / "mlc.toml").write_text('target = "nc5"\nsources = ["main.il"]\n')
    path = str((tmp_path / "main.il").resolve())
    target = load_target("nc5")
    lines = random_program(random.Random(5), target, 400)
    ws = Workspace()
    ws.open(path, "\n".join(lines) + "\n")
    ws.analysis(path)
    seen = []
    real = {name: getattr(resolver._Resolver, name) for name in ("plain_line", "resolved")}

    def spy(name):
        def spied(self, mnemonic, texts):
            seen.append((mnemonic, texts))
            return real[name](self, mnemonic, texts)
        return spied

    for name in real:  # the usual line's shortest way, and the whole way
        setattr(resolver._Resolver, name, spy(name))
    try:
        lines[10] = "MOV K1234 D4321"
        ws.open(path, "\n".join(lines) + "\n")
        ws.analysis(path)
    finally:
        for name, method in real.items():
            setattr(resolver._Resolver, name, method)
    assert set(seen) == {("MOV", ("K1234", "D4321"))}


def test_memo_follows_the_target(tmp_path):
    """The same file checked for another target (or model) with the same memo: the resolver's
    caches of the first target are not used for the second."""
    rnd = random.Random(11)
    memo = CheckMemo()
    text = "\n".join(random_program(rnd, load_target("vs"), 300)) + "\n"
    for name, model in [("vs", None), ("nc5", None), ("vs", "VS1"), ("vs", None)]:
        target = load_target(name, model)
        src = SourceText("/p/main.il", text)
        assert check_texts([src], target, memo=memo).diagnostics == check_texts([src], target).diagnostics


def test_memo_follows_the_named_labels(tmp_path):
    """Named labels get P numbers in order of definition (VS): removing the first moves the
    second's number, so the lines naming it resolve anew."""
    (tmp_path / "mlc.toml").write_text('target = "vs"\nsources = ["main.il"]\n')
    path = str((tmp_path / "main.il").resolve())
    head = ["LD X0", "CJ DONE", "LD X1", "CALL FILL", "FEND"]
    tail = ["FILL:", "LD X2", "OUT Y0", "SRET", "END"]
    ws = Workspace()
    for body in (["DONE:"], [], ["DONE:"], ["P10:"], ["DONE:", "P10:"]):
        text = "\n".join(head + body + tail) + "\n"
        ws.open(path, text)
        got = ws.analysis(path)
        assert got.result.diagnostics == _fresh([path], {path: text}, tmp_path)
        calls = [i.operands[0].number for i in got.result.modules[0].instrs if i.spec.op == "call"]
        fresh = check_texts([SourceText(path, text)], load_target("vs")).modules[0].instrs
        assert calls == [i.operands[0].number for i in fresh if i.spec.op == "call"]
