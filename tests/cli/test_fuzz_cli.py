"""Any bytes at all: a diagnostic and exit 1 or 2, never a traceback or an internal error."""

from __future__ import annotations

import json

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.conftest import run_mlc

WORDS = ["LD", "LDI", "AND", "OUT", "SET", "RST", "MOV", "DMOV", "TMR", "CNT", "DCNT", "CJ", "CALL",
         "FEND", "END", "SRET", "FOR", "NEXT", "MPS", "MRD", "MPP", "ANB", "ORB", "LD=", "DAND<>",
         "VRT", "FADD", "ZRST", "DECO", "P10", "P10:", ".define", ".export", ".library", "X0", "Y0",
         "M0", "T0", "C64", "D0", "D5V0", "K20V0", "K2M0Z1", "K-1", "F1.5", "H10", "K99999999",
         ",", ";", "//", "0000", "\t", "\u3000", "\uff0c", "@", "\"", "(", "é", "中"]

token_soup = st.lists(st.sampled_from(WORDS) | st.text(max_size=6), max_size=40).map(
    lambda ws: " ".join(ws))
lines = st.lists(token_soup, max_size=30).map(lambda ls: "\n".join(ls))


def _run(tmp_path, data: bytes) -> None:
    p = tmp_path / "fuzz.il"
    p.write_bytes(data)
    r = run_mlc("check", "--format", "json", str(p))
    assert "Traceback" not in r.err and "internal error" not in r.err, r.err
    assert r.code in (0, 1, 2), (r.code, r.err)
    data = json.loads(r.out)
    # 2 for an unreadable input (binary, not UTF-8, too large: docs/reliability.md), else 1 on errors
    unreadable = any(d["code"] in ("E100", "E101", "E102", "E104") for d in data["diagnostics"])
    assert r.code == (2 if unreadable else 1 if data["errors"] else 0), (r.code, data)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.binary(max_size=600))
def test_random_bytes(tmp_path, data):
    _run(tmp_path, data)


@settings(max_examples=250, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(lines)
def test_token_soup(tmp_path, text):
    _run(tmp_path, text.encode("utf-8"))


def test_huge_and_long_lines(tmp_path):
    _run(tmp_path, b"LD X0\nOUT Y0\n" * 50_000 + b"END\n")
    _run(tmp_path, b"LD " + b"X" * 200_000 + b"\nEND\n")
    _run(tmp_path, b"MOV " + b"K1 " * 50_000 + b"D0\nEND\n")
