"""The on-disk cache (mlctool/cache.py) and the compiled code kept in it
(mlctool/sim/engines/codecache.py): entries are used only when sound, anything else is ignored and
rebuilt, the cache can be switched off, and results never depend on it."""

from __future__ import annotations

import json
import os

import pytest

from conftest import run_mlc
from mlctool import cache
from mlctool.sim.engines import codecache

SOURCE = "LD X0\nOR M0\nANI X1\nOUT M0\nLD M0\nTMR T0 K5\nLD T0\nOUT Y0\nMOV K7 D0\nEND\n"


@pytest.fixture()
def folder(tmp_path, monkeypatch):
    d = tmp_path / "cache"
    monkeypatch.setenv(cache.ENV_DIR, str(d))
    monkeypatch.delenv(cache.ENV_SWITCH, raising=False)
    codecache._MEMO.clear()
    yield d
    codecache._MEMO.clear()


def _entries(d):
    return sorted(p for p in d.iterdir() if p.name.endswith(".bin")) if d.exists() else []


def test_store_and_load(folder):
    k = cache.key("t", "a")
    assert cache.load("t", k) is None
    assert cache.store("t", k, ("x", [1, 2], {"y": 3.5}))
    assert cache.load("t", k) == ("x", [1, 2], {"y": 3.5})
    assert cache.load("t", cache.key("t", "b")) is None
    assert cache.load("t", k, accept=lambda v: False) is None  # the caller's check has the last word
    assert (os.stat(folder).st_mode & 0o777) == 0o700
    assert not [p for p in folder.iterdir() if p.name.endswith(".tmp")]  # no temporary left


@pytest.mark.parametrize("damage", ["flip a payload byte", "truncate", "empty", "other magic",
                                    "other format", "foreign entry", "not marshal"])
def test_unsound_entries_are_ignored(folder, damage):
    k = cache.key("t", "a")
    assert cache.store("t", k, {"v": list(range(100))})
    path = _entries(folder)[0]
    data = bytearray(path.read_bytes())
    if damage == "flip a payload byte":
        data[-5] ^= 0x40
    elif damage == "truncate":
        data = data[:len(data) // 2]
    elif damage == "empty":
        data = bytearray()
    elif damage == "other magic":
        data[0:8] = b"NOTCACHE"
    elif damage == "other format":
        data[8] = cache.FORMAT + 1
    elif damage == "foreign entry":  # another key's sound entry under this key's name
        other = cache.key("t", "b")
        cache.store("t", other, {"v": "other"})
        data = bytearray(next(p for p in _entries(folder) if other.hex() in p.name).read_bytes())
    elif damage == "not marshal":  # a sound seal over bytes that do not decode
        import hashlib

        payload = b"\xff\x00garbage"
        data = data[:9] + k + hashlib.sha256(payload).digest() + payload
    path.write_bytes(bytes(data))
    assert cache.load("t", k) is None
    assert cache.store("t", k, {"v": 1}) and cache.load("t", k) == {"v": 1}  # rebuilt over it


def test_switched_off_or_unsafe_folder_is_not_used(folder, monkeypatch):
    k = cache.key("t", "a")
    monkeypatch.setenv(cache.ENV_SWITCH, "off")
    assert not cache.store("t", k, 1) and cache.load("t", k) is None and not _entries(folder)
    monkeypatch.delenv(cache.ENV_SWITCH)
    if os.name == "posix":
        folder.mkdir(exist_ok=True)
        folder.chmod(0o777)  # anyone may write it: nothing is read from it or written to it
        assert not cache.store("t", k, 1) and not _entries(folder)
        folder.chmod(0o700)
        assert cache.store("t", k, 1)
        folder.chmod(0o777)
        assert cache.load("t", k) is None
        folder.chmod(0o700)
        assert cache.load("t", k) == 1


def test_a_relative_cache_folder_is_refused_with_w612(tmp_path, monkeypatch):
    """A relative MLC_CACHE_DIR lies in whatever folder the command runs in (a cloned
    project's): refused, W612 once, the run goes on without the cache (issue 30, What to
    build 2)."""
    (tmp_path / "p.il").write_text(SOURCE)
    assert run_mlc("build", "p.il", "-o", "p.mlx", cwd=tmp_path).code == 0
    monkeypatch.setenv(cache.ENV_DIR, "mlc-cache")
    monkeypatch.delenv(cache.ENV_SWITCH, raising=False)
    monkeypatch.setattr(cache, "_said", set())
    codecache._MEMO.clear()
    r = run_mlc("sim", "p.mlx", "--scans", "30", "--json", cwd=tmp_path)
    assert r.code == 0 and r.err.count("warning[W612]") == 1 and "'mlc-cache' is not an absolute path" in r.err, r.err
    assert not (tmp_path / "mlc-cache").exists()
    assert not cache.store("t", cache.key("t"), 1)


def _sim(d, *extra):
    r = run_mlc("sim", str(d / "p.mlx"), "--scans", "30", "--json", *extra, cwd=d)
    assert r.code == 0, r.err
    return json.loads(r.out)


def test_sim_of_an_object_uses_the_cache_and_gives_the_same_result(folder, tmp_path, monkeypatch):
    (tmp_path / "p.il").write_text(SOURCE)
    assert run_mlc("build", "p.il", "-o", "p.mlx", cwd=tmp_path).code == 0
    monkeypatch.setenv(cache.ENV_SWITCH, "off")
    plain = _sim(tmp_path)
    monkeypatch.delenv(cache.ENV_SWITCH)
    assert _sim(tmp_path) == plain
    (entry,) = [p for p in _entries(folder) if p.name.startswith(codecache.KIND)]
    codecache._MEMO.clear()

    def refuse(prog):
        raise AssertionError("compiled again although the cache holds the code")

    with monkeypatch.context() as m:  # the next run loads the code
        m.setattr(codecache, "compile_program", refuse)
        assert _sim(tmp_path) == plain
    codecache._MEMO.clear()
    data = bytearray(entry.read_bytes())
    data[len(data) // 2] ^= 0xFF  # corrupt: ignored, compiled again, rewritten
    entry.write_bytes(bytes(data))
    assert _sim(tmp_path) == plain
    codecache._MEMO.clear()
    with monkeypatch.context() as m:
        m.setattr(codecache, "compile_program", refuse)
        assert _sim(tmp_path) == plain


def test_programs_from_sources_are_not_cached(folder, tmp_path):
    (tmp_path / "p.il").write_text(SOURCE)
    r = run_mlc("sim", "p.il", "--scans", "3", cwd=tmp_path)
    assert r.code == 0 and not _entries(folder)


def test_decoded_objects_come_back_equal_from_the_cache(folder, tmp_path, monkeypatch):
    """A decoded and validated object is kept; the next decode of the same bytes for the same
    target rebuilds it from the entry, equal to a fresh decode (specs are the target's own
    objects); a damaged entry or another target decodes afresh; bad objects keep their
    diagnostics (never cached)."""
    from mlctool.asm import objfile
    from mlctool.targetapi import load_target

    nc5 = load_target("nc5")
    (tmp_path / "p.il").write_text("LD X0\nMOV K5 D0V1\nDMOV F1.5 D10\nOUT Y0\nLD X1\nCJ P10\nP10:\nEND\n")
    assert run_mlc("build", "p.il", "-o", "p.mlx", cwd=tmp_path).code == 0
    data = (tmp_path / "p.mlx").read_bytes()
    monkeypatch.setenv(cache.ENV_SWITCH, "off")
    fresh = objfile.decode(data, nc5)
    monkeypatch.delenv(cache.ENV_SWITCH)
    assert objfile.decode(data, nc5) == fresh
    (entry,) = [p for p in _entries(folder) if p.name.startswith("object-")]
    with monkeypatch.context() as m:
        m.setattr(objfile, "_decode", lambda *a: pytest.fail("decoded again"))
        again = objfile.decode(data, nc5)
    assert again == fresh and again.digest == fresh.digest == data[-32:].hex()
    assert all(a.spec is b.spec for a, b in zip(again.instrs, fresh.instrs))
    entry.write_bytes(entry.read_bytes()[:-3])  # damaged: decoded and validated again
    assert objfile.decode(data, nc5) == fresh
    with pytest.raises(objfile.ObjectError) as e:  # another target: not this entry
        objfile.decode(data, load_target("vs"))
    assert e.value.code == "E503"
    bad = bytearray(data)
    bad[40] ^= 0xFF
    with pytest.raises(objfile.ObjectError) as e:
        objfile.decode(bytes(bad), nc5)
    assert e.value.code == "E502"
