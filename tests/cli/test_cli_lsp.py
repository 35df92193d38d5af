"""`mlc lsp`'s exit codes, as its help says them: 0 when the editor ended the session (shutdown
then exit), 1 when it went away without a shutdown (#30.18: it always exited 0)."""

from __future__ import annotations

import json
import subprocess

import pytest

from tests.conftest import MLC_COMMAND

pytest.importorskip("pygls")


def frame(method: str, msg_id: int | None = None, params: dict | None = None) -> bytes:
    msg = {"jsonrpc": "2.0", "method": method, **({"id": msg_id} if msg_id is not None else {}),
           **({"params": params} if params is not None else {})}
    body = json.dumps(msg).encode()
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


INITIALIZE = frame("initialize", 1, {"processId": None, "rootUri": None, "capabilities": {}})


@pytest.mark.parametrize(("messages", "code"), [
    (INITIALIZE + frame("initialized", params={}) + frame("shutdown", 2) + frame("exit"), 0),
    (INITIALIZE, 1),  # the editor went away: standard input closed
])
def test_exit_code_says_how_the_session_ended(messages, code):
    r = subprocess.run([*MLC_COMMAND, "lsp"], input=messages, capture_output=True, timeout=60)
    assert r.returncode == code, r.stderr.decode()[-2000:]
    assert b"Traceback" not in r.stderr
