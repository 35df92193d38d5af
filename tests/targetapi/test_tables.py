"""The nc5 target tables checked against the manual's own text.

The manual (a text conversion of the PDF) is parsed here independently of mlctool:
- 2.1 basic-instruction tables (mnemonic, operand kinds, steps, "1~2" entries),
- 2.2 per-instruction operand rows (X Y M A T C D V、Z with bullets),
- 3.1 application-instruction summary (API, 16/32-bit names, operand count, steps),
- 3.5 alphabetical index (API and names),
- chapter 4 pages: the operand `*` tables and the "(n STEPS)" lines.
Every mnemonic of the target must appear there with the same facts, and vice versa.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from mlctool.check import check_texts
from mlctool.syntax.source import decode
from mlctool.targetapi import load_target

MANUAL = Path(__file__).resolve().parents[3] / "shared" / "manuals" / "000_a33d4a328dc57a96.txt"

pytestmark = pytest.mark.skipif(not MANUAL.is_file(), reason=f"manual text not found at {MANUAL}")

NONE = ("-", "–", "")
COLUMNS = ["X", "Y", "M", "A", "K", "F", "KnX", "KnY", "KnM", "KnA", "T", "C", "D", "V", "Z"]


@pytest.fixture(scope="module")
def t():
    return load_target("nc5")


@pytest.fixture(scope="module")
def lines() -> list[str]:
    return MANUAL.read_text("utf-8").split("\n")


def _section(lines: list[str], start: str, end: str) -> list[str]:
    """Lines from the first line equal to `start` (a heading, not the table of contents) to `end`."""
    i = next(k for k, x in enumerate(lines) if x.strip() == start)
    j = next(k for k in range(i + 1, len(lines)) if lines[k].strip().startswith(end))
    return lines[i:j]


# ------------------------------------------------------------------ 2.1 basic instructions

def parse_2_1(lines):
    """{mnemonic: (operand text, steps text)} from the 2.1 tables."""
    out = {}
    for x in _section(lines, "## 2.1 基本指令一覽表", "## 2.2 基本指令說明"):
        f = x.split("\t")
        if len(f) == 5 and re.fullmatch(r"[A-Z]+", f[0]):
            out[f[0]] = (f[2].strip(), f[4].strip())
    return out


def parse_2_2_operands(lines):
    """{mnemonic: set of kinds with a bullet} from the 2.2 pages' operand rows."""
    sec = _section(lines, "## 2.2 基本指令說明", "# 3")
    out = {}
    page = None
    for k, x in enumerate(sec):
        m = re.match(r"^[#\s]*■\s*([A-Z]+)\s", x)
        if m:
            page = m[1]
        f = x.strip().split("\t")
        if f[:8] == ["X", "Y", "M", "A", "T", "C", "D", "V、Z"] and page:
            row = sec[k + 1].strip().split("\t")
            kinds = set()
            for col, mark in zip(f, row, strict=False):
                if mark.strip() == "•":
                    kinds |= {"V", "Z"} if col == "V、Z" else {col}
            out[page] = kinds
    return out


def test_2_1_lists_every_basic_instruction(t, lines):
    table = parse_2_1(lines)
    assert len(table) == 29  # 11 general, 3 output, 3 timer/counter, 6 edge, 2 pulse, END, 3 other
    for name in table:
        assert name in t.instructions, f"2.1 lists {name}, the target does not"
    basic = {n for n, s in t.instructions.items() if s.api is None}
    # every target instruction without an API number is a 2.1 row
    assert basic <= set(table)


def test_2_1_fixed_steps(t, lines):
    for name, (_ops, steps) in parse_2_1(lines).items():
        spec = t.instructions[name]
        if steps == "1~2":
            continue
        assert not spec.short_steps, name
        assert spec.steps == int(steps), f"{name}: manual 2.1 says {steps} steps, target {spec.steps}"


def test_2_1_one_to_two_steps_are_the_documented_decision(t, lines):
    one_two = [n for n, (_o, s) in parse_2_1(lines).items() if s == "1~2"]
    assert sorted(one_two) == sorted(["LD", "LDI", "AND", "ANI", "OR", "ORI", "OUT", "SET", "RST"])
    assert "short_operand" in t.settings
    for name in one_two:
        spec = t.instructions[name]
        assert spec.short_steps, f"{name} is '1~2' in 2.1 but has no steps_rule = 'short'"
    # the decision is recorded next to the entry (LD carries it; the others share it)
    assert any("1~2" in n for n in t.instructions["LD"].notes)


def _steps_of(t, line: str) -> int:
    src, _ = decode("s.il", (line + "\n").encode())
    prefix = "" if line.split()[0] in ("LD", "LDI") else "LD X0\n"
    src, _ = decode("s.il", (prefix + line + "\nEND\n").encode())
    res = check_texts([src], t)
    ins = [i for i in res.modules[0].instrs if i.line == (2 if prefix else 1)]
    assert ins, res.diagnostics
    return ins[0].steps


@pytest.mark.parametrize("name,short,long", [
    ("LD", "X0", "M20000"), ("LDI", "Y511", "M30000"), ("AND", "M14999", "M15000"),
    ("ANI", "T255", "M60000"), ("OR", "C79", "M39000"), ("ORI", "A511", "M49000"),
    ("OUT", "Y0", "M20000"), ("SET", "M0", "M60000"), ("RST", "D9999", "D10000"),
])
def test_1_to_2_steps_both_cases(t, name, short, long):
    """'1~2' (2.1): 1 step with an operand in target.toml short_operand, else 2."""
    lo = t.settings["short_operand"]
    kind = short[0]
    assert lo[kind][0] <= int(short[1:]) <= lo[kind][1]
    assert not lo[long[0]][0] <= int(long[1:]) <= lo[long[0]][1]
    assert _steps_of(t, f"{name} {short}") == 1
    assert _steps_of(t, f"{name} {long}") == 2


def test_1_to_2_steps_shift_addresses(t):
    # the decision shows in the addresses: W107 flags an export that counted otherwise
    src, _ = decode("a.il", b"0 LD X0\n1 OUT M21000\n3 LD M0\n4 OUT Y0\n5 END\n")
    assert [d.code for d in check_texts([src], t).diagnostics] == []
    src, _ = decode("a.il", b"0 LD X0\n1 OUT M21000\n2 LD M0\n3 OUT Y0\n4 END\n")
    found = [(d.code, d.span.line, d.span.col) for d in check_texts([src], t).diagnostics]
    assert found == [("W107", 3, 1)]  # the one line after OUT M20000, not every one after it


def test_2_1_operand_kinds(t, lines):
    for name, (ops, _s) in parse_2_1(lines).items():
        spec = t.instructions[name]
        if ops in NONE:
            assert spec.operands == (), name
        elif "、" in ops or re.fullmatch(r"[A-Z]", ops):
            kinds = set(ops.split("、"))
            mine = set(spec.operands[0].kinds)
            if name in ("PLS", "PLF"):
                # documented decision (note 10.15): the table's X/T/C outputs are not accepted
                assert mine < kinds and any("10.15" in n or "as PLS" in n for n in spec.notes), name
            else:
                assert mine == kinds, f"{name}: manual {sorted(kinds)}, target {sorted(mine)}"
        elif name == "P":
            assert ops == "P0 ~ P255"
            assert spec.operands[0].kinds == {"P"} and (t.devices["P"].lo, t.devices["P"].hi) == (0, 255)
        else:
            assert name in ("TMR", "CNT", "DCNT"), (name, ops)


def test_2_2_operand_rows_agree_with_2_1(t, lines):
    rows = parse_2_2_operands(lines)
    table = parse_2_1(lines)
    assert len(rows) >= 24
    for name, kinds in rows.items():
        spec = t.instructions[name]
        mine = set(spec.operands[0].kinds) if spec.operands else set()
        if name in ("PLS", "PLF"):
            assert mine < kinds
        else:
            assert mine == kinds, f"2.2 {name}: manual {sorted(kinds)}, target {sorted(mine)}"
        ops = table[name][0]
        assert kinds == (set() if ops in NONE else set(ops.split("、")))


def test_2_2_timer_counter_operands(t, lines):
    sec = _section(lines, "## 2.2 基本指令說明", "# 3")
    forms = {}
    for x in sec:
        m = re.match(r"^([TC])-([KD])\t([TC])(\d+) ~ [TC](\d+) · ([KD])([-+\d,]+) ~ [KD]([-+\d,]+)", x)
        if m:
            forms.setdefault(m[1], []).append(
                (m[2], int(m[4]), int(m[5]), int(m[7].replace(",", "")), int(m[8].replace(",", ""))))
    # TMR, CNT, DCNT: two forms each, in page order
    assert len(forms["T"]) == 2 and len(forms["C"]) == 4
    tmr = t.instructions["TMR"]
    for kind, lo, hi, klo, khi in forms["T"]:
        assert (lo, hi) == (t.devices["T"].lo, t.devices["T"].hi)
        assert kind in tmr.operands[1].kinds
        if kind == "K":
            assert tmr.operands[1].range16 == (klo, khi)
        else:
            assert (klo, khi) == (t.devices["D"].lo, t.devices["D"].hi)
    cnt, dcnt = t.instructions["CNT"], t.instructions["DCNT"]
    (k16, d16, k32, d32) = forms["C"]
    assert cnt.operands[0].devices16 == (k16[1], k16[2]) == (d16[1], d16[2])
    assert dcnt.operands[0].devices32 == (k32[1], k32[2]) == (d32[1], d32[2])
    assert cnt.operands[1].range16 == (k16[3], k16[4])
    assert dcnt.operands[1].range32 == (k32[3], k32[4])
    assert tuple(t.settings["counters16"]) == (k16[1], k16[2])
    assert tuple(t.settings["counters32"]) == (k32[1], k32[2])


# ------------------------------------------------------------------ 3.1 and 3.5

def parse_3_1(lines):
    """[(api, name16, name32, operand count, steps16, steps32)] from the 3.1 table."""
    out = []
    for x in _section(lines, "### 3.1 應用指令一覽表", "### 3.2"):
        f = [c.strip() for c in x.split("\t")]
        k = next((i for i, c in enumerate(f) if re.fullmatch(r"\d\d", c)), None)
        if k is None or len(f) < k + 7:
            continue
        api, n16, n32, count, _func, s16, s32 = f[k:k + 7]
        out.append((int(api), n16, n32, count, s16, s32))
    return out


def parse_3_5(lines):
    out = []
    for x in _section(lines, "### 3.5 指令索引", "(此頁有意留為空白)"):
        f = [c.strip() for c in x.split("\t")]
        k = next((i for i, c in enumerate(f) if re.fullmatch(r"\d\d", c)), None)
        if k is not None and len(f) >= k + 3:
            out.append((int(f[k]), f[k + 1], f[k + 2]))
    return out


def test_3_1_every_api_row(t, lines):
    rows = parse_3_1(lines)
    apis = [r[0] for r in rows]
    # API 00-02, 06-28, 34-69: 62 rows; 03-05 and 29-33 do not exist
    assert len(rows) == 62 and len(set(apis)) == 62
    assert set(apis) == set(range(0, 3)) | set(range(6, 29)) | set(range(34, 70))
    for api, n16, n32, count, s16, s32 in rows:
        for name, steps, width in ((n16, s16, 16), (n32, s32, 32)):
            if name in NONE:
                assert steps in NONE, (api, name, steps)
                continue
            spec = t.instructions.get(name)
            assert spec is not None, f"3.1 API {api:02d} {name} missing from the target"
            assert spec.api == api, f"{name}: manual API {api}, target {spec.api}"
            assert spec.width == width, name
            assert spec.steps == int(steps), f"{name}: manual 3.1 {steps} steps, target {spec.steps}"
            n = 0 if count in NONE else int(count)
            assert len(spec.operands) == n, f"{name}: manual 3.1 {n} operands, target {len(spec.operands)}"
        # no form the manual does not list
        forms = {s.mnemonic for s in t.instructions.values() if s.api == api}
        assert forms == {x for x in (n16, n32) if x not in NONE}, api


def test_3_1_and_2_1_cover_the_target(t, lines):
    listed = {n for r in parse_3_1(lines) for n in r[1:3] if n not in NONE} | set(parse_2_1(lines))
    assert set(t.instructions) == listed


def test_3_5_index_agrees(t, lines):
    index = parse_3_5(lines)
    summary = {r[0]: (r[1], r[2]) for r in parse_3_1(lines)}
    assert len(index) == len(summary)
    dash = str.maketrans("–", "-")
    for api, n16, n32 in index:
        assert tuple(x.translate(dash) for x in summary[api]) == (n16.translate(dash), n32.translate(dash)), api
        for name in (n16, n32):
            if name not in NONE:
                assert t.instructions[name].api == api


def test_no_pulse_or_16_bit_float_forms(t):
    # 3.2.4: every application instruction is continuous; floats are 32-bit only (4.8)
    for name, spec in t.instructions.items():
        assert not (spec.api is not None and name.endswith("P") and name[:-1] in t.instructions), name
        if spec.is_float:
            assert spec.width == 32, name


# ------------------------------------------------------------------ chapter 4 pages

def _role(cell: str) -> str:
    return re.sub(r"\s*<sub>(\d)</sub>\s*", r"\1", cell).strip()


def parse_ch4(lines):
    """{api: {"rows": {role: kinds}, "steps": {mnemonic: n}, "header": bool}} per chapter-4 page."""
    sec = _section(lines, "### ■ API-00 CJ 條件跳躍", "## MLC 特 M、D 命令與功能")
    pages: dict[int, dict] = {}
    apis: list[int] = []
    k = 0
    while k < len(sec):
        x = sec[k]
        m = re.search(r"■\s*API-(\d\d)(?:\s*~\s*(\d\d))?(?:.*API-(\d\d))?", x)
        if m:
            a = int(m[1])
            apis = list(range(a, int(m[2]) + 1)) if m[2] else [a] + ([int(m[3])] if m[3] else [])
            for a in apis:
                pages[a] = {"rows": {}, "steps": {}, "header": False, "line": k}
        f = [c.strip() for c in x.split("\t")]
        if "KnX" in f and "X" in f and apis:
            cols = {i: c for i, c in enumerate(f) if c}
            assert [cols[i] for i in sorted(cols)] == COLUMNS
            rows = {}
            k += 1
            while k < len(sec) and sec[k].strip():
                r = sec[k].split("\t")
                rows[_role(r[0])] = {cols[i] for i, c in enumerate(r) if c.strip() == "*"}
                k += 1
            for a in apis:
                pages[a]["rows"] = rows
                pages[a]["header"] = True
            continue
        s = re.match(r"(16|32) 位元指令：(\S+?)\s*連續執行型 \((\d+) STEPS?\)", x)
        if s and apis:
            for a in apis:
                pages[a]["steps"][s[2]] = int(s[3])
        k += 1
    return pages


CMP = {"=": 0, ">": 1, "<": 2, "<>": 3, "<=": 4, ">=": 5}


def test_ch4_has_a_page_for_every_api(t, lines):
    pages = parse_ch4(lines)
    apis = {s.api for s in t.instructions.values() if s.api is not None} - {35, 36, 37, 38}
    assert set(pages) == apis
    assert all(p["header"] for p in pages.values())


def test_ch4_page_steps(t, lines):
    pages = parse_ch4(lines)
    checked = 0
    for api, page in pages.items():
        for name, steps in page["steps"].items():
            if "※" in name:  # LD※ / DLD※ pages: the 6 comparisons of this API
                base = [s for s in t.instructions.values() if s.api == api]
                spec = next(s for s in base if s.mnemonic.startswith(name.replace("※", "")) and
                            s.mnemonic[len(name) - 1:] in CMP)
            else:
                if t.instructions.get(name) is None or t.instructions[name].api != api:
                    continue  # the MOV page also lists FMOV (API 67), checked on its own key
                spec = t.instructions[name]
            assert spec.steps == steps, f"{spec.mnemonic}: page says {steps} steps, target {spec.steps}"
            checked += 1
    assert checked >= 90


def _target_roles(spec) -> dict[str, set[str]]:
    return {o.role: set(o.kinds) for o in spec.operands}


# pages whose `*` table is empty in the text; what the target decided instead
EMPTY_TABLE = {0: {"S": {"P"}}, 1: {"S": {"P"}}, 7: {"S": {"K", "D"}}}


def test_ch4_operand_tables(t, lines):
    """Each API page's `*` table (note: [TABLE] facts) equals the target's operand kinds."""
    pages = parse_ch4(lines)
    for api, page in sorted(pages.items()):
        specs = [s for s in t.instructions.values() if s.api == api]
        assert specs, api
        for spec in specs:
            mine = _target_roles(spec)
            rows = page["rows"]
            if api in EMPTY_TABLE:
                assert all(not v for v in rows.values()), f"API {api}: table no longer empty"
                assert mine == EMPTY_TABLE[api], spec.mnemonic
                continue
            assert list(mine) == list(rows), f"{spec.mnemonic}: roles {list(mine)} vs manual {list(rows)}"
            assert mine == rows, f"{spec.mnemonic} (API {api}): target {mine}, manual {rows}"


def test_for_decision_is_recorded(t):
    assert any("K" in n and "table" in n for n in t.instructions["FOR"].notes)
    assert any("P" in s for s in t.instructions["CJ"].section.split()) or t.instructions["CJ"].operands[0].kinds == {"P"}


def test_ch4_z_notes_match_device_table(t, lines):
    """'S、D 運算元若使用 Z 裝置僅可使用 16 位元指令' appears on pages; Z is width16_only."""
    text = "\n".join(lines)
    assert text.count("若使用 Z 裝置僅可使用 16 位元指令") >= 10
    assert t.devices["Z"].width16_only


def test_ch4_fixed_ranges(t, lines):
    text = "\n".join(lines)
    # ROR/ROL n = K1-K16 / K1-K32
    assert "n = K1 ~ K16 (16 位元) · n = K1 ~ K32 (32 位元)" in text
    for name in ("ROR", "ROL"):
        o = t.instructions[name].operands[1]
        assert (o.range16, o.range32) == ((1, 16), (1, 32))
    # BON n = 0-15 / 0-31
    assert "n = 0 ~ 15 (16 位元指令)。n = 0 ~ 31 (32 位元指令)" in text
    o = t.instructions["BON"].operands[2]
    assert (o.range16, o.range32) == ((0, 15), (0, 31))
    # VRT n = 1-6
    assert "n：來源裝置數量 (n = 1 ~ 6)" in text
    assert t.instructions["VRT"].operands[1].range16 == (1, 6)
    # DECO/ENCO n
    assert "D 運算元為字元裝置時，n 運算元範圍 n = 1 ~ 4" in text
    for name in ("DECO", "ENCO"):
        o = t.instructions[name].operands[2]
        assert o.range16 == (1, 8) and o.word_range == (1, 4)
    # FCMP D occupies 3 points
    assert "D 運算元會佔用連續 3 點" in text
    assert t.instructions["FCMP"].operands[2].bits == 3
    # FOR N = K1-K32,767; nesting 5; CALL nesting 5
    assert "巢串式 FOR ~ NEXT 迴路最多可使用 5 層" in text
    assert t.settings["for_depth"] == 5 and t.settings["call_depth"] == 5


# ------------------------------------------------------------------ devices (1.1.1, 1.1.2)

def test_1_1_1_device_ranges(t, lines):
    sec = _section(lines, "### 1.1.1 MLC 中所有裝置的範圍與個數", "## 1.1.2")
    found = {}
    kind = None
    for x in sec:
        f = [c.strip() for c in x.split("\t")]
        k = next((i for i, c in enumerate(f) if re.fullmatch(r"[XYMATCDVZP]", c)), None)
        if k is not None:
            kind = f[k]
        for c in f:
            m = re.fullmatch(r"(\d+) ~ (\d+)", c)
            if m and kind and (int(m[2]) != 65535 or kind in "MD"):
                lo, hi = int(m[1]), int(m[2])
                a, b = found.get(kind, (lo, hi))
                found[kind] = (min(a, lo), max(b, hi))
    assert set(found) == set("XYMATCDVZP")
    for kind, (lo, hi) in found.items():
        assert (t.devices[kind].lo, t.devices[kind].hi) == (lo, hi), kind


def test_1_1_2_areas(t, lines):
    """The X/Y/M/D area maps of 1.1.2 equal devices.toml areas, with their write class."""
    sec = _section(lines, "## 1.1.2 MLC 中各部裝置設定一覽表", "## 1.2")
    checked = 0
    for prev, x in zip(sec, sec[1:], strict=False):
        f = x.split("\t")
        names = prev.split("\t")
        for i, c in enumerate(f):
            m = re.fullmatch(r"([XYMD])(\d+) ~ \1(\d+)", c.strip())
            if not m:
                continue
            dev = t.devices[m[1]]
            lo, hi = int(m[2]), int(m[3])
            area = dev.area(lo)
            assert area is not None and (area.lo, area.hi) == (lo, hi), f"{m[0]}: target has {area}"
            name = names[i] if i < len(names) else ""
            if "保留" in name or "未定義" in name:
                assert area.write == "reserved", m[0]
            elif re.search(r"\b(NC|HMI)\b", name):
                # the special M/D of ch. 5: who writes each number is the signal table's
                # (signals.tsv, check/signals.py), not the area's
                assert area.write == "signals", m[0]
            else:
                assert area.write == "ok", m[0]
            assert area.latched == ("斷電保持" in name), m[0]
            checked += 1
    assert checked == 5 + 4 + 12 + 12
    # and nothing else: the areas of X, Y, M, D are exactly these
    assert sum(len(t.devices[k].areas) for k in "XYMD") == checked


def test_timer_bases(t, lines):
    assert "T0 ~ T199 (單位：100 ms) T200 ~ T255 (單位：10 ms)" in "\n".join(lines)
    assert t.timer_base_ms(0) == t.timer_base_ms(199) == 100
    assert t.timer_base_ms(200) == t.timer_base_ms(255) == 10
