"""Bool lanes' results made lazily (RunResult.lazy): the devices and views of a scenario run as
a lane are read from the group's lane words when first asked for, and equal, pickle and print
as the single run's RunResult field by field."""

from __future__ import annotations

import dataclasses
import pickle
import random

from test_sim_batch import PROGRAM

from mlctool.sim.campaign.batch import Options, run_batch
from mlctool.sim.run.run import ExpectOutcome, Failure, RunResult
from mlctool.sim.state import parse_device_name
from simkit import NC5, image_of


def _scenarios(tmp_path, n: int = 40) -> list[str]:
    """Set lines on the program's inputs and on devices outside it (each scenario its own),
    forces, expectations that hold (computed) and that fail (random)."""
    rnd = random.Random(3)
    paths = []
    for k in range(n):
        lines = [f"#{rnd.randrange(20)} X{rnd.randrange(6)}={rnd.randrange(2)}" for _ in range(8)]
        lines.append(f"#{rnd.randrange(20)} M{rnd.randrange(100, 110)}=1")
        if k % 4 == 1:
            lines += ["#3 force X2=1", "#12 release X2"]
        if k % 3 == 0:
            lines.append(f"#25 expect M0={rnd.randrange(2)} Y3={rnd.randrange(2)}")
        (tmp_path / f"s{k:02}.stim").write_text("\n".join(lines) + "\nrun #30\n")
        paths.append(f"s{k:02}.stim")
    return paths


def _same(a: RunResult, b: RunResult) -> None:
    for f in dataclasses.fields(RunResult):
        assert getattr(a, f.name) == getattr(b, f.name), f.name
    assert list(a.devices.items()) == list(b.devices.items())  # the JSON order
    assert (a.ok, a.failed, a.time_us) == (b.ok, b.failed, b.time_us)
    assert a == b


def test_lazy_lane_results_equal_single_runs_field_by_field(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    paths = _scenarios(tmp_path)
    image = image_of(PROGRAM)
    watch = [parse_device_name("Y7", NC5), parse_device_name("M0", NC5)]
    for opts in (Options(), Options(watch=watch)):
        lanes, stats = run_batch(image, NC5, paths, opts)
        single, _ = run_batch(image, NC5, paths, opts, lanes=False)
        assert stats.lanes > 20 and stats.reruns > 2  # both kinds of results are compared
        lazy = [sc.result for sc in lanes if "_final" in vars(sc.result)]
        assert len(lazy) == stats.lanes
        # pickled before anything was read (as a cluster worker sends them), all at once
        shipped = pickle.loads(pickle.dumps([sc.result for sc in lanes]))
        assert [("_final" in vars(r)) for r in shipped] == [("_final" in vars(sc.result)) for sc in lanes]
        for a, b, c in zip(lanes, single, shipped):
            assert a.stim == b.stim
            _same(a.result, b.result)
            _same(c, b.result)
            _same(pickle.loads(pickle.dumps(a.result)), b.result)  # pickled after its values were read
            assert [d.message for d in a.diagnostics] == [d.message for d in b.diagnostics]
        assert any(v.name == "Y7" for v in lazy[0].views) == bool(opts.watch)


def test_lazy_result_reads_its_values_once_and_equals_the_eager_one():
    m0 = parse_device_name("M0", NC5)
    calls = []

    def final():
        calls.append(1)
        return {"M0": 1}, [m0]

    fail = Failure(2, 5, 10_000, 1, "M0", "0", 1, "", "M0=0")
    for outcomes in ([ExpectOutcome(2, "#1 expect M0=1", 10_000, 1)],
                     [ExpectOutcome(2, "#1 expect M0=0", 10_000, 1, [fail])]):
        eager = RunResult(10_000, 3, {"M0": 1}, [m0], outcomes, [], None, [])
        calls.clear()
        lazy = RunResult.lazy(10_000, 3, outcomes, final)
        assert lazy.ok == eager.ok and lazy.failed == eager.failed and not calls  # no values read for these
        _same(lazy, eager)
        assert len(calls) == 1 and repr(lazy) == repr(eager)
        assert type(lazy) is RunResult and not hasattr(lazy, "no_such_field")


def test_set_lines_kept_as_tuples_run_and_read_as_events(tmp_path, monkeypatch):
    """A stimulus keeps its set lines as tuples until its events are read (Stimulus.entries):
    the lanes read the tuples, and give the results they give from the Events; the events
    read later, or after pickling (a cluster's chunks), are the parser's."""
    from mlctool.sim.stimulus.stimulus import NameCache, load_stimulus

    monkeypatch.chdir(tmp_path)
    paths = _scenarios(tmp_path)
    image = image_of(PROGRAM)

    def loaded(read_events: bool) -> dict:
        names = NameCache(NC5)
        out = {p: load_stimulus(p, NC5, names) for p in paths}
        for st, _ in out.values():
            assert st.compact and any(type(e) is tuple for e in st.entries)
            if read_events:
                assert st.events and not st.compact
        return out

    compact = loaded(False)
    shipped = pickle.loads(pickle.dumps(compact))
    a, _ = run_batch(image, NC5, paths, Options(), loaded=compact)
    b, _ = run_batch(image, NC5, paths, Options(), loaded=loaded(True))
    assert [sc.result for sc in a] == [sc.result for sc in b]
    eager = loaded(True)
    for p in paths:
        events = eager[p][0].events
        assert shipped[p][0].events == compact[p][0].events == events
        assert all(type(e) is not tuple for e in events) and any(e.kind == "set" for e in events)
