"""`mlc verify` as a stage: a checked program and a property file in, a verdict per property
out, each by the engine asked for or chosen (explicit first: exact and shortest; the symbolic
engine where the explicit search runs out of budget and the program is one it models)."""

from __future__ import annotations

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Image
from mlctool.sim.decode import program_devices
from mlctool.sim.run.run import DEFAULT_SCAN_US
from mlctool.sim.scan import load_program
from mlctool.sim.signals import SIGNAL
from mlctool.sim.state import DeviceView
from mlctool.targetapi.model import Target
from mlctool.verify.explicit import DEFAULT_MAX_STATES, Budget, index_modified, search
from mlctool.verify.props import Props, views_of
from mlctool.verify.results import UNKNOWN, Verdict
from mlctool.verify.space import Space, SpaceError, input_space
from mlctool.verify.symbolic import Unmodelled

ENGINES = ("auto", "explicit", "symbolic")


class VerifyError(ValueError):
    """Input the engines cannot take: diagnostics, exit 2."""

    def __init__(self, diagnostics: list[Diagnostic]):
        super().__init__(diagnostics[0].message)
        self.diagnostics = diagnostics


def program_inputs(image: Image, target: Target) -> list[DeviceView]:
    """The input bits (X) the program reads, one view each (a group's bits one by one)."""
    prog = load_program(image, target)
    out: set[DeviceView] = set()
    for v in program_devices(prog):
        kind = v.gdev if v.view == "group" else v.kind
        dev = target.devices.get(kind)
        if dev is None or not dev.input:
            continue
        if v.view == "group":
            out.update(DeviceView(kind, n, "bit", radix=dev.radix) for n in range(v.number, v.number + 4 * v.digits))
        elif v.view == "bit":
            out.add(v)
    return sorted(out, key=DeviceView.sort_key)


def prepare(image: Image, target: Target, props: Props) -> tuple[Space, int]:
    """The input space and the scan time. Raises VerifyError (E702, E703)."""
    named = []  # input bits a property names are free too (the program may not read them)
    for prop in props.properties:
        for view in views_of(prop.expr) + (views_of(prop.response) if prop.response is not None else []):
            if view.kind.startswith(SIGNAL):
                raise VerifyError([diag(props.path, Span.at(prop.line, prop.col, len(prop.text)), "E703",
                                        f"{view.name}: device models (`model` lines of a stimulus) are not part of "
                                        "a search; properties are over the PLC's devices")])
            dev = target.devices.get(view.kind)
            if view.view == "bit" and dev is not None and dev.input:
                named.append(view)
    try:
        space = input_space(props, sorted(set(program_inputs(image, target)) | set(named), key=DeviceView.sort_key))
    except SpaceError as e:
        raise VerifyError([e.diagnostic]) from None
    return space, props.scan_us or DEFAULT_SCAN_US


def verify(image: Image, target: Target, props: Props, engine: str = "auto", max_states: int = DEFAULT_MAX_STATES,
           max_seconds: float | None = None, sim_engine: str | None = None) -> tuple[list[Verdict], Space, int]:
    """A verdict for every property of `props`, in file order."""
    space, period = prepare(image, target, props)
    budget = Budget(max_states, max_seconds)
    symbolic_model = None
    if engine in ("auto", "symbolic"):
        from mlctool.verify.symbolic import model_of

        try:
            symbolic_model = model_of(image, target, space, period)
        except Unmodelled as e:
            if engine == "symbolic":
                raise VerifyError([diag(props.path, Span.at(1), "E703", f"{e}; the explicit engine runs every "
                                        "instruction the simulator does: --engine explicit")]) from None
    if engine != "symbolic":
        where = index_modified(image)
        if where:
            raise VerifyError([diag(props.path, Span.at(1), "E703",
                                    f"{where[0]}: an index-modified operand reaches any device, so the explicit "
                                    "search has no finite state to hash" + (f" ({len(where)} such instructions)"
                                                                            if len(where) > 1 else ""))])
    if symbolic_model is None:
        return search(image, target, props.properties, space, period, budget, sim_engine), space, period
    from mlctool.verify.symbolic import QUICK_DEPTH, prove

    decided: dict[int, Verdict] = {}
    for k, prop in enumerate(props.properties):
        try:
            if engine == "symbolic":
                decided[k] = prove(symbolic_model, prop, budget)
            else:  # auto: a short bounded check and induction first (often milliseconds), then the search
                quick = prove(symbolic_model, prop, budget, depth=QUICK_DEPTH, induction=QUICK_DEPTH)
                if quick.status != UNKNOWN:
                    decided[k] = quick
        except Unmodelled as e:
            if engine == "symbolic":
                raise VerifyError([diag(props.path, Span.at(prop.line, prop.col, len(prop.text)), "E703",
                                        f"{e}; --engine explicit decides it")]) from None
    left = [p for k, p in enumerate(props.properties) if k not in decided]
    if left:
        found = dict(zip([id(p) for p in left], search(image, target, left, space, period, budget, sim_engine),
                         strict=True))
        for k, prop in enumerate(props.properties):
            verdict = found.get(id(prop))
            if verdict is None:
                continue
            if verdict.status == UNKNOWN and verdict.trace is None:  # the search ran out: the solver, in full
                try:
                    tried = prove(symbolic_model, prop, Budget(max_states, max_seconds))
                except Unmodelled:
                    tried = verdict
                if tried.status != UNKNOWN:
                    tried.method += f" (the explicit search stopped: {verdict.reason})"
                    verdict = tried
            decided[k] = verdict
    return [decided[k] for k in range(len(props.properties))], space, period
