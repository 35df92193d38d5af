"""The HTML ladder page and the simulation report in a real browser: headless chromium
(Debian's package) loads them from local files, the page's script counts the rungs (DOM
query), a screenshot is taken, and no console message may appear. A 40-contact rung fits a
1280 px window (measured by the browser), and a failing scenario's report opens at its
failing scan."""

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
    r = chromium(tmp_path, "dom", "--dump-dom", "--window-size=1280,900", url)
    assert r.returncode == 0, r.stderr[-2000:]
    assert console_messages(r.stderr) == []
    shot = tmp_path / (page.stem + ".png")
    s = chromium(tmp_path, "shot", f"--screenshot={shot}", "--window-size=1280,900", url)
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


# after the page's own script: the page's scroll width and the right edge of its widest drawing
MEASURE = ("<script>document.body.setAttribute('data-measured',document.documentElement.scrollWidth+' '+"
           "Math.ceil(Math.max.apply(null,Array.prototype.map.call(document.querySelectorAll('svg'),"
           "function(s){return s.getBoundingClientRect().right;}))));</script>")


def measured(tmp_path: Path, page: Path) -> tuple[int, int, str]:
    """(scroll width, right edge of the widest SVG, DOM) of the page in a 1280 px wide window."""
    probe = page.with_name(page.stem + "-measured.html")
    probe.write_text(page.read_text("utf-8").replace("</body>", MEASURE + "</body>"), "utf-8")
    dom = load(tmp_path, probe)
    width, right = re.search(r'data-measured="(\d+) (\d+)"', dom).groups()
    return int(width), int(right), dom


def test_a_40_contact_rung_fits_a_1280_px_window(tmp_path):
    src = tmp_path / "wide.il"
    src.write_text("\n".join(["LD X0"] + [f"AND M{i}" for i in range(1, 40)]
                             + ["OUT Y0", "LD X1", "OUT Y1", "END"]) + "\n")
    out = tmp_path / "wide.html"
    assert run_mlc("ladder", str(src), "-o", str(out)).code == 0
    width, right, _ = measured(tmp_path, out)
    assert width <= 1280 and right <= 1280, (width, right)  # no horizontal scrolling
    # the same drawing unwrapped would be 40 columns of 84 px
    assert out.read_text("utf-8").count('class="wrap"') == 6


def test_report_page_lights_the_chosen_scan(tmp_path):
    src = tmp_path / "p.il"
    src.write_text("LD X0\nOR Y0\nANI X1\nOUT Y0\nLD Y0\nMPS\nANDP X2\nOUT M0\nMPP\nOUT Y1\nEND\n")
    stim = tmp_path / "p.stim"
    stim.write_text("scan 10ms\n0ms X0=1\n20ms X0=0\n50ms X1=1\nrun 80ms\n")
    out = tmp_path / "report.html"
    r = run_mlc("sim", str(src), "--stimulus", str(stim), "--watch", "X0,X1,Y0", "--report", str(out))
    assert r.code == 0, r.err
    # scan 1: X0 On, Y0 holds itself, X1 Off: the first rung's contacts and coil, LD Y0 and
    # Y1 are lit; ANDP X2 (X2 Off) and M0 are not
    dom = load(tmp_path, out, "#scan=1")
    assert re.search(r'<span id="count">2 of 2 rungs</span>', dom)
    assert re.search(r'id="scaninfo">scan 1 \(t = 0.01 s\), 6 lit<', dom)
    lit = sorted(int(i) for i in re.findall(r'<g class="el on" data-i="(\d+)"', dom))
    assert lit == [0, 1, 2, 3, 4, 9]
    # no failure: the page opens at the last scan, where X1 broke the self-hold
    dom = load(tmp_path, out)
    assert re.search(r'id="scaninfo">scan 7 \(t = 0.07 s\), 0 lit<', dom)
    assert 'class="el on"' not in dom


def test_a_failing_report_opens_at_the_failing_scan(tmp_path):
    stim = tmp_path / "bad.stim"
    text = Path("samples/nc5/conveyor.stim").read_text("utf-8")
    stim.write_text(text.replace("3s      expect Y0=1 M1=0", "3s      expect Y0=0 M1=0"))
    out = tmp_path / "failed.html"
    r = run_mlc("sim", "samples/nc5/conveyor.il", "--stimulus", str(stim), "--report", str(out))
    assert r.code == 1
    width, right, dom = measured(tmp_path, out)
    assert width <= 1280 and right <= 1280, (width, right)
    assert re.search(r'id="scaninfo">scan 300 \(t = 3 s\), \d+ lit<', dom)
    # the failing row is the current one; the cursor on the waves at scan 300 of 1300
    assert re.search(r'<tr class="fail cur" data-scan="300" id="first-failure">', dom)
    x = float(re.search(r'<line id="cursor" x1="([\d.]+)"', dom).group(1))
    assert abs(x - (150 + 300.5 * 900 / 1300)) < 0.01
    # OUT MOTOR (Y0, index 19) is marked as failing on the ladder and lit (Y0 is On)
    assert re.search(r'<g class="el fail on" data-i="19">', dom)
