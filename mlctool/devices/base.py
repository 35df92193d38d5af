"""The interface between the scan loop and device (plant) models.

A model reads the PLC's outputs and drives its inputs once per scan, before the scan runs,
on the same virtual clock (`t_us` = start time of the coming scan). Models never read the
wall clock. A stimulus file attaches one with `model KIND key=value ...` (docs/stimulus.md).
"""

from __future__ import annotations

from mlctool.sim import signals
from mlctool.sim.signals import SIGNAL
from mlctool.sim.state import DeviceView, Machine, NameError_, parse_device_name
from mlctool.sim.stimulus.stimulus import StimError, parse_time
from mlctool.targetapi.model import Target


class ModelIO:
    """What a model may touch: named devices, the servo table (WRTL/RDTL, 4.9) and the
    PLC's serial ports."""

    def __init__(self, machine: Machine):
        self._m = machine

    def memory(self, kind: str):
        """The live container of device `kind` (bits: 0/1 items; words: raw 16-bit items), for a
        model that reads and writes many devices every step (the NC5's virtual NC). Asked for
        each step: a power cycle renews the containers."""
        m = self._m
        return m.bits[kind] if kind in m.bits else m.words[kind]

    def get(self, view: DeviceView) -> int | float:
        return view.read(self._m)

    def set(self, view: DeviceView, value: int | float) -> None:
        view.write(self._m, value)

    def torque_limit(self, station: int) -> int | None:
        return self._m.servo_limit.get(station)

    def set_torque_reached(self, station: int, reached: bool) -> None:
        self._m.servo_at_limit[station] = 1 if reached else 0

    def publish(self, model: str, values: dict[str, int]) -> None:
        """A model's signals (sim/signals.py) as of this step: `XC1.pos` and the like."""
        kind = SIGNAL + model
        for signal, value in values.items():
            self._m.signals[(kind, signals.index(signal))] = int(value)

    def publisher(self, model: str, names: list[str]):
        """publish() for a model that publishes the same signals every step: put(values) stores
        `values` (in the order of `names`) where they differ from the `last` values it is given."""
        kind = SIGNAL + model
        keys = [(kind, signals.index(s)) for s in names]

        def put(values: list[int], last: list[int]) -> None:
            store = self._m.signals
            if len(last) != len(values):
                last = [None] * len(values)
            for key, v, old in zip(keys, values, last):
                if v != old:
                    store[key] = v
        return put

    def warn(self, model: DeviceModel, code: str, message: str) -> None:
        """A run-time warning (a W code of codes.toml) of `model`, reported at its stimulus line
        as the program's run-time warnings are at their instruction (sim/semantics.py warn):
        once per message in a run; the run goes on."""
        self._m.warnings.append((self._m.now_us, model.at, code, message))

    def on_read(self, model: str, refresh) -> None:
        """refresh() runs before a signal of `model` is read (an expectation, the trace, the
        debugger): a model that skips steps while nothing but time passes (the NC5's virtual
        NC) brings its signals up to date there."""
        self._m.signal_refresh[SIGNAL + model] = refresh

    def set_pulse_mode(self, axis: int, mode: str) -> None:
        """The pulse output mode ("UD", "PR", "AB") of pulse axis `axis` for this run, over the
        project's setting; a target with pulse axes reads Machine.ext["pulse_modes"]."""
        self._m.ext.setdefault("pulse_modes", {})[axis] = mode

    def serial_port(self, name: str):
        """The PLC's serial port `name` (CP1...), for models on a Modbus link (sim/hardware/seriallink.py)."""
        from mlctool.sim.hardware.seriallink import port  # only models on a link need it

        return port(self._m, name)


class DeviceModel:
    """Base class. Subclasses set `kind`, read their parameters in __init__ (raising
    ParamError naming the parameter) and implement `step`."""

    kind = ""
    name = ""  # set by models that publish signals (sim/signals.py): `XC1` of `XC1.pos`
    at: tuple[str, int] = ("<model>", 1)  # its stimulus file and line (build_models): where it warns

    def __init__(self, params: dict[str, str], target: Target):
        self.params = params
        self.target = target
        self.used: set[str] = set()

    @classmethod
    def build(cls, params: dict[str, str], target: Target, folder: str) -> DeviceModel:
        """The model of a stimulus line; `folder` is the stimulus file's, against which a
        model that reads files of its own (inputs()) finds them."""
        return cls(params, target)

    def inputs(self) -> list[str]:
        """Files the model read (an NC part program): inputs no output may overwrite."""
        return []

    # -- parameter helpers
    def device(self, key: str, default: str | None = None) -> DeviceView:
        text = self._param(key, default)
        try:
            return parse_device_name(text, self.target)
        except NameError_ as e:
            raise ParamError(key, str(e), "E602") from None

    def time(self, key: str, default: str | None = None) -> int:
        text = self._param(key, default)
        try:
            return parse_time(text)
        except StimError as e:
            raise ParamError(key, e.message) from None

    def _param(self, key: str, default: str | None) -> str:
        self.used.add(key)
        if key in self.params:
            return self.params[key]
        if default is None:
            raise ParamError(key, f"model {self.kind} needs {key}=...")
        return default

    def check_unused(self) -> None:
        for key in sorted(self.params):
            if key not in self.used:
                raise ParamError(key, f"model {self.kind} has no parameter {key!r}")

    # -- simulation
    def power_cycle(self) -> None:
        """The PLC's power went off and on (a stimulus `power` line), after the step of that
        scan. A device with its own supply ignores it (the default); the NC5's NC, the same
        controller as its MLC, starts again."""

    def devices(self) -> list[DeviceView]:
        """Devices the model reads or drives (reported in JSON and waveforms)."""
        return []

    def step(self, io: ModelIO, t_us: int, period_us: int) -> None:  # pragma: no cover
        raise NotImplementedError


class ParamError(ValueError):
    def __init__(self, key: str, message: str, code: str = "E601"):
        super().__init__(message)
        self.key = key
        self.message = message
        self.code = code


class ModelInputError(ValueError):
    """A file the model reads is wrong: its diagnostics (file, line, column, code)."""

    def __init__(self, diags: list):
        super().__init__(f"{len(diags)} diagnostics")
        self.diags = diags
