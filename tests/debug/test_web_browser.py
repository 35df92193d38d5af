"""The live ladder monitor in a real browser: headless chromium (Debian's package, as
tests/ladder/test_ladder_browser.py) loads the page from a live `mlc debug --web` server and
is driven over the DevTools protocol: real mouse clicks on a contact (force it) and on the
Scan button, then the coil it drives is lit and the box below shows the new value in the
DOM; shift-click releases. A screenshot is taken and no console message may appear."""

from __future__ import annotations

import base64
import itertools
import json
import os
import re
import shutil
import subprocess
import threading
import time
import urllib.request
from contextlib import ExitStack, contextmanager
from pathlib import Path

import pytest

BROWSER = next((p for p in map(shutil.which, ("chromium", "chromium-browser")) if p), None)
pytestmark = pytest.mark.skipif(BROWSER is None, reason="chromium is not installed (apt-get install chromium)")

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-dev-shm-usage", "--window-size=1200,900", "--remote-debugging-port=0"]
NO_PROXY = urllib.request.build_opener(urllib.request.ProxyHandler({}))

# Y0 latches on X0 until X1; while Y0 is On, D0 counts scans
PROGRAM = "LD X0\nOR Y0\nANI X1\nOUT Y0\nLD Y0\nADD D0 K1 D0\nEND\n"
CONTACT_X0, COIL_Y0, ADD = 0, 3, 5  # instruction indexes (data-i)


class DevTools:
    """A DevTools protocol client on one page target (the websockets package's client)."""

    def __init__(self, ws_url: str, stack: ExitStack):
        from websockets.sync.client import connect

        self.ws = stack.enter_context(connect(ws_url, open_timeout=20, max_size=None))
        self.ids = itertools.count(1)
        self.events: list[dict] = []

    def call(self, method: str, **params) -> dict:
        n = next(self.ids)
        self.ws.send(json.dumps({"id": n, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv(timeout=30))
            if msg.get("id") == n:
                assert "error" not in msg, msg
                return msg.get("result", {})
            self.events.append(msg)

    def js(self, expression: str):
        r = self.call("Runtime.evaluate", expression=expression, returnByValue=True)
        assert "exceptionDetails" not in r, r
        return r["result"].get("value")

    def wait(self, expression: str, what: str, timeout: float = 15):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            value = self.js(expression)
            if value:
                return value
            time.sleep(0.05)
        pytest.fail(f"the page did not get there: {what}\n{self.js('document.body.innerText')[:2000]}\n{self.complaints()}")

    def click(self, selector: str, shift: bool = False) -> None:
        """A real mouse click at the middle of the element."""
        box = self.js(f"(function(){{var e=document.querySelector({json.dumps(selector)});"
                      "e.scrollIntoView({block:'center'}); var r=e.getBoundingClientRect();"
                      "return [r.left+r.width/2, r.top+r.height/2];})()")
        x, y = box
        for kind in ("mousePressed", "mouseReleased"):
            self.call("Input.dispatchMouseEvent", type=kind, x=x, y=y, button="left", clickCount=1,
                      modifiers=8 if shift else 0)

    def type(self, selector: str, text: str, replace: bool = False) -> None:
        """Click into a field, type `text` (over its content: `replace`) and press Enter."""
        self.click(selector)
        if replace:
            self.js(f"document.querySelector({json.dumps(selector)}).select()")
        self.call("Input.insertText", text=text)
        for kind in ("keyDown", "keyUp"):
            self.call("Input.dispatchKeyEvent", type=kind, key="Enter", code="Enter", windowsVirtualKeyCode=13,
                      **({"text": "\r"} if kind == "keyDown" else {}))

    def complaints(self) -> list[dict]:
        """Console calls, uncaught exceptions and browser log entries (failed loads...)."""
        return [e for e in self.events if e.get("method") in ("Runtime.consoleAPICalled", "Runtime.exceptionThrown")
                or e.get("method") == "Log.entryAdded"]


def classes(dom: str, index: int) -> set[str]:
    m = re.search(rf'<g class="([^"]*)" data-i="{index}"', dom)
    assert m, f"no element {index}"
    return set(m[1].split())


@contextmanager
def monitor_page(tmp_path: Path):
    """A live monitor of PROGRAM and a headless chromium on its page: the DevTools client."""
    from mlctool.debug.load import load_session
    from mlctool.debug.web import Monitor, WebServer
    from mlctool.targets import load_target

    src = tmp_path / "p.il"
    src.write_text(PROGRAM)
    server = WebServer(Monitor(load_session([str(src)], None, load_target("nc5"))), 0)
    server.start()
    chrome = subprocess.Popen([BROWSER, *FLAGS, f"--user-data-dir={tmp_path / 'profile'}", "about:blank"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                              env={**os.environ, "HOME": str(tmp_path)})
    killer = threading.Timer(90, chrome.kill)  # a hung browser fails the test, not the suite
    killer.start()
    try:
        with ExitStack() as stack:
            line = ""
            while "DevTools listening on" not in line:
                line = chrome.stderr.readline()
                assert line, "chromium ended before its DevTools endpoint was up"
            port = re.search(r"ws://127\.0\.0\.1:(\d+)/", line)[1]
            threading.Thread(target=chrome.stderr.read, daemon=True).start()  # drain
            with NO_PROXY.open(f"http://127.0.0.1:{port}/json/list", timeout=20) as r:
                page = next(t for t in json.load(r) if t["type"] == "page")
            dt = DevTools(page["webSocketDebuggerUrl"], stack)
            for domain in ("Runtime", "Log", "Page"):
                dt.call(f"{domain}.enable")
            dt.call("Page.navigate", url=server.url)
            dt.wait("document.getElementById('where') && /^scan 0 /.test(document.getElementById('where').textContent)",
                    "the first state")
            yield dt
            assert dt.complaints() == []
            dt.call("Browser.close")
        assert chrome.wait(30) is not None
    finally:
        killer.cancel()
        if chrome.poll() is None:
            chrome.kill()
        server.shutdown()


def test_click_a_contact_step_a_scan_see_the_coil(tmp_path: Path):
    with monitor_page(tmp_path) as dt:
        dt.click(f'.el[data-i="{CONTACT_X0}"]')
        dt.wait(f"document.querySelector('.el[data-i=\"{CONTACT_X0}\"]').classList.contains('forced')",
                "X0 forced by the click")
        dt.click("#b-scan")
        dt.wait("document.body.getAttribute('data-scan')==='1'", "the scan done")
        dom = dt.js("document.documentElement.outerHTML")
        assert {"on", "forced", "click"} <= classes(dom, CONTACT_X0)
        assert "on" in classes(dom, COIL_Y0)  # the coil X0 drives
        assert re.search(r'<text class="val"[^>]*>D0=1</text>', dom)  # ADD ran once
        assert re.search(r'<span id="forced">forced: <span> X0=1<button type="button" '
                         r'data-release="X0">release</button></span></span>', dom)
        assert "scan done: scan 1 (t=10ms)" in dom

        shot = dt.call("Page.captureScreenshot", format="png")
        png = base64.b64decode(shot["data"])
        assert png[:8] == b"\x89PNG\r\n\x1a\n"
        (tmp_path / "monitor.png").write_bytes(png)

        dt.click(f'.el[data-i="{CONTACT_X0}"]', shift=True)  # release; Y0 holds itself
        dt.wait(f"!document.querySelector('.el[data-i=\"{CONTACT_X0}\"]').classList.contains('forced')",
                "X0 released by the shift-click")
        dt.click("#b-scan")
        dt.wait("document.body.getAttribute('data-scan')==='2'", "the second scan")
        dom = dt.js("document.documentElement.outerHTML")
        assert "on" in classes(dom, COIL_Y0) and "forced" not in classes(dom, CONTACT_X0)
        assert re.search(r'<text class="val"[^>]*>D0=2</text>', dom)

        dt.js("document.getElementById('speed').value='0'")  # run as fast as it goes
        dt.click("#b-run")
        dt.wait("+document.body.getAttribute('data-scan')>20 && "
                "/^running: /.test(document.getElementById('where').textContent)", "running")
        dt.click("#b-pause")
        dt.wait("/^paused at scan /.test(document.getElementById('stop').textContent)", "paused")
        scan = int(dt.js("document.body.getAttribute('data-scan')"))
        values = dt.js(f"document.querySelector('.el[data-i=\"{ADD}\"] text.val').textContent")
        assert values == f"D0={scan}"  # D0 counted every scan run


def row(device: str) -> str:
    return f'#devtable tr[data-device="{device}"]'


def test_the_device_table_add_edit_force(tmp_path: Path):
    """The device table as a user works it: type a device and Enter (a row), type a value in
    it and Enter (set once: the ladder shows it too), tick force (held at the scan's end
    though the program adds to it), untick (released: the program's value again)."""
    with monitor_page(tmp_path) as dt:
        assert dt.js("document.getElementById('devtable').classList.contains('empty')")
        dt.type("#add-dev", "D0")
        dt.wait(f"!!document.querySelector('{row('D0')} input.val')", "the row of D0")
        assert dt.js(f"document.querySelector('{row('D0')} input.val').value") == "0"
        dt.type(f"{row('D0')} input.val", "K25", replace=True)
        dt.wait(f"document.querySelector('{row('D0')} input.val').value==='25'", "D0 written")
        assert dt.js(f"document.querySelector('.el[data-i=\"{ADD}\"] text.val').textContent") == "D0=25"
        assert not dt.js(f"document.querySelector('{row('D0')}').classList.contains('forced')")

        dt.type("#add-dev", "X0")
        dt.wait(f"!!document.querySelector('{row('X0')} input.val')", "the row of X0")
        dt.type(f"{row('X0')} input.val", "1", replace=True)  # Y0 latches, ADD runs each scan
        dt.wait(f"document.querySelector('{row('X0')} input.val').value==='1'", "X0 written")
        dt.click(f"{row('D0')} input[type=checkbox]")  # force D0 at 25
        dt.wait(f"document.querySelector('{row('D0')}').classList.contains('forced')", "D0 forced")
        dt.click("#b-scan")
        dt.wait("document.body.getAttribute('data-scan')==='1'", "the scan done")
        assert dt.js(f"document.querySelector('{row('D0')} input.val').value") == "25"  # ADD ran; the force held
        assert "on" in classes(dt.js("document.documentElement.outerHTML"), COIL_Y0)
        assert dt.js("document.getElementById('forced').textContent").startswith("forced:  D0=25")

        dt.click(f"{row('D0')} input[type=checkbox]")  # release
        dt.wait(f"!document.querySelector('{row('D0')}').classList.contains('forced')", "D0 released")
        dt.click("#b-scan")
        dt.wait(f"document.querySelector('{row('D0')} input.val').value==='26'", "the program's value again")
        dt.click(f"{row('X0')} button")  # remove
        dt.wait(f"!document.querySelector('{row('X0')}')", "X0's row removed")
        (tmp_path / "table.png").write_bytes(base64.b64decode(dt.call("Page.captureScreenshot", format="png")["data"]))
