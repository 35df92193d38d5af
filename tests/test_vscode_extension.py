"""editors/vscode: the extension's manifest agrees with mlc (languages, grammars, commands,
the debugger type, the problem matcher against real `mlc check` output), and its grammar
tests pass when its npm packages are installed (editors/vscode/ci.sh installs them in CI;
the .vsix is built there, not here: it needs the npm registry)."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from conftest import run_mlc

EXT = Path(__file__).resolve().parents[1] / "editors" / "vscode"
MANIFEST = json.loads((EXT / "package.json").read_text("utf-8"))
CONTRIB = MANIFEST["contributes"]


def test_languages_and_grammars():
    langs = {lang["id"]: lang for lang in CONTRIB["languages"]}
    assert langs["il"]["extensions"] == [".il"] and langs["stim"]["extensions"] == [".stim"]
    for lang in langs.values():
        config = json.loads((EXT / lang["configuration"]).read_text("utf-8"))
        assert config["comments"]["lineComment"].strip() in (";", "#")
    scopes = {g["language"]: g for g in CONTRIB["grammars"]}
    for lang, scope in (("il", "source.il"), ("stim", "source.stim")):
        grammar = json.loads((EXT / scopes[lang]["path"]).read_text("utf-8"))
        assert grammar["scopeName"] == scopes[lang]["scopeName"] == scope
        tests = list((EXT / "test").glob(f"*.{lang}"))
        assert tests and all(f'SYNTAX TEST "{scope}"' in t.read_text("utf-8").split("\n", 1)[0] for t in tests)


def test_settings_commands_and_debugger():
    props = CONTRIB["configuration"]["properties"]
    assert props["mlc.path"]["type"] == "string" and ".venv" in props["mlc.path"]["markdownDescription"]
    source = (EXT / "extension.js").read_text("utf-8")
    commands = {c["command"] for c in CONTRIB["commands"]}
    assert {"mlc.build", "mlc.runScenario", "mlc.showLadder"} <= commands
    for command in commands:  # every contributed command is registered by the extension
        assert f'registerCommand("{command}"' in source, command
    assert [d["type"] for d in CONTRIB["debuggers"]] == ["mlc"]
    assert '["debug", "--dap"]' in source and 'args: ["lsp"]' in source
    assert '[".venv", "bin", "mlc"]' in source  # the fallback the setting's description promises
    # the client starts the server for both languages the server answers for (.stim: mlctool/lsp/stim.py)
    selector = re.search(r"documentSelector: \[(.*?)\],\n", source)[1]
    assert set(re.findall(r'language: "(\w+)"', selector)) == {"il", "stim"}


def test_problem_matcher_reads_mlc_check_output(tmp_path):
    (tmp_path / "bad.il").write_text("LD X0\nOUTT Y0\nOUT Y1\nOUT Y1\nEND\n")
    r = run_mlc("check", "bad.il", cwd=tmp_path)
    assert r.code == 1
    (matcher,) = CONTRIB["problemMatchers"]
    pattern = matcher["pattern"]
    regex = re.compile(pattern["regexp"])  # a JavaScript regex, written in the subset Python shares
    found = [m for line in r.err.splitlines() if (m := regex.match(line))]
    assert found, r.err
    got = {(m[pattern["file"]], m[pattern["line"]], m[pattern["column"]], m[pattern["severity"]], m[pattern["code"]])
           for m in found}
    assert ("bad.il", "2", "1", "error", "E201") in got
    assert all(m[pattern["severity"]] in ("error", "warning", "note") for m in found)


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_extension_js_parses():
    r = subprocess.run(["node", "--check", str(EXT / "extension.js")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


@pytest.mark.skipif(not (EXT / "node_modules" / ".bin" / "vscode-tmgrammar-test").exists(),
                    reason="npm packages of editors/vscode not installed (editors/vscode/ci.sh)")
def test_grammar_tests_pass():
    r = subprocess.run([str(EXT / "node_modules" / ".bin" / "vscode-tmgrammar-test"),
                        "-g", "syntaxes/il.tmLanguage.json", "-g", "syntaxes/stim.tmLanguage.json",
                        "test/*.il", "test/*.stim"], cwd=EXT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.count("successfuly") == 2, r.stdout


@pytest.mark.skipif(shutil.which("node") is None, reason="node is not installed")
def test_show_ladder_draws_a_module_with_the_other_sources(tmp_path):
    """`mlc: show ladder` on a module of a project: all of its sources (alone, conveyor.il's
    CALL P10 has no label and `mlc ladder` draws nothing); a file of no project: itself."""
    script = (
        'const fs = require("fs"), path = require("path");'
        'eval(fs.readFileSync("extension.js", "utf8").match(/function ladderFiles[\\s\\S]*?\\n}\\n/)[0]);'
        'const root = process.argv[1];'
        'console.log(JSON.stringify([ladderFiles(path.join(root, "samples/project/src/conveyor.il"),'
        ' path.join(root, "samples/project")), ladderFiles(path.join(root, "samples/nc5/conveyor.il"),'
        ' path.join(root, "samples/nc5"))]));')
    root = EXT.parents[1]
    r = subprocess.run(["node", "-e", script, str(root)], cwd=EXT, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    project, alone = json.loads(r.stdout)
    assert project == [str(root / "samples/project/src/conveyor.il"), str(root / "samples/project/src/pickplace.il")]
    assert alone == [str(root / "samples/nc5/conveyor.il")]
    assert run_mlc("ladder", *project, "-o", str(tmp_path / "ladder.html")).code == 0  # they check together
    assert run_mlc("ladder", project[0], "-o", str(tmp_path / "alone.html")).code == 1
