"""The compiled engine's function layout: the blocks compile._Gen generates (their bodies,
with goto() and CALL marks in place of control transfers) laid out into the functions the
driver (engine.Scanner) calls. See _Layout."""

from __future__ import annotations

_GOTO = "\0goto "  # a goto() line, resolved by _Layout
_CALL = "\0call "  # CALL of a subroutine (flow()): "<target block> <return block>"
REGION_LINES = 3000  # blocks are laid out into one function until it is this long ...
REGION_BLOCKS = 32  # ... or holds this many blocks (entering block k tests k - lo block numbers)
INLINE_LINES = 40  # a subroutine of one block up to this long is inlined where it is called
_SRET = "\0goto BLK.get(m.calls.pop(), NB)"  # how SRET's goto() reads (inlined: `m.calls.pop()`)
_NO_FALL = frozenset({"fend", "end", "sret"})  # the block after one of these is reached by a jump only


def function_head(name: str, params: str, used: set[str], marks: bool) -> list[str]:
    """`def` of a generated function: the containers its code names (bM, wD ... ; R: the
    writer stamps) are parameters whose defaults are the containers (G_<name>), so a call
    binds them without a global load each (engine.Scanner sets the defaults again when the
    machine replaces a container); `now` is read per call. A local the function takes from
    a container is called as the container without its G_ prefix."""
    names = sorted(used - {"now"}) + (["R"] if marks else [])
    params += "".join(f", {n}=G_{n}" for n in names)
    return [f"def {name}({params}):"] + (["    now = m.now_us"] if "now" in used else [])


class _Body:
    """The code of one block (_Gen.block): lines at depth >= 1 and their steps."""

    __slots__ = ("lines", "linemap", "used", "marks", "first")

    def __init__(self, lines: list[str], linemap: list[int], used: set[str], marks: bool, first: int):
        self.lines, self.linemap, self.used, self.marks, self.first = lines, linemap, used, marks, first


class _Layout:
    """Blocks laid out into functions F<r>(m, ws, ex, jb), each a run of consecutive blocks
    (a region) entered at block jb: `while True:` around one `if jb <= k:` section per block,
    so control falls from block to block, a forward jump sets jb and falls through the
    sections before its target, a backward one sets jb and continues the loop, and a CALL
    calls its subroutine's function directly. Each section counts its block first: `ex`
    (steps this scan, for the watchdog: a block that would pass the limit returns -2-k to
    the driver, which runs it on the interpreter) and the stamp `ws` (one per block
    execution, Writers). A function returns the next block to the driver (engine.Scanner),
    -1 at the end of the scan, with the stamp and steps reached in LX.

    A region ends after a block that never falls through (FEND, END, SRET: what follows is
    a subroutine or another entry) and at REGION_LINES / REGION_BLOCKS."""

    def __init__(self, bodies: list[_Body], steps: list[int], last_ops: list[str]):
        self.bodies, self.steps = bodies, steps
        self.region_of: list[int] = []
        self.regions: list[tuple[int, int]] = []
        lo, size = 0, 0
        for k, body in enumerate(bodies):
            size += len(body.lines)
            self.region_of.append(len(self.regions))
            if last_ops[k] in _NO_FALL or size >= REGION_LINES or k + 1 - lo >= REGION_BLOCKS \
                    or k + 1 == len(bodies):
                self.regions.append((lo, k + 1))
                lo, size = k + 1, 0
        # subroutines of one block, small: their code goes where they are called
        self.inline = {k for k, body in enumerate(bodies)
                       if last_ops[k] == "sret" and len(body.lines) <= INLINE_LINES
                       and [t.lstrip() for t in body.lines if t.lstrip().startswith("\0")] == [_SRET]}
        self.funcs = [f"F{r}" for r in self.region_of]
        self.lines: list[str] = []
        self.linemap: list[int] = []
        for r, (lo, hi) in enumerate(self.regions):
            self.function(r, lo, hi)

    def function(self, r: int, lo: int, hi: int) -> None:
        lines, linemap, bodies = self.lines, self.linemap, self.bodies
        first = bodies[lo].first
        parts = bodies[lo:hi] + [bodies[t] for t in self.called(lo, hi) if t in self.inline]
        used = set().union(*(b.used for b in parts))
        out = function_head(f"F{r}", "m, ws, ex, jb", used, any(b.marks for b in parts)) + ["    a = False",
                                                                                           "    while True:"]
        lines += out
        linemap += [first] * len(out)
        for k in range(lo, hi):
            lines.append(f"        if jb <= {k}:")
            linemap.append(bodies[k].first)
            self.section(k, "            ", lambda mark, indent, k=k: self.transfer(mark, indent, k, lo, hi))
        lines.append(f"        LX[0] = ws; LX[1] = ex; return {hi}")  # (every path has left before)
        linemap.append(bodies[hi - 1].first)

    def called(self, lo: int, hi: int) -> set[int]:
        """Blocks the CALLs of region [lo, hi) call."""
        return {int(t.lstrip()[len(_CALL):].split()[0]) for b in self.bodies[lo:hi] for t in b.lines
                if t.lstrip().startswith(_CALL)}

    def section(self, k: int, indent: str, transfer) -> None:
        """Block k's code at `indent`: its steps and stamp counted, then its body with its
        control transfers resolved by `transfer`."""
        body, n, at = self.bodies[k], self.steps[k], self.bodies[k].first
        self.lines += [f"{indent}ex += {n}",
                       f"{indent}if ex > WD: LX[0] = ws; LX[1] = ex - {n}; return {-2 - k}",
                       f"{indent}ws += 1"]
        self.linemap += [at] * 3
        for text, step in zip(body.lines, body.linemap):
            inner = indent + text[4:]  # body lines are at depth >= 1
            if text.lstrip().startswith("\0"):
                at_indent = inner[:len(inner) - len(text.lstrip())]
                for t in transfer(text.lstrip(), at_indent):
                    self.lines.append(at_indent + t)
                    self.linemap.append(step)
            else:
                self.lines.append(inner)
                self.linemap.append(step)

    def transfer(self, mark: str, indent: str, k: int, lo: int, hi: int) -> list[str]:
        """The statements of a goto()/CALL line of block k laid out in region [lo, hi) (an
        inlined subroutine: written at `indent` here)."""
        if mark.startswith(_CALL):
            target, ret = (int(x) for x in mark[len(_CALL):].split())
            if target in self.inline:  # its SRET returns here (the CALL pushed this return)
                self.section(target, indent, lambda mark, indent: ["m.calls.pop()"])
                return []
            return [f"rb = F{self.region_of[target]}(m, ws, ex, {target}); ws = LX[0]; ex = LX[1]",
                    f"if rb != {ret}: return rb"]
        target = mark[len(_GOTO):]
        if not target.lstrip("-").isdigit():  # known at run time only
            return [f"LX[0] = ws; LX[1] = ex; return {target}"]
        t = int(target)
        if t == k + 1 and t < hi:
            return ["pass"]
        if lo <= t <= k:
            return [f"jb = {t}; continue"]
        if k < t < hi:
            return [f"jb = {t}"]
        return [f"LX[0] = ws; LX[1] = ex; return {t}"]
