"""Run a folder of real programs (vendor exports) through import -> check -> build -> ladder ->
sim and print one table row per file (docs/formats.md shows a run).

    python tools/run_corpus.py FOLDER [--target vs] [--markdown]

Each file is imported with `mlc import` (format recognised, or refused with its code); the IL
then goes through `mlc check`, `mlc build`, `mlc ladder` and `mlc sim` (with FILE's stem .stim
beside it as the stimulus if there is one, else 1 s of virtual time). The steps column says
whether the export's own step numbers (a .gxw: its stored step widths) agree with the built
addresses (the import's W107; "-" where the format has none or the dialect's count is not
compared). Stages after a failed one are not run. The exit code is 0 whatever the programs do: this is a report.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

SUFFIXES = (".csv", ".txt", ".il", ".gxw", ".wpg", ".dvp", ".isp", ".pdw", ".ldr")


def mlc(*args: str, cwd: str) -> tuple[int, str]:
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[1]))
    r = subprocess.run([sys.executable, "-m", "mlctool", *args], cwd=cwd, capture_output=True, text=True,
                       env=env, timeout=300)
    return r.returncode, r.stdout + r.stderr


def codes(text: str) -> list[str]:
    return sorted(set(re.findall(r"(?:error|warning|note)\[([A-Z][0-9]{3})\]", text)))


def run_one(path: Path, target: str) -> dict[str, str]:
    row = {"file": path.name, "format": "", "import": "", "steps": "-", "check": "", "build": "", "ladder": "",
           "sim": ""}
    with tempfile.TemporaryDirectory() as tmp:
        code, out = mlc("import", "--target", target, str(path.resolve()), "-o", "p.il", cwd=tmp)
        found = re.search(r": (\w+) -> p\.il", out)
        row["format"] = found[1] if found else ""
        row["import"] = f"exit {code}" + (f" {' '.join(codes(out))}" if codes(out) else "")
        if code != 0:
            return row
        if row["format"] in ("gxworks2", "gxdeveloper", "gxw", "winproladder"):  # gxw: stored widths; pdw: words
            row["steps"] = "differ (W107)" if "W107" in codes(out) else "equal"
        code, out = mlc("check", "--target", target, "p.il", cwd=tmp)
        row["check"] = f"exit {code}" + (f" {' '.join(codes(out))}" if codes(out) else "")
        if code != 0:
            return row
        code, out = mlc("build", "--target", target, "p.il", "-o", "p.mlx", cwd=tmp)
        row["build"] = "ok" if code == 0 else f"exit {code} {' '.join(codes(out))}"
        if code != 0:
            return row
        code, out = mlc("ladder", "--target", target, "p.il", "-o", "p.svg", cwd=tmp)
        row["ladder"] = "ok" if code == 0 else f"exit {code}"
        stim = path.with_suffix(".stim")
        if stim.is_file():
            code, out = mlc("sim", "--target", target, "p.il", "--stimulus", str(stim.resolve()), cwd=tmp)
            said = re.search(r"(\d+) passed, (\d+) failed", out)
            row["sim"] = f"{said[1]} passed, {said[2]} failed" if said else f"exit {code}"
        else:
            code, out = mlc("sim", "--target", target, "p.il", "--until", "1s", cwd=tmp)
            row["sim"] = "ran 1 s" if code == 0 else f"exit {code} {' '.join(codes(out))}"
    return row


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder")
    ap.add_argument("--target", default="vs")
    ap.add_argument("--markdown", action="store_true", help="a Markdown table")
    args = ap.parse_args()
    files = sorted(p for p in Path(args.folder).rglob("*") if p.suffix.lower() in SUFFIXES and p.is_file()
                   and not p.name.upper().startswith("COMMENT"))
    rows = [run_one(p, args.target) for p in files]
    cols = ["file", "format", "import", "steps", "check", "build", "ladder", "sim"]
    if args.markdown:
        print("| " + " | ".join(cols) + " |")
        print("|" + " --- |" * len(cols))
        for r in rows:
            print("| " + " | ".join(r[c] or "-" for c in cols) + " |")
    else:
        width = {c: max(len(c), *(len(r[c]) for r in rows)) if rows else len(c) for c in cols}
        print("  ".join(c.ljust(width[c]) for c in cols))
        for r in rows:
            print("  ".join((r[c] or "-").ljust(width[c]) for c in cols))
    return 0


if __name__ == "__main__":
    sys.exit(main())
