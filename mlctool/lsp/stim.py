"""Stimulus files (`.stim`, docs/stimulus.md) in the editor: the diagnostics `mlc sim
--stimulus` gives before it runs (the parser's E601/E602, the device models', a run too
long), completion of keywords, model kinds and the target's devices, hover on a keyword or a
device. The target is the one of the `mlc.toml` above the file (nc5 without one).

Positions are 1-based lines and columns, as in features.py.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.targetapi.model import Target

_TOKEN = re.compile(r"\S+")

# what each word does, after the table of docs/stimulus.md "Lines"
KEYWORD_DOCS = {
    "scan": "`scan PERIOD`: the scan period (e.g. `scan 10ms`). Overrides `--scan-time`.",
    "run": "`run TIME` / `run #N`: run the scans that start before TIME / run N scans. "
           "`--until` and `--scans` override it; without any of them the run ends with the scan of "
           "the last timed line.",
    "model": "`model KIND key=value ...`: attach a device model (docs/stimulus.md, Device models).",
    "port": "`port CPn key=value ...`: the PLC's serial port settings (docs/stimulus.md, Serial ports).",
    "expect": "`TIME expect CHECK ...`: check devices after the scan. A CHECK is `DEV=VALUE`, "
              "`DEV!=VALUE` or `DEV=LOW..HIGH` (inclusive); `expect alarm NAME`: the alarm has been "
              "raised at or before this scan.",
    "alarm": "`TIME expect alarm NAME`: the alarm NAME has been raised at or before this scan.",
    "force": "`TIME force DEV=VALUE ...`: write the value before and after every scan until "
             "`release` (the program cannot change it).",
    "release": "`TIME release DEV ...`: end a force; the device keeps its value until something "
               "writes it.",
    "power-cycle": "`TIME power-cycle`: power off and on before the scan (docs/simulator.md).",
    "pulses": "`TIME DEV pulses FREQ [until TIME | for TIME]`: a pulse train on input DEV "
              "(`X0/X1 pulses 1kHz`: an A/B pair, B lagging; a negative frequency: B leading).",
    "until": "`... pulses FREQ until TIME`: the train stops at TIME.",
    "for": "`... pulses FREQ for TIME`: the train lasts TIME.",
    "receive": "`TIME CPn receive BYTE|\"TEXT\" ...`: bytes sent to the PLC's serial port.",
}
LINE_STARTS = ("scan", "run", "model", "port")  # the words that may start a line instead of a time
ACTIONS = ("expect", "force", "release", "power-cycle")  # the words after a time


def diagnostics(path: str, text: str, target: Target) -> list[Diagnostic]:
    """What `mlc sim --stimulus FILE` says of the file before it runs: the stimulus parser's
    diagnostics, the device models' (unknown kind, bad parameter, a signal of no model), and a
    run past the bound of scans (at the default scan period unless the file sets one)."""
    from mlctool.sim.run.run import DEFAULT_SCAN_US, RunTooLong, build_models, plan_scans
    from mlctool.sim.stimulus.stimulus import parse_stimulus_text

    st, diags = parse_stimulus_text(path, text, target)
    _, model_diags = build_models(st, target)
    diags = diags + model_diags
    if not any(d.severity == "error" for d in diags):
        try:
            plan_scans(st, st.scan_us or DEFAULT_SCAN_US, None, None)
        except RunTooLong as e:
            diags.append(diag(path, Span.at(1), "E601", str(e)))
    return sorted(diags, key=lambda d: (d.span.line, d.span.col))


@dataclass(frozen=True)
class StimCompletion:
    label: str
    kind: str  # keyword | device | model
    detail: str


def completions(line_text: str, col: int, target: Target) -> list[StimCompletion]:
    """Keywords where the line's grammar takes one, model kinds after `model`, the target's
    devices where a device name goes (the letters with their ranges)."""
    from mlctool.devices.registry import models_of

    code = line_text[:col - 1]
    if len(_code(code).split()) < len(code.split()):  # in a comment
        return []
    words = code.split()
    if words and not code.endswith((" ", "\t")):
        current = words.pop()
    else:
        current = ""
    if "=" in current:  # a value
        return []
    if not words:
        return [StimCompletion(k, "keyword", _form(k)) for k in LINE_STARTS]
    head = words[0].lower()
    if head == "model":
        return [StimCompletion(k, "model", f"device model {k}") for k in sorted(models_of(target))] if len(words) == 1 else []
    if head in LINE_STARTS:
        return []
    devices = [StimCompletion(d.name, "device", f"{d.kind} {d.name}{d.lo}-{d.name_of(d.hi)[len(d.name):]} "
                                                f"({d.section})") for d in target.devices.values()
               if d.kind != "pointer"]
    if len(words) == 1:  # after the time: an action or a device to write
        keywords = [StimCompletion(k, "keyword", _form(k)) for k in ACTIONS]
        return keywords + devices
    action = words[1].lower()
    if action == "power-cycle" or (action == "expect" and len(words) > 2 and words[2].lower() == "alarm"):
        return []
    if action == "expect" and len(words) == 2:
        return [StimCompletion("alarm", "keyword", _form("alarm"))] + devices
    if len(words) == 2 and "=" not in words[1] and action not in ACTIONS:  # `1s X0 ...`
        return [StimCompletion("pulses", "keyword", _form("pulses"))]
    return devices


def _form(word: str) -> str:
    return KEYWORD_DOCS[word].split(":", 1)[0].strip("`")


def hover(line_text: str, col: int, target: Target) -> tuple[str, int, int, str | None] | None:
    """(markdown, first col, end col, device name or None) of the word under the cursor: a
    keyword's form and meaning; a device's view, value range and the target's device kind.
    The caller adds where the program reads and writes the device."""
    from mlctool.sim.state import NameError_, parse_device_name
    from mlctool.sim.stimulus.stimulus import _range

    code = _code(line_text)
    for m in _TOKEN.finditer(code):
        if not m.start() < col <= m.end():
            continue
        word = m.group()
        first, end = m.start() + 1, m.end() + 1
        if word.lower() in KEYWORD_DOCS:
            return KEYWORD_DOCS[word.lower()], first, end, None
        name = re.split(r"!=|=", word, maxsplit=1)[0]
        if "/" in name:  # X0/X1 pulses: the one under the cursor
            offset = col - first
            parts, start = name.split("/"), 0
            for part in parts:
                if start <= offset <= start + len(part):
                    name, first = part, first + start
                    break
                start += len(part) + 1
        try:
            view = parse_device_name(name, target)
        except NameError_:
            return None
        values = "On/Off (1/0)" if view.view == "bit" else (
            "a float" if view.is_float else "{}..{}".format(*_range(view)))
        out = [f"**{view.name}**: " + {"bit": "bit", "w": "16-bit word", "d": "32-bit pair", "f": "float (32-bit pair)",
                                       "h": "raw 16-bit pattern", "group": f"bit group of {view.digits * 4} bits"}
               .get(view.view, view.view) + f", values {values}"]
        dev = target.devices.get(view.gdev if view.view == "group" else view.kind)
        device = None
        if dev is not None and view.special is None:
            device = dev.name_of(view.number)
            area = dev.area(view.number)
            out.append(f"{dev.kind} device {dev.name}{dev.lo}-{dev.name_of(dev.hi)[len(dev.name):]}"
                       + (f", {area.name}" + (", latched" if area.latched else "") if area else "")
                       + (", an input" if dev.input else "") + f" (manual {dev.section})")
        return "\n\n".join(out), first, first + len(name), device
    return None


def _code(text: str) -> str:
    """The line without its comment: `#` starts one except `#250` (a scan number) first on the
    line or after `run` (mlctool/sim/stimulus/stimulus.py)."""
    from mlctool.sim.stimulus.stimulus import _strip_comment

    return _strip_comment(text)
