"""`--cluster tcp://HOST:PORT` (mlctool/sim/campaign/cluster.py): `mlc test` and a `mlc sim` batch run
on a Dask scheduler's workers give the local run's JSON, JUnit, coverage and exit status."""

from __future__ import annotations

import shutil
import socket
import subprocess
import threading
import time

import pytest
from test_sim_batch import PROGRAM, STIMULI

from conftest import MLC_COMMAND, ROOT, run_mlc, without_times
from mlctool.sim.campaign import cluster

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def scheduler():
    """Two workers in this process, on loopback only (no dashboard)."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, protocol="tcp",
                                  host="127.0.0.1", dashboard_address=None) as lc:
        yield lc


def _executed(lc) -> int:
    """Tasks the workers have run so far: proof that the work went to the cluster (which
    worker runs which chunk is the scheduler's choice)."""
    return sum(w.state.executed_count for w in lc.workers.values())


def test_chunks_are_contiguous_and_cover_all():
    items = list(range(10))
    for n in (1, 3, 4, 10, 20):
        parts = cluster.chunks(items, n)
        assert [x for p in parts for x in p] == items
        assert len(parts) == min(n, 10) and all(parts)
        assert max(map(len, parts)) - min(map(len, parts)) <= 1


@pytest.fixture()
def batch_project(tmp_path):
    (tmp_path / "p.il").write_text(PROGRAM.strip() + "\n")
    d = tmp_path / "tests"
    d.mkdir()
    for name, text in STIMULI.items():
        (d / name).write_text(text)
    for k in range(9):  # more lane scenarios, so that each worker gets several
        (d / f"h{k}.stim").write_text(f"0ms X0={k % 2} X2=1\n10ms expect M0={k % 2}\n")
    return tmp_path


def test_sim_batch_on_cluster_equals_local(batch_project, scheduler):
    args = ["sim", "p.il", "--stimulus", "tests/*.stim", "--json"]
    local = run_mlc(*args, "--junit", "local.xml", cwd=batch_project)
    before = _executed(scheduler)
    remote = run_mlc(*args, "--junit", "remote.xml", "--cluster", scheduler.scheduler_address, cwd=batch_project)
    assert _executed(scheduler) - before >= 2  # the chunks
    assert local.code == 1 and remote.code == local.code, remote.err
    assert remote.out == local.out
    assert without_times((batch_project / "remote.xml").read_bytes()) == \
        without_times((batch_project / "local.xml").read_bytes())


def test_mlc_test_on_cluster_equals_local(tmp_path, scheduler):
    proj = tmp_path / "project"
    shutil.copytree(ROOT / "samples" / "project", proj, ignore=shutil.ignore_patterns("build"))
    args = ["test", "--json", "--coverage"]
    local = run_mlc(*args, "--junit", "local.xml", "--coverage-dir", "cov_local", cwd=proj)
    before = _executed(scheduler)
    remote = run_mlc(*args, "--junit", "remote.xml", "--coverage-dir", "cov_remote",
                     "--cluster", scheduler.scheduler_address, cwd=proj)
    assert _executed(scheduler) - before >= 2  # the chunks
    assert remote.code == local.code, remote.err
    assert remote.out == local.out and local.out.lstrip().startswith("{")
    assert without_times((proj / "remote.xml").read_bytes()) == without_times((proj / "local.xml").read_bytes())
    assert (proj / "cov_remote" / "coverage.json").read_bytes() == (proj / "cov_local" / "coverage.json").read_bytes()


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_unreachable_scheduler_is_E118(batch_project, monkeypatch):
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT_S", 1)
    address = f"tcp://127.0.0.1:{_closed_port()}"
    r = run_mlc("sim", "p.il", "--stimulus", "tests/*.stim", "--junit", "j.xml", "--cluster", address,
                cwd=batch_project)
    assert r.code == 2 and "E118" in r.err and "Traceback" not in r.err + r.out
    assert not (batch_project / "j.xml").exists()


def _silent_peer():
    """A local socket that accepts connections and never says a word (issue 30.13)."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    held = []

    def accept():
        while True:
            try:
                held.append(server.accept()[0])
            except OSError:  # closed: the test is over
                return

    threading.Thread(target=accept, daemon=True).start()
    return server, held


def test_a_peer_that_accepts_and_never_answers_is_E118_in_time(batch_project, monkeypatch):
    """Dask's Client waited without limit for the handshake; the docs promise E118 within
    CONNECT_TIMEOUT_S (10 s; 1 s here)."""
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT_S", 1)
    server, held = _silent_peer()
    try:
        started = time.monotonic()
        r = run_mlc("sim", "p.il", "--stimulus", "tests/*.stim", "--junit", "j.xml", "--cluster",
                    f"tcp://127.0.0.1:{server.getsockname()[1]}", cwd=batch_project)
        elapsed = time.monotonic() - started
    finally:
        server.close()
        for c in held:
            c.close()
    assert r.code == 2 and "E118" in r.err and "did not answer within 1 s" in r.err, r.err
    assert elapsed < 5, elapsed
    assert not (batch_project / "j.xml").exists()


def test_an_address_dask_cannot_use_is_E118_at_once_and_quietly(batch_project):
    """tls:// without Dask's TLS settings was exit 3 (a TypeError from the Client), then 20 s
    and an "Exception ignored in Client.__del__" traceback while the failed client closed:
    a subprocess, to see what is printed when the interpreter ends."""
    started = time.monotonic()
    r = subprocess.run([*MLC_COMMAND, "sim", "p.il", "--stimulus", "tests/*.stim", "--cluster", "tls://127.0.0.1:1"],
                       cwd=batch_project, capture_output=True, text=True, timeout=60)
    elapsed = time.monotonic() - started
    assert r.returncode == 2 and "E118" in r.stderr and "tls:// needs the TLS settings" in r.stderr, r.stderr
    assert "Exception ignored" not in r.stderr and "Traceback" not in r.stderr
    assert elapsed < 10, elapsed
    for address in ("ucx://127.0.0.1:1", "tcp://", "inproc://x"):
        with pytest.raises(cluster.ClusterError, match="takes tcp://HOST:PORT or tls://HOST:PORT"):
            cluster.map_chunks(address, len, None, [1])


def test_a_fake_scheduler_announcing_a_huge_message_is_E118_not_out_of_memory(monkeypatch):
    """A peer whose first frame announces 10^12 bytes: Dask's reader asks for that much memory;
    that is the peer's fault, said as such (before: "mlc: error: out of memory on this input")."""
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT_S", 2)
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)

    def serve():
        try:
            conn = server.accept()[0]
        except OSError:
            return
        with conn:
            conn.sendall((10**12).to_bytes(8, "little"))
            conn.recv(1)

    threading.Thread(target=serve, daemon=True).start()
    try:
        with pytest.raises(cluster.ClusterError, match="did not answer as a Dask scheduler: it announced a message "
                                                       "too large to hold"):
            cluster.map_chunks(f"tcp://127.0.0.1:{server.getsockname()[1]}", len, None, [1])
    finally:
        server.close()


def test_cluster_takes_a_batch(batch_project, scheduler):
    r = run_mlc("sim", "p.il", "--stimulus", "tests/a_pass.stim", "--cluster", scheduler.scheduler_address, cwd=batch_project)
    assert r.code == 2 and "--cluster runs a batch" in r.err
