"""The VS manual's example programs in samples/vs/ (issue 8): each cites its section, checks
clean, builds, and passes its stimulus file; the stimulus catches a wrong program."""

from __future__ import annotations

import pytest

from conftest import SAMPLES, run_mlc

VS_SAMPLES = ["fountain", "cj_skip", "index", "fountain_modes", "container_fill", "traffic_light",
              "sfc_parallel", "traffic_light_parallel", "parking"]


@pytest.mark.parametrize("name", VS_SAMPLES)
def test_sample_cites_the_manual_and_passes_its_stimulus(name, tmp_path):
    il, stim = SAMPLES / "vs" / f"{name}.il", SAMPLES / "vs" / f"{name}.stim"
    assert "VS manual" in il.read_text("utf-8").splitlines()[0]
    r = run_mlc("check", "--target", "vs", "--werror", str(il))
    assert r.code == 0, r.err
    r = run_mlc("build", "--target", "vs", str(il), "-o", str(tmp_path / "p.mlx"))
    assert r.code == 0, r.err
    r = run_mlc("sim", "--target", "vs", str(tmp_path / "p.mlx"), "--stimulus", str(stim))
    assert r.code == 0, r.out + r.err


@pytest.mark.parametrize("name, wrong, right", [
    ("fountain", "OUT  T1 K100", "OUT  T1 K50"),       # outer jets 5 s instead of 10 s
    ("cj_skip", "CJ   P63", "OUT  M0"),                 # no jump to END
    ("index", "MOV  K10 Z0", "MOV  K8 Z0"),            # X10, not X12
    ("fountain_modes", "LD   X2\n", "LD   X1\n"),      # single step switched by the wrong input
    ("container_fill", "ANI  M1\n", "ANI  M9001\n"),  # no mask: the filled container starts S11 again
    ("traffic_light", "OUT  T6 K100", "OUT  T6 K80"),  # A green 8 s, not the chart's 10 s
    ("sfc_parallel", "STL  S24\nLD   X3", "STL  S23\nLD   X3"),  # merges S22 with S23: too early
    ("traffic_light_parallel", "OUT  T1 K80", "OUT  T1 K100"),  # B green 10 s, not 8 s
    ("parking", "LDI  X4\nOUT  Y2", "LDI  X3\nOUT  Y2"),  # car 2 stops at the wrong position
])
def test_stimulus_catches_a_wrong_program(name, wrong, right, tmp_path):
    il = tmp_path / f"{name}.il"
    text = (SAMPLES / "vs" / f"{name}.il").read_text("utf-8")
    assert wrong in text
    il.write_text(text.replace(wrong, right), "utf-8")
    r = run_mlc("sim", "--target", "vs", str(il), "--stimulus", str(SAMPLES / "vs" / f"{name}.stim"))
    assert r.code == 1 and "E603" in r.out + r.err
