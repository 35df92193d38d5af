"""The compiled engine's code for word, timer, counter and float instructions: a mixin of
compile._Gen (its output, device-expression and writer-record helpers are the core's)."""

from __future__ import annotations

import math

from mlctool.sim.decode import Step
from mlctool.sim.engines.codegen import _ARITH, _FHI, _FL, _FLOAT, _fold, _fold_float, _word
from mlctool.sim.operands import ConstRef, GroupRef, WordRef
from mlctool.sim.state import F32_QUIET_NAN, bits_f32, f32_bits, to_f32


class OpsCode:
    """TMR, CNT, MOV/ADD/SUB/INC/DEC/CML/WAND/WOR/WXOR (16 and 32-bit), MUL, FADD/FSUB/FMUL."""

    def tmr(self, s: Step) -> None:
        """semantics.tmr and advance_timer inline for a plain timer with a K or plain D preset."""
        i = s.index
        t, pre = s.ops
        target = self.prog.target
        preset = self.preset(pre, self.timer_range, 0, 0)
        if t.ix is not None or preset is None or target.timer_base(t.num).get("retentive"):
            self.reference(s)
            return
        n = t.num
        base = target.timer_base_ms(n) * 1000
        wt, bt, tr, tl, tf, tp, ts = (self.use(x) for x in ("wT", "bT", "tr", "tl", "tf", "tp", "ts"))
        self.use("now")
        self.direct(("T", n), i)
        self.bit_written("T", n)
        self.emit(f"{ts}[{n}] = 1", i)
        self.emit("if a:", i)
        if preset.isdigit():  # a constant preset: a literal where it is used
            pr = preset
            self.emit(f"{self.mark({('T', n): i})}; {tp}[{n}] = {pr}", i, 2)
        else:
            pr = "pr"
            self.emit(f"{self.mark({('T', n): i})}; pr = {preset}; {tp}[{n}] = pr", i, 2)
        self.emit(f"if {tr}[{n}]:", i, 2)
        # less than one time base since the last update (most scans): only the fraction moves
        self.emit(f"d = now - {tl}[{n}] + {tf}[{n}]; {tl}[{n}] = now", i, 3)
        self.emit(f"if 0 <= d < {base}: {tf}[{n}] = d", i, 3)
        self.emit("else:", i, 3)
        self.emit(f"q, {tf}[{n}] = divmod(d, {base})", i, 4)
        self.emit(f"v = {wt}[{n}]", i, 4)
        self.emit(f"if v < {pr}:", i, 4)
        self.emit(f"v += q; {wt}[{n}] = v if v < {pr} else {pr}", i, 5)
        self.emit("else:", i, 2)
        self.emit(f"{tr}[{n}] = 1; {tl}[{n}] = now; {tf}[{n}] = 0", i, 3)
        self.emit(f"{bt}[{n}] = {wt}[{n}] >= {pr}", i, 2)  # a bool stores 1/0 in the bytearray
        self.emit("else:", i)
        self.emit(f"{wt}[{n}] = 0; {bt}[{n}] = 0; {tr}[{n}] = 0; {tf}[{n}] = 0", i, 2)

    def word_op(self, s: Step) -> None:
        op, i = s.ins.spec.op, s.index
        ops = s.ops
        mask = "65535" if s.width == 16 else "4294967295"
        if op == "mov":
            dst, di = ops[1], 1
        elif op in ("inc", "dec"):
            dst, di = ops[0], 0
        elif op == "cml":
            dst, di = ops[1], 1
        else:
            dst, di = ops[2], 2
        if not self.storable(dst) or not all(self.readable(r) for k, r in enumerate(ops) if k != di):
            self.reference(s)
            return
        keys = self.store_keys(dst)
        self.cond(keys, i, ("V", "Z") if dst.kind == "V" else (dst.kind,))
        masked = False
        if op == "mov":
            src = self.value(ops[0], i, 0, 2, unsigned=True)
            masked = s.width == 16 and (_word(ops[0]) and (ops[0].width == 16 or ops[0].kind == "Z")
                                        or type(ops[0]) is ConstRef
                                        or type(ops[0]) is GroupRef and ops[0].n <= 16)  # unsigned read
        elif op in ("inc", "dec"):
            src = f"({self.value(ops[0], i, 0, 2, unsigned=True)} {'+' if op == 'inc' else '-'} 1)"
        elif op == "cml":
            src = f"(~{self.value(ops[0], i, 0, 2, unsigned=True)} & {mask})"
        else:
            pairs = [self.pair(r) for r in ops[:2]] if s.width == 32 and self.pair(dst) else None
            if pairs and all(pairs) and not all(w.isdigit() for p in pairs for w in p):
                self.pair_op(op, pairs, dst, keys, i)
                return
            src = (f"({self.value(ops[0], i, 0, 2, unsigned=True)} {_ARITH[op]} "
                   f"{self.value(ops[1], i, 1, 2, unsigned=True)})")
        self.store(dst, src, s, di, masked)

    def pair(self, ref) -> tuple[str, str] | None:
        """The low and high words of a 32-bit constant or plain register pair (not V:Z)."""
        if type(ref) is ConstRef and ref.ix is None:
            v = ref.get(None) & 0xFFFFFFFF
            return str(v & 0xFFFF), str(v >> 16)
        if _word(ref) and ref.ix is None and ref.kind not in ("V", "Z") and ref.num + 1 <= ref.hi:
            return self.known_word((ref.kind, ref.num)), self.known_word((ref.kind, ref.num + 1))
        return None

    def pair_op(self, op: str, pairs: list[tuple[str, str]], dst, keys, i: int) -> None:
        """A 32-bit add, subtract or logic operation word by word: the low words' carry or
        borrow (v >> 16, floor division for a borrow) goes into the high word; Python ints
        stay below 2^30 (no multi-digit ints, unlike the 32-bit value)."""
        (alo, ahi), (blo, bhi) = pairs
        sym = _ARITH[op]
        arr = self.use("w" + dst.kind)
        lo, hi = f"{arr}[{dst.num}]", f"{arr}[{dst.num + 1}]"
        if op in ("add", "sub"):
            # both words are read before either is stored (the pairs may overlap); the carry
            # or borrow and the wrap by compares and +/- (CPython specialises these for ints,
            # not the shifts and masks)
            self.emit(f"v = {alo} {sym} {blo}; h = {ahi} {sym} {bhi}", i, 2)
            if op == "add":
                self.emit(f"if v < 65536: {lo} = v", i, 2)
                self.emit(f"else: {lo} = v - 65536; h += 1", i, 2)
                self.emit(f"{hi} = h if h < 65536 else h - 65536", i, 2)
            else:
                self.emit(f"if v >= 0: {lo} = v", i, 2)
                self.emit(f"else: {lo} = v + 65536; h -= 1", i, 2)
                self.emit(f"{hi} = h if h >= 0 else h + 65536", i, 2)
        else:
            self.emit(f"v = {alo} {sym} {blo}; h = {ahi} {sym} {bhi}", i, 2)
            self.emit(f"{lo} = v & 65535; {hi} = h & 65535", i, 2)
        self.learn(keys, None)
        self.gwrite(keys, i)

    def words_keys(self, ref, count: int) -> list[tuple[str, int]] | None:
        """Writer keys of `count` consecutive words from a plain D/T operand (set_words)."""
        if type(ref) is WordRef and ref.ix is None and ref.kind in ("D", "T") \
                and ref.num + count - 1 <= ref.hi:
            return [(ref.kind, ref.num + k) for k in range(count)]
        return None

    def mul(self, s: Step) -> None:
        """semantics.mul: the product in 2 (16-bit) or 4 (32-bit) words from D."""
        i = s.index
        count = 2 if s.width == 16 else 4
        keys = self.words_keys(s.ops[2], count)
        if keys is None or not all(type(r) is ConstRef and r.ix is None or _word(r) and r.ix is None
                                   for r in s.ops[:2]):
            self.reference(s)
            return
        x, y = self.value(s.ops[0], i, 0), self.value(s.ops[1], i, 1)
        if "(m)" in x + y:
            self.reference(s)
            return
        arr = self.use("w" + s.ops[2].kind)
        self.cond(keys, i)
        x, y = self.value(s.ops[0], i, 0, 2), self.value(s.ops[1], i, 1, 2)  # constants folded in
        c = _fold(f"{x} * {y}")
        if c is not None:
            words = [(c >> (16 * k)) & 0xFFFF for k in range(len(keys))]
            self.emit("; ".join(f"{arr}[{key[1]}] = {words[k]}" for k, key in enumerate(keys)), i, 2)
        else:
            words = None
            parts = [f"{arr}[{key[1]}] = (v >> {16 * k}) & 65535" if k else f"{arr}[{key[1]}] = v & 65535"
                     for k, key in enumerate(keys)]
            self.emit(f"v = {x} * {y}; " + "; ".join(parts), i, 2)
        self.learn(keys, words)
        self.gwrite(keys, i)

    def preset(self, pre, rng, floor: int, outside: int) -> str | None:
        """A timer or counter preset as semantics.tmr/cnt take it from a K or plain D operand:
        at least `floor` (its 16-bit value), and `outside` when the signed value is outside the
        target's range; None: another operand, or a range the unsigned word cannot test."""
        if type(pre) is ConstRef and pre.ix is None:
            v = pre.get(None)
            return str(outside if rng and not rng[0] <= v <= rng[1] else max(v & 0xFFFF, floor))
        if not (type(pre) is WordRef and pre.ix is None and pre.kind == "D"):
            return None
        word = f"{self.use('wD')}[{pre.num}]"
        if rng is None:
            return f"max({word}, {floor})" if floor else word
        if not 0 <= rng[0] <= rng[1] <= 32767:
            return None
        # in range as a signed value <=> in range as the unsigned word (negative words > 32767)
        p = f"max(p, {floor})" if floor > rng[0] else "p"
        return f"({p} if {rng[0]} <= (p := {word}) <= {rng[1]} else {outside})"

    def cnt(self, s: Step) -> None:
        """semantics.cnt for a 16-bit counter with a K or plain D preset."""
        i = s.index
        c, pre = s.ops
        preset = self.preset(pre, self.counter_range, 1, 1)
        if c.ix is not None or c.num >= self.c32_lo or preset is None:
            self.reference(s)
            return
        n = c.num
        e, cv, bc = self.use("bE"), self.use("cv"), self.use("bC")
        self.direct(("C", n), i)
        if type(pre) is ConstRef:
            pr = preset
        else:
            pr = "pr"
            self.emit(f"pr = {preset}", i)
        # a rising rung counts below the preset; the edge memory follows the rung
        self.emit("if a:", i)
        self.emit(f"if not {e}[{i}]:", i, 2)
        self.emit(f"{e}[{i}] = 1; v = {cv}[{n}]", i, 3)
        self.emit(f"if v < {pr}:", i, 3)
        self.emit(f"{cv}[{n}] = v + 1; {self.mark({('C', n): i})}", i, 4)
        self.emit(f"elif {e}[{i}]:", i)
        self.emit(f"{e}[{i}] = 0", i, 2)
        self.emit(f"if {cv}[{n}] >= {pr} and not {bc}[{n}]:", i)
        self.emit(f"m.c_pending[{n}] = 1", i, 2)

    def fvalue(self, ref, i: int, j: int) -> str | None:
        """An expression for the single-precision float `_float` computes from an operand
        (None: not inlined): a constant as a literal; a D pair (plain or index-modified) as
        FB[hi] + FS[hi] * lo from its two words (engine._f32_tables: exact, struct-free; the
        high word in a local first unless it is a known constant). Index-modified pairs emit
        their address first (faults in operand order, as Ref.getf)."""
        if type(ref) is ConstRef and ref.ix is None:
            x = to_f32(ref.getf(None))
            return repr(x) if math.isfinite(x) else None
        if not (_word(ref) and ref.kind == "D"):
            return None
        if ref.ix is None:
            if ref.num + 1 > ref.hi:
                return None
            lo, hi = (self.known_word(("D", n)) for n in (ref.num, ref.num + 1))
        else:
            n = self.index(ref, i, j, 2, 2)
            arr = self.use("wD")
            lo, hi = f"{arr}[{n}]", f"{arr}[{n} + 1]"
        fb, fs = self.use("FB"), self.use("FS")
        if lo.isdigit() and hi.isdigit():
            x = bits_f32(int(hi) << 16 | int(lo))
            if math.isfinite(x):
                return repr(x)
        elif not hi.isdigit():
            h = self.new_tmp("fh")
            self.emit(f"{h} = {hi}", i, 2)
            hi = h
        return f"({fb}[{hi}] + {fs}[{hi}] * {lo})"

    def known_word(self, key: tuple[str, int]) -> str:
        """A word of the open group: the constant it was set to, or its read."""
        return repr(self.known[key]) if key in self.known else f"{self.use('w' + key[0])}[{key[1]}]"

    def float_op(self, s: Step) -> None:
        """FADD/FSUB/FMUL (semantics._float): operands and result in single precision."""
        i = s.index
        dst = s.ops[2]
        keys = self.words_keys(dst, 2) if type(dst) is WordRef and dst.kind == "D" else None
        if keys is None or not all(type(r) is ConstRef and r.ix is None and math.isfinite(to_f32(r.getf(None)))
                                   or _word(r) and r.kind == "D" and (r.ix is not None or r.num + 1 <= r.hi)
                                   for r in s.ops[:2]):
            self.reference(s)
            return
        self.cond(keys, i)
        x, y = self.fvalue(s.ops[0], i, 0), self.fvalue(s.ops[1], i, 1)
        arr = self.use("wD")
        lo, hi = f"{arr}[{dst.num}]", f"{arr}[{dst.num + 1}]"
        sym = _FLOAT[s.ins.spec.op]
        c = _fold_float(f"{x} {sym} {y}")
        if c is not None:  # constants (and known words): the stored pattern is known
            bits = f32_bits(c) if c == c else F32_QUIET_NAN
            words = [bits & 0xFFFF, bits >> 16]
            self.emit(f"{lo} = {words[0]}; {hi} = {words[1]}", i, 2)
            self.learn(keys, words)
            self.gwrite(keys, i)
            return
        # a NaN result stores the quiet NaN (semantics._float); any other goes through the
        # float buffer (FM: rounded to single precision as f32_bits rounds) and out as two words
        self.emit(f"r = {x} {sym} {y}", i, 2)
        self.emit(f"if r != r: {lo} = {F32_QUIET_NAN & 0xFFFF}; {hi} = {F32_QUIET_NAN >> 16}", i, 2)
        self.emit(f"else: {self.use('FM')}[0] = r; {lo} = {self.use('FH')}[{_FL}]; {hi} = FH[{_FHI}]", i, 2)
        self.learn(keys, None)
        self.gwrite(keys, i)
