"""Run a folder of real programs (vendor exports and projects) through import -> check -> build ->
ladder -> sim and print one table row per file (docs/formats.md shows two runs).

    python tools/run_corpus.py FOLDER [--target vs] [--scans 100] [--markdown]

If FOLDER holds `manifest.tsv` (tab-separated: file, repository, commit, path; one row per file,
`#` lines and a first row naming those columns ignored), only the files it lists are run and
each row cites where the file came from, so a table over public programs can name its sources
without the files being committed. Otherwise every file with a known suffix is run.

Each file is imported with `mlc import` (format recognised, or refused with its code); the IL
then goes through `mlc check`, `mlc build` (with a listing: the built program's steps), `mlc
ladder` and `mlc sim` (with FILE's stem .stim beside it as the stimulus if there is one, else
`--scans` scans with no stimulus: the program runs, nothing is asserted). Columns: the format
the import recognised, the CPU the export names (GX CSV exports; "-" where the format names
none), the instructions imported and the built program's steps, the steps column saying whether
the export's own step numbers (a .gxw: its stored widths; a .wpg: those and the NOP fill after
END, W916) agree with the built addresses (the import's W107 at the first disagreement; "-"
where the format has none), and per stage "ok" or
the exit code and the diagnostic codes said. Stages after a failed one are not run. The exit code
is 0 whatever the programs do: this is a report.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from mlctool.imports import export_cpu  # noqa: E402  (the CPU row as the importer reads it)

SUFFIXES = (".csv", ".txt", ".il", ".gxw", ".wpg", ".dvp", ".isp", ".pdw", ".ldr")
STAGES = ("import", "check", "build", "ladder", "sim")


def mlc(*args: str, cwd: str) -> tuple[int, str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    r = subprocess.run([sys.executable, "-m", "mlctool", *args], cwd=cwd, capture_output=True, text=True,
                       env=env, timeout=300)
    return r.returncode, r.stdout + r.stderr


def codes(text: str) -> list[str]:
    return sorted(set(re.findall(r"(?:error|warning|note)\[([A-Z][0-9]{3})\]", text)))


def said(code: int, out: str) -> str:
    """ok, with the codes said; or the exit code and the codes."""
    found = " ".join(codes(out))
    return ("ok" if code == 0 else f"exit {code}") + (f" {found}" if found else "")


def cpu_of(path: Path) -> str:
    data = path.read_bytes()[:4096]
    for encoding in ("utf-16", "utf-8", "cp932", "gbk") if data[:2] in (b"\xff\xfe", b"\xfe\xff") else \
            ("utf-8", "cp932", "gbk"):
        try:
            text = data.decode(encoding)
        except UnicodeDecodeError:
            continue
        return export_cpu(text) or "-"
    return "-"


def run_one(path: Path, target: str, scans: int) -> dict[str, str]:
    row = {"file": path.name, "format": "-", "cpu": cpu_of(path) if path.suffix.lower() == ".csv" else "-",
           "size": "-", "steps": "-", **{s: "" for s in STAGES}}
    with tempfile.TemporaryDirectory() as tmp:
        code, out = mlc("import", "--target", target, str(path.resolve()), "-o", "p.il", cwd=tmp)
        found = re.search(r": (\w+) -> p\.il", out)
        row["format"] = found[1] if found else "-"
        row["import"] = said(code, out)
        if code != 0:
            return row
        # gxw: stored widths; pdw: words; wpg: stored widths and the NOP fill to the memory's size (W916)
        if row["format"] in ("gxworks2", "gxdeveloper", "gxw", "winproladder", "wpg"):
            differ = [c for c in ("W107", "W916") if c in codes(out)]
            row["steps"] = f"differ ({' '.join(differ)})" if differ else "equal"
        lines = [ln for ln in Path(tmp, "p.il").read_text(encoding="utf-8").splitlines()
                 if ln.strip() and not ln.lstrip().startswith((".", ";", "//"))]
        row["size"] = f"{len(lines)} instr."
        code, out = mlc("check", "--target", target, "p.il", cwd=tmp)
        row["check"] = said(code, out)
        if code != 0:
            return row
        code, out = mlc("build", "--target", target, "p.il", "-o", "p.mlx", "--listing", "p.lst", cwd=tmp)
        row["build"] = said(code, out)
        if code != 0:
            return row
        built = re.search(r"program for \w+, (\d+) steps", Path(tmp, "p.lst").read_text(encoding="utf-8"))
        if built:
            row["size"] += f" / {built[1]} steps"
        code, out = mlc("ladder", "--target", target, "p.il", "-o", "p.svg", cwd=tmp)
        row["ladder"] = said(code, out)
        if code != 0:
            return row
        stim = path.with_suffix(".stim")
        if stim.is_file():
            code, out = mlc("sim", "--target", target, "p.il", "--stimulus", str(stim.resolve()), cwd=tmp)
            ran = re.search(r"(\d+) passed, (\d+) failed", out)
            row["sim"] = f"{ran[1]} passed, {ran[2]} failed" if ran else said(code, out)
        else:
            code, out = mlc("sim", "--target", target, "p.il", "--scans", str(scans), cwd=tmp)
            row["sim"] = f"{scans} scans" + (f" {' '.join(codes(out))}" if codes(out) else "") if code == 0 \
                else said(code, out)
    return row


def manifest(folder: Path) -> dict[str, tuple[str, str, str]] | None:
    """file -> (repository, commit, path), from FOLDER/manifest.tsv; None without one."""
    listed = folder / "manifest.tsv"
    if not listed.is_file():
        return None
    out = {}
    for n, line in enumerate(listed.read_text(encoding="utf-8").splitlines(), 1):
        if not line.strip() or line.startswith("#"):
            continue
        cells = line.split("\t")
        if len(cells) != 4:
            sys.exit(f"{listed}:{n}: {len(cells)} cells where a row has 4 (file, repository, commit, path)")
        if n == 1 and cells == ["file", "repository", "commit", "path"]:
            continue  # a header row naming the columns
        out[cells[0]] = (cells[1], cells[2], cells[3])
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder")
    ap.add_argument("--target", default="vs")
    ap.add_argument("--scans", type=int, default=100, help="scans to run a program with no .stim (default 100)")
    ap.add_argument("--markdown", action="store_true", help="a Markdown table")
    args = ap.parse_args()
    folder = Path(args.folder)
    sources = manifest(folder)
    if sources is None:
        files = sorted(p for p in folder.rglob("*") if p.suffix.lower() in SUFFIXES and p.is_file()
                       and not p.name.upper().startswith("COMMENT"))
    else:
        files = [folder / name for name in sources]
        if missing := [p.name for p in files if not p.is_file()]:
            sys.exit(f"{folder / 'manifest.tsv'}: listed but not in the folder: {', '.join(missing)}")
    rows = []
    for p in files:
        row = run_one(p, args.target, args.scans)
        if sources is not None:
            repository, commit, path = sources[p.name]
            row = {"repository": repository, "commit": commit, "path": path, **row}
            del row["file"]
        rows.append(row)
    cols = list(rows[0]) if rows else ["file", "format", "cpu", "size", "steps", *STAGES]
    if args.markdown:
        print("| " + " | ".join(cols) + " |")
        print("|" + " --- |" * len(cols))
        for r in rows:
            print("| " + " | ".join((r[c] or "-").replace("|", "\\|") for c in cols) + " |")
    else:
        width = {c: max(len(c), *(len(r[c]) for r in rows)) if rows else len(c) for c in cols}
        print("  ".join(c.ljust(width[c]) for c in cols))
        for r in rows:
            print("  ".join((r[c] or "-").ljust(width[c]) for c in cols))
    reached = {s: sum(1 for r in rows if r[s].startswith("ok") or s == "sim" and r[s] and "exit" not in r[s])
               for s in STAGES}
    print(f"\n{len(rows)} files: " + ", ".join(f"{s} {reached[s]}" for s in STAGES), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
