"""Every file a command reads is refused as every one of its outputs (issue 30.2, 30.3).

One mechanism holds it (mlctool/fileio.py): every input is opened through fileio, which notes
it in the command's register of inputs; an output is checked against the register when it is
planned, an input against the planned outputs when it is opened, and every output once more
when it is written. This test walks every command that writes files: it runs each once,
watching (an audit hook) every file opened for reading in the project, asserts that fileio
noted each of them, then gives each such file as each output option and asserts E606, exit 2,
the file unchanged and no temporary file left. A new command, a new output option or a new
reader that opens files behind fileio's back fails here.
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

import pytest

from conftest import ROOT, run_mlc
from mlctool import fileio
from mlctool.cli import all_commands

_OPENED: list[str] | None = None  # files opened for reading while a command runs under _watching


def _audit(event: str, args: tuple) -> None:
    if _OPENED is None or event != "open":
        return
    path, mode, flags = args
    if not isinstance(path, (str, bytes, os.PathLike)):
        return  # a file descriptor
    reading = ("r" in mode and "+" not in mode) if isinstance(mode, str) else \
        (flags & os.O_ACCMODE) == os.O_RDONLY
    if reading:
        _OPENED.append(os.fsdecode(path))


sys.addaudithook(_audit)  # for the whole process (an audit hook cannot be removed): idle unless watching


def _watching(project: Path, args: list[str]) -> tuple[object, set[Path], set[Path]]:
    """Run `mlc ARGS` in `project`: (result, files opened for reading in the project, files
    fileio noted as inputs)."""
    global _OPENED
    _OPENED = []
    try:
        result = run_mlc(*args, cwd=project)
        opened = list(_OPENED)
    finally:
        _OPENED = None
    inside = {Path(os.path.realpath(project / p)) for p in opened}
    inside = {p for p in inside if p.is_file() and project in p.parents}
    noted = {Path(os.path.realpath(project / p)) for p in fileio.inputs_read()}
    return result, inside, noted


# command -> (files of the project, the command line, its output options: option -> the
# suffix its file must have, or "" for any). Every command that writes a file is here.
NC5 = {"a.il": ROOT / "samples/nc5/conveyor.il", "s.stim": ROOT / "samples/nc5/conveyor.stim"}
CASES = {
    "sim": (NC5, ["sim", "a.il", "--stimulus", "s.stim", "--config", "my.toml"],
            {"--vcd": "", "--junit": "", "--report": ""}),
    "sim --table": ({"h.il": ROOT / "samples/fbs/home_and_run.il", "h.stim": ROOT / "samples/fbs/home_and_run.stim",
                     "home.pos": ROOT / "samples/fbs/home.pos"},
                    ["sim", "--target", "fbs", "h.il", "--stimulus", "h.stim", "--table", "R5000=home.pos",
                     "--config", "my.toml"], {"--vcd": ""}),
    "sim batch": ({"a.il": NC5["a.il"], "t/s.stim": NC5["s.stim"]},
                  ["sim", "a.il", "--stimulus", "t/*.stim", "--config", "my.toml"], {"--junit": ""}),
    "build": (NC5, ["build", "a.il", "--config", "my.toml", "-o", "out.mlx"],
              {"-o": ".mlx", "--listing": "", "--map": ""}),
    "link": ({"a.mlo": None}, ["link", "a.mlo", "--config", "my.toml", "-o", "out.mlx"],
             {"-o": ".mlx", "--listing": "", "--map": ""}),
    "ladder": (NC5, ["ladder", "a.il", "--config", "my.toml", "-o", "out.svg"], {"-o": ".svg"}),
    "import": ({"g.csv": ROOT / "tests/corpus/gxworks2_en.csv", "c.csv": ROOT / "tests/corpus/COMMENT_en.csv"},
               ["import", "g.csv", "--comments", "c.csv", "--config", "my.toml", "-o", "out.il"], {"-o": ""}),
    "export": ({"a.il": ROOT / "tests/corpus/mrd_compare_blocks.il"},
               ["export", "--target", "vs", "--to", "gxworks2", "a.il", "--config", "my.toml", "-o", "out.csv"],
               {"-o": ""}),
    "verify": ({"a.il": NC5["a.il"], "p.props": ROOT / "samples/nc5/conveyor.props"},
               ["verify", "a.il", "--props", "p.props", "--config", "my.toml"], {"--sarif": "", "--junit": ""}),
    "test": ({"src/a.il": NC5["a.il"], "tests/s.stim": NC5["s.stim"]}, ["test"], {"--junit": ""}),
    "objdump": ({"a.mlx": None}, ["objdump", "a.mlx", "--il-dir", "il"], {}),  # its outputs: below
}
# commands that write no file (fmt rewrites the files it reads, by design: docs/reliability.md
# Outputs 5; debug's `save` is the debugger's own test, tests/debug)
WRITE_NOTHING = {"check", "debug", "device", "explain", "fmt", "lsp", "mcp", "run", "targets"}
# commands that read no file of the user's and write only files that do not exist yet (init:
# E122 for any file already there; tests/cli/test_cli_init.py)
WRITE_NEW_ONLY = {"init"}


def test_every_command_that_writes_files_is_walked():
    assert {case.split()[0] for case in CASES} | WRITE_NOTHING | WRITE_NEW_ONLY == set(all_commands())


def _project(tmp_path: Path, case: str) -> Path:
    files, _, _ = CASES[case]
    project = tmp_path / "p"
    project.mkdir()
    for name, source in files.items():
        (project / name).parent.mkdir(parents=True, exist_ok=True)
        if source is not None:
            shutil.copy(source, project / name)
    (project / "my.toml").write_text(f'target = "{"fbs" if "table" in case else "nc5"}"\n')
    if case == "test":
        (project / "mlc.toml").write_text('target = "nc5"\nsources = ["src/a.il"]\ntests = ["tests/*.stim"]\n')
    if case in ("link", "objdump"):
        shutil.copy(NC5["a.il"], project / "a.il")
        flag = ["-c"] if case == "link" else ["-o", "a.mlx"]
        assert run_mlc("build", "a.il", *flag, cwd=project).code == 0
        os.unlink(project / "a.il")
    return project


@pytest.mark.parametrize("case", list(CASES))
def test_every_file_a_command_reads_is_refused_as_each_output(tmp_path, case):
    project = _project(tmp_path, case)
    _, args, options = CASES[case]
    result, opened, noted = _watching(project, args)
    assert result.code in (0, 1), result.err
    assert opened, "the command read no file of the project?"
    assert opened <= noted, f"read behind fileio's back (not noted as inputs): {sorted(opened - noted)}"
    for path in sorted(opened):
        before = path.read_bytes()
        for option, suffix in options.items():
            given = path
            if suffix and path.suffix != suffix:  # the option takes only that suffix: a hard link to the input
                given = path.with_name(path.stem + "-link" + suffix)
                os.link(path, given)
            r = run_mlc(*args, option, os.path.relpath(given, project), cwd=project)
            assert r.code == 2 and "E606" in r.err, (case, option, path.name, r.err)
            assert "is the input" in r.err
            assert path.read_bytes() == before, (case, option, path.name)
            assert not list(project.rglob(".mlc-*.tmp"))
            if given != path:
                os.unlink(given)


def test_objdump_refuses_to_write_a_module_over_the_object_it_reads(tmp_path):
    """objdump --il-dir names its outputs after the modules: the object named as its module."""
    project = _project(tmp_path, "objdump")
    (project / "il").mkdir()
    os.replace(project / "a.mlx", project / "il" / "a.il")
    before = (project / "il" / "a.il").read_bytes()
    r = run_mlc("objdump", "il/a.il", "--il-dir", "il", cwd=project)
    assert r.code == 2 and "E606" in r.err, r.err
    assert (project / "il" / "a.il").read_bytes() == before


def test_import_refuses_its_comments_file_through_a_missing_folder(tmp_path):
    """`-o nosuch/../c.csv` names c.csv (the folder would be created on the way)."""
    project = _project(tmp_path, "import")
    before = (project / "c.csv").read_bytes()
    for out in ("c.csv", "nosuch/../c.csv", "./nosuch/../../p/c.csv"):
        r = run_mlc("import", "g.csv", "--comments", "c.csv", "-o", out, cwd=project)
        assert r.code == 2 and "E606" in r.err and "is the input c.csv" in r.err, r.err
        assert (project / "c.csv").read_bytes() == before
        assert not (project / "nosuch").exists()


def test_an_input_opened_after_the_output_was_planned_is_refused(tmp_path):
    """The order does not matter: an output planned first refuses the input opened later
    (mlc import plans -o, then reads the export and --comments)."""
    plan = fileio.Outputs()
    fileio.begin_command()
    out = tmp_path / "c.csv"
    out.write_text("x")
    plan.add(str(tmp_path / "sub" / ".." / "c.csv"), "-o")
    with pytest.raises(fileio.MlcError) as e:
        fileio.read_input(str(out), 100)
    assert e.value.diagnostic.code == "E606"
    plan.discard()  # the plan is over: the file may be read again
    assert fileio.read_input(str(out), 100) == b"x"
    fileio.begin_command()
