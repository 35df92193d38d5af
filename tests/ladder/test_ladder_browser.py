"""The HTML ladder page and the simulation report in a real browser: headless chromium
(Debian's package) loads them from local files, the page's script counts the rungs (DOM
query), a screenshot is taken, and no console message may appear."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from tests.conftest import run_mlc

BROWSER = next((p for p in map(shutil.which, ("chromium", "chromium-browser")) if p), None)
pytestmark = pytest.mark.skipif(BROWSER is None, reason="chromium is not installed (apt-get install chromium)")

SAMPLES = ["samples/nc5/man_2_2_anb.il", "samples/nc5/man_2_2_orb.il", "samples/nc5/man_2_2_mps.il",
           "samples/nc5/man_2_2_contacts.il"]
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-dev-shm-usage", "--enable-logging=stderr", "--v=0"]


def chromium(tmp_path: Path, name: str, *args: str) -> subprocess.CompletedProcess:
    profile = tmp_path / f"profile-{name}"  # a fresh profile per run
    return subprocess.run([BROWSER, *FLAGS, f"--user-data-dir={profile}", *args],
                          capture_output=True, text=True, timeout=60,
                          env={**os.environ, "HOME": str(tmp_path)})


def console_messages(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if ":CONSOLE" in line]


def load(tmp_path: Path, page: Path, fragment: str = "") -> str:
    """The DOM after the page's scripts ran; fails on console output; takes a screenshot."""
    url = page.resolve().as_uri() + fragment
    r = chromium(tmp_path, "dom", "--dump-dom", url)
    assert r.returncode == 0, r.stderr[-2000:]
    assert console_messages(r.stderr) == []
    shot = tmp_path / (page.stem + ".png")
    s = chromium(tmp_path, "shot", f"--screenshot={shot}", "--window-size=1200,900", url)
    assert s.returncode == 0 and shot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert console_messages(s.stderr) == []
    return r.stdout


def test_ladder_page_renders_every_rung(tmp_path):
    out = tmp_path / "ladder.html"
    assert run_mlc("ladder", *SAMPLES, "-o", str(out)).code == 0
    expected = out.read_text("utf-8").count('<div class="rung"')
    assert expected == 9  # 1 + 1 + 1 + 6 rungs in the four files
    dom = load(tmp_path, out)
    # the count the page's own script got from document.querySelectorAll('div.rung')
    assert re.search(rf'<span id="count">{expected} of {expected} rungs</span>', dom), dom[:500]


def test_report_page_lights_the_chosen_scan(tmp_path):
    src = tmp_path / "p.il"
    src.write_text("LD X0\nOR Y0\nANI X1\nOUT Y0\nLD Y0\nMPS\nANDP X2\nOUT M0\nMPP\nOUT Y1\nEND\n")
    stim = tmp_path / "p.stim"
    stim.write_text("scan 10ms\n0ms X0=1\n20ms X0=0\n50ms X1=1\nrun 80ms\n")
    out = tmp_path / "report.html"
    r = run_mlc("sim", str(src), "--stimulus", str(stim), "--watch", "X0,X1,Y0", "--report", str(out))
    assert r.code == 0, r.err
    # scan 1: X0 On, Y0 holds itself, X1 Off: the first rung conducts, Y1 is driven, the
    # ANDP X2 branch (no edge) and M0 are not
    dom = load(tmp_path, out, "#scan=1")
    assert re.search(r'<span id="count">2 of 2 rungs</span>', dom)
    assert re.search(r'id="scaninfo">scan 1 \(t = 10 ms\), 6 conducting<', dom)
    lit = sorted(int(i) for i in re.findall(r'<g class="el on" data-i="(\d+)"', dom))
    assert lit == [0, 1, 2, 3, 4, 9]
    # the last scan (the slider's start): X1 broke the self-hold, nothing conducts
    dom = load(tmp_path, out)
    assert re.search(r'id="scaninfo">scan 7 \(t = 70 ms\), 0 conducting<', dom)
    assert 'class="el on"' not in dom
