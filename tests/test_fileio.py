"""Outputs (mlctool/fileio.py): every output option creates the folders on its way; an output
never clobbers an input or another output, is checked before any work, and the outputs of a
run are written all or none (issue 21 items 1, 3 and 13; docs/reliability.md)."""

from __future__ import annotations

import os
import shutil
import tracemalloc

import pytest

from conftest import SAMPLES, run_mlc
from mlctool.diagnostics import MlcError
from mlctool.fileio import Outputs

PROJECT = SAMPLES / "project"
NC5 = SAMPLES / "nc5"


@pytest.fixture
def work(tmp_path):
    shutil.copy(NC5 / "conveyor.il", tmp_path / "c.il")
    shutil.copy(NC5 / "conveyor.stim", tmp_path / "c.stim")
    return tmp_path


@pytest.mark.parametrize("args, outputs", [
    (["build", "c.il", "-o", "build/x.mlx", "--listing", "lst/x.lst", "--map", "map/x.map"],
     ["build/x.mlx", "lst/x.lst", "map/x.map"]),
    (["build", "c.il", "-o", "mods/deep/c.mlo"], ["mods/deep/c.mlo"]),
    (["build", "-c", "c.il", "-o", "objs/"], ["objs/c.mlo"]),
    (["sim", "c.il", "--stimulus", "c.stim", "--vcd", "w/c.vcd", "--junit", "j/c.xml", "--report", "r/c.html"],
     ["w/c.vcd", "w/c.gtkw", "j/c.xml", "r/c.html"]),
    (["ladder", "c.il", "-o", "pics/c.svg"], ["pics/c.svg"]),
    (["import", "c.il", "--target", "nc5", "-o", "imported/c.il"], ["imported/c.il"]),
])
def test_missing_output_folders_are_created(work, args, outputs):
    r = run_mlc(*args, cwd=work)
    assert r.code == 0, r.err
    for out in outputs:
        assert (work / out).is_file(), out


def test_compile_folder_that_is_a_file_is_refused(work):
    (work / "objs").write_text("not a folder\n")
    r = run_mlc("build", "-c", "c.il", "-o", "objs", cwd=work)
    assert r.code == 2 and "E510" in r.err and "is a file" in r.err


def test_folder_that_cannot_be_created_is_e605(work):
    (work / "blocker").write_text("a file where a folder is needed\n")
    r = run_mlc("build", "c.il", "-o", "blocker/x.mlx", cwd=work)
    assert r.code != 0 and "E605" in r.err and "Traceback" not in r.err


CONVEYOR_IL = (SAMPLES / "nc5" / "conveyor.il").read_text()
CONVEYOR_STIM = (SAMPLES / "nc5" / "conveyor.stim").read_text()


@pytest.fixture
def project(tmp_path):
    (tmp_path / "c.il").write_text(CONVEYOR_IL)
    (tmp_path / "c.stim").write_text(CONVEYOR_STIM)
    return tmp_path


def _snapshot(folder) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


# ---------------------------------------------------------------- an output that is an input

@pytest.mark.parametrize("args", [
    ["--vcd", "c.il"],             # the source replaced by a waveform
    ["--junit", "c.stim"],         # the stimulus replaced by a report
    ["--report", "./c.il"],        # another name for the same file
    ["--vcd", "f.vcd", "--junit", "f.vcd"],  # two outputs into one file
    ["--vcd", "sub/../c.stim"],
])
def test_sim_refuses_an_output_that_is_an_input_or_another_output(project, args):
    (project / "sub").mkdir()
    before = _snapshot(project)
    r = run_mlc("sim", "c.il", "--stimulus", "c.stim", *args, cwd=project)
    assert r.code == 2 and "error[E606]" in r.err, r.err
    assert _snapshot(project) == before  # nothing written, nothing replaced


def test_sim_refuses_a_symlink_or_hard_link_to_an_input(project):
    os.symlink("c.il", project / "link.vcd")
    os.link(project / "c.stim", project / "hard.xml")
    before = _snapshot(project)
    r = run_mlc("sim", "c.il", "--stimulus", "c.stim", "--vcd", "link.vcd", cwd=project)
    assert r.code == 2 and "E606" in r.err and "input c.il" in r.err
    r = run_mlc("sim", "c.il", "--stimulus", "c.stim", "--junit", "hard.xml", cwd=project)
    assert r.code == 2 and "E606" in r.err and "input c.stim" in r.err
    assert _snapshot(project) == before


def test_sim_batch_refuses_junit_onto_a_matched_stimulus(project):
    (project / "tests").mkdir()
    (project / "tests" / "a.stim").write_text(CONVEYOR_STIM)
    before = (project / "tests" / "a.stim").read_bytes()
    r = run_mlc("sim", "c.il", "--stimulus", "tests/*.stim", "--junit", "tests/a.stim", cwd=project)
    assert r.code == 2 and "E606" in r.err
    assert (project / "tests" / "a.stim").read_bytes() == before


def test_sim_refuses_the_configuration_file_as_an_output(project):
    (project / "mlc.toml").write_text('target = "nc5"\n')
    r = run_mlc("sim", "c.il", "--stimulus", "c.stim", "--junit", "mlc.toml", cwd=project)
    assert r.code == 2 and "E606" in r.err
    assert (project / "mlc.toml").read_text() == 'target = "nc5"\n'


# ---------------------------------------------------------------- all or none

def test_sim_checks_every_output_before_writing_any(project):
    """--vcd v.vcd --junit BAD/j.xml: v.vcd was replaced and then the run failed (exit 2)."""
    (project / "v.vcd").write_text("old waveform\n")
    (project / "afile").write_text("a file, not a folder\n")
    r = run_mlc("sim", "c.il", "--stimulus", "c.stim", "--vcd", "v.vcd", "--junit", "afile/j.xml",
                cwd=project)
    assert r.code == 2 and "E605" in r.err and "afile" in r.err
    assert (project / "v.vcd").read_text() == "old waveform\n"
    assert not (project / "v.gtkw").exists()
    assert not [p for p in project.iterdir() if p.name.startswith(".mlc-")]  # no temporary left


def test_a_failed_stage_leaves_every_target_as_it_was(tmp_path):
    (tmp_path / "a.txt").write_text("old a")
    (tmp_path / "b").mkdir()  # a folder where the second file should go: its rename fails
    plan = Outputs()
    with pytest.raises(MlcError) as e:
        plan.write({str(tmp_path / "a.txt"): "new a", str(tmp_path / "b"): "new b"})
    assert e.value.diagnostic.code == "E605"
    assert (tmp_path / "a.txt").read_text() in ("old a", "new a")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b"]  # no temporary file left


def test_outputs_are_validated_before_the_run(project):
    r = run_mlc("sim", "c.il", "--stimulus", "c.stim", "--vcd", ".", cwd=project)
    assert r.code == 2 and ("E605" in r.err or "directory" in r.err)


# ---------------------------------------------------------------- the GTKWave save file

def test_vcd_keeps_a_users_gtkw_and_says_so(project):
    user = "[*] my own view\n@28\nmlc.Y0\n"
    (project / "x.gtkw").write_text(user)
    r = run_mlc("sim", "c.il", "--stimulus", "c.stim", "--vcd", "x.vcd", cwd=project)
    assert r.code == 0, r.err
    assert (project / "x.gtkw").read_text() == user
    assert "x.gtkw" in r.err and "kept" in r.err
    assert (project / "x.vcd").stat().st_size > 0


def test_vcd_replaces_its_own_gtkw(project):
    r = run_mlc("sim", "c.il", "--stimulus", "c.stim", "--vcd", "x.vcd", "--watch", "Y0", cwd=project)
    assert r.code == 0 and "mlc.C0_w" not in (project / "x.gtkw").read_text()
    r = run_mlc("sim", "c.il", "--stimulus", "c.stim", "--vcd", "x.vcd", "--watch", "C0:w", cwd=project)
    assert r.code == 0 and "kept" not in r.err
    assert "mlc.C0_w" in (project / "x.gtkw").read_text()


# ---------------------------------------------------------------- the streamed VCD

def test_streamed_vcd_equals_the_vcd_of_the_kept_trace(project):
    from mlctool.sim.run.run import Simulation, build_models
    from mlctool.sim.run.vcd import to_vcd
    from mlctool.sim.stimulus.stimulus import load_stimulus
    from mlctool.targetapi import load_target

    r = run_mlc("sim", "c.il", "--stimulus", "c.stim", "--vcd", "s.vcd", cwd=project)
    assert r.code == 0
    target = load_target("nc5")
    from mlctool.asm import program_from_paths
    from mlctool.config import Config

    image, _, _ = program_from_paths([str(project / "c.il")], target, Config())
    st, _ = load_stimulus(str(project / "c.stim"), target)
    models, _ = build_models(st, target)
    sim = Simulation(image, target, st, models, st.scan_us or 10_000, [], trace=True)
    kept = to_vcd(sim.run(1300), image, target)
    assert (project / "s.vcd").read_text() == kept.replace(str(project / "c.il"), "c.il")


def _toggler(bits: int) -> str:
    return "".join(f"LDI M{k}\nOUT M{k}\n" for k in range(bits)) + "END\n"


def _vcd_peak(tmp_path, scans: int, stream: bool) -> int:
    """Peak Python memory of a traced run of `scans` scans of 64 bits changing every scan,
    the VCD streamed to a file as `mlc sim --vcd` does (or the trace kept, as before)."""
    from mlctool.asm import program_from_paths
    from mlctool.config import Config
    from mlctool.sim.run.run import Simulation
    from mlctool.sim.run.vcd import VcdStream
    from mlctool.sim.stimulus.stimulus import Stimulus
    from mlctool.targetapi import load_target

    (tmp_path / "t.il").write_text(_toggler(64))
    target = load_target("nc5")
    image, _, _ = program_from_paths([str(tmp_path / "t.il")], target, Config())
    sim = Simulation(image, target, Stimulus("<none>", []), [], 10_000, [], trace=True)
    with open(tmp_path / "t.vcd", "w", encoding="utf-8", newline="") as f:
        vcd = VcdStream(f, sim.views, image, target)
        if stream:
            sim.trace_sink = vcd.add
        tracemalloc.start()
        try:
            result = sim.run(scans)
            _, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        vcd.close(result.time_us)
    return peak


def test_vcd_memory_does_not_grow_with_the_changes(tmp_path):
    """Kept in memory, 64 changes per scan cost ~113 bytes each. Streamed, the peak is the
    same whatever the number of scans: a bound set by the devices, not the changes."""
    short = _vcd_peak(tmp_path, 100, stream=True)
    long = _vcd_peak(tmp_path, 1000, stream=True)  # 64,000 value changes
    assert (tmp_path / "t.vcd").stat().st_size > 200_000  # the changes are all in the file
    kept = _vcd_peak(tmp_path, 1000, stream=False)
    assert kept > 50 * 1000 * 64  # the measure sees the kept trace (what the CLI did before)
    assert long < short + 200_000, (short, long)
    assert long < kept / 10, (long, kept)


# ---------------------------------------------------------------- every command with outputs

@pytest.mark.parametrize("args", [
    ["build", "c.il", "-o", "c.mlx", "--map", "c.mlx"],
    ["build", "c.il", "-o", "c.mlx", "--listing", "c.il"],
    ["build", "c.il", "-o", "c.il.mlo", "--listing", "c.il.mlo"],
    ["build", "-c", "c.il", "-o", "objs", "--listing", "x"],  # usage error first: still nothing written
    ["ladder", "c.il", "-o", "l.svg"],  # l.svg is a symbolic link to c.il
    ["import", "c.il", "-o", "c.il"],
    ["fmt", "c.il", "./c.il"],          # one file named twice would be rewritten twice
    ["build", "c.il", "-o", "c.mlx", "--listing", "h.lst"],  # h.lst is a hard link to c.il
])
def test_commands_refuse_an_output_that_is_an_input(project, args):
    os.symlink("c.il", project / "l.svg")
    os.link(project / "c.il", project / "h.lst")
    (project / "objs").mkdir()
    before = _snapshot(project)
    r = run_mlc(*args, cwd=project)
    assert r.code == 2, r.err
    assert "E606" in r.err or "-c writes objects only" in r.err
    assert _snapshot(project) == before and not os.listdir(project / "objs")


def test_project_build_refuses_a_listing_onto_a_source(project):
    (project / "src").mkdir()
    (project / "src" / "pickplace.il").write_text(CONVEYOR_IL)
    (project / "mlc.toml").write_text('sources = ["src/pickplace.il"]\nlisting = "src/pickplace.il"\n')
    r = run_mlc("build", cwd=project)
    assert r.code == 2 and "E606" in r.err and "mlc.toml listing" in r.err
    assert (project / "src" / "pickplace.il").read_text() == CONVEYOR_IL
    assert not (project / "build").exists()


def test_link_refuses_an_output_that_is_an_object(project):
    assert run_mlc("build", "c.il", "-o", "c.mlo", cwd=project).code == 0
    before = (project / "c.mlo").read_bytes()
    r = run_mlc("link", "c.mlo", "-o", "p.mlx", "--listing", "c.mlo", cwd=project)
    assert r.code == 2 and "E606" in r.err
    assert (project / "c.mlo").read_bytes() == before and not (project / "p.mlx").exists()


def test_objdump_il_dir_refuses_to_overwrite_its_object(project):
    assert run_mlc("build", "c.il", "-o", "c.il.mlx", cwd=project).code == 0
    os.rename(project / "c.il.mlx", project / "c.il")  # the object now has the module's name
    before = (project / "c.il").read_bytes()
    r = run_mlc("objdump", "c.il", "--il-dir", ".", "--target", "nc5", cwd=project)
    assert r.code == 2 and "E606" in r.err, r.err
    assert (project / "c.il").read_bytes() == before


def test_mlc_test_refuses_junit_onto_a_scenario(project):
    (project / "tests").mkdir()
    (project / "tests" / "a.stim").write_text(CONVEYOR_STIM)
    (project / "mlc.toml").write_text('sources = ["c.il"]\ntests = ["tests/*.stim"]\n')
    r = run_mlc("test", "--junit", "tests/a.stim", cwd=project)
    assert r.code == 2 and "E606" in r.err
    assert (project / "tests" / "a.stim").read_text() == CONVEYOR_STIM
    r = run_mlc("test", "--coverage", "--coverage-dir", "c.il", cwd=project)
    assert r.code == 2 and ("E605" in r.err or "E606" in r.err)
    assert (project / "c.il").read_text() == CONVEYOR_IL
