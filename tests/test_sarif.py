"""SARIF (mlctool/sarif.py): URIs relative to the repository root and percent-encoded,
invocations with the exit code, a helpUri per rule that lands on the code's row in the docs."""

from __future__ import annotations

import json
import re
from pathlib import Path
from urllib.parse import unquote, urlsplit

import jsonschema

from conftest import run_mlc
from mlctool.codes import CODES

ROOT = Path(__file__).resolve().parent.parent
SCHEMA = json.loads((ROOT / "tests" / "data" / "sarif-schema-2.1.0.json").read_text())
NAME = "主 程式.il"  # a blank and Chinese: both must be percent-encoded


def _sarif(args, cwd):
    r = run_mlc("check", "--format", "sarif", *args, cwd=cwd)
    doc = json.loads(r.out)
    jsonschema.validate(doc, SCHEMA)
    return r.code, doc["runs"][0]


def test_uris_are_relative_to_the_git_top_level_and_percent_encoded(tmp_path):
    repo = tmp_path / "repo"
    (repo / ".git").mkdir(parents=True)
    src = repo / "src dir"
    src.mkdir()
    (src / NAME).write_text("LD X0\nOUT X1\nEND\n", "utf-8")  # E210
    outside = tmp_path / "elsewhere.il"
    outside.write_text("LD X0\nOUT X1\nEND\n")
    code, run = _sarif([NAME, str(outside)], cwd=src)  # run from a subfolder of the repository
    assert code == 1
    assert run["originalUriBaseIds"]["%SRCROOT%"]["uri"] == repo.resolve().as_uri() + "/"
    locs = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]: r["locations"][0]
            ["physicalLocation"]["artifactLocation"] for r in run["results"]}
    inside = "src%20dir/%E4%B8%BB%20%E7%A8%8B%E5%BC%8F.il"
    assert locs[inside]["uriBaseId"] == "%SRCROOT%"
    assert unquote(inside) == f"src dir/{NAME}"
    far = outside.resolve().as_uri()
    assert "uriBaseId" not in locs[far] and far.startswith("file:///")
    assert all(" " not in u and u.isascii() for u in locs)


def test_without_a_repository_the_current_folder_is_the_root(tmp_path):
    (tmp_path / "a.il").write_text("LD X0\nOUT X1\nEND\n")
    _code, run = _sarif(["a.il"], cwd=tmp_path)
    assert run["originalUriBaseIds"]["%SRCROOT%"]["uri"] == tmp_path.resolve().as_uri() + "/"
    assert run["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "a.il"


def test_invocations_carry_the_exit_code(tmp_path):
    (tmp_path / "ok.il").write_text("LD X0\nOUT Y0\nEND\n")
    (tmp_path / "bad.il").write_text("LD X0\nOUT X1\nEND\n")
    for args, expect in ((["ok.il"], 0), (["bad.il"], 1), (["missing.il"], 2)):
        code, run = _sarif(args, cwd=tmp_path)
        assert code == expect
        assert run["invocations"] == [{"executionSuccessful": expect != 2, "exitCode": expect}]


def test_every_rule_has_a_help_uri_landing_on_its_docs_anchor(tmp_path):
    (tmp_path / "ok.il").write_text("LD X0\nOUT Y0\nEND\n")
    _code, run = _sarif(["ok.il"], cwd=tmp_path)
    anchors = set(re.findall(r'<a id="([a-z0-9]+)"></a>', (ROOT / "docs" / "check.md").read_text("utf-8")))
    rules = run["tool"]["driver"]["rules"]
    assert [r["id"] for r in rules] == list(CODES)
    for rule in rules:
        url = urlsplit(rule["helpUri"])
        assert url.scheme == "https" and url.path.endswith("/docs/check.md"), rule["helpUri"]
        assert url.fragment == rule["id"].lower()
        assert url.fragment in anchors, \
            f'docs/check.md: the row of {rule["id"]} needs its anchor: | <a id="{url.fragment}"></a>`{rule["id"]}` |'
