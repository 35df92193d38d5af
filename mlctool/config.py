"""Project configuration: `mlc.toml` or `[tool.mlc]` in pyproject.toml, found upward from cwd.

    target = "nc5"
    capacity = 65536          # program capacity override (steps)
    [severity]                # per-code severity: "error" | "warning" | "off"
    W401 = "off"

The file is validated as it is read: an unknown key (`taget`), a value of the wrong type
(`capacity = "big"`), an unknown code in [severity] or an error turned off is E110 at the
key's own line, with the nearest known spelling. tomllib gives no positions, so the keys'
lines come from a small scan of the text (`key_positions`).
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from mlctool.diagnostics import Diagnostic, MlcError, Span, diag
from mlctool.fileio import read_input
from mlctool.limits import long_number, too_long_message
from mlctool.suggest import did_you_mean


@dataclass
class Config:
    target: str | None = None
    capacity: int | None = None
    severity: dict[str, str] = field(default_factory=dict)
    data: dict = field(default_factory=dict)  # the whole table, for other commands (build, test)
    root: Path | None = None
    file: Path | None = None  # mlc.toml or pyproject.toml, as read
    positions: dict[tuple[str, ...], tuple[int, int, int]] = field(default_factory=dict, repr=False)

    def locate(self, *keys: str) -> tuple[str, Span]:
        """Where a key of the configuration is written: (file, span); the nearest enclosing
        table's line when the key itself is not found, line 1 when nothing is."""
        where = str(self.file) if self.file else "mlc.toml"
        prefix = ("tool", "mlc") if self.file is not None and self.file.name == "pyproject.toml" else ()
        for k in range(len(keys), -1, -1):
            found = self.positions.get(prefix + keys[:k])
            if found:
                line, col, length = found
                return where, Span.at(line, col, length)
        return where, Span.at(1)


SEVERITIES = ("error", "warning", "off")


def _is_str(v) -> bool:
    return isinstance(v, str)


def _is_str_list(v) -> bool:
    return isinstance(v, list) and all(isinstance(s, str) for s in v)


def _is_capacity(v) -> bool:
    return isinstance(v, int) and not isinstance(v, bool) and v > 0


def _is_channels(v) -> bool:
    return isinstance(v, int) and not isinstance(v, bool) and 1 <= v <= 8


def _is_table(v) -> bool:
    return isinstance(v, dict)


# FATEK FBs: the pulse output mode of Ps0-Ps3, as the manual spells them (11.6: "務必設定
# Pulse Output 之工作模式 ... 為 U/D，P/R 或 A/B 等三種模式之一"); "" = not set (the Y pins
# stay ordinary outputs). Decision in docs/fbs.md.
PULSE_MODES = ("U/D", "P/R", "A/B", "")


def _is_pulse_modes(v) -> bool:
    return isinstance(v, list) and 1 <= len(v) <= 4 and all(m in PULSE_MODES for m in v)


# key -> (test of the value, what the value must be); docs/project.md lists them
KEYS = {
    "target": (_is_str, 'a target name string (`target = "vs"`)'),
    "model": (_is_str, 'a model name string (`model = "VS1"`)'),
    "capacity": (_is_capacity, "a positive whole number of steps (`capacity = 65536`)"),
    "sources": (_is_str_list, 'a list of path strings (`sources = ["src/main.il"]`)'),
    "tests": (_is_str_list, 'a list of glob strings (`tests = ["tests/*.stim"]`)'),
    "output": (_is_str, "a path string"),
    "listing": (_is_str, "a path string"),
    "map": (_is_str, "a path string"),
    "name": (_is_str, "a string"),
    "encoding": (_is_str, 'an encoding name string (`encoding = "cp950"`)'),
    "symbols": (_is_table, 'a table of NAME = "OPERAND" (`[symbols]`)'),
    "pulse_modes": (_is_pulse_modes, 'a list of 1-4 pulse output modes for Ps0-Ps3, each "U/D", "P/R", '
                    '"A/B" or "" (`pulse_modes = ["A/B", "U/D"]`, fbs target)'),
    "channels": (_is_channels, "a whole number of NC channels 1-8 (`channels = 2`, nc5 target; default 1)"),
    "tables": (_is_str_list, 'a list of "[SR=]FILE" register tables (`tables = ["R5000=tables/home.pos"]`, '
               'fbs target)'),
    "severity": (_is_table, 'a table of CODE = "error" | "warning" | "off" (`[severity]`)'),
    "verify": (lambda v: isinstance(v, dict) and set(v) <= {"properties", "checks"}
               and _is_str_list(v.get("properties", [])) and _is_str_list(v.get("checks", [])),
               'a table with `properties` (globs: `properties = ["tests/*.props"]`) and `checks` (built-in checks: '
               '`checks = ["no-chatter"]`)'),
}


class ConfigError(MlcError):
    """The configuration is wrong: every problem found, with the file's lines to show them."""

    def __init__(self, diagnostics: list[Diagnostic], lines: dict[str, list[str]]):
        super().__init__(diagnostics[0], 2)
        self.diagnostics, self.lines = diagnostics, lines


# ------------------------------------------------------------------ where a key is written

_BARE_OR_QUOTED = r'(?:[A-Za-z0-9_-]+|"[^"\n]*"|\'[^\'\n]*\')'
_DOTTED = rf"{_BARE_OR_QUOTED}(?:\s*\.\s*{_BARE_OR_QUOTED})*"
_TABLE_LINE = re.compile(rf"\s*\[\[?\s*({_DOTTED})\s*\]\]?")
_KEY_LINE = re.compile(rf"\s*({_DOTTED})\s*=")
_PART = re.compile(_BARE_OR_QUOTED)


def _parts(dotted: str) -> tuple[str, ...]:
    return tuple(p.strip("\"'") for p in _PART.findall(dotted))


def key_positions(text: str) -> dict[tuple[str, ...], tuple[int, int, int]]:
    """Every table header and `key =` of a TOML text -> (line, column, length of the key).

    Not a TOML parser: a scan of line starts that skips the insides of multi-line strings,
    enough to point at the line of a key that tomllib has already read."""
    out: dict[tuple[str, ...], tuple[int, int, int]] = {}
    table: tuple[str, ...] = ()
    open_quote = None
    for n, line in enumerate(text.split("\n"), 1):
        if open_quote:
            if line.count(open_quote) % 2:
                open_quote = None
            continue
        m = _TABLE_LINE.match(line)
        if m:
            table = _parts(m.group(1))
            out.setdefault(table, (n, m.start(1) + 1, len(m.group(1))))
            continue
        m = _KEY_LINE.match(line)
        if not m:
            continue
        out.setdefault(table + _parts(m.group(1)), (n, m.start(1) + 1, len(m.group(1))))
        rest = line[m.end():]
        for quote in ('"""', "'''"):
            if rest.count(quote) % 2:
                open_quote = quote
    return out


# ------------------------------------------------------------------ reading and validating

MAX_CONFIG_BYTES = 1024 * 1024


def _read(path: Path) -> tuple[str, dict]:
    try:
        data = read_input(str(path), MAX_CONFIG_BYTES + 1)  # noted as an input: never an output (fileio.py)
    except OSError as e:
        raise MlcError(diag(str(path), Span.at(1), "E100", f"cannot read configuration: {e.strerror or e}")) from e
    if len(data) > MAX_CONFIG_BYTES:
        raise MlcError(diag(str(path), Span.at(1), "E104", f"configuration is more than {MAX_CONFIG_BYTES} bytes"))
    try:
        text = data.decode("utf-8").replace("\r\n", "\n").replace("\r", "\n")  # as text mode reads it
    except UnicodeDecodeError as e:
        raise MlcError(diag(str(path), Span.at(1), "E110", f"configuration is not UTF-8 ({e.reason})")) from e
    try:
        return text, tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        at = re.search(r"at line (\d+), column (\d+)", str(e))
        lines = text.split("\n")
        line, col = (int(at.group(1)), int(at.group(2))) if at else (len(lines), 1)  # "at end of document"
        message = re.sub(r"\s*\(at (line \d+, column \d+|end of document)\)", "", str(e))
        raise ConfigError([diag(str(path), Span.at(line, col), "E110", f"not valid TOML: {message}")],
                          {str(path): lines}) from e
    except ValueError as e:  # tomllib met Python's int-conversion limit (4,300 digits)
        long = long_number(text)
        if long is None:
            raise
        line = text.count("\n", 0, long.start()) + 1
        col = long.start() - text.rfind("\n", 0, long.start())
        raise ConfigError([diag(str(path), Span.at(line, col, len(long[0])), "E110",
                                too_long_message("the value", len(long[0])))],
                          {str(path): text.split("\n")}) from e


def validate(path: str, text: str, table: dict, prefix: tuple[str, ...] = ()) -> list[Diagnostic]:
    """The E110 problems of a configuration table read from `text` (`prefix`: where the
    table sits in the file, ("tool", "mlc") for pyproject.toml)."""
    from mlctool.codes import CODES

    positions = key_positions(text)
    section = "[tool.mlc]" if prefix else Path(path).name

    def at(*keys: str) -> Span:
        for k in range(len(keys), -1, -1):  # the key itself, else the nearest table that holds it
            found = positions.get(prefix + keys[:k])
            if found:
                line, col, length = found
                return Span.at(line, col, length)
        return Span.at(1)

    out: list[Diagnostic] = []
    for key, value in table.items():
        if key not in KEYS:
            out.append(diag(path, at(key), "E110", f"unknown key `{key}` in {section}"
                            + did_you_mean(key, KEYS, "`"),
                            f"known keys: {', '.join(KEYS)} (docs/project.md)"))
            continue
        ok, wanted = KEYS[key]
        if not ok(value):
            out.append(diag(path, at(key), "E110", f"`{key}` must be {wanted}, not {_shown(value)}"))
    severity = table.get("severity")
    if isinstance(severity, dict):
        for code, value in severity.items():
            where = at("severity", code)
            c = CODES.get(code.upper())
            if c is None:
                out.append(diag(path, where, "E110", f"unknown code `{code}` in [severity]"
                                + did_you_mean(code, CODES, "`"), "`mlc explain CODE` documents each code"))
            elif not isinstance(value, str) or value.lower() not in SEVERITIES:
                out.append(diag(path, where, "E110", f"severity of {c.code} must be \"error\", \"warning\" "
                                f"or \"off\", not {_shown(value)}"))
            elif c.severity == "error" and value.lower() != "error":
                out.append(diag(path, where, "E110", f"{c.code} is an error and cannot be "
                                f"{'turned off' if value.lower() == 'off' else 'made a warning'}",
                                "errors say the program is not valid for the target; only warnings "
                                "can be turned off or down (docs/check.md)"))
    target = table.get("target")
    if isinstance(target, str):
        from mlctool.targetapi import available_targets

        names = available_targets()
        if target not in names:
            out.append(diag(path, at("target"), "E110", f"unknown target {target!r}" + did_you_mean(target, names, "'", 0.5),
                            f"available: {', '.join(names)}"))
    return sorted(out, key=Diagnostic.sort_key)


def _shown(value) -> str:
    text = repr(value) if not isinstance(value, (dict, list)) else f"{type(value).__name__} {value!r}"
    return text if len(text) <= 60 else text[:57] + "..."


def _table(path: Path) -> tuple[dict, str] | None:
    text, data = _read(path)
    prefix: tuple[str, ...] = ()
    if path.name == "pyproject.toml":
        tool = data.get("tool")
        data = tool.get("mlc") if isinstance(tool, dict) else None
        if data is None:
            return None
        prefix = ("tool", "mlc")
        if not isinstance(data, dict):
            raise ConfigError([diag(str(path), Span.at(1), "E110", "[tool.mlc] must be a table")],
                              {str(path): text.split("\n")})
    problems = validate(str(path), text, data, prefix)
    if problems:
        raise ConfigError(problems, {str(path): text.split("\n")})
    return data, text


def load_config(start: Path | None = None, explicit: str | None = None) -> Config:
    if explicit:
        candidates = [Path(explicit)]
    else:
        here = (start or Path.cwd()).resolve()
        candidates = []
        for d in (here, *here.parents):
            candidates += [d / "mlc.toml", d / "pyproject.toml"]
    for path in candidates:
        if path.is_file():
            found = _table(path)
            if found is None:
                continue
            table, text = found
            sev = {k.upper(): v.lower() for k, v in table.get("severity", {}).items()}
            return Config(table.get("target"), table.get("capacity"), sev, table, path.parent, path,
                          key_positions(text))
    return Config()


def severity_of(code: str, default: str, config: Config | None, ignore: frozenset[str] = frozenset()) -> str:
    """The severity a diagnostic is shown with: the configured one, "off" when ignored.
    An error (a code whose default is error) stays an error whatever the configuration,
    `--ignore` or a `; mlc: noqa` say: it means the program cannot be built or run."""
    if default == "error":
        return "error"
    if code in ignore:
        return "off"
    return config.severity.get(code, default) if config else default


def rules_dropped(ignore: tuple[str, ...] | list[str], select: tuple[str, ...] | list[str],
                  no_lint: bool = False) -> frozenset[str]:
    """The codes `mlc check --ignore CODE --select W4xx[,W4xx] --no-lint` drop. An unknown code,
    an error in --ignore or a non-lint code in --select is E110 (exit 2), with the nearest code."""
    if not (ignore or select or no_lint):
        return frozenset()  # without reading the codes (codes.toml: a few ms of every check)
    from mlctool.codes import CODES

    lint = {c for c in CODES if c.startswith("W4")}
    where = "<command line>"
    problems = []
    ignored = set()
    for item in ignore:
        for raw in (c.strip() for c in item.split(",")):
            code = raw.upper()
            if not code:
                continue
            c = CODES.get(code)
            if c is None:
                problems.append(diag(where, Span.at(1), "E110", f"--ignore {raw}: unknown code"
                                     + did_you_mean(code, CODES)))
            elif c.severity == "error":
                problems.append(diag(where, Span.at(1), "E110", f"--ignore {c.code}: {c.code} is an error "
                                     "and cannot be ignored", "errors say the program is not valid for the "
                                     "target; only warnings can be ignored (docs/check.md)"))
            else:
                ignored.add(code)
    if no_lint:
        ignored |= lint
    chosen = {c.strip().upper() for item in select for c in item.split(",") if c.strip()}
    for code in sorted(chosen - lint):
        problems.append(diag(where, Span.at(1), "E110", f"--select {code}: {code} is not a lint rule (W4xx)"
                             + did_you_mean(code, lint), f"lint rules: {', '.join(sorted(lint))}"))
    if problems:
        raise ConfigError(problems, {})
    if chosen:
        ignored |= lint - chosen
    return frozenset(ignored)
