"""A test suite: one program, many stimulus files (the scenarios), optional coverage.

`mlc test` discovers the scenarios from the project file (`tests = ["tests/*.stim"]` in
mlc.toml), runs each like `mlc sim PROGRAM --stimulus FILE`, in worker processes when asked,
and merges their JUnit results and coverage. Results do not depend on the number of jobs.
"""

from __future__ import annotations

import glob
import os
import pickle
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field

from mlctool.config import Config
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.fileio import note_input
from mlctool.program import Image
from mlctool.sim.campaign.coverage import Probe
from mlctool.sim.run.output import run_diagnostics
from mlctool.sim.run.run import (
    DEFAULT_SCAN_US,
    RunResult,
    RunTooLong,
    Simulation,
    build_models,
    model_inputs,
    plan_scans,
)
from mlctool.sim.stimulus.stimulus import load_stimulus
from mlctool.targetapi import Target


@dataclass
class Scenario:
    """The outcome of one stimulus file."""

    stim: str
    result: RunResult | None  # None: the stimulus could not be loaded
    diagnostics: list[Diagnostic] = field(default_factory=list)
    stim_lines: list[str] = field(default_factory=list)
    probe: Probe | None = None
    # wall time of loading and running the scenario (JUnit `time`); scenarios run together as
    # lanes share the group's time evenly. Not part of a result's identity (it is not deterministic).
    seconds: float = field(default=0.0, compare=False)
    artifacts: tuple[str, ...] = field(default=(), compare=False)  # a failure's VCD and report page
    inputs: tuple[str, ...] = ()  # files its models read (run.model_inputs): the command's inputs too

    @property
    def ok(self) -> bool:
        return self.result is not None and self.result.ok


def _escapes(pattern: str) -> bool:
    """A glob that could walk outside the project: absolute (`/**` walked the whole disk), on
    another drive, or with a `..` part."""
    parts = pattern.replace("\\", "/").split("/")
    return os.path.isabs(pattern) or bool(os.path.splitdrive(pattern)[0]) or ".." in parts


def discover(config: Config) -> tuple[list[str], list[str], list[Diagnostic]]:
    """(program sources, stimulus files, problems) named by the project file, relative to its folder."""
    where, at = config.locate()
    problems = []
    sources = config.data.get("sources") or []
    patterns = config.data.get("tests") or []
    if not sources:
        problems.append(diag(where, at, "E105", "mlc.toml names no `sources` (the program to test)"))
    if not patterns:
        problems.append(diag(where, at, "E105", 'mlc.toml names no `tests` (e.g. tests = ["tests/*.stim"])'))
    outside = [p for p in patterns if isinstance(p, str) and _escapes(p)]
    for pat in outside:
        problems.append(diag(*config.locate("tests"), "E105", f"`tests` pattern {pat!r} leaves the project "
                             "folder: patterns are relative to mlc.toml, without `..` (docs/project.md)"))
    if outside:
        return list(sources), [], problems
    stims = sorted({p for pat in patterns for p in glob.glob(pat, recursive=True)})
    if patterns and not stims:
        problems.append(diag(*config.locate("tests"), "E105", f"no stimulus file matches {patterns}"))
    return list(sources), stims, problems


def run_scenario(image: Image, target: Target, stim_path: str, coverage: bool = False,
                 loaded: tuple | None = None, preload: list = ()) -> Scenario:
    """`loaded`: load_stimulus's result for stim_path, when it was read already; `preload`:
    the register tables loaded with the program (mlc.toml `tables`)."""
    start = time.perf_counter()
    sc = _run_scenario(image, target, stim_path, coverage, loaded, preload)
    sc.seconds = time.perf_counter() - start
    return sc


def _run_scenario(image: Image, target: Target, stim_path: str, coverage: bool, loaded: tuple | None,
                  preload: list) -> Scenario:
    st, diags = loaded if loaded is not None else load_stimulus(stim_path, target)
    if st is None or any(d.severity == "error" for d in diags):
        return Scenario(stim_path, None, diags, st.lines if st else [])
    models, model_diags = build_models(st, target)
    if any(d.severity == "error" for d in model_diags):
        return Scenario(stim_path, None, diags + model_diags, st.lines)
    probe = Probe(len(image.instrs)) if coverage else None
    period = st.scan_us or DEFAULT_SCAN_US
    try:
        n_scans = plan_scans(st, period, None, None)
    except RunTooLong as e:
        return Scenario(stim_path, None, [diag(stim_path, Span.at(1), "E601", str(e))], st.lines)
    sim = Simulation(image, target, st, models, period, [], trace=False, probe=probe, preload=preload)
    result = sim.run(n_scans)
    return Scenario(stim_path, result, run_diagnostics(result, stim_path), st.lines, probe,
                    inputs=tuple(model_inputs(models)))


_WORKER: dict = {}


def _init_worker(blob: bytes) -> None:
    """A worker process takes the program and the target as the parent built them: a target
    loaded again by its name lost the project's model and mlc.toml `pulse_modes`."""
    root, _WORKER["args"] = pickle.loads(blob)
    os.chdir(root)  # the scenarios' paths are relative to the parent's folder


def _run_in_worker(stim: str) -> Scenario:
    image, target, coverage, preload = _WORKER["args"]
    return run_scenario(image, target, stim, coverage, preload=preload)


def _run_chunk(shared, chunk: list[tuple[str, tuple]]) -> list[Scenario]:
    """A cluster worker's part of a suite (mlctool/sim/campaign/cluster.py)."""
    image, target, coverage, preload = shared
    return [run_scenario(image, target, stim, coverage, loaded, preload) for stim, loaded in chunk]


def run_all(image: Image, target: Target, stims: list[str], jobs: int = 1,
            coverage: bool = False, cluster: str | None = None, preload: list = ()) -> list[Scenario]:
    """The scenarios' outcomes in the order of `stims`: here, in `jobs` processes, or on the
    Dask scheduler at `cluster` (ClusterError when it cannot be used). (`mlc test` without
    coverage runs its scenarios with mlctool/sim/campaign/batch.py's run_batch instead.)"""
    if cluster is not None:
        from mlctool.sim.campaign.cluster import map_chunks

        items = [(s, load_stimulus(s, target)) for s in stims]
        parts = map_chunks(cluster, _run_chunk, (image, target, coverage, list(preload)), items, per_thread=4)
        return [sc for part in parts for sc in part]
    if jobs <= 1 or len(stims) <= 1:
        return [run_scenario(image, target, s, coverage, preload=preload) for s in stims]
    for s in stims:  # read by the worker processes: inputs of this command all the same (E606)
        note_input(s)
    blob = pickle.dumps((os.getcwd(), (image, target, coverage, list(preload))))
    with ProcessPoolExecutor(max_workers=jobs, initializer=_init_worker, initargs=(blob,)) as pool:
        return list(pool.map(_run_in_worker, stims))


def merged_probe(n_steps: int, scenarios: list[Scenario]) -> Probe:
    probe = Probe(n_steps)
    for sc in scenarios:
        if sc.probe is not None:
            probe.merge(sc.probe)
    return probe


ARTIFACT_DIR = "mlc-test-out"  # where `mlc test` puts failure artefacts when there is no --junit


def artifact_paths(stim: str, folder: str) -> tuple[str, str]:
    """(waveform, report page) of a failing scenario, flat in `folder` (beside the JUnit file,
    not among the sources): the stimulus path with its folders joined by `-` and .vcd / .html
    for .stim (`tests/pick_cycle.stim` -> `FOLDER/tests-pick_cycle.vcd`)."""
    rel = os.path.normpath(stim)
    if os.path.isabs(rel) or rel.startswith(".."):  # a scenario outside the project: its name only
        rel = os.path.basename(rel)
    stem = os.path.splitext(rel)[0].replace(os.sep, "-").replace("/", "-")
    return os.path.join(folder, stem + ".vcd"), os.path.join(folder, stem + ".html")


def failure_artifacts(image: Image, target: Target, sc: Scenario, lines: dict[str, list[str]],
                      folder: str, preload: list = ()) -> dict[str, str]:
    """A failing scenario run again with its trace kept: {path: text} of its VCD, the GTKWave
    save file beside it and the HTML report page (the ladder lit by scan, waveforms)."""
    from mlctool.ladder.report import ScanLamps, report_html
    from mlctool.sim.run.vcd import gtkw_path, to_gtkw, to_vcd

    st, _ = load_stimulus(sc.stim, target)
    models, _ = build_models(st, target)
    period = st.scan_us or DEFAULT_SCAN_US
    sim = Simulation(image, target, st, models, period, [], trace=True, preload=preload)
    scan_lamps = ScanLamps(sim, lines)
    result = sim.run(plan_scans(st, period, None, None))
    vcd, html = artifact_paths(sc.stim, folder)
    return {vcd: to_vcd(result, image, target), gtkw_path(vcd): to_gtkw(vcd, result.views),
            html: report_html(sim, result, scan_lamps, [], sc.stim)}
