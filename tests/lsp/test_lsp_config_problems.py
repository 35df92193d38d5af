"""A bad mlc.toml is a diagnostic in the editor, and the language features go on (issue 30.6:
`encoding = "rot13"` made every hover of `mlc lsp` answer "internal error")."""

from __future__ import annotations

import shutil

import pytest

from conftest import ROOT
from mlctool.lsp import features
from mlctool.lsp.project import Workspace


@pytest.mark.parametrize("codec", ["rot13", "hex", "undefined"])
def test_a_codec_that_is_not_a_text_encoding_is_a_config_diagnostic(tmp_path, codec):
    shutil.copytree(ROOT / "samples" / "project" / "src", tmp_path / "src")
    (tmp_path / "mlc.toml").write_text(f'target = "nc5"\nencoding = "{codec}"\n'
                                       'sources = ["src/conveyor.il", "src/pickplace.il"]\n')
    path = str(tmp_path / "src" / "conveyor.il")
    text = (tmp_path / "src" / "conveyor.il").read_text()
    workspace = Workspace()
    workspace.open(path, text)  # pickplace.il is read from disk, with the configured encoding
    a = workspace.analysis(path)
    problems = [d for d in a.result.diagnostics if d.code == "E110"]
    assert problems and problems[0].file.endswith("mlc.toml") and problems[0].span.line == 2
    assert "not an encoding of text files" in problems[0].message
    assert str(tmp_path / "src" / "pickplace.il") in a.sources  # read as UTF-8 meanwhile
    line = next(k for k, s in enumerate(text.split("\n"), 1) if s.startswith("LD"))
    found = features.hover(a, path, line, 1)
    assert found is not None and "LD" in found[0]
