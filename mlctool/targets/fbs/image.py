"""Register images of a positioning table: CSV and JSON an HMI (or `mlc objdump`) can load.

CSV: a header row `register,value,hex`, then one row per register from SR on, e.g.
`R5000,42330,A55A`; value is the unsigned 16-bit word. JSON: see docs/fbs-positioning.md.
Both are deterministic (no time stamps) so builds can be compared byte for byte.
"""

from __future__ import annotations

import csv
import io
import json
import re
from dataclasses import dataclass

from mlctool.limits import clip, is_decimal, long_number, too_long_message
from mlctool.targets.fbs.model import tables

FORMAT = "mlctool-fbs-table"
VERSION = 1
_SR = re.compile(r"([RD])([0-9]{1,20})", re.IGNORECASE)  # digits bounded as limits.MAX_DIGITS
# SR areas FUN140/FUN147 accept (operand tables: HR R0-R3839, DR D0-D3999, ROR R5000-R8071)
SR_AREAS = {"R": ((0, 3839), (5000, 8071)), "D": ((0, 3999),)}


class ImageError(ValueError):
    pass


@dataclass(frozen=True, slots=True)
class Register:
    kind: str  # R | D
    number: int

    def name(self, offset: int = 0) -> str:
        return f"{self.kind}{self.number + offset}"


def parse_sr(text: str, words: int) -> Register:
    """`R5000` -> Register; the whole table (`words` registers) must lie in one SR area."""
    m = _SR.fullmatch(text.strip())
    if not m:
        raise ImageError(f"--sr {clip(text)!r}: the table starts at a register Rnnnn or Dnnnn")
    kind, n = m[1].upper(), int(m[2])
    for lo, hi in SR_AREAS[kind]:
        if lo <= n and n + words - 1 <= hi:
            return Register(kind, n)
    areas = ", ".join(f"{kind}{lo}-{kind}{hi}" for lo, hi in SR_AREAS[kind])
    raise ImageError(f"--sr {text}: {words} registers from {kind}{n} do not fit in {areas}")


def to_csv(words: list[int], sr: Register) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["register", "value", "hex"])
    for k, v in enumerate(words):
        w.writerow([sr.name(k), v, f"{v:04X}"])
    return buf.getvalue()


def to_json(words: list[int], sr: Register, instruction: str) -> str:
    doc = {
        "format": FORMAT, "version": VERSION, "instruction": instruction,
        "sr": sr.name(), "registers": len(words), "words": words,
        "image": [{"register": sr.name(k), "value": v, "hex": f"{v:04X}"} for k, v in enumerate(words)],
    }
    return json.dumps(doc, indent=1) + "\n"


def _words_checked(values: list, where: str) -> list[int]:
    out = []
    for k, v in enumerate(values):
        if not isinstance(v, int) or isinstance(v, bool) or not 0 <= v <= 0xFFFF:
            raise ImageError(f"{where}: word {k} = {v!r} is not a 16-bit value 0-65535")
        out.append(v)
    return out


def read_image(text: str) -> tuple[list[int], str]:
    """JSON or CSV image text -> (words, SR name). Raises ImageError."""
    stripped = text.lstrip()
    long = long_number(text)
    if long:  # bounded before json/int convert it (mlctool/limits.py)
        line = text.count("\n", 0, long.start()) + 1
        raise ImageError(f"line {line}: " + too_long_message("the image", len(long[0])))
    if stripped.startswith("{"):
        try:
            doc = json.loads(text)
        except json.JSONDecodeError as e:
            raise ImageError(f"not valid JSON (line {e.lineno}: {e.msg})") from None
        if not isinstance(doc, dict) or doc.get("format") != FORMAT or not isinstance(doc.get("words"), list):
            raise ImageError(f"JSON is not an {FORMAT} image (needs format and words)")
        return _words_checked(doc["words"], "words"), str(doc.get("sr", "R0"))
    reader = csv.reader(io.StringIO(text))
    try:
        rows = [r for r in reader if r and any(c.strip() for c in r)]
    except csv.Error as e:  # a field past the csv module's limit (131,072 characters)
        raise ImageError(f"CSV line {reader.line_num}: {e}") from None
    if rows and rows[0][0].strip().lower() == "register":
        rows = rows[1:]
    if not rows:
        raise ImageError("empty register image")
    words, first = [], rows[0][0].strip()
    for k, r in enumerate(rows, start=2):
        if len(r) < 2 or not is_decimal(r[1].strip()):
            raise ImageError(f"CSV row {k}: expected register,value[,hex]")
        words.append(int(r[1].strip()))
    return _words_checked(words, "CSV"), first


def dialect_name(words: list[int]) -> str:
    d = tables().by_header(words[0]) if words else None
    return d.instruction if d else "?"
