"""`mlc sim --report` and `mlc test`'s page of a failing scenario: every expectation with its
result, the ladder lit scan by scan, and waveforms, in one self-contained HTML page that
opens at the first failing expectation (docs/ladder.md).

The ladder is lit by lighting.py's rule, the one the live monitor uses: `ScanLamps` is the
simulation's `scan_end` hook and samples the lit elements at the end of every scan.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

from mlctool.ladder.document import RungView, Sheet, image_sheet
from mlctool.ladder.html import _e, page, sheets_body
from mlctool.ladder.lighting import lamps, lit
from mlctool.ladder.svg import anchor
from mlctool.sim.run.run import Failure, RunResult, Simulation
from mlctool.sim.state import DeviceView, Machine
from mlctool.targetapi.registry import simulation_of

MAX_SCANS = 20_000  # scans recorded for the page; longer runs are cut (the page says so)
MAX_WAVES = 24  # devices plotted when no --watch names them
MAX_ROWS = 2_000  # expectation rows listed (the failing ones first when there are more)


class ScanLamps:
    """The ladder of a simulation and, per scan, the elements lit at its end: installed as
    the Simulation's `scan_end` hook."""

    def __init__(self, sim: Simulation, lines: dict[str, list[str]]):
        self.sheet: Sheet = image_sheet(sim.image, lines, sim.target)
        self.lamps = lamps(self.sheet)
        self.steps = sim.prog.steps
        self.on: list[list[int]] = []
        sim.scan_end = self.sample

    def sample(self, m: Machine, k: int) -> None:
        if k < MAX_SCANS:
            self.on.append(lit(self.lamps, self.steps, m))

    def deltas(self) -> list[list[int]]:
        """Per scan, the indices whose state changed from the scan before (keeps the page small)."""
        out, prev = [], set()
        for cur in map(set, self.on):
            out.append(sorted(cur ^ prev))
            prev = cur
        return out


# ------------------------------------------------------------------ expectations


@dataclass(frozen=True, slots=True)
class Row:
    """One checked `DEV=V` of an expect line."""

    line: int
    scan: int
    time_us: int
    device: str
    expected: str
    actual: str
    held: bool
    why: str = ""  # a failure's writer and note


def _fmt(v) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def expectation_rows(result: RunResult) -> list[Row]:
    rows = []
    for o in result.expectations:
        failed = {f.device: f for f in o.failures}
        for c in o.checks:
            rows.append(Row(o.line, o.scan, o.time_us, c.device, c.expected, _fmt(c.actual), c.held,
                            _why(failed[c.device]) if c.device in failed else ""))
        if not o.checks:  # an expectation the run ended before: its failure only
            rows += [Row(o.line, o.scan, o.time_us, f.device, f.expected, _fmt(f.actual), False, _why(f))
                     for f in o.failures]
    return rows


def _why(f: Failure) -> str:
    return "; ".join(x for x in (f.writer and f"last written by {f.writer}", f.note) if x)


def seconds(us: int) -> str:
    return f"{round(us / 1e6, 6):g} s"


def _table(rows: list[Row], first_fail: Row | None) -> str:
    shown = rows if len(rows) <= MAX_ROWS else [r for r in rows if not r.held][:MAX_ROWS]
    out = ['<table id="expectations"><thead><tr><th>line</th><th>time</th><th>scan</th><th>device</th>'
           '<th>expected</th><th>actual</th><th>result</th></tr></thead><tbody>']
    for r in shown:
        cls = "pass" if r.held else "fail"
        rid = ' id="first-failure"' if r is first_fail else ""
        why = f'<div class="why">{_e(r.why)}</div>' if r.why else ""
        out.append(f'<tr class="{cls}" data-scan="{r.scan}"{rid}><td>{r.line}</td><td>{seconds(r.time_us)}</td>'
                   f'<td>{r.scan}</td><td>{_e(r.device)}</td><td>{_e(r.expected)}</td><td>{_e(r.actual)}</td>'
                   f'<td>{"held" if r.held else "FAILED"}{why}</td></tr>')
    out.append("</tbody></table>")
    if len(shown) < len(rows):
        out.append(f'<div class="small">{len(rows)} checks: the {len(shown)} failing ones are listed</div>')
    return "".join(out)


# ------------------------------------------------------------------ waveforms

WAVE_LEFT = 150
WAVE_W = 900
WAVE_ROW = 30
DENSE = 8  # a word wave with a change every DENSE pixels or more often is drawn as a line


def _series(result: RunResult, views: list[DeviceView], scans: int) -> dict[str, list[tuple[int, object]]]:
    """device name -> [(scan, value)] at each change, from the run's trace."""
    pos = {v: k for k, v in enumerate(result.views)}
    wanted = {pos[v]: v.name for v in views if v in pos}
    out: dict[str, list[tuple[int, object]]] = {name: [] for name in wanted.values()}
    for t, changes in result.trace:
        k, between = divmod(t, result.period_us)
        if k >= scans:
            break
        if between:  # an output a routine's REF put out between scans: the columns are scans
            continue
        for i, value in changes:
            if i in wanted:
                out[wanted[i]].append((k, value))
    return out


def _words(v: DeviceView) -> set[tuple[str, int]]:
    """The 16-bit words a word view shows (a 32-bit view: both halves)."""
    if v.view in ("d", "f"):
        return {(v.kind, v.number), (v.kind, v.number + 1)}
    return {(v.kind, v.number)} if v.view in ("w", "h") else set()


def default_waves(sim: Simulation, result: RunResult, failing: list[str], scans: int) -> list[DeviceView]:
    """What a scenario is about, first: the devices of failing expectations, the devices the
    stimulus sets and checks (in its order), the target's own registers (FBs: each axis's
    position, frequency, ...), then the program's devices that change in the run. A word
    already shown in a 32-bit view (or the reverse) is not shown again."""
    by_name = {v.name: v for v in result.views}
    own = simulation_of(sim.target).views
    candidates = [by_name[n] for n in failing if n in by_name]
    for e in sim.st.events:
        candidates += [v for v, _ in e.assigns] + [c.view for c in e.checks]
    candidates += list(own(sim.target, sim.prog)) if own is not None else []
    fixed = len(candidates)
    changing = _series(result, result.views, scans)
    candidates += [v for v in result.views if len(changing.get(v.name, ())) > 1]
    out: list[DeviceView] = []
    seen: set[str] = set()
    words: set[tuple[str, int]] = set()
    for k, v in enumerate(candidates):
        w = _words(v)
        if v.name in seen or (w and w <= words) or (k >= fixed and w & words):
            continue
        seen.add(v.name)
        words |= w
        out.append(v)
        if len(out) == MAX_WAVES:
            break
    return out


def _ticks(total_s: float) -> list[float]:
    """Times for the axis labels: a step of 1, 2 or 5 times a power of ten, at most 10 steps."""
    if total_s <= 0:
        return [0.0]
    step = 10 ** math.floor(math.log10(total_s / 10))
    for f in (1, 2, 5, 10):
        if total_s / (step * f) <= 10:
            step *= f
            break
    return [round(k * step, 9) for k in range(int(total_s / step + 1e-9) + 1)]


def _analog(changes: list[tuple[int, object]], top: int, n: int, sx: float) -> str:
    """A word that changes too often for labelled segments (an axis position, a frequency):
    a line between its lowest and highest value, one point per pixel column."""
    lo, hi = min(v for _, v in changes), max(v for _, v in changes)
    span = (hi - lo) or 1
    points: list[tuple[float, float]] = []
    for k, v in changes:
        x, y = round(WAVE_LEFT + k * sx, 1), round(top + 22 - (v - lo) / span * 18, 1)
        if points and points[-1][0] == x:
            points[-1] = (x, y)
        else:
            if points:
                points.append((x, points[-1][1]))  # the value holds until it changes
            points.append((x, y))
    points.append((round(WAVE_LEFT + n * sx, 1), points[-1][1]))
    d = " ".join(f"{'M' if i == 0 else 'L'}{x:g},{y:g}" for i, (x, y) in enumerate(points))
    return (f'<path class="analog" d="{d}"/><text class="small" x="{WAVE_LEFT - 8}" y="{top + 27}" '
            f'text-anchor="end">{_e(_fmt(lo))}..{_e(_fmt(hi))}</text>')


def waves_svg(series: dict[str, list[tuple[int, object]]], bits: set[str], scans: int, period_us: int,
              marks: list[tuple[int, str, str]]) -> str:
    """The waveforms; `marks`: (scan, device, text) of each failed check, a red ring on the
    device's wave and a line across all of them."""
    n = max(scans, 1)
    sx = WAVE_W / n
    h = WAVE_ROW * len(series) + 24
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" class="lad waves" id="waves" width="{WAVE_LEFT + WAVE_W + 10}" '
             f'height="{h}" viewBox="0 0 {WAVE_LEFT + WAVE_W + 10} {h}" data-scans="{n}" '
             f'data-left="{WAVE_LEFT}" data-width="{WAVE_W}">']
    for t in _ticks(n * period_us / 1e6):
        x = WAVE_LEFT + t * 1e6 / period_us * sx
        parts.append(f'<line class="grid" x1="{x:.1f}" y1="0" x2="{x:.1f}" y2="{h - 16}"/>'
                     f'<text class="small" x="{x:.1f}" y="{h - 4}" text-anchor="middle">{t:g} s</text>')
    rows = {}
    for row, (name, points) in enumerate(series.items()):
        top = row * WAVE_ROW + 4
        rows[name] = top
        parts.append(f'<text x="{WAVE_LEFT - 8}" y="{top + 14}" text-anchor="end">{_e(name)}</text>')
        changes = points or [(0, 0)]
        if name in bits:
            d, level = [], None
            for k, v in changes:
                y = top + (4 if v else 22)
                x = WAVE_LEFT + k * sx
                d.append(f"{'M' if level is None else 'L'}{x:.1f},{y}" if level is None
                         else f"L{x:.1f},{level} L{x:.1f},{y}")
                level = y
            d.append(f"L{WAVE_LEFT + n * sx:.1f},{level}")
            parts.append(f'<path class="bit" d="{" ".join(d)}"/>')
        elif len(changes) > WAVE_W / DENSE and all(isinstance(v, int | float) and v == v for _, v in changes):
            parts.append(_analog(changes, top, n, sx))
        else:
            for j, (k, v) in enumerate(changes):
                x0 = WAVE_LEFT + k * sx
                x1 = WAVE_LEFT + (changes[j + 1][0] if j + 1 < len(changes) else n) * sx
                parts.append(f'<path class="bus" d="M{x0 + 2:.1f},{top + 4} L{x1 - 2:.1f},{top + 4} '
                             f'L{x1:.1f},{top + 13} L{x1 - 2:.1f},{top + 22} L{x0 + 2:.1f},{top + 22} '
                             f'L{x0:.1f},{top + 13} Z"/>')
                text = _fmt(v)
                if x1 - x0 > 7 * len(text) + 6:
                    parts.append(f'<text class="small" x="{(x0 + x1) / 2:.1f}" y="{top + 17}" '
                                 f'text-anchor="middle">{_e(text)}</text>')
    for k, dev, text in marks:
        x = WAVE_LEFT + (k + 0.5) * sx  # checked after scan k: the middle of its column
        parts.append(f'<g class="failmark"><line x1="{x:.1f}" y1="0" x2="{x:.1f}" y2="{h - 16}"/>'
                     + (f'<circle cx="{x:.1f}" cy="{rows[dev] + 13}" r="7"/>' if dev in rows else "")
                     + f"<title>{_e(text)}</title></g>")
    parts.append(f'<line id="cursor" x1="{WAVE_LEFT}" y1="0" x2="{WAVE_LEFT}" y2="{h - 16}"/></svg>')
    return "".join(parts)


# ------------------------------------------------------------------ the page

REPORT_STYLE = """
#panel{padding:8px 16px;background:#fff;border-bottom:1px solid #ddd}
#panel label{font-size:14px}
#panel h2{font-size:15px;margin:10px 0 4px}
#scan{width:60%;vertical-align:middle}
#failure{background:#fdecea;border:1px solid #e0a39a;padding:6px 10px;margin:6px 0;font-size:14px}
#expectations{border-collapse:collapse;font-size:13px;max-width:100%}
#expectations th,#expectations td{border:1px solid #ddd;padding:2px 8px;text-align:left;vertical-align:top}
#expectations tr.fail td{background:#fdecea;color:#8a1c1c}
#expectations tr.cur td{outline:2px solid #c0392b}
#expectations tbody tr{cursor:pointer}
#expectations .why{font-size:11px;color:#555}
#checks{max-height:260px;overflow:auto;display:inline-block;max-width:100%}
.small{font-size:12px;color:#555}
.waves .bit{stroke:#0a6f1f;stroke-width:1.5;fill:none}
.waves .bus{stroke:#1f4f9f;stroke-width:1;fill:#eef3fb}
.waves .analog{stroke:#1f4f9f;stroke-width:1.5;fill:none}
.waves .grid{stroke:#e3e3e3;stroke-width:1}
.waves .failmark line{stroke:#c0392b;stroke-width:1;stroke-dasharray:3 3}
.waves .failmark circle{stroke:#c0392b;stroke-width:2;fill:none}
#cursor{stroke:#c0392b;stroke-width:2}
.waves{cursor:crosshair}
.lad .el.fail text{fill:#c0392b;font-weight:bold}
.lad .el.fail .sym,.lad .el.fail .box{stroke:#c0392b}
""".strip()

REPORT_SCRIPT = """
(function(){
  var data=JSON.parse(document.getElementById('power').textContent);
  var slider=document.getElementById('scan'), info=document.getElementById('scaninfo');
  var byIndex={};
  Array.prototype.forEach.call(document.querySelectorAll('.el[data-i]'),function(g){
    (byIndex[g.getAttribute('data-i')]=byIndex[g.getAttribute('data-i')]||[]).push(g);
  });
  data.failing.forEach(function(i){ (byIndex[i]||[]).forEach(function(g){ g.classList.add('fail'); }); });
  var rows=Array.prototype.slice.call(document.querySelectorAll('#expectations tbody tr'));
  var waves=document.getElementById('waves'), cursor=document.getElementById('cursor');
  function secs(k){ return +(k*data.period_us/1e6).toFixed(6); }
  function show(k){
    var on={};
    for(var s=0;s<=k&&s<data.deltas.length;s++){
      data.deltas[s].forEach(function(i){ if(on[i]) delete on[i]; else on[i]=1; });
    }
    Object.keys(byIndex).forEach(function(i){
      byIndex[i].forEach(function(g){ g.classList.toggle('on',!!on[i]); });
    });
    info.textContent='scan '+k+' (t = '+secs(k)+' s), '+Object.keys(on).length+' lit';
    rows.forEach(function(r){ r.classList.toggle('cur',+r.getAttribute('data-scan')===k); });
    if(cursor){
      var x=+waves.getAttribute('data-left')+(k+0.5)*(+waves.getAttribute('data-width'))/Math.max(1,+waves.getAttribute('data-scans'));
      cursor.setAttribute('x1',x); cursor.setAttribute('x2',x);
    }
  }
  function go(k){ slider.value=Math.max(0,Math.min(+slider.max,k)); show(+slider.value); }
  slider.addEventListener('input',function(){ show(+slider.value); });
  document.getElementById('prev').addEventListener('click',function(){ go(+slider.value-1); });
  document.getElementById('next').addEventListener('click',function(){ go(+slider.value+1); });
  rows.forEach(function(r){ r.addEventListener('click',function(){ go(+r.getAttribute('data-scan')); }); });
  if(waves) waves.addEventListener('click',function(ev){
    var r=waves.getBoundingClientRect(), left=+waves.getAttribute('data-left'), w=+waves.getAttribute('data-width');
    go(Math.floor((ev.clientX-r.left-left)/w*(+waves.getAttribute('data-scans'))));
  });
  var m=/^#scan=(\\d+)$/.exec(location.hash);  // a link to one scan: report.html#scan=12
  go(m ? +m[1] : data.start);
  var first=document.getElementById('first-failure');
  if(first&&!m) first.scrollIntoView({block:'nearest'});
})();
""".strip()


def _failing_elements(sheet: Sheet, devices: list[str]) -> list[int]:
    """The instructions that name a failing device (as its word, `D0` for `D0:d`)."""
    names = {d.split(":")[0].upper() for d in devices}
    return [k for k, ins in enumerate(sheet.instrs) if any(str(op).upper() in names for op in ins.operands)]


def _rung_of(sheet: Sheet, index: int) -> str | None:
    for it in sheet.items:
        if isinstance(it, RungView) and it.rung.start <= index < it.rung.stop:
            return anchor(0, it)
    return None


def _first_failure(sheet: Sheet, row: Row, failing: list[int], scans: int) -> str:
    writers = [k for k in failing if sheet.instrs[k].spec.cls == "output"
               and sheet.instrs[k].operands and str(sheet.instrs[k].operands[0]).upper()
               == row.device.split(":")[0].upper()]
    rung = _rung_of(sheet, (writers or failing or [-1])[0])
    link = f' <a href="#{rung}">the rung that writes {_e(row.device)}</a>' if rung else ""
    cut = "" if row.scan < scans else " (after the scans the page shows)"
    return (f'<div id="failure"><b>First failure</b>: line {row.line}, at {seconds(row.time_us)} '
            f'(scan {row.scan}{cut}): {_e(row.device)} expected {_e(row.expected)}, actual {_e(row.actual)}'
            + (f"; {_e(row.why)}" if row.why else "") + f".{link}</div>")


def report_html(sim: Simulation, result: RunResult, scan_lamps: ScanLamps, watch: list[DeviceView],
                title: str) -> str:
    sheet = scan_lamps.sheet
    scans = min(result.scans, MAX_SCANS)
    rows = expectation_rows(result)
    failed = [r for r in rows if not r.held]
    failing_devices = list(dict.fromkeys(r.device for r in failed))
    if watch:  # the devices asked for, after those of failing expectations
        by_name = {v.name: v for v in result.views}
        views = [by_name[d] for d in failing_devices if d in by_name and by_name[d] not in watch] + list(watch)
    else:
        views = default_waves(sim, result, failing_devices, scans)
    series = _series(result, views, scans)
    bits = {v.name for v in views if v.view == "bit"}
    marks = [(r.scan, r.device, f"line {r.line}: {r.device} expected {r.expected}, actual {r.actual}")
             for r in failed if r.scan < scans]
    failing = _failing_elements(sheet, failing_devices)
    last = max(scans - 1, 0)
    start = min(failed[0].scan, last) if failed else last
    data = {"period_us": result.period_us, "scans": scans, "deltas": scan_lamps.deltas(), "start": start,
            "failing": failing}
    cut = (f" (the run had {result.scans} scans; the first {MAX_SCANS} are shown)"
           if result.scans > MAX_SCANS else "")
    panel = (f'<div id="panel"><div class="small">{_e(result_line(result) + cut)}</div>'
             + (_first_failure(sheet, failed[0], failing, scans) if failed else "")
             + (f'<h2>Expectations</h2><div id="checks">{_table(rows, failed[0] if failed else None)}</div>' if rows else "")
             + f'<h2>Scan</h2><button id="prev" type="button">&lt;</button> '
             f'<input id="scan" type="range" min="0" max="{last}" value="{start}" aria-label="scan"> '
             f'<button id="next" type="button">&gt;</button> <label id="scaninfo"></label>'
             f'<h2>Waveforms</h2>{waves_svg(series, bits, scans, result.period_us, marks)}</div>')
    body = (panel + "\n" + sheets_body([sheet])
            + f'\n<script type="application/json" id="power">{json.dumps(data, separators=(",", ":"))}</script>')
    return page(title or f"Simulation: {sheet.path}", body, REPORT_STYLE, REPORT_SCRIPT)


def result_line(r: RunResult) -> str:
    failed = len(r.failed)
    out = f"{r.scans} scans of {r.period_us / 1000:g} ms ({seconds(r.time_us)}); {len(r.expectations)} expectation(s)"
    out += f", {failed} failed" if failed else ", all held" if r.expectations else ""
    return out + (f"; fault: {r.fault.message}" if r.fault else "")
