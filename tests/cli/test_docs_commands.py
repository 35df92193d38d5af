"""Every `mlc ...` command line the documentation shows runs, so the docs cannot drift from the
tool.

Harvested: each line of a fenced block (```) in README.md and docs/*.md that starts with
`mlc` and a subcommand or option (after a `$ ` prompt, a YAML `- ` or `run: `, and in
`a && mlc b` chains), with `\\` continuations joined; and the Examples of every command's
`--help` (tests/cli/test_cli_help.py checks they are there). Shell redirections and pipes end a
command (`mlc check > out.sarif` runs `mlc check`).

Synopsis notation is turned into one concrete command: an optional group `[--a | --b X]`
becomes its first alternative (`--a`), `X...` becomes `X`, and the placeholders the docs use
(FILES, PROGRAM, OUT.svg, F, DIR, CODE, PORT, ...) become names from PLACEHOLDERS.

Example file names are mapped to bundled files: each document runs in a fresh copy of one
workspace (WORKSPACE_FILES), in which the names the docs use are copies of bundled samples:
`src/main.il` and `src/lib.il` are samples/project's conveyor and pick-and-place library,
`prog.il`/`s.stim` the NC5 conveyor sample (docs/vs.md: the VS traffic light), `export.csv`
a GX Works2 export from tests/data, `MAIN.wpg` a GX Developer program body of tests/wpgkit.py
(`PROJECT` a GX Developer project folder holding it),
`prog.pos` an FBs positioning sample, `project.pdw` / `rungs.il` a WinProladder project of
tests/pdwkit.py and its IL; `mlc.toml` makes it
a project (sources src/main.il, src/lib.il; scenarios tests/*.stim), `samples/` is a copy of
the bundled samples, and the project is built beforehand (build/program.mlx, .map, .lst and
objs/*.mlo), so a line that reads an output of another example runs on its own.

Each command is first parsed by click (unknown options, bad choices and missing arguments
fail), then run in the document's order in its workspace: it must exit 0, with no traceback
or internal error. `mlc device serve` serves until stopped, so it is only parsed.

The README's example program and stimulus (IL, not commands) are run by tests/test_readme.py.
"""

from __future__ import annotations

import glob
import re
import shlex
import shutil
from pathlib import Path

import click
import pytest

from mlctool.cli import all_commands, main_group
from tests.conftest import ROOT, SAMPLES, run_mlc

DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

WORKSPACE_FILES = {
    "src/main.il": "samples/project/src/conveyor.il",
    "src/lib.il": "samples/project/src/pickplace.il",
    "tests/start.stim": "samples/project/tests/pick_cycle.stim",
    "prog.il": "samples/nc5/conveyor.il",
    "s.stim": "samples/nc5/conveyor.stim",
    "export.csv": "tests/data/vs_imports/gxworks2.csv",
    "program.csv": "tests/data/vs_imports/gxworks2.csv",
    "MAIN.csv": "tests/corpus/gxworks2_zh_cn.csv",
    "COMMENT.csv": "tests/corpus/COMMENT.csv",
    "MAIN.wpg": "tests/data/wpg/MAIN.wpg",
    "PROJECT/Gppw.gpj": "tests/data/wpg/Gppw.gpj",  # (empty: mlc import only looks for it)
    "PROJECT/Resource/POU/Body/MAIN.wpg": "tests/data/wpg/MAIN.wpg",
    "prog.pos": "samples/fbs/run.pos",
    "project.pdw": "tests/data/winproladder/project.pdw",
    "rungs.il": "tests/data/winproladder/rungs.il",
}
VS_PROGRAM = {"prog.il": "samples/vs/traffic_light.il"}
OVERRIDES = {"docs/vs.md": VS_PROGRAM, "mlc targets --help": VS_PROGRAM, "mlc export --help": VS_PROGRAM}

PROJECT_TOML = """\
sources = ["src/main.il", "src/lib.il"]
output = "build/program.mlx"
listing = "build/program.lst"
map = "build/program.map"
tests = ["tests/*.stim"]
"""

# placeholder -> name; (option, placeholder) -> name where the option decides
PLACEHOLDERS = {
    "FILES": "src/*.il", "FILE": "prog.il", "PROGRAM": "prog.il", "S.stim": "s.stim",
    "OUT.svg": "out.svg", "OUT.html": "out.html", "DIR": "rebuilt", "CODE": "W401",
    "PATH": "/dev/null", ("--map", "F"): "build/other.map", ("--listing", "F"): "build/other.lst",
}
PARSE_ONLY = {("device", "serve"), ("lsp",), ("debug",), ("run",), ("mcp",)}  # serve until stopped; debug reads commands or DAP frames from stdin

COMMAND = re.compile(r"^(?:\$ |- |run: )?(mlc (?:[a-z-]|--?[a-z]).*)$")


def harvest(text: str) -> list[str]:
    """The `mlc` command lines of the fenced blocks of a Markdown text, in order."""
    out = []
    for block in re.findall(r"^\s*```[^\n]*\n(.*?)^\s*```", text, re.S | re.M):
        for line in re.sub(r"\\\n\s*", " ", block).splitlines():
            for part in re.split(r"\s*&&\s*", line.strip()):
                m = COMMAND.match(part.strip())
                if m:
                    out.append(m.group(1))
    return out


def concrete(line: str) -> list[str]:
    """One runnable argument list for a documented command line (without the leading mlc)."""
    while True:  # [a | b] -> a, innermost first
        line, n = re.subn(r"\[([^\[\]]*)\]", lambda m: m.group(1).split("|")[0].strip(), line)
        if not n:
            break
    line = re.sub(r"(?<=\S)\.\.\.(?=\s|$)", "", line)
    line = line.replace(":PORT", ":5020")
    lexer = shlex.shlex(line, posix=True, punctuation_chars="|&;<>")
    lexer.whitespace_split = True
    lexer.commenters = "#"
    words = []
    for word in lexer:
        if word and set(word) <= set("|&;<>"):
            break  # a redirection or pipe ends the command
        words.append(word)
    assert words[0] == "mlc", line
    args = []
    for word in words[1:]:
        prev = args[-1] if args else None
        args.append(PLACEHOLDERS.get((prev, word), PLACEHOLDERS.get(word, word)))
    return args


def parse_only(args: list[str]) -> tuple[str, ...]:
    """Let click parse the arguments without running the command; the command's path."""
    cmd: click.Command = main_group
    ctx = click.Context(main_group, info_name="mlc")
    path: list[str] = []
    rest = list(args)
    while isinstance(cmd, click.Group):
        name, cmd, rest = cmd.resolve_command(ctx, rest)
        path.append(name)
        if isinstance(cmd, click.Group):
            ctx = click.Context(cmd, info_name=name, parent=ctx)
    cmd.make_context(path[-1], list(rest), parent=ctx)
    return tuple(path)


@pytest.fixture(scope="module")
def template(tmp_path_factory) -> Path:
    ws = tmp_path_factory.mktemp("docs-workspace")
    shutil.copytree(SAMPLES, ws / "samples", ignore=shutil.ignore_patterns("build", "out"))
    for name, source in WORKSPACE_FILES.items():
        (ws / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / source, ws / name)
    for stim in sorted((SAMPLES / "project" / "tests").glob("*.stim")):
        shutil.copy(stim, ws / "tests" / stim.name)
    (ws / "mlc.toml").write_text(PROJECT_TOML)
    for args in (["build"], ["build", "-c", "src/main.il", "src/lib.il", "-o", "objs/"]):
        r = run_mlc(*args, cwd=ws)
        assert r.code == 0, r.err
    return ws


def _help_examples() -> dict[str, list[str]]:
    out = {}

    def walk(prefix: list[str], cmd: click.Command) -> None:
        ctx = click.Context(cmd, info_name=" ".join(["mlc", *prefix]))
        text = cmd.get_help(ctx)
        if "\n  Examples:\n" in text:
            out[" ".join(["mlc", *prefix])] = [
                line.strip() for line in text.split("\n  Examples:\n", 1)[1].splitlines() if line.strip()]
        if isinstance(cmd, click.Group):
            for name in cmd.list_commands(ctx):
                walk([*prefix, name], cmd.get_command(ctx, name))

    all_commands()
    walk([], main_group)
    return out


SOURCES = {str(p.relative_to(ROOT)): harvest(p.read_text("utf-8")) for p in DOCS}
SOURCES.update({f"{name} --help": [cmd for line in lines for cmd in harvest(f"```\n{line}\n```\n")]
                for name, lines in _help_examples().items()})


def test_the_docs_show_commands():
    assert len(SOURCES["README.md"]) >= 10
    assert sum(map(len, SOURCES.values())) >= 60
    assert concrete("mlc objdump prog.mlx [--json | --il | --il-dir DIR]") == ["objdump", "prog.mlx", "--json"]
    assert concrete("mlc link objs/a.mlo -o p.mlx [--map F] [--listing F]  # x") == [
        "link", "objs/a.mlo", "-o", "p.mlx", "--map", "build/other.map", "--listing", "build/other.lst"]
    assert concrete("mlc check --format sarif src > mlc.sarif") == ["check", "--format", "sarif", "src"]
    assert concrete("mlc ladder [--target nc5] FILES... -o OUT.svg") == [
        "ladder", "--target", "nc5", "src/*.il", "-o", "out.svg"]


@pytest.mark.parametrize("source", sorted(s for s in SOURCES if SOURCES[s]))
def test_documented_commands_run(source, template, tmp_path):
    ws = tmp_path / "ws"
    shutil.copytree(template, ws)
    for name, bundled in OVERRIDES.get(source, {}).items():
        shutil.copy(ROOT / bundled, ws / name)
    for line in SOURCES[source]:
        args = concrete(line)
        try:
            path = parse_only(args)
        except click.ClickException as e:
            pytest.fail(f"{source}: `{line}` does not parse: {e.format_message()}")
        if path in PARSE_ONLY:
            continue
        args = [a for arg in args for a in _glob(arg, ws)]
        r = run_mlc(*args, cwd=ws)
        assert "Traceback" not in r.err and "internal error" not in r.err, f"{source}: `{line}`\n{r.err}"
        assert r.code == 0, f"{source}: `{line}` -> mlc {shlex.join(args)} exited {r.code}\n{r.out}{r.err}"


def _glob(arg: str, ws: Path) -> list[str]:
    """A shell expands an unquoted glob; a pattern for mlc itself (--stimulus 'tests/*.stim')
    was quoted in the docs and arrives here without quotes, so only source globs expand."""
    if "*" in arg and arg.endswith(".il"):
        return sorted(glob.glob(arg, root_dir=ws)) or [arg]
    return [arg]
