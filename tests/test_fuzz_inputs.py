"""A fuzz target per input format: IL programs through every command that takes them,
stimulus files, objects, mlc.toml, vendor CSV exports.

Each target feeds generated input to the CLI in-process and holds the promise of
docs/reliability.md: a diagnostic and exit 1 or 2 (0 where the input happens to be valid),
never a traceback, an internal error (exit 3) or a hang. In CI (CI set) the examples are
derandomized, so a failure reproduces; `make fuzz` runs the same targets with a larger budget
(MLC_FUZZ_EXAMPLES) and fresh randomness.
"""

from __future__ import annotations

import hashlib
import os
import random

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import SAMPLES, run_mlc

BUDGET = int(os.environ.get("MLC_FUZZ_EXAMPLES", "0"))


def examples(n: int):
    """The suite's budget per target, or `make fuzz`'s."""
    return settings(max_examples=BUDGET or n, deadline=None,
                    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def assert_diagnosed(r, allowed=(0, 1, 2)) -> None:
    assert "Traceback" not in r.err and "internal error" not in r.err, r.err[-2000:]
    assert r.code in allowed, (r.code, r.err[-2000:])


# --- IL programs that pass `mlc check` go through build, ladder and sim too --------------------

CONTACTS = ["LD", "LDI", "AND", "ANI", "OR", "ORI", "LDP", "LDF", "ANDP", "ORF"]
BITS = ["X0", "X1", "X2", "Y0", "Y1", "M0", "M1", "M2", "T0", "C0", "S10", "S20"]
COILS = ["OUT Y0", "OUT Y1", "OUT M0", "SET M1", "RST M1", "RST C0", "RST T0", "PLS M2",
         "TMR T0 K5", "CNT C0 K3", "MOV K10 D0", "ADD D0 K1 D1", "INC D2", "CMP D0 K5 M10",
         "ZRST M0 M2", "ALT M3"]
STACK = ["MPS", "MRD", "MPP", "ANB", "ORB"]
NC5_CONTROL = ["FEND", "CJ P1", "P1:", "CALL P2", "SRET", "P2:", "FOR K2", "NEXT", "MC N0 M5",
               "MCR N0", "END"]


@st.composite
def rungs(draw):
    out = []
    for _ in range(draw(st.integers(1, 8))):
        n = draw(st.integers(1, 4))
        out.append(f"{draw(st.sampled_from(CONTACTS[:2]))} {draw(st.sampled_from(BITS))}")
        for _ in range(n - 1):
            pick = draw(st.integers(0, 9))
            if pick < 9:
                out.append(f"{draw(st.sampled_from(CONTACTS))} {draw(st.sampled_from(BITS))}")
            else:
                out.append(draw(st.sampled_from(STACK)))
        out.append(draw(st.sampled_from(COILS)))
        if draw(st.integers(0, 5)) == 0:
            out.append(draw(st.sampled_from(NC5_CONTROL)))
    out.append("END")
    return "\n".join(out) + "\n"


@examples(60)
@given(rungs())
def test_il_that_checks_clean_builds_draws_and_runs(tmp_path, text):
    src = tmp_path / "p.il"
    src.write_text(text, "utf-8")
    r = run_mlc("check", "--no-lint", str(src))
    assert_diagnosed(r)
    if r.code != 0:
        return
    assert_diagnosed(run_mlc("build", str(src), "-o", str(tmp_path / "p.mlx"),
                             "--listing", str(tmp_path / "p.lst")), (0,))
    assert_diagnosed(run_mlc("ladder", str(src), "--term"), (0,))
    assert_diagnosed(run_mlc("sim", str(src), "--scans", "3", "--json"), (0, 1))


# --- stimulus files ---------------------------------------------------------------------------

STIM_WORDS = ["scan", "10ms", "0ms", "1s", "run", "expect", "force", "release", "X0=1", "Y0=1",
              "D0=10", "D0:d=-1", "D0:f=1.5", "T0=1", "#3", "+5ms", "X0=pulse", "model", "to",
              "1000000000s", "#99999999999", "=", "!=", ">", "K1", "X0=2", "D0=70000", "at",
              "X0..X7=1", "10hz", "every", ";", "#", "\t", "1e9s", "9" * 30]
stim_lines = st.lists(st.lists(st.sampled_from(STIM_WORDS) | st.text(max_size=5), max_size=8)
                      .map(" ".join), max_size=15).map("\n".join)


@examples(150)
@given(stim_lines)
def test_stimulus_files(tmp_path, text):
    (tmp_path / "s.stim").write_text(text, "utf-8")
    r = run_mlc("sim", str(SAMPLES / "nc5" / "conveyor.il"), "--stimulus", str(tmp_path / "s.stim"),
                "--scans", "20", "--json")
    assert_diagnosed(r)


@examples(60)
@given(st.binary(max_size=400))
def test_stimulus_bytes(tmp_path, data):
    (tmp_path / "s.stim").write_bytes(data)
    r = run_mlc("sim", str(SAMPLES / "nc5" / "conveyor.il"), "--stimulus", str(tmp_path / "s.stim"),
                "--scans", "5")
    assert_diagnosed(r)


# --- objects: mutated bytes, and mutated payloads under a valid seal ----------------------------

_OBJECTS: dict[str, bytes] = {}


def _object(tmp_path, name: str, target: str) -> bytes:
    if name not in _OBJECTS:
        out = tmp_path / "good.mlx"
        r = run_mlc("build", "--target", target, str(name), "-o", str(out))
        assert r.code == 0, r.err
        _OBJECTS[name] = out.read_bytes()
    return _OBJECTS[name]


def _reseal(data: bytes) -> bytes:
    """The seal is the SHA-256 of what precedes it (docs/object-format.md): mutate a payload
    and seal it again, so decoding proceeds past the integrity check."""
    if len(data) <= 32:
        return data
    body = data[:-32]
    return body + hashlib.sha256(body).digest()


OBJ_SOURCES = [(str(SAMPLES / "nc5" / "conveyor.il"), "nc5"), (str(SAMPLES / "vs" / "index.il"), "vs")]


@examples(80)
@given(st.sampled_from(OBJ_SOURCES), st.integers(0, 2**32), st.integers(1, 8), st.booleans())
def test_objects(tmp_path, source, seed, flips, reseal):
    good = _object(tmp_path, *source)
    rng = random.Random(seed)
    data = bytearray(good)
    for _ in range(flips):
        pos = rng.randrange(len(data))
        data[pos] = rng.randrange(256) if rng.random() < 0.8 else data[pos] ^ 0x80
    if rng.random() < 0.2:
        del data[rng.randrange(len(data)):]
    blob = _reseal(bytes(data)) if reseal else bytes(data)
    p = tmp_path / "m.mlx"
    p.write_bytes(blob)
    assert_diagnosed(run_mlc("objdump", str(p)))
    assert_diagnosed(run_mlc("objdump", "--json", str(p)))
    assert_diagnosed(run_mlc("sim", "--target", source[1], str(p), "--scans", "3"))


# --- mlc.toml ---------------------------------------------------------------------------------

TOML_LINES = ['target = "nc5"', 'target = "vs"', "target = 5", 'taget = "nc5"', "capacity = 100",
              'capacity = "big"', 'sources = ["p.il"]', "sources = [1, 2]", 'sources = ["/**"]',
              "tests = [1]", "[severity]", 'W401 = "off"', 'E201 = "off"', 'X999 = "warning"',
              'W401 = "loud"', "[tool.mlc]", "[build]", 'output = "p.il"', 'model = "VS1"',
              "model = []", 'encoding = "big5"', "encoding = 1", "= =", "[[x]]", '"\\u0000" = 1']


@examples(120)
@given(st.lists(st.sampled_from(TOML_LINES) | st.text(max_size=8), max_size=8).map("\n".join))
def test_config_files(tmp_path, text):
    (tmp_path / "mlc.toml").write_text(text, "utf-8")
    (tmp_path / "p.il").write_text("LD X0\nOUT Y0\nEND\n", "utf-8")
    assert_diagnosed(run_mlc("check", "p.il", cwd=tmp_path))
    assert_diagnosed(run_mlc("build", cwd=tmp_path))


# --- vendor CSV exports -----------------------------------------------------------------------

CSV_CELLS = ['"Step Number"', '"Line Statement"', '"Instruction"', '"I/O(Device)"', '"Blank"',
             '"PI Statement"', '"Note"', '"0"', '"LD"', '"X000"', '"OUT"', '"Y000"', '"K50"', '""',
             "Step", "Instruction", "Operand1", "0", "LD", "X0", "END", "MPS", "步号", "指令",
             '"', "\t", ",", "NOPLF", "U1\\G3", "I001", "M8002"]
csv_text = st.lists(st.lists(st.sampled_from(CSV_CELLS) | st.text(max_size=4), max_size=6)
                    .map(lambda cells: st_join(cells)), max_size=12).map("\n".join)


def st_join(cells: list[str]) -> str:
    return ("\t" if len(cells) % 2 else ",").join(cells)


@examples(120)
@given(csv_text, st.sampled_from(["utf-8", "utf-16"]))
def test_import_exports(tmp_path, text, encoding):
    p = tmp_path / "export.csv"
    p.write_bytes(text.encode(encoding))
    r = run_mlc("import", "--target", "vs", str(p), "-o", str(tmp_path / "out.il"))
    assert_diagnosed(r)


# --- Modbus streams (`mlc device serve`) -------------------------------------------------------

def _modbus_frame(framing: str, unit: int, pdu: bytes) -> bytes:
    from mlctool.devices.framing import RECEIVERS, Frame

    return RECEIVERS[framing].encode(Frame(unit, b"", 7), pdu)


_PDUS = st.one_of(
    st.binary(min_size=1, max_size=30),  # anything, as a well-framed request
    st.tuples(st.sampled_from([3, 6, 16]), st.integers(0, 0xFFFF), st.integers(0, 70),
              st.binary(max_size=20)).map(
        lambda t: bytes([t[0]]) + t[1].to_bytes(2, "big") + t[2].to_bytes(2, "big")
        + (bytes([len(t[3])]) + t[3] if t[0] == 16 else b"")),
)


@examples(200)
@given(framing=st.sampled_from(["rtu", "ascii", "tcp"]),
       parts=st.lists(st.one_of(st.binary(max_size=60),
                                st.tuples(st.integers(0, 3), _PDUS)), max_size=12),
       cuts=st.lists(st.integers(1, 64), min_size=1, max_size=8))
def test_modbus_streams(framing, parts, cuts):
    """Junk and well-framed requests of any content, cut anywhere: the receivers and the
    XC100's request handling never raise, and every reply is a well-formed frame of the same
    framing for the unit asked (docs/reliability.md "The Modbus server")."""
    from mlctool.devices.framing import RECEIVERS, crc16
    from mlctool.devices.xc100 import controller as c
    from mlctool.devices.xc100.server import Line, Server

    line = Line({1: c.new_xc100(), 2: c.new_xc100()})
    server = Server(line, framing, tcp=("127.0.0.1", 1))  # never started: answer() only
    receiver = RECEIVERS[framing]()
    data = b"".join(p if isinstance(p, bytes) else _modbus_frame(framing, *p) for p in parts)
    at = k = 0
    while at < len(data) and not receiver.broken:
        n = cuts[k % len(cuts)]
        for frame in receiver.feed(data[at:at + n], 0.0):
            reply = server.answer(frame)
            if reply is None:
                assert frame.unit == 0 or (framing != "tcp" and frame.unit not in (1, 2))
                continue
            raw = receiver.encode(frame, reply)
            if framing == "rtu":  # replies carry no length of their own: check the CRC
                assert raw[:-2] == bytes([frame.unit]) + reply
                assert crc16(raw[:-2]) == int.from_bytes(raw[-2:], "little")
            else:
                back = RECEIVERS[framing]().feed(raw, 0.0)
                assert [(f.unit, f.pdu) for f in back] == [(frame.unit, reply)]
            assert reply[0] in (frame.pdu[0], frame.pdu[0] | 0x80)  # echo or exception
        at, k = at + n, k + 1
    assert len(receiver.buf) <= 1024 + 64
