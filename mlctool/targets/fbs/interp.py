"""FUN147 MHSPO: linear interpolation of up to four axes on virtual time (manual 001 ch. 11,
FUN147; notes A8). A group owns the axes its step's LIN/LINE names (notes A8.1 [A]).

The lead axis (largest travel) runs at F x L / sqrt(sum d_i^2) (the Euclidean component of
the line speed F); every axis i has output floor(s x |d_i| / L) pulses when the lead has
output s, so all end together with exact counts. Ramps are constant-time: P13 from 0 to the
working frequency and back (P13 = 0: no ramp). LINE runs the travels as a ratio until its
transfer condition holds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from mlctool.targets.fbs.axis import TICK_US, Axis, Env
from mlctool.targets.fbs.model import PosProgram


@dataclass
class Group:
    program: PosProgram
    axes: list[Axis]  # Ps0-Ps3 (shared with FUN140)
    wr0: int = 0
    state: str = "idle"  # idle | run | wait
    freq: float = 0.0  # lead-axis frequency
    vector: float = 0.0  # line speed now (DR4068)
    error: int = 0
    end_step: int = 0
    dn: bool = False
    done_last: bool = False
    last_en: bool = False
    p13_ms: int = 500
    used: list[int] = field(default_factory=list)
    travel: list[int] = field(default_factory=lambda: [0] * 4)  # signed pulses (LINE: ratio)
    out: list[int] = field(default_factory=lambda: [0] * 4)  # pulses output per axis this step
    lead: float = 0.0  # L (INF for LINE)
    s: float = 0.0  # lead pulses output
    f_work: float = 0.0
    t_us: int = 0  # since the step started
    t_wait: int = 0

    @property
    def step(self):
        return self.program.steps[self.wr0 - 1]

    def run(self, env: Env, en: bool, pau: bool, abt: bool, dt_us: int) -> None:
        if abt:
            self.stop()
            self.wr0 = 0
        elif not en:
            if self.state != "idle":
                self.stop()
        elif not self.last_en and self.state == "idle":
            self.done_last = False
            n = len(self.program.steps)
            self.begin(env, self.wr0 + 1 if 0 <= self.wr0 < n else 1)
        self.last_en = en and not abt
        t = 0
        while t < dt_us:
            tick = min(TICK_US, dt_us - t)
            if not pau:
                self.tick(env, tick)
            elif self.state == "run":
                self.freq = self.vector = 0.0
            t += tick

    def stop(self) -> None:
        self.state, self.freq, self.vector = "idle", 0.0, 0.0
        for i in self.used:
            self.axes[i].freq, self.axes[i].ready = 0.0, True

    def fail(self, code: int) -> None:
        self.error = code
        self.stop()

    def begin(self, env: Env, k: int) -> None:
        self.wr0, s = k, self.program.steps[k - 1]
        m = s.motion
        self.used, self.travel, self.out = [], [0] * 4, [0] * 4
        for i, v in enumerate(m.travel):
            if v.kind == "":
                continue  # blank: the axis does not output
            a = self.axes[i]
            raw = v.n if v.kind == "K" else env.dword(v.kind, v.n)
            if abs(raw) > 1999999:
                return self.fail(40)
            pulses = round(raw * (1 if m.unit == "Ps" else a.params.ut_pulses))
            if m.coord == "ABS" and m.op == "LIN":
                pulses -= a.position
            if pulses:
                self.used.append(i)
                self.travel[i] = pulses
        f = (s.speed.n if s.speed.kind == "K" else env.dword(s.speed.kind, s.speed.n))
        self.state, self.s, self.t_us, self.t_wait = "run", 0.0, 0, 0
        if not self.used:
            self.lead = 0.0
            return
        norm = math.sqrt(sum(d * d for d in self.travel))
        big = max(abs(d) for d in self.travel)
        self.f_work = f * big / norm if f > 0 else 0.0
        self.lead = math.inf if m.op == "LINE" else float(big)
        if self.f_work and any(f * abs(d) / norm > 921600 for d in self.travel):
            return self.fail(37)
        for i in self.used:
            self.axes[i].ready = False

    def tick(self, env: Env, dt_us: int) -> None:
        if self.state == "run":
            self.t_us += dt_us
            self.move(dt_us)
            c = self.step.cond
            if self.s < self.lead:
                if c is not None and c.op == "EXT" and env.bit(c.val.kind, c.val.n):
                    return self.transfer(env)
                if self.lead == math.inf and c is not None and self.cond_holds(env, self.t_us):
                    return self.transfer(env)
                return
            self.freq = self.vector = 0.0
            for i in self.used:
                self.axes[i].freq = 0.0
            self.dn, self.end_step, self.state = True, self.wr0, "wait"
        if self.state == "wait":
            self.t_wait += dt_us
            if self.step.cond is None or self.cond_holds(env, self.t_wait):
                self.transfer(env)

    def cond_holds(self, env: Env, t_us: int) -> bool:
        c = self.step.cond
        if c.time:
            ticks = c.val.n if c.val.kind == "K" else env.word(c.val.kind, c.val.n)
            return t_us >= 10_000 * ticks
        return env.bit(c.val.kind, c.val.n)

    def move(self, dt_us: int) -> None:
        if not self.used:
            self.s = self.lead
            return
        dt = dt_us / 1e6
        t_ramp = self.p13_ms / 1000
        f = self.f_work
        if t_ramp:
            rate = f / t_ramp  # constant time: 0 -> f in P13
            left = self.lead - self.s
            braking = f * t_ramp / 2 * (self.freq / f) ** 2 if f else 0
            if left != math.inf and left <= braking + self.freq * dt:
                f = max(rate * dt, self.freq - rate * dt)
            else:
                f = min(f, self.freq + rate * dt)
        self.freq = f
        self.s = min(self.lead, self.s + f * dt)
        big = max(abs(d) for d in self.travel)
        norm = math.sqrt(sum(d * d for d in self.travel))
        self.vector = f * norm / big
        for i in self.used:
            d = self.travel[i]
            want = int(self.s * abs(d) / big) if self.lead == math.inf else int(self.s * abs(d) // big)
            n, self.out[i] = want - self.out[i], want
            a = self.axes[i]
            a.dir = 1 if d > 0 else -1
            a.freq = f * abs(d) / big
            sign = -a.dir if a.params.p9_count_down else a.dir
            a.position += sign * n
            a.pulses_out += n

    def transfer(self, env: Env) -> None:
        self.dn, self.end_step = True, self.wr0
        n = len(self.program.steps)
        if self.step.mend:
            self.done_last = True
            return self.stop()
        if self.wr0 == n:
            self.done_last = True
        g = self.step.goto
        k = self.wr0 + 1 if g.kind == "NEXT" else (g.n if g.kind == "K" else env.word(g.kind, g.n))
        if not 1 <= k <= n:
            k = 1 if g.kind == "NEXT" else 0
        if not k:
            return self.fail(34)
        for i in self.used:
            self.axes[i].ready = True
        self.begin(env, k)
