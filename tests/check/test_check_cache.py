"""The checker's shortcuts change no result: generated programs checked with them (a line
keyed by its text, the plain-form resolution, the parser's memo of lines) and without give
the same modules and the same diagnostics (issue 19 §2: the speed of checking)."""

from __future__ import annotations

import random

import pytest
from progen import random_edit, random_program

from mlctool.check import check_texts
from mlctool.check.resolve import _Resolver
from mlctool.syntax.parser import parse
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target

TARGETS = [("nc5", None), ("vs", None), ("vs", "VS1"), ("fbs", None)]


def _check(text: str, target, shortcuts: bool, monkeypatch):
    monkeypatch.setattr(_Resolver, "shortcuts", shortcuts)
    result = check_texts([SourceText("gen.il", text)], target)
    return result.modules, result.diagnostics


@pytest.mark.parametrize(("name", "model"), TARGETS)
def test_shortcuts_change_no_result(name, model, monkeypatch):
    target = load_target(name, model)
    rnd = random.Random(f"{name}{model}")
    compared = 0
    for _ in range(12):
        text = "\n".join(random_program(rnd, target, rnd.randint(20, 400))) + "\n"
        fast = _check(text, target, True, monkeypatch)
        plain = _check(text, target, False, monkeypatch)
        assert fast[1] == plain[1]
        assert fast[0] == plain[0]
        compared += len(fast[0][0].instrs)
    assert compared > 1000


def test_shortcuts_are_taken(monkeypatch):
    """The comparison above compares two different ways: the plain-form resolution and the
    text key are used on a generated program (and not with shortcuts off)."""
    target = load_target("nc5")
    text = "\n".join(random_program(random.Random(3), target, 300)) + "\n"
    taken = {"plainly_resolved": [], "plain_line": []}

    def spy(name):
        real = getattr(_Resolver, name)

        def spied(self, *args):
            found = real(self, *args)
            taken[name].append(found is not None)
            return found
        monkeypatch.setattr(_Resolver, name, spied)

    spy("plainly_resolved")
    spy("plain_line")
    check_texts([SourceText("gen.il", text)], target)
    assert sum(taken["plain_line"]) > 20
    # the mnemonics of several forms (VS OUT Y0 / OUT T0 K50) that plain_line leaves
    vs = load_target("vs")
    text = "\n".join(random_program(random.Random(3), vs, 300) + ["OUT Y1", "OUT M7"]) + "\n"
    check_texts([SourceText("gen.il", text)], vs)
    assert sum(taken["plainly_resolved"]) > 0


@pytest.mark.parametrize(("name", "model"), TARGETS)
def test_parse_memo_between_versions(name, model):
    """A memo kept across edited versions of a text gives the statements a fresh parse does."""
    target = load_target(name, model)
    rnd = random.Random(7)
    lines = random_program(rnd, target, 200) + ["變頻器1通訊:", "CALL 緊急停止", "LD\u3000X0"]
    memo: dict = {}
    for _ in range(30):
        src = SourceText("gen.il", "\n".join(lines) + "\n")
        fresh, kept = parse(src), parse(src, memo=memo)
        assert kept.statements == fresh.statements
        assert kept.diagnostics == fresh.diagnostics
        lines = random_edit(rnd, target, lines)
