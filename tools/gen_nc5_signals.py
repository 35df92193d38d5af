"""Generate mlctool/targets/nc5/signals.tsv, the NC5's special M/D (the MLC <-> NC and
MLC <-> HMI signals), from the manual's own text plus the decisions below, each citing its
lines, and the English names of tools/nc5_signal_names.toml.

    python3 tools/gen_nc5_signals.py > mlctool/targets/nc5/signals.tsv
    (the manual is found in shared/manuals/ beside the checkout or above it; NC5_MANUAL=path
    names it elsewhere)

Read from the manual (000_a33d4a328dc57a96.txt, chapter 5):
- 5.2.1 (special M) and 5.2.2 (special D): one row per device pattern: name, description,
  裝置類型 R or R/W. `x` in a pattern is the channel digit (1-8);
- 5.3.1-5.3.15: the function groups, which list the same devices again: a row's sections;
- 5.3.16-5.3.19: the NC macro variables of the HMI points and registers (#25000 ...);
- 5.3.20: the EtherCAT rows.
tests/targets/nc5/test_nc5_signals.py counts the manual's rows on its own and regenerates
the file; the two must agree with what is committed.
"""

from __future__ import annotations

import os
import re
import sys
import tomllib
from pathlib import Path

MANUAL_NAME = "000_a33d4a328dc57a96.txt"
NAMES = Path(__file__).resolve().parent / "nc5_signal_names.toml"
COLUMNS = ("device", "name", "english", "direction", "access", "type", "table", "sections", "line",
           "variable", "decision")
DEVICE = re.compile(r"[MD][0-9x]{5}")
# the first digit of a special M/D says who writes it (5.1, L3502)
DIRECTION = {"2": "MLC->NC", "3": "NC->MLC", "4": "MLC->HMI", "5": "HMI->MLC"}
AXES = ["X axis", "Y axis", "Z axis", "A axis", "B axis", "C axis", "U axis", "V axis", "W axis",
        *(f"axis {n}" for n in range(10, 17))]

# Where the manual contradicts itself about a row (notes: shared/notes/nc5_ch5_ch6.md), the
# row as decided: the fields it sets and why. tests/targets/nc5/test_nc5_signals.py holds
# each one.
DECISIONS: dict[str, dict[str, str]] = {
    **{f"M3x00{k}": {"decision": "the mode feedback is M3x000-M3x007 (5.2.1 L3930-L3937, 5.3.1, 6.1's "
                     "own heading L5644); 6.1's table (L5630-L5638) printing M2x288-M2x295 in its "
                     "feedback column is a misprint: those are the synchronous follower relays"}
       for k in range(8)},
    **{f"M2x{n}": {"decision": "a synchronous follower relay (5.2.1 L3707 ff., 5.3.11, 6.15), MLC->NC; "
                   "not the mode feedback 6.1's table (L5630-L5638) prints here"}
       for n in range(288, 296)},
    "M3x016": {"access": "R", "decision": "the 裝置類型 cell is empty (L3940); R like every other "
               "M3x row: the NC sets it while a program runs (5.2.1, 6.2)"},
    "M2x000": {"decision": "cycle start (程式啟動), as 5.2.1 and 5.3.2 name it; 6.2's example "
               "(L5776) calling M21000 【程序執行中】 is a slip: running is M3x016"},
    "M2x010": {"decision": "the block-skip character is '/' (6.2 prose L5730); the name prints "
               "' / ' (L3517) and 5.3.2 prints ( ' ) (L4814)"},
    "M3x357": {"decision": "the C axis (the row describes C's machine coordinate, L4180, and the "
               "axis order X Y Z A B C U V W puts C here); the name prints V, the V axis is M3x359"},
    **{f"M3x{n}": {"decision": "the MLC requests the switch with the same axis's relay of M2x432-M2x447 "
                   "(L4269 ff. say '當 NC 系統透過 M2x432 設 ON': the NC only answers)"} for n in range(432, 448)},
    "D2x024": {"type": "32-bit", "decision": "32-bit: 6.10 gives 0 ~ 2147483647 (L6401) and "
               "D2x025 is no row of its own; 5.2.2 (L4397) does not mark it"},
    "D2x030": {"type": "32-bit", "decision": "32-bit, as D2x024 (6.10 names both, L6397-L6401)"},
    "D3x050": {"type": "32-bit", "decision": "32-bit: the S code it shows is the first spindle's "
               "command, which D3x024 holds in 32 bits (L4619), and S takes D2x024's 0 ~ 2147483647 "
               "(L6401); D3x051 is no row of its own (M, S and T step by two: D3x048, D3x050, "
               "D3x052); 5.2.2 (L4638) does not mark it"},
    **{f"D2x{n}": {"type": "32-bit float", "decision": "a floating-point value in two words (6.14 "
                   "L6823, L6834: 須為浮點數型態數值); 5.2.2 says only 32-bit"}
       for n in range(256, 320, 2)},
    **{f"D4900{k}": {"decision": "R as printed (L4780-L4782): the system writes the time although "
                     "the range is MLC->HMI (5.1); an MLC write fights it"} for k in range(3)},
    **{f"D49x0{k}": {"decision": "the channel is the third digit in the HMI ranges (5.1 L3492-L3500: "
                     "D49100 = channel 1), not the second as L3502 says"} for k in (0, 2)},
    "D49x04": {"decision": "R/W as printed (L4785): the system counts the time, and the MLC may "
               "preset or clear it as it may the part counters"},
    "D49x06": {"decision": "R/W as printed (L4786), as D49x04"},
}


def find_manual() -> Path:
    if os.environ.get("NC5_MANUAL"):
        return Path(os.environ["NC5_MANUAL"])
    for folder in Path(__file__).resolve().parents:
        path = folder / "shared" / "manuals" / MANUAL_NAME
        if path.is_file():
            return path
    raise SystemExit(f"gen_nc5_signals: {MANUAL_NAME} not found in shared/manuals above {__file__}; "
                     "set NC5_MANUAL")


def _sections(lines: list[str]) -> dict[str, tuple[int, int]]:
    """Heading number -> (first line, line after the last) of chapter 5's sections, 0-based."""
    starts = []
    for k, line in enumerate(lines):
        m = re.match(r"#+ (5\.[0-9.]+)\s", line)
        if m and k > 3000:
            starts.append((m[1], k))
        elif line.startswith("# 6") and starts:
            starts.append(("6", k))
            break
    return {name: (k, starts[i + 1][1]) for i, (name, k) in enumerate(starts[:-1])}


def _cells(line: str) -> list[str]:
    return [" ".join(c.split()) for c in line.split("\t")]


def summary_rows(lines: list[str], lo: int, hi: int, table: str) -> list[dict]:
    """The rows of a 5.2 table: 功能名稱 / 特 M or 特 D / 說明 / 裝置類型."""
    out = []
    for k in range(lo, hi):
        cells = _cells(lines[k])
        if len(cells) == 4 and DEVICE.fullmatch(cells[1]):
            name, device, _description, access = cells
            out.append({"device": device, "name": name, "access": access, "table": table, "line": k + 1,
                        "description": _description})
    return out


def function_devices(lines: list[str], lo: int, hi: int, width: int) -> list[tuple[str, str, str]]:
    """(name, device, variable) of a 5.3 table: pairs (name, device) or, width 3, triples
    (name, device, macro variable), two to a line."""
    out = []
    for k in range(lo, hi):
        cells = _cells(lines[k])
        if len(cells) < width:
            continue
        for i in range(0, len(cells) - width + 1, width):
            group = cells[i:i + width]
            if DEVICE.fullmatch(group[1]):
                out.append((group[0], group[1], group[2] if width == 3 else ""))
    return out


def _expand(key: str, order: list[str]) -> list[str]:
    """The patterns a names key covers, in table order."""
    first, _, last = key.partition("-")
    if not last:
        return [first]
    if first not in order or last not in order:
        raise SystemExit(f"gen_nc5_signals: names key {key!r}: {first if first not in order else last} is no row")
    return order[order.index(first):order.index(last) + 1]


def english_names(order: list[str]) -> dict[str, str]:
    table = tomllib.loads(NAMES.read_text("utf-8"))["names"]
    out: dict[str, str] = {}
    for key, template in table.items():
        devices = _expand(key, order)
        for n, device in enumerate(devices, 1):
            if device in out:
                raise SystemExit(f"gen_nc5_signals: {device} is named twice in {NAMES.name}")
            out[device] = template.format(n=n, axis=AXES[n - 1] if n <= len(AXES) else f"axis {n}")
    missing = [d for d in order if d not in out]
    if missing:
        raise SystemExit(f"gen_nc5_signals: no English name for {missing[:10]} in {NAMES.name}")
    return out


def word_type(row: dict) -> str:
    if row["device"][0] == "M":
        return "bit"
    text = row["name"] + " " + row["description"]
    return "32-bit" if "32-bit" in text else "word"


def generate(manual: Path) -> str:
    lines = manual.read_text("utf-8").split("\n")
    sections = _sections(lines)
    rows = summary_rows(lines, *sections["5.2.1"], "5.2.1") + summary_rows(lines, *sections["5.2.2"], "5.2.2")
    by_device = {r["device"]: r for r in rows}
    if len(by_device) != len(rows):
        raise SystemExit("gen_nc5_signals: a device appears twice in 5.2")
    for number in sorted((s for s in sections if s.startswith("5.3.")), key=lambda s: int(s.split(".")[2])):
        width = 3 if number in ("5.3.16", "5.3.17", "5.3.18", "5.3.19") else 2
        for _name, device, variable in function_devices(lines, *sections[number], width):
            row = by_device.get(device)
            if row is None:
                raise SystemExit(f"gen_nc5_signals: {device} of {number} is no row of 5.2")
            if number not in row.setdefault("sections", []):
                row["sections"].append(number)
            if variable:
                if variable not in row["description"]:  # 5.2.1 says it too: 對應變量#25000
                    raise SystemExit(f"gen_nc5_signals: {device}: {number} gives {variable}, 5.2 does not")
                row["variable"] = variable
    english = english_names([r["device"] for r in rows])
    unused = set(DECISIONS) - set(by_device)
    if unused:
        raise SystemExit(f"gen_nc5_signals: decisions for devices that are no row: {sorted(unused)}")
    out = ["# GENERATED by tools/gen_nc5_signals.py from the NC5 manual (" + MANUAL_NAME + ", 5.2.1, 5.2.2,",
           "# 5.3.1-5.3.20) and tools/nc5_signal_names.toml: edit those, then regenerate. One row per",
           "# device pattern; x = the channel (1-8). `line`: the row's line in the manual. `decision`:",
           "# where the manual contradicts itself about the row (DECISION, tested in",
           "# tests/targets/nc5/test_nc5_signals.py).",
           "\t".join(COLUMNS)]
    for row in rows:
        decided = DECISIONS.get(row["device"], {})
        device = row["device"]
        fields = {
            "device": device, "name": row["name"], "english": english[device],
            "direction": DIRECTION[device[1]], "access": decided.get("access", row["access"]),
            "type": decided.get("type", word_type(row)), "table": row["table"],
            "sections": ",".join(row.get("sections", ())), "line": str(row["line"]),
            "variable": row.get("variable", ""),
            "decision": ("DECISION: " + decided["decision"]) if "decision" in decided else "",
        }
        if fields["access"] not in ("R", "R/W"):
            raise SystemExit(f"gen_nc5_signals: {device}: 裝置類型 {row['access']!r} (L{row['line']}) needs a decision")
        out.append("\t".join(fields[c] for c in COLUMNS))
    return "\n".join(out) + "\n"


def main() -> None:
    sys.stdout.reconfigure(encoding="utf-8")
    sys.stdout.write(generate(find_manual()))


if __name__ == "__main__":
    main()
