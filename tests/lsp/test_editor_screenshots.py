"""tools/editor_screenshots.py, the screenshots of docs/editor.md (CI writes them into
build/editor-screenshots, .ci/run): the pages hold the server's real answers, and headless
chromium makes PNGs of them (skipped without chromium)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("pygls")
ROOT = Path(__file__).resolve().parents[2]
TOOL = ROOT / "tools" / "editor_screenshots.py"
BROWSER = next((p for p in map(shutil.which, ("chromium", "chromium-browser")) if p), None)


def test_screenshots_of_the_ladder_webview_and_the_editor(tmp_path):
    out = tmp_path / "shots"
    r = subprocess.run([sys.executable, str(TOOL), str(out)], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    ladder = (out / "ladder.html").read_text("utf-8")
    assert "<title>conveyor.il</title>" in ladder and "src/pickplace.il" in ladder  # the whole project drawn
    editor = (out / "editor.html").read_text("utf-8")
    # the server's diagnostics (the typo and the coil written twice), hover and token colours
    assert "[E201] unknown instruction &#x27;SETT&#x27; for target nc5; did you mean SET?" in editor
    assert "[W401] CONVEYOR is also driven at src/conveyor.il:27" in editor
    assert "<b>START</b> = <code>X0</code> (symbol)" in editor and "Read at: src/conveyor.il:17" in editor
    assert '<span style="color:#569cd6">LD</span>' in editor and 'class="err">SETT</span>' in editor
    if BROWSER is None:
        assert "chromium is not installed" in r.stderr
        pytest.skip("chromium is not installed: the HTML is checked, no PNG made")
    for name in ("ladder.png", "editor.png"):
        png = (out / name).read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 20_000  # a drawn page, not a blank one
