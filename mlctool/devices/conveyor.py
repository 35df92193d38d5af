"""A conveyor belt with a part sensor: the example device model.

    model conveyor motor=Y0 sensor=X0 travel=2s every=3s [first=0s] [window=200ms] [count=D100]

Parts are put on the belt at the loading end every `every` from `first` on. While the
`motor` output is On, every part moves; a part reaches the sensor after `travel` of belt
movement and covers it for `window` more, then drops off the end (adding 1 to the optional
`count` word). `sensor` is On while a part covers it.
"""

from __future__ import annotations

from mlctool.devices.base import DeviceModel, ModelIO, ParamError
from mlctool.sim.state import DeviceView
from mlctool.targetapi.model import Target


class Conveyor(DeviceModel):
    kind = "conveyor"

    def __init__(self, params: dict[str, str], target: Target):
        super().__init__(params, target)
        self.motor = self.device("motor")
        self.sensor = self.device("sensor")
        self.travel = self.time("travel")
        self.every = self.time("every")
        self.first = self.time("first", "0s")
        self.window = self.time("window", "200ms")
        self.count = self.device("count") if "count" in params else None
        self.check_unused()
        if self.every <= 0:
            raise ParamError("every", "every must be a positive time")
        for key, view in (("motor", self.motor), ("sensor", self.sensor)):
            if view.view != "bit":
                raise ParamError(key, f"{key} must be a bit device such as Y0 or X0")
        if self.count is not None and self.count.view not in ("w", "d"):
            raise ParamError("count", "count must be a word such as D100")
        self.parts: list[int] = []  # belt travel of each part so far (us)
        self.next_part = self.first
        self.last_t: int | None = None

    def devices(self) -> list[DeviceView]:
        return [self.motor, self.sensor] + ([self.count] if self.count else [])

    def step(self, io: ModelIO, t_us: int, period_us: int) -> None:
        if self.last_t is not None and io.get(self.motor):
            moved = t_us - self.last_t
            self.parts = [p + moved for p in self.parts]
        self.last_t = t_us
        end = self.travel + self.window
        dropped = sum(p >= end for p in self.parts)
        if dropped:
            self.parts = [p for p in self.parts if p < end]
            if self.count is not None:
                io.set(self.count, io.get(self.count) + dropped)
        while t_us >= self.next_part:
            self.parts.append(0)
            self.next_part += self.every
        io.set(self.sensor, any(self.travel <= p < end for p in self.parts))
