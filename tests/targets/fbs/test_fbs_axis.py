"""FUN140 axis model on the chapter's worked examples: pulse counts, positions, flags."""

from __future__ import annotations

from pathlib import Path

from mlctool.targets.fbs.axis import Axis, Params
from mlctool.targets.fbs.lang import parse_program
from mlctool.targets.fbs.model import tables

SAMPLES = Path(__file__).resolve().parents[3] / "samples" / "fbs"
HSPSO = tables().dialects["hspso"]


class Env:
    """Registers and contacts for one axis; R4072 reads the axis' remaining pulses."""

    def __init__(self, words=None, bits=None):
        self.words = dict(words or {})
        self.bits = dict(bits or {})
        self.axis = None
        self.hook = None  # f(axis, env) -> None, per read of a bit (a plant)

    def dword(self, kind, n):
        if (kind, n) == ("R", 4072):
            return self.axis.remaining
        return self.words.get((kind, n), 0)

    def word(self, kind, n):
        return self.words.get((kind, n), 0)

    def bit(self, kind, n):
        if self.hook:
            self.hook(self.axis, self)
        return bool(self.bits.get((kind, n), False))


def axis_for(text_or_file: str, env: Env, **params) -> Axis:
    text = (SAMPLES / text_or_file).read_text("utf-8") if text_or_file.endswith(".pos") else text_or_file
    prog, diags = parse_program("t.pos", text, HSPSO)
    assert not diags, diags
    ax = Axis(prog, Params(**params))
    env.axis = ax
    return ax


def run(ax: Axis, env: Env, seconds: float, en=True, pau=False, abt=False, scan_us=10_000, until=None):
    for _ in range(int(seconds * 1e6 / scan_us)):
        ax.run(env, en, pau, abt, scan_us)
        if until and until(ax):
            return True
    return False


def test_program_format_example():
    env = Env({("R", 1000): 20000, ("D", 100): 500, ("R", 500): 20, ("R", 1002): 4000, ("D", 102): 3000})
    ax = axis_for("man_program_format.pos", env, p8_accel_ms=100)
    assert run(ax, env, 60, until=lambda a: a.state == "wait")
    assert ax.position == 100000 and ax.pulses_out == 100000  # 10000 Ut x 10 Ps/Ut
    assert ax.dn and ax.end_step == 1 and ax.wr0 == 1
    assert run(ax, env, 60, until=lambda a: a.state == "wait" and a.wr0 == 2)
    assert ax.position == 105000  # + DD100 = 500 Ut
    assert run(ax, env, 1, until=lambda a: a.wr0 == 3)
    assert ax.t_out < 10_000  # dwell R500 = 20 x 10 ms, then step 3 started
    # step 3: reverse DD102 = 3000 Ut; X0 (EXT) after ~1 s cuts it short
    run(ax, env, 1.0)
    moved = 105000 - ax.position
    assert 0 < moved < 30000 and ax.remaining == 30000 - moved
    env.bits[("X", 0)] = True
    assert run(ax, env, 0.02, until=lambda a: a.wr0 == 4)
    # step 4 outputs exactly the pulses step 3 left (DR4072), in reverse, then waits for X1
    assert run(ax, env, 60, until=lambda a: a.state == "wait" and a.wr0 == 4)
    assert ax.position == 75000 and ax.pulses_out == 105000 + 30000
    env.bits[("X", 1)] = True
    assert run(ax, env, 0.02, until=lambda a: a.wr0 == 1)
    assert ax.done_last  # step N completed (M1996)


def test_drvc_three_segments_without_stopping():
    env = Env()
    ax = axis_for("man_drvc.pos", env, p8_accel_ms=50)
    freqs = []

    def record(a):
        freqs.append((a.wr0, a.freq))
        return a.state == "wait"
    assert run(ax, env, 60, until=record)
    assert ax.position == 850000 and ax.pulses_out == 850000  # 20000 + 60000 + 5000 Ut
    assert ax.end_step == 3 and not ax.act
    # never stopped between segments: the frequency stays above the start speed
    running = [f for k, f in freqs if f > 0]
    assert len(running) == len(freqs) - 1
    assert max(f for k, f in freqs if k == 2) == 50000
    env.bits[("X", 0)] = True
    assert run(ax, env, 0.02, until=lambda a: a.wr0 == 1)


def test_drvc_abs_sign_is_the_chain_direction():
    """11.6 DRVC row (`ABS，−`): "DRVC 之運轉方向決定祇能由 '+' 或 '−' 決定"; the first segment
    outputs |target - position| in the written direction, the chain follows it."""
    env = Env()
    ax = axis_for("001 SPD 5000\n DRVC ABS,-,100,Ps\n GOTO NEXT\n002 SPD 2000\n DRV ADR,+,50,Ps\n MEND\n",
                  env, p8_accel_ms=100)
    ax.position = 1000
    assert run(ax, env, 5, until=lambda a: a.done_last)
    assert ax.position == 1000 - 900 - 50 and ax.pulses_out == 950  # the second segment's + is void


def test_jog_short_and_long_press():
    env = Env()
    ax = axis_for("man_jog_forward.pos", env)
    run(ax, env, 0.3)  # press < 0.5 s
    run(ax, env, 0.1, en=False)
    assert ax.pulses_out == 1 and ax.position == 1
    ax.wr0 = 0  # "每次由第一步開始執行"
    run(ax, env, 1.5)  # press > 0.5 s: one pulse, then a continuous 10 kHz run
    assert ax.wr0 == 2 and ax.pulses_out > 1000
    run(ax, env, 0.1, en=False)
    assert not ax.act and ax.ready
    assert ax.position == ax.pulses_out


def test_step_cycle_net_travel_is_zero():
    env = Env(bits={("M", 200): True, ("X", 16): True})
    ax = axis_for("man_step_cycle.pos", env, p8_accel_ms=100, ut_pulses=1)
    assert run(ax, env, 100, until=lambda a: a.done_last)
    assert ax.position == 0 and ax.pulses_out == 2 * 60000
    assert ax.wr0 == 1  # GOTO 1


def test_step_mode_runs_one_step_per_start():
    env = Env(bits={("X", 16): True})
    ax = axis_for("man_step_cycle.pos", env, p8_accel_ms=100, ut_pulses=1)
    run(ax, env, 30, until=lambda a: a.dn)
    run(ax, env, 0.02, en=False)  # DN stops the run in step mode
    assert ax.position == 20000 and ax.wr0 == 1
    ax.dn = False  # the ladder clears WR+1
    run(ax, env, 30, until=lambda a: a.dn)
    assert ax.position == 60000 and ax.wr0 == 2


def test_coordinates_abs_and_adr():
    env = Env()
    ax = axis_for("man_coordinates.pos", env, p8_accel_ms=10, ut_pulses=1)
    positions = []
    real = ax.transfer
    ax.transfer = lambda e: positions.append(ax.position) or real(e)
    assert run(ax, env, 200, until=lambda a: a.done_last)
    # ABS 300, ABS 0 (goes to 0: the 11.2 example), ADR +200, ADR -300 twice, ADR -40000,
    # ABS -10000, ADR +20000, ABS 10000 (already there)
    assert positions == [300, 0, 200, -100, -400, -40400, -10000, 10000, 10000]


def test_compensation_and_backlash():
    env = Env()
    text = "001 SPD 1000\n DRV ADR,+,100,Ps\n GOTO NEXT\n002 SPD 1000\n DRV ADR,-,100,Ps\n MEND\n"
    ax = axis_for(text, env, p10_fwd=3, p11_rev=5, p7_backlash=2, p8_accel_ms=10)
    assert run(ax, env, 5, until=lambda a: a.done_last)
    assert ax.pulses_out == 103 + 107 and ax.position == 0


def test_runtime_errors():
    env = Env({("R", 0): 1_000_000})
    ax = axis_for("001 SPD R0\n DRV ADR,+,10,Ps\n MEND\n", env)
    run(ax, env, 0.05)
    assert ax.error == 37 and not ax.act
    ax = axis_for("001 SPD 100\n DRV ADR,+,10,Ps\n MEND\n", env)
    run(ax, env, 0.05)
    assert ax.error == 38
    ax = axis_for("001 SPD 1000\n DRV ADR,-,10,Ps\n MEND\n", env, p11_rev=-20)
    run(ax, env, 0.05)
    assert ax.error == 39
    for params, code in (({"dog": None}, 51), ({"dog": 3, "pg0": 20}, 52), ({"dog": 3, "pg0": 4, "clr": 30}, 53)):
        ax = axis_for("001 SPD 5000\n DRVZ MD2\n MEND\n", env, **params)
        run(ax, env, 0.05)
        assert ax.error == code


def dog_plant(lo: int, hi: int, pg0_every: int | None = None):
    """DOG (X0) on while the position is inside [lo, hi]; PG0 (X4) a pulse every n Ps."""
    def hook(axis, env):
        env.bits[("X", 0)] = lo <= axis.position <= hi
        if pg0_every:
            env.bits[("X", 4)] = axis.position % pg0_every == 0
    return hook


def test_homing_md0():
    env = Env()
    env.hook = dog_plant(-2000, -1000)
    ax = axis_for("001 SPD 5000\n DRVZ MD0\n MEND\n", env, dog=0, p6_creep=1000, p16_origin=100, clr=8,
                  p8_accel_ms=100)
    ax.position = 5000
    assert run(ax, env, 10, until=lambda a: a.done_last)
    # zero at the DOG falling edge (leaving DOG toward the origin); P16 loaded
    assert ax.position == 100 and ax.error == 0
    assert 7000 - 2 <= ax.pulses_out <= 7000 + 2  # from 5000 to just past -2000


def test_homing_md1_stops_waits_and_reverses():
    env = Env()
    env.hook = dog_plant(-2000, -1000)
    ax = axis_for("001 SPD 5000\n DRVZ MD1\n MEND\n", env, dog=0, p16_origin=0, p8_accel_ms=100)
    ax.position = 5000
    assert run(ax, env, 10, until=lambda a: a.done_last)
    assert ax.position == 0
    # to the DOG edge at -1000 and back; inputs per 1 ms; ~3 Ps each way braking at P4/P8
    assert 6000 <= ax.pulses_out <= 6000 + 20


def test_homing_md1_decelerates_at_the_p8_slope():
    """11.7 MD1 b: "碰到原點感知信號時(中斷處理)，由目前速度以加減速時間設定(參數8)之斜率減速停止"
    (at DOG, decelerate from the current speed to a stop at the parameter-8 slope)."""
    env = Env()
    env.hook = dog_plant(-20000, -1000)
    ax = axis_for("001 SPD 5000\n DRVZ MD1\n MEND\n", env, dog=0, p8_accel_ms=5000)
    ax.position = 5000
    slope = 460000 / 5.0  # P4 / P8 in Ps/s^2
    run(ax, env, 10, scan_us=1000, until=lambda a: a.home == "stopping")
    at_dog, t = ax.position, 0
    while ax.home == "stopping":
        ax.run(env, True, False, False, 1000)
        t += 1000
    overrun = at_dog - ax.position
    expected = (5000 ** 2 - 141 ** 2) / (2 * slope)  # ~135 Ps from 5000 Ps/s down to P5
    assert abs(t / 1e6 - (5000 - 141) / slope) <= 0.002  # ~53 ms, not within 1 ms
    assert abs(overrun - expected) <= 10  # 1 ms steps; stopping at once would be ~5 Ps
    assert ax.state == "home_pause" and ax.freq == 0
    assert run(ax, env, 10, until=lambda a: a.done_last) and ax.position == 0


def test_homing_completes_only_after_clr():
    """11.7 (MD0, MD1, MD2) e: "找到零點位置時，會輸出一脈波寬度大於20mS之信號；完成信號輸出後，
    才代表整個歸零動作完成" (the return is complete only after the CLR signal has been output)."""
    for mode, extra in ((0, {}), (1, {}), (2, {"pg0": 4, "p17_count": 1})):
        env = Env()
        env.hook = dog_plant(-2000, -1000, pg0_every=100 if mode == 2 else None)
        ax = axis_for(f"001 SPD 5000\n DRVZ MD{mode}\n MEND\n", env, dog=0, clr=8, p16_origin=7,
                      p8_accel_ms=100, **extra)
        ax.position = 5000
        samples: list[tuple[bool, bool, bool]] = []

        def record(a, samples=samples):
            samples.append((a.clr, a.dn, a.done_last))
            return a.done_last
        assert run(ax, env, 10, scan_us=1000, until=record)
        clr_on = [i for i, (c, _, _) in enumerate(samples) if c]
        assert len(clr_on) >= 20, mode  # > 20 ms of 1 ms scans
        assert not any(dn or last for _, dn, last in samples[: clr_on[-1] + 1]), mode
        assert not ax.clr and ax.position == 7


def test_homing_md2_counts_pg0():
    env = Env()
    env.hook = dog_plant(-3000, -1000, pg0_every=100)
    ax = axis_for("man_home_drvz.pos", env, dog=0, pg0=4, p17_count=10, p16_origin=100, clr=8,
                  p8_accel_ms=100)
    ax.position = 5000
    clr_seen = []
    assert run(ax, env, 10, until=lambda a: clr_seen.append(a.clr) or a.done_last)
    assert ax.position == 100 and any(clr_seen)
    assert 6000 + 900 <= ax.pulses_out <= 6000 + 1001  # DOG at -1000, then 10 PG0 marks


def test_abort_restarts_at_step_one_and_pause_resumes():
    env = Env(bits={("M", 200): True, ("X", 16): True})
    ax = axis_for("man_step_cycle.pos", env, p8_accel_ms=100)
    run(ax, env, 1.0)
    before = ax.pulses_out
    run(ax, env, 1.0, pau=True)
    assert ax.pulses_out == before  # paused: no pulses
    run(ax, env, 1.0)
    assert ax.pulses_out > before
    run(ax, env, 0.02, abt=True)
    assert ax.wr0 == 0 and ax.ready and not ax.act


def limit_plant(lo: int, hi: int, limit_at: int):
    """dog_plant, plus the travel limit (X1) on at and beyond `limit_at` (homing side)."""
    dog = dog_plant(lo, hi)

    def hook(axis, env):
        dog(axis, env)
        env.bits[("X", 1)] = axis.position <= limit_at
    return hook


def test_homing_from_past_the_dog_uses_the_travel_limit():
    """11.7 (start on or before DOG, P15-1): to the limit, reverse at once until DOG 1 -> 0,
    then the mode (MD0) from there."""
    for start in (-3000, -1500):  # past the DOG, and on it
        env = Env()
        env.hook = limit_plant(-2000, -1000, -4000)
        ax = axis_for("001 SPD 5000\n DRVZ MD0\n MEND\n", env, dog=0, limit=1, p6_creep=1000,
                      p16_origin=100, p8_accel_ms=100)
        ax.position = start
        assert run(ax, env, 10, until=lambda a: a.done_last)
        assert ax.position == 100 and ax.error == 0
        # start -> -4000 -> just past -1000 -> just past -2000 (inputs per 1 ms: a few Ps late)
        want = start + 4000 + 3000 + 1000
        assert want <= ax.pulses_out <= want + 30, (start, ax.pulses_out)
