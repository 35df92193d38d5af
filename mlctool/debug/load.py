"""Program + stimulus -> a DebugSession, or the diagnostics that prevent one (shared by the
console, the DAP server and the web monitor)."""

from __future__ import annotations

import os

from mlctool.asm import program_from_paths
from mlctool.config import Config
from mlctool.debug.session import DebugSession
from mlctool.diagnostics import Diagnostic
from mlctool.sim.decode import unsimulated
from mlctool.sim.run.run import DEFAULT_SCAN_US, build_models
from mlctool.sim.stimulus.stimulus import Stimulus, load_stimulus


class LoadError(Exception):
    def __init__(self, diagnostics: list[Diagnostic], lines: dict[str, list[str]]):
        super().__init__("; ".join(f"{d.file}:{d.span.line}: {d.code} {d.message}" for d in diagnostics))
        self.diagnostics = diagnostics
        self.lines = lines


def load_session(program: list[str], stim_path: str | None, target, config: Config | None = None,
                 scan_us: int | None = None, engine: str | None = None,
                 checkpoint_every: int = 100, cwd: str | None = None, preload: list = ()) -> DebugSession:
    """`cwd`: the session's current folder (relative `save` paths; the folder `save` may write
    into when the program is in no project), by default the process's. `preload`: the register
    tables loaded with the program (mlc.toml `tables`, `--table`: as mlc sim loads them). The
    files read are in fileio's register of inputs, which `save` never overwrites."""
    image, diags, lines = program_from_paths(list(program), target, config)
    if image is None:
        raise LoadError([d for d in diags if d.severity == "error"], lines)
    refused = unsimulated(image, target)
    if refused:
        raise LoadError(refused, lines)
    st, stim_diags = (load_stimulus(stim_path, target) if stim_path else (Stimulus("<none>", []), []))
    if st is None:
        raise LoadError(stim_diags, {})
    models, model_diags = build_models(st, target)
    bad = [d for d in stim_diags + model_diags if d.severity == "error"]
    if bad:
        raise LoadError(bad, {st.path: st.lines})
    period = st.scan_us or scan_us or DEFAULT_SCAN_US
    session = DebugSession(image, target, st, models, period, engine=engine, checkpoint_every=checkpoint_every,
                           preload=preload)
    session.lines = lines
    session.cwd = cwd or os.getcwd()
    if config is not None and config.root is not None:
        session.folder, session.folder_is = str(config.root), "the project's folder"
    else:
        session.folder = session.cwd
    return session
