"""One FUN140 axis on virtual time: step sequencing, ramps, exact pulse counts, homing.

`Axis.run(env, en, pau, abt, dt_us)` advances the axis by dt (one scan) in 1 ms ticks
(`TICK_US`); `env` gives the registers and contacts a program names (SPD Rxxxx, WAIT X0,
DOG ...). Pulse counts are exact: a step outputs its travel (+ compensation) and never a
pulse more; the ramp only shapes the timing. Inputs are sampled once per tick.
Manual 001 ch. 11, FUN140/FUN141; decisions in docs/fbs.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol

from mlctool.targets.fbs.model import PosProgram, Step, Val

TICK_US = 1000
INF = math.inf


class Env(Protocol):
    def dword(self, kind: str, n: int) -> int: ...
    def word(self, kind: str, n: int) -> int: ...
    def bit(self, kind: str, n: int) -> bool: ...


@dataclass
class Params:
    """FUN141 parameters in motor units (P0 = 1), the manual's defaults."""

    p4_max: int = 460000  # maximum speed (Ps/s)
    p5_start: int = 141  # start/stop speed
    p6_creep: int = 1000  # homing creep speed
    p7_backlash: int = 0  # added on a reverse after a forward move
    p8_accel_ms: int = 5000  # 0 -> P4 time (constant slope)
    p9_count_down: bool = False  # P9-0 = 1: forward pulses decrease the position
    p9_home_left: bool = True  # P9-1 = 1: homing toward decreasing position (default 0100H)
    p10_fwd: int = 0  # forward compensation
    p11_rev: int = 0  # reverse compensation
    p12_decel_ms: int = 0  # 0 -> P8
    p13_ms: int = 500  # FUN147 interpolation ramp: constant time 0 -> working frequency
    ut_pulses: float = 10  # one Ut in pulses: 10**(3-P3), P3 = 2 (notes A5, decision)
    speed_scale: float = 1.0  # SPD unit in Ps/s (P0 = 0: 1000 A / (6 B), notes A5)
    dog: int | None = None  # P15-0: X number (None = FFH)
    dog_nc: bool = False
    limit: int | None = None  # P15-1: travel-limit X number (None = FFH)
    limit_nc: bool = False
    pg0: int | None = None  # P15-2
    pg0_trailing: bool = False
    clr: int | None = None  # P15-3: Y number
    p16_origin: int = 0
    p17_count: int = 1

    @property
    def accel(self) -> float:
        return self.p4_max / (self.p8_accel_ms / 1000) if self.p8_accel_ms else INF

    @property
    def decel(self) -> float:
        ms = self.p12_decel_ms or self.p8_accel_ms
        return self.p4_max / (ms / 1000) if ms else INF


@dataclass
class Axis:
    program: PosProgram
    params: Params = field(default_factory=Params)
    # registers and flags the chapter lists (per axis)
    wr0: int = 0  # WR+0: current / last step
    position: int = 0  # DR4088+2Ps
    remaining: int = 0  # DR4072+2Ps
    freq: float = 0.0  # DR4080+2Ps
    error: int = 0  # R4060+Ps
    end_step: int = 0  # R4064+Ps
    act: bool = False
    dn: bool = False  # WR+1 b14, stays until cleared
    done_last: bool = False  # M1996+Ps
    ready: bool = True  # M1992+Ps
    clr: bool = False  # homing CLR output
    pulses_out: int = 0  # every pulse output (with compensation), for tests and traces
    # internal
    state: str = "idle"  # idle | run | wait | home_pause | home_clr (CLR on, 11.7 e)
    last_en: bool = False
    last_dir: int = 0
    dir: int = 1
    to_go: float = 0.0  # pulses left in this step (INF: continuous)
    counted: float = 0.0  # of those, pulses that move the position (compensation excluded)
    acc: float = 0.0  # fractional pulse
    t_out: int = 0  # us since the step's output started
    t_wait: int = 0  # us since its pulses completed
    chain: bool = False  # DRVC: continue into the next segment at speed
    spd: int = 0  # the step's SPD value when it started (R4056 = 5AH: read live instead)
    soft_stop: bool = False  # M1991: stop and pause decelerate (set by the scan, per call)
    braking: bool = False  # EN went 0 with M1991: decelerating to a stop
    home: str = ""  # homing phase: fast | escape | creep | count | stopping | pause | back
    home_seen: int = 0
    prev_dog: bool = False
    prev_pg0: bool = False
    home_started: bool = False
    clr_us: int = 0

    # ------------------------------------------------------------ scan interface
    def run(self, env: Env, en: bool, pau: bool, abt: bool, dt_us: int) -> None:
        if abt:
            self.stop()
            self.wr0 = 0  # next EN starts at step 1 (FUN140 note 6)
        elif not en:
            if self.state != "idle" and not self.braking:
                if self.soft_stop and self.freq > 0 and self.state == "run":
                    self.braking = True  # M1991: decelerate, then stop
                else:
                    self.stop()
        elif not self.last_en and self.state == "idle":
            self.start(env)
        self.last_en = en and not abt
        t = 0
        while t < dt_us:
            tick = min(TICK_US, dt_us - t)
            if self.braking or (pau and self.soft_stop and self.freq > 0 and self.state == "run"):
                self.brake(tick)
            elif not pau:
                self.tick(env, tick)
            elif self.state == "run":
                self.freq = 0.0  # paused (without M1991: at once); resumes from P5
            t += tick

    def stop(self) -> None:
        """EN = 0 without M1991, ABT, PSOFF: output stops at once."""
        self.state, self.act, self.ready, self.freq, self.home = "idle", False, True, 0.0, ""
        self.braking, self.clr, self.clr_us = False, False, 0

    def brake(self, dt_us: int) -> None:
        """M1991 On: a stop (EN = 0) or pause decelerates at the P12/P8 slope down to P5,
        then output stops; the pulses are exact (never more than the step's travel)."""
        p = self.params
        f = self.freq - (p.decel * dt_us / 1e6 if p.decel != INF else self.freq)
        if f <= p.p5_start or self.to_go <= 0:
            self.freq, self.acc = 0.0, 0.0
            if self.braking:
                self.stop()
            return
        self.freq = f
        self.acc += f * dt_us / 1e6
        n = int(self.acc) if self.to_go == INF else min(int(self.acc), int(self.to_go))
        self.acc -= n
        if n:
            self.emit(n)

    def start(self, env: Env) -> None:
        n = len(self.program.steps)
        self.done_last = False
        self.begin(env, self.wr0 + 1 if 0 <= self.wr0 < n else 1)

    # ------------------------------------------------------------ steps
    def value(self, env: Env, v: Val, pair: bool = True) -> int:
        if v.kind == "K":
            return v.n
        return env.dword(v.kind, v.n) if pair else env.word(v.kind, v.n)

    def fail(self, code: int) -> None:
        self.error = code
        self.stop()

    def begin(self, env: Env, k: int) -> None:
        self.wr0 = k
        s = self.step
        self.state, self.ready, self.act = "run", False, True
        self.t_out = self.t_wait = 0
        self.chain = s.motion.op == "DRVC"
        self.spd = self.value(env, s.speed)
        if s.motion.op == "DRVZ":
            self.begin_home()
            return
        self.plan_move(env, s)

    @property
    def step(self) -> Step:
        return self.program.steps[self.wr0 - 1]

    def plan_move(self, env: Env, s: Step) -> None:
        m, p = s.motion, self.params
        raw = self.value(env, m.travel[0])
        scale = p.ut_pulses if m.unit == "Ut" else 1
        if m.coord == "ABS":
            delta = raw * scale - self.position
            direction = 1 if delta >= 0 else -1
            n = round(abs(delta))
            if m.sign:  # DRVC ABS,+|-: "DRVC之運轉方向決定祇能由'+'或'−'決定" (docs/fbs-positioning.md)
                direction = 1 if m.sign == "+" else -1
            if self.chain_follow:
                direction = self.dir
        else:
            direction = {"+": 1, "-": -1}.get(m.sign, 1 if raw >= 0 else -1)
            n = round(abs(raw) * scale)
            if m.op == "DRV" and raw == 0:
                n = INF  # ADR travel 0: continuous run (WR+1 b10)
        if self.chain_follow:
            direction = self.dir  # DRVC: the first segment's direction governs
        if abs(raw) > 99999999:
            return self.fail(40)
        comp = (p.p10_fwd if direction > 0 else p.p11_rev)
        if self.last_dir and direction != self.last_dir:
            comp += p.p7_backlash
        if n != INF and n + comp < 0:
            return self.fail(39)
        self.dir = direction
        self.spd = self.value(env, s.speed)
        self.counted = n
        self.to_go = n + comp if n != INF else INF
        self.remaining = int(self.to_go) if n != INF else 0

    chain_follow: bool = False

    def target_freq(self, env: Env) -> float:
        s = self.step
        if self.home in ("creep", "count", "back"):
            return self.params.p6_creep
        dynamic = env.word("R", 4056) & 0xFF == 0x5A  # R4056 low byte 5AH: SPD read live
        f = self.value(env, s.speed) if dynamic or self.spd <= 0 else self.spd
        return float(f) * self.params.speed_scale

    # ------------------------------------------------------------ time
    def tick(self, env: Env, dt_us: int) -> None:
        if self.state == "home_clr":
            self.clr_us -= dt_us
            if self.clr_us <= 0:
                self.clr, self.clr_us = False, 0
                self.home_done(env)
            return
        if self.state == "run":
            self.t_out += dt_us
            if self.home:
                self.home_inputs(env)
                if self.state != "run":
                    return
            if self.home == "stopping":
                return self.home_decel(dt_us)
            self.output(env, dt_us)
            cond = self.step.cond
            if self.to_go > 0 and cond is not None and self.state == "run" and not self.home:
                if cond.op == "ACT" and self.t_out >= 10_000 * self.value(env, cond.val, False):
                    return self.transfer(env)
                if cond.op == "EXT" and env.bit(cond.val.kind, cond.val.n):
                    return self.transfer(env)
            if self.to_go <= 0 and self.state == "run":
                self.pulses_done(env)
        elif self.state == "wait":
            self.t_wait += dt_us
            self.t_out += dt_us
            self.check_wait(env)
        elif self.state == "home_pause":
            self.t_wait += dt_us
            if self.t_wait >= 500_000:  # MD1: 0.5 s, then reverse at the creep speed
                self.state, self.home, self.dir = "run", "back", -self.dir

    def output(self, env: Env, dt_us: int) -> None:
        p = self.params
        target = self.target_freq(env)
        if target <= 0:
            self.freq = 0.0  # SPD 0: wait until the value becomes non-zero
            return
        if target > min(p.p4_max, 921600):
            return self.fail(37)
        if target < p.p5_start and not self.home:
            return self.fail(38)
        dt = dt_us / 1e6
        f = self.freq or min(p.p5_start, target)
        braking = (f * f - p.p5_start ** 2) / (2 * p.decel) if p.decel != INF else 0
        if not self.chain and not self.home and self.to_go != INF and self.to_go <= braking:
            f = max(p.p5_start, f - p.decel * dt)
        elif f < target:
            f = min(target, f + p.accel * dt)
        elif f > target:
            f = max(target, f - p.decel * dt)
        self.freq = f
        self.acc += f * dt
        n = int(self.acc)
        if self.to_go != INF:
            n = min(n, int(self.to_go))
        self.acc -= n
        if n:
            self.emit(n)

    def emit(self, n: int) -> None:
        moving = min(n, self.counted) if self.counted != INF else n
        self.counted -= moving
        sign = -self.dir if self.params.p9_count_down else self.dir
        self.position += sign * int(moving)
        self.pulses_out += n
        self.last_dir = self.dir
        if self.to_go != INF:
            self.to_go -= n
            self.remaining = int(self.to_go)

    def pulses_done(self, env: Env) -> None:
        self.act = False
        self.acc = 0.0
        if self.chain:  # DRVC: straight into the next segment, no stop
            nxt = self.goto_target(env)
            self.wr0 = nxt
            self.chain_follow = True
            self.chain = self.step.motion.op == "DRVC"
            self.act = True
            self.plan_move(env, self.step)
            self.chain_follow = False
            return
        self.freq = 0.0
        self.dn = True
        self.end_step = self.wr0
        self.state, self.t_wait = "wait", 0
        self.check_wait(env)

    def check_wait(self, env: Env) -> None:
        s = self.step
        c = s.cond
        if c is not None:
            if c.time:
                base = self.t_wait if c.op == "WAIT" else self.t_out
                if base < 10_000 * self.value(env, c.val, False):
                    return
            elif not env.bit(c.val.kind, c.val.n):
                return
        self.transfer(env)

    def transfer(self, env: Env) -> None:
        """The transfer condition holds: GOTO, or the end of the program (MEND)."""
        n = len(self.program.steps)
        self.dn, self.end_step = True, self.wr0
        if self.step.mend:
            self.done_last = True
            self.stop()
            return
        if self.wr0 == n:
            self.done_last = True  # DECISION (notes A6.4.6): the numerically last step done
        self.acc, self.freq = 0.0, 0.0
        self.begin(env, self.goto_target(env))

    def goto_target(self, env: Env) -> int:
        s, n = self.step, len(self.program.steps)
        if s.goto.kind == "NEXT":
            return self.wr0 + 1 if self.wr0 < n else 1
        k = self.value(env, s.goto, False)
        if not 1 <= k <= n:
            self.fail(34)
            return 1
        return k

    # ------------------------------------------------------------ DRVZ (11.7)
    def begin_home(self) -> None:
        p = self.params
        if p.dog is None or not 0 <= p.dog <= 15:
            return self.fail(51)
        if self.step.motion.mode == 2 and (p.pg0 is None or not 0 <= p.pg0 <= 15):
            return self.fail(52)
        if p.clr is not None and not 0 <= p.clr <= 23:
            return self.fail(53)
        left = p.p9_home_left
        self.dir = (-1 if left else 1) * (-1 if p.p9_count_down else 1)
        self.to_go, self.counted, self.home, self.home_seen = INF, INF, "fast", 0
        self.prev_dog = self.prev_pg0 = False
        self.home_started = False

    def home_inputs(self, env: Env) -> None:
        p, mode = self.params, self.step.motion.mode
        dog = env.bit("X", p.dog) != p.dog_nc
        if not self.home_started and p.limit is not None:
            self.prev_dog = dog  # with a limit switch, starting on DOG is not a DOG edge
        self.home_started = True
        rise, fall = dog and not self.prev_dog, self.prev_dog and not dog
        self.prev_dog = dog
        if p.limit is not None and self.home in ("fast", "escape"):
            # 11.7: started on or past DOG, the axis runs to the travel limit, reverses at
            # once until DOG goes 1 -> 0, then homes in its mode from there
            if self.home == "fast" and env.bit("X", p.limit) != p.limit_nc:
                self.home, self.dir, self.freq = "escape", -self.dir, 0.0
                return
            if self.home == "escape":
                if fall:
                    self.home, self.dir, self.freq = "fast", -self.dir, 0.0
                return
        pg0 = env.bit("X", p.pg0) if p.pg0 is not None else False
        pg0_rise = pg0 and not self.prev_pg0
        self.prev_pg0 = pg0
        if self.home == "stopping":
            return  # MD1: decelerating after DOG; the pause starts at standstill
        if self.home == "fast" and rise:
            if mode == 1:
                self.home = "stopping"  # 11.7 MD1 b: decelerate at the P8 slope, then stop
                return
            self.home = "count" if mode == 2 and not p.pg0_trailing else "creep"
            return
        if mode == 2 and self.home == "creep" and fall:
            self.home = "count"  # trailing: count PG0 from the DOG falling edge
            return
        if self.home == "count" and pg0_rise:
            self.home_seen += 1
            if self.home_seen >= p.p17_count:
                self.zero()
            return
        if mode in (0, 1) and self.home in ("creep", "back") and fall:
            self.zero()

    def home_decel(self, dt_us: int) -> None:
        """MD1 at DOG (11.7 b): "from the current speed, decelerate to a stop with the slope
        of the acceleration/deceleration time setting (parameter 8)"; the slope is P4 / P8
        (P8 = 0: at once). At P5 or below the output stops and the 0.5 s pause begins."""
        p = self.params
        f = self.freq - (p.accel * dt_us / 1e6 if p.accel != INF else self.freq)
        if f <= p.p5_start:
            self.freq, self.acc, self.state, self.t_wait, self.home = 0.0, 0.0, "home_pause", 0, "pause"
            return
        self.freq = f
        self.acc += f * dt_us / 1e6
        n = int(self.acc)
        self.acc -= n
        if n:
            self.emit(n)

    def zero(self) -> None:
        """The zero point: stop, load P16; with P15-3 set, output CLR for > 20 ms and only
        then is the return complete (11.7 d/e: "完成信號輸出後，才代表整個歸零動作完成")."""
        self.position = self.params.p16_origin
        self.home, self.to_go, self.freq, self.act = "", 0, 0.0, False
        if self.params.clr is not None:
            self.clr, self.clr_us, self.state = True, 20_000 + TICK_US, "home_clr"
            return
        self.home_done(None)

    def home_done(self, env: Env | None) -> None:
        """The return is complete: DN, the step's end number, then its transfer condition."""
        self.dn, self.end_step = True, self.wr0
        self.state, self.t_wait = "wait", 0
        if env is not None:
            self.check_wait(env)
