"""Batch runs (`mlc sim PROGRAM --stimulus 'dir/*.stim'`): per scenario, the same JSON and
JUnit as `mlc sim PROGRAM --stimulus FILE`, whether run as lanes, one by one or in processes."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import pytest

from conftest import run_mlc, without_times
from mlctool.sim.campaign.batch import Options, run_batch
from simkit import NC5, image_of

PROGRAM = """
LD X0
ANI X1
OR M0
AND X2
OUT M0
LDP X3
SET Y1
LDF X3
RST Y1
LD M0
MPS
AND X4
OUT Y2
MPP
INV
PLS M5
LD M0
LD X5
ORI X1
ORB
OUT Y3
END
"""

STIMULI = {
    "a_pass.stim": "0ms X0=1 X2=1\n10ms expect M0=1 Y3=1\n20ms X0=0\n30ms expect M0=1\n",
    "b_fail.stim": "0ms X0=1\n10ms expect M0=1 Y2=1\n",  # X2 is 0: M0 stays Off
    "c_edges.stim": "0ms X3=1\n10ms expect Y1=1\n20ms X3=0\n20ms expect Y1=0 M5=1\nrun 100ms\n",
    "d_force.stim": "0ms force X2=1\n0ms X0=1\n10ms expect M0=1\n20ms release X2\n20ms X2=0\n"
                    "30ms expect M0=0\n",
    "e_words.stim": "0ms X0=1 X2=1 D5=7\n10ms expect D5=7 M0=1\n",  # a word: not a lane
    "f_scan.stim": "scan 5ms\n0ms X5=1\n5ms expect Y3=1\n",
    "g_late.stim": "0ms X0=1\n10ms expect M0=0\nrun 5ms\n",  # expectation after the run
}


@pytest.fixture()
def project(tmp_path):
    (tmp_path / "p.il").write_text(PROGRAM.strip() + "\n")
    d = tmp_path / "tests"
    d.mkdir()
    for name, text in STIMULI.items():
        (d / name).write_text(text)
    return tmp_path


def _xml(suite) -> bytes:
    suite.tail = None
    return without_times(ET.tostring(suite))


def _single(project, name, *extra):
    return run_mlc("sim", "p.il", "--stimulus", f"tests/{name}", *extra, cwd=project)


def test_batch_json_and_junit_equal_one_by_one_runs(project, sim_engine):
    batch = run_mlc("sim", "p.il", "--stimulus", "tests/*.stim", "--json", "--junit", "all.xml",
                    cwd=project)
    assert batch.code == 1  # b_fail and g_late fail
    docs = json.loads(batch.out)["scenarios"]
    assert list(docs) == [f"tests/{n}" for n in sorted(STIMULI)]
    suites = {s.get("name"): _xml(s) for s in ET.parse(project / "all.xml").getroot()}
    codes = {}
    for name in STIMULI:
        one = _single(project, name, "--json", "--junit", "one.xml")
        assert docs[f"tests/{name}"] == json.loads(one.out), name
        [suite] = ET.parse(project / "one.xml").getroot()
        assert suites[f"tests/{name}"] == _xml(suite), name
        codes[name] = one.code
    assert codes["b_fail.stim"] == codes["g_late.stim"] == 1 and codes["a_pass.stim"] == 0
    assert "last_write" in batch.out and "t" in batch.err  # the failure names its writer


def test_lanes_processes_and_one_by_one_agree(project, monkeypatch):
    monkeypatch.chdir(project)
    image = image_of(PROGRAM)
    paths = [f"tests/{n}" for n in sorted(STIMULI)]
    lanes, stats = run_batch(image, NC5, paths, Options(), jobs=1)
    assert stats.lanes + stats.reruns == 5 and stats.reruns >= 1 and stats.single == 2
    single, _ = run_batch(image, NC5, paths, Options(), jobs=1, lanes=False)
    procs, _ = run_batch(image, NC5, paths, Options(), jobs=2, lanes=False)
    for a, b, c in zip(lanes, single, procs):
        assert a.stim == b.stim == c.stim
        assert a.result == b.result == c.result, a.stim
        assert [d.message for d in a.diagnostics] == [d.message for d in b.diagnostics]


def test_many_lanes_match_single_runs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    import random

    rnd = random.Random(5)
    paths = []
    for k in range(70):
        lines = [f"{rnd.randrange(0, 200, 10)}ms X{rnd.randrange(6)}={rnd.randrange(2)}" for _ in range(8)]
        lines.append(f"{rnd.randrange(0, 200, 10)}ms expect M0={rnd.randrange(2)} Y3={rnd.randrange(2)}")
        (tmp_path / f"s{k:02}.stim").write_text("\n".join(lines) + "\nrun 200ms\n")
        paths.append(f"s{k:02}.stim")
    image = image_of(PROGRAM)
    lanes, stats = run_batch(image, NC5, paths, Options())
    single, _ = run_batch(image, NC5, paths, Options(), lanes=False)
    assert stats.lanes > 10 and stats.reruns > 10
    assert [s.result for s in lanes] == [s.result for s in single]


def test_batch_errors(project):
    r = run_mlc("sim", "p.il", "--stimulus", "nothing/*.stim", cwd=project)
    assert r.code == 2 and "E100" in r.err
    r = run_mlc("sim", "p.il", "--stimulus", "tests/*.stim", "--vcd", "x.vcd", cwd=project)
    assert r.code == 2 and "--vcd" in r.err
    (project / "tests" / "z_bad.stim").write_text("0ms X0=7\n")
    r = run_mlc("sim", "p.il", "--stimulus", "tests/*.stim", cwd=project)
    assert r.code == 2 and "z_bad.stim:1:5: error[E601]" in r.err and "Traceback" not in r.err
    assert "batch: 8 scenarios" in r.out


WORD_PROGRAM = """
LD X0
TMR T0 K3
LD X1
CNT C0 K4
LD T0
OUT Y0
LD C0
OUT Y1
LD M100
MOV K7 D0
ADD D0 D1 D2
SUB D2 K30000 D3
MUL D2 K300 D4
WAND D1 K255 D6
INC D7
LD> D2 K10
OR= D8 K-1
OUT M1
LDP X2
DADD D10 K70000 D10
DMOV D10 D12
CML D1 D14
LD M1
ANI X3
SET Y2
LD X3
RST Y2
LD< D10 K0
OUT Y3
END
"""


def test_word_lanes_match_single_runs(tmp_path, monkeypatch):
    """Numpy word lanes: the same results (devices, expectations, reruns of failures) as one
    run per scenario."""
    monkeypatch.chdir(tmp_path)
    import random

    from mlctool.sim.campaign.word_lanes import WordLaneProgram
    from mlctool.sim.scan import load_program

    image = image_of(WORD_PROGRAM)
    assert WordLaneProgram(load_program(image, NC5)).ok
    rnd = random.Random(7)
    paths = []
    for k in range(48):
        lines = [f"{rnd.randrange(0, 300, 10)}ms X{rnd.randrange(4)}={rnd.randrange(2)}" for _ in range(6)]
        lines += [f"{rnd.randrange(0, 300, 10)}ms {rnd.choice(['D1', 'D8'])}="
                  f"{rnd.choice([0, 1, 5, -1, 32767, -32768])}" for _ in range(3)]
        lines.append(f"{rnd.randrange(0, 100, 10)}ms M100={rnd.randrange(2)}")
        lines.append(f"{rnd.randrange(0, 300, 10)}ms D10:d={rnd.randrange(-2**31, 2**31)}")
        if k % 5 == 0:
            lines.append(f"{rnd.randrange(0, 100, 10)}ms force D1={rnd.randrange(-5, 5)}")
            lines.append(f"{rnd.randrange(100, 300, 10)}ms release D1")
        if k % 2:  # expectations that mostly fail (the failing lanes are run again on their own)
            lines.append(f"{rnd.randrange(0, 300, 10)}ms expect Y0={rnd.randrange(2)} D7={rnd.randrange(0, 40)}")
        (tmp_path / f"w{k:02}.stim").write_text("\n".join(lines) + "\nrun 300ms\n")
        paths.append(f"w{k:02}.stim")
    first, _ = run_batch(image, NC5, paths, Options(), lanes=False)
    for k, sc in enumerate(first):  # expectations that hold: the single run's final values
        if k % 2 == 0:
            d = sc.result.devices
            with open(paths[k], "a") as f:
                f.write(f"290ms expect D2={d['D2']} D4={d['D4']} D5={d['D5']} D10:d={d['D10:d']} T0:w={d['T0:w']} "
                        f"C0:w={d['C0:w']} Y2={d['Y2']} D14={d['D14']}\n")
    lanes, stats = run_batch(image, NC5, paths, Options())
    single, _ = run_batch(image, NC5, paths, Options(), lanes=False)
    assert stats.word_lanes > 15 and stats.reruns > 5
    assert [s.result for s in lanes] == [s.result for s in single]
    assert [[d.message for d in s.diagnostics] for s in lanes] == [[d.message for d in s.diagnostics] for s in single]


def test_lane_results_are_single_runs_in_order(tmp_path, monkeypatch):
    """Lanes report exactly the single run's result, device order included (the JSON order):
    scenarios that name devices outside the program (each its own), the same device written
    `M7` and `m7`, scan-number and time lines, several items on a line, comments, forces,
    expectations that hold and fail (run again alone), and a scenario with a bad line."""
    import random

    monkeypatch.chdir(tmp_path)
    rnd = random.Random(11)
    paths = []
    for k in range(96):
        lines = ["# generated"]
        for _ in range(12):
            dev = rnd.choice(["X0", "X1", "X2", "X3", "X4", "X5", "M0", f"M{rnd.randrange(10, 40)}",
                              f"m{rnd.randrange(10, 40)}", f"Y{rnd.randrange(8)}", f"A{rnd.randrange(3)}"])
            when = rnd.choice([f"#{rnd.randrange(30)}", f"{rnd.randrange(0, 300, 10)}ms"])
            lines.append(f"{when} {dev}={rnd.randrange(2)}" + rnd.choice(["", " X1=0", "  # note"]))
        if k % 3 == 0:
            lines += [f"{rnd.randrange(0, 100, 10)}ms force X2=1", f"{rnd.randrange(100, 200, 10)}ms release X2"]
        if k % 4 == 0:
            lines.append(f"{rnd.randrange(0, 300, 10)}ms expect M0={rnd.randrange(2)} M{rnd.randrange(50, 60)}=0")
        if k == 50:
            lines.append("#5 M7=2")
        (tmp_path / f"s{k:02}.stim").write_text("\n".join(lines) + "\nrun 300ms\n")
        paths.append(f"s{k:02}.stim")
    image = image_of(PROGRAM)
    lanes, stats = run_batch(image, NC5, paths, Options())
    single, _ = run_batch(image, NC5, paths, Options(), lanes=False)
    assert stats.lanes > 60 and stats.reruns > 3 and lanes[50].result is None
    for a, b in zip(lanes, single):
        assert a.result == b.result, a.stim
        if a.result is not None:
            assert list(a.result.devices.items()) == list(b.result.devices.items()), a.stim
            assert a.result.views == b.result.views
        assert [(d.code, d.message) for d in a.diagnostics] == [(d.code, d.message) for d in b.diagnostics]
