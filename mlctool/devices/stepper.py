"""A stepper (or pulse-train servo) motor on a pulse output axis of the PLC.

    model stepper axis=0 [pulses_per_rev=200 | step_angle=1.8 [drive=full|half]]
                  [um_per_rev=5000] [mode=U/D|P/R|A/B] [name=MOT1]

FATEK FBs manual 11.5.1: "馬達之回轉角度與外部輸入之脈波數成正比，而馬達之轉速與脈波頻率成正比",
N (RPM) = 60 x f / n, f the pulse frequency (Ps/s), n the pulses per revolution (Ps/Rev),
n = 360 / θs, with the step-angle table of 11.5.1 (5-phase 0.36°/0.72°, 4-phase 0.90°,
2-phase 1.80°; HALF drive halves the angle). The model reads the axis' output frequency and
position registers (the target's `pulse_axes` setting, FBs: DR4080+2Ps and DR4088+2Ps) and
publishes, as its signals (sim/signals.py):

  NAME.freq    pulse frequency, Ps/s, as DR4080+2Ps
  NAME.pulses  position in pulses, as DR4088+2Ps
  NAME.rpm     shaft speed, 0.01 rpm: 60 x f x 100 / n, negative while the position falls
  NAME.angle   shaft angle, 0.01 deg, 0 <= angle < 36000
  NAME.travel  travel in um (0.001 mm): pulses x um_per_rev / n, the conversion of the
               manual's parameters 1 and 2 (pulses per revolution, travel per revolution,
               11.6 MPARA); 0 without um_per_rev

`mode=` is the axis' pulse output mode (U/D, P/R, A/B) for this run, the manual's "Pulse
Output 之工作模式" set in the programming tool: it overrides mlc.toml `pulse_modes` for the axis
(docs/fbs.md "Pulse pins"). Rounding: rpm, angle and travel are truncated toward zero.
"""

from __future__ import annotations

from mlctool.devices.base import DeviceModel, ModelIO, ParamError
from mlctool.limits import is_decimal
from mlctool.sim.signals import KINDS, MODEL_NAME
from mlctool.sim.state import DeviceView, NameError_, parse_device_name
from mlctool.sim.state import parse_signal_name as parse_signal
from mlctool.targetapi.model import Target

# 11.5.1 step-angle table: basic step angle (0.01 deg) -> pulses per revolution, FULL drive;
# HALF drive doubles it (0.36° -> 1000 / 2000, 0.72° -> 500 / 1000, 0.90° -> 400 / 800,
# 1.80° -> 200 / 400)
STEP_ANGLES = {"0.36": 1000, "0.72": 500, "0.9": 400, "0.90": 400, "1.8": 200, "1.80": 200}
MODES = {"U/D": "UD", "P/R": "PR", "A/B": "AB"}


def rpm_x100(freq: int, pulses_per_rev: int) -> int:
    """11.5.1: N (RPM) = 60 x f / n, in 0.01 rpm, truncated toward zero."""
    return int(60 * 100 * freq / pulses_per_rev)


def travel_um(pulses: int, pulses_per_rev: int, um_per_rev: int) -> int:
    """Travel of `pulses` at um_per_rev per revolution of pulses_per_rev, truncated toward zero."""
    return int(pulses * um_per_rev / pulses_per_rev)


class Stepper(DeviceModel):
    kind = "stepper"

    def __init__(self, params: dict[str, str], target: Target):
        super().__init__(params, target)
        axes = target.settings.get("pulse_axes")
        if not axes:
            raise ParamError("axis", f"target {target.name} has no pulse output axes for a stepper "
                                     f"(the fbs target has Ps0-Ps3)")
        self.axis = self._int("axis", None, 0, axes["count"] - 1)
        self.pulses_per_rev = self._pulses_per_rev()
        self.um_per_rev = self._int("um_per_rev", "0", 0, 10**9)
        self.mode = self._mode()
        self.name = self._name()
        self.check_unused()
        stride = axes.get("stride", 2)
        self.freq = self._register(axes["frequency"], stride)
        self.position = self._register(axes["position"], stride)
        self.last_pulses, self.reverse = 0, False

    def _int(self, key: str, default: str | None, lo: int, hi: int) -> int:
        text = self._param(key, default)
        if not is_decimal(text) or not lo <= int(text) <= hi:  # ASCII digits (mlctool/limits.py)
            raise ParamError(key, f"{key} takes {lo}..{hi}, not {text!r}")
        return int(text)

    def _pulses_per_rev(self) -> int:
        if "pulses_per_rev" in self.params:
            for key in ("step_angle", "drive"):
                if key in self.params:
                    raise ParamError(key, "give pulses_per_rev or step_angle, not both")
            return self._int("pulses_per_rev", None, 1, 10**7)
        angle = self._param("step_angle", "1.8")
        if angle not in STEP_ANGLES:
            raise ParamError("step_angle", "step_angle takes 0.36, 0.72, 0.9 or 1.8 (degrees, the "
                                           f"step-angle table of 11.5.1), not {angle!r}")
        drive = self._param("drive", "full").lower()
        if drive not in ("full", "half"):
            raise ParamError("drive", f"drive takes full or half, not {drive!r}")
        return STEP_ANGLES[angle] * (2 if drive == "half" else 1)

    def _mode(self) -> str | None:
        if "mode" not in self.params:
            return None
        text = self._param("mode", None).upper()
        if text not in MODES:
            raise ParamError("mode", f"mode takes U/D, P/R or A/B (the pulse output mode), not {text!r}")
        return MODES[text]

    def _name(self) -> str:
        text = self._param("name", "")
        if text and not MODEL_NAME.fullmatch(text):
            raise ParamError("name", f"name takes a letter then letters, digits or _ (e.g. MOT1), not {text!r}")
        return text.upper()

    def _register(self, base: str, stride: int) -> DeviceView:
        kind = base.rstrip("0123456789")
        number = int(base[len(kind):]) + stride * self.axis
        try:
            return parse_device_name(f"{kind}{number}:d", self.target)
        except NameError_ as e:  # pragma: no cover - the target's own table names its registers
            raise ParamError("axis", str(e)) from None

    # -- simulation
    def devices(self) -> list[DeviceView]:
        return [parse_signal(f"{self.name}.{s}") for s in KINDS["stepper"]] if self.name else []

    def step(self, io: ModelIO, t_us: int, period_us: int) -> None:
        if self.mode is not None:
            io.set_pulse_mode(self.axis, self.mode)
        if not self.name:  # named by run.build_models when not by name=
            return
        freq, pulses = int(io.get(self.freq)), int(io.get(self.position))
        if pulses != self.last_pulses:  # the register's frequency has no sign: the position's motion has
            self.reverse = pulses < self.last_pulses
        self.last_pulses = pulses
        n = self.pulses_per_rev
        io.publish(self.name, {
            "freq": freq,
            "pulses": pulses,
            "rpm": -rpm_x100(freq, n) if self.reverse else rpm_x100(freq, n),
            "angle": pulses % n * 36000 // n,
            "travel": travel_um(pulses, n, self.um_per_rev),
        })
