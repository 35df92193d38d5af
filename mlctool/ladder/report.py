"""`mlc sim --report`: the ladder with the contacts and coils that conduct at a chosen scan,
and waveforms of the watched devices, in one self-contained HTML page.

The hook into the simulator is its `probe` (the one coverage uses: it wraps each decoded
step's contact and routine, and runs on the reference interpreter): a contact conducts when
its own condition holds at execution (LDP/LDF: the edge it saw), an output when its driving
result is On. Steps a scan does not execute (jumped over, subroutine not called) do not
conduct in that scan.
"""

from __future__ import annotations

import json
from collections.abc import Callable

from mlctool.ladder.document import build_sheet
from mlctool.ladder.html import _e, page, sheets_body
from mlctool.sim.run import RunResult, Simulation
from mlctool.sim.state import DeviceView

MAX_SCANS = 20_000  # scans recorded for the page; longer runs are cut (the page says so)
MAX_WAVES = 32  # devices plotted when no --watch names them


class PowerProbe:
    """A simulator probe (the `probe` of mlctool/sim/decode.py, as coverage uses): per scan,
    the instruction indices that conducted."""

    def __init__(self, period_us: int):
        self.period_us = period_us
        self.on: dict[int, set[int]] = {}

    def mark(self, now_us: int, index: int) -> None:
        k = now_us // self.period_us
        if k < MAX_SCANS:
            self.on.setdefault(k, set()).add(index)

    def contact(self, contact: Callable) -> Callable:
        """A contact conducts when its own value is On (LDP/LDF: the edge it saw)."""
        mark = self.mark

        def observed(m, s):
            v = contact(m, s)
            if v:
                mark(m.now_us, s.index)
            return v
        return observed

    def step(self, run: Callable, cls: str) -> Callable:
        """An output conducts when its driving result is On; a step's state box (STL) when
        the step is active (its bus On)."""
        mark = self.mark
        if cls == "bus":
            def active(m, s):
                r = run(m, s)
                if m.bus:
                    mark(m.now_us, s.index)
                return r
            return active
        if cls != "output":
            return run

        def driven(m, s):
            if m.acc:
                mark(m.now_us, s.index)
            return run(m, s)
        return driven


def _deltas(trace: PowerProbe, scans: int) -> list[list[int]]:
    """Per scan, the indices whose state changed from the scan before (keeps the page small)."""
    out, prev = [], set()
    for k in range(min(scans, MAX_SCANS)):
        cur = trace.on.get(k, set())
        out.append(sorted(cur ^ prev))
        prev = cur
    return out


# ------------------------------------------------------------------ waveforms

WAVE_LEFT = 150
WAVE_W = 900
WAVE_ROW = 30


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


def _fmt(v) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def waves_svg(series: dict[str, list[tuple[int, object]]], bits: set[str], scans: int) -> str:
    n = max(scans, 1)
    sx = WAVE_W / n
    h = WAVE_ROW * len(series) + 24
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" class="lad waves" id="waves" width="{WAVE_LEFT + WAVE_W + 10}" '
             f'height="{h}" viewBox="0 0 {WAVE_LEFT + WAVE_W + 10} {h}" data-scans="{n}" '
             f'data-left="{WAVE_LEFT}" data-width="{WAVE_W}">']
    for k in range(0, n + 1, max(1, n // 10)):
        x = WAVE_LEFT + k * sx
        parts.append(f'<line class="grid" x1="{x:.1f}" y1="0" x2="{x:.1f}" y2="{h - 16}"/>'
                     f'<text class="small" x="{x:.1f}" y="{h - 4}" text-anchor="middle">{k}</text>')
    for row, (name, points) in enumerate(series.items()):
        top = row * WAVE_ROW + 4
        parts.append(f'<text x="{WAVE_LEFT - 8}" y="{top + 16}" text-anchor="end">{_e(name)}</text>')
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
    parts.append(f'<line id="cursor" x1="{WAVE_LEFT}" y1="0" x2="{WAVE_LEFT}" y2="{h - 16}"/></svg>')
    return "".join(parts)


REPORT_STYLE = """
#panel{padding:8px 16px;background:#fff;border-bottom:1px solid #ddd}
#panel label{font-size:14px}
#scan{width:60%;vertical-align:middle}
.waves .bit{stroke:#0a6f1f;stroke-width:1.5;fill:none}
.waves .bus{stroke:#1f4f9f;stroke-width:1;fill:#eef3fb}
.waves .grid{stroke:#e3e3e3;stroke-width:1}
#cursor{stroke:#c0392b;stroke-width:2}
.waves{cursor:crosshair}
""".strip()

REPORT_SCRIPT = """
(function(){
  var data=JSON.parse(document.getElementById('power').textContent);
  var slider=document.getElementById('scan'), info=document.getElementById('scaninfo');
  var byIndex={};
  Array.prototype.forEach.call(document.querySelectorAll('.el[data-i]'),function(g){
    (byIndex[g.getAttribute('data-i')]=byIndex[g.getAttribute('data-i')]||[]).push(g);
  });
  var waves=document.getElementById('waves'), cursor=document.getElementById('cursor');
  function show(k){
    var on={};
    for(var s=0;s<=k&&s<data.deltas.length;s++){
      data.deltas[s].forEach(function(i){ if(on[i]) delete on[i]; else on[i]=1; });
    }
    Object.keys(byIndex).forEach(function(i){
      byIndex[i].forEach(function(g){ g.classList.toggle('on',!!on[i]); });
    });
    info.textContent='scan '+k+' (t = '+(k*data.period_us/1000)+' ms), '+Object.keys(on).length+' conducting';
    if(cursor){
      var x=+waves.getAttribute('data-left')+k*(+waves.getAttribute('data-width'))/Math.max(1,+waves.getAttribute('data-scans'));
      cursor.setAttribute('x1',x); cursor.setAttribute('x2',x);
    }
  }
  slider.addEventListener('input',function(){ show(+slider.value); });
  document.getElementById('prev').addEventListener('click',function(){ slider.value=Math.max(0,+slider.value-1); show(+slider.value); });
  document.getElementById('next').addEventListener('click',function(){ slider.value=Math.min(+slider.max,+slider.value+1); show(+slider.value); });
  if(waves) waves.addEventListener('click',function(ev){
    var r=waves.getBoundingClientRect(), left=+waves.getAttribute('data-left'), w=+waves.getAttribute('data-width');
    var k=Math.round((ev.clientX-r.left-left)/w*(+waves.getAttribute('data-scans')));
    slider.value=Math.max(0,Math.min(+slider.max,k)); show(+slider.value);
  });
  var m=/^#scan=(\\d+)$/.exec(location.hash);  // a link to one scan: report.html#scan=12
  if(m) slider.value=Math.min(+slider.max,+m[1]);
  show(+slider.value);
})();
""".strip()


def report_html(sim: Simulation, result: RunResult, trace: PowerProbe, lines: dict[str, list[str]],
                watch: list[DeviceView], title: str) -> str:
    image = sim.image
    names = [p for p, _, _ in image.modules] or sorted({i.file for i in image.instrs if i.file})
    sheet = build_sheet(" + ".join(names), image.instrs, lines, sim.target)
    scans = min(result.scans, MAX_SCANS)
    views = watch or result.views[:MAX_WAVES]
    series = _series(result, views, scans)
    bits = {v.name for v in views if v.view == "bit"}
    data = {"period_us": result.period_us, "scans": scans, "deltas": _deltas(trace, scans)}
    cut = (f" (the run had {result.scans} scans; the first {MAX_SCANS} are shown)"
           if result.scans > MAX_SCANS else "")
    panel = (f'<div id="panel"><button id="prev" type="button">&lt;</button> '
             f'<input id="scan" type="range" min="0" max="{max(scans - 1, 0)}" value="{max(scans - 1, 0)}" '
             f'aria-label="scan"> <button id="next" type="button">&gt;</button> '
             f'<label id="scaninfo"></label><div class="small">{_e(result_line(result) + cut)}</div>'
             f'<h2 style="font-size:15px">Waveforms</h2>{waves_svg(series, bits, scans)}</div>')
    body = (panel + "\n" + sheets_body([sheet])
            + f'\n<script type="application/json" id="power">{json.dumps(data, separators=(",", ":"))}</script>')
    return page(title or f"Simulation: {sheet.path}", body, REPORT_STYLE, REPORT_SCRIPT)


def result_line(r: RunResult) -> str:
    failed = len(r.failed)
    out = f"{r.scans} scans of {r.period_us / 1000:g} ms; {len(r.expectations)} expectation(s)"
    out += f", {failed} failed" if failed else ", all held" if r.expectations else ""
    return out + (f"; fault: {r.fault.message}" if r.fault else "")
