"""Sheets -> one self-contained HTML page: inline CSS, SVG and script, no network access.

Each rung is its own inline <svg> in a `div.rung` with an anchor id (file number and step
address, e.g. `#f0-s14`) and a `data-text` of its devices, symbols and comments for the
search box. The simulation report (report.py) reuses `page` with its own panel and script.
"""

from __future__ import annotations

import html

from mlctool.ladder.document import RungView, Sheet, search_text
from mlctool.ladder.svg import STYLE, anchor, geometry, item_height, item_svg

PAGE_STYLE = """
body{margin:0;font-family:system-ui,-apple-system,"Segoe UI",sans-serif;color:#111;background:#fafafa}
header{position:sticky;top:0;z-index:2;background:#fff;border-bottom:1px solid #ccc;padding:8px 16px;
display:flex;gap:16px;align-items:center;flex-wrap:wrap}
header h1{font-size:16px;margin:0}
#q{font-size:14px;padding:4px 8px;width:22em}
nav{padding:8px 16px;font-size:13px;border-bottom:1px solid #ddd;background:#fff}
nav a{margin-right:8px}
main{padding:8px 16px}
section.file h2{font-size:15px;font-family:monospace;margin:16px 0 4px}
div.rung,div.row{position:relative;margin:0}
div.rung>a.here,div.row>a.here{position:absolute;left:2px;top:2px;font-size:11px;color:#999;text-decoration:none}
div.rung:target svg{background:#fff8d0}
.hidden{display:none}
""".strip()

SEARCH_SCRIPT = """
(function(){
  var q=document.getElementById('q'), n=document.getElementById('count');
  var items=Array.prototype.slice.call(document.querySelectorAll('div.rung,div.row'));
  function run(){
    var t=q.value.trim().toLowerCase(), shown=0;
    items.forEach(function(d){
      var hit=!t||d.getAttribute('data-text').toLowerCase().indexOf(t)>=0;
      d.classList.toggle('hidden',!hit); if(hit&&d.classList.contains('rung')) shown++;
    });
    n.textContent=shown+' of '+document.querySelectorAll('div.rung').length+' rungs';
  }
  q.addEventListener('input',run); run();
})();
""".strip()


def _e(s: str) -> str:
    return html.escape(s, quote=True)


def sheets_body(sheets: list[Sheet], comments: bool = False) -> str:
    """Navigation and the rungs of every sheet (`comments`: device comments under contacts)."""
    geo = geometry(sheets, comments)
    nav = []
    out = []
    for no, sh in enumerate(sheets):
        nav.append(f'<a href="#f{no}">{_e(sh.path)}</a>')
        out.append(f'<section class="file" id="f{no}"><h2>{_e(sh.path)} '
                   f'<small>({sh.rungs} rungs)</small></h2>')
        for it in sh.items:
            cls = "rung" if isinstance(it, RungView) else "row"
            aid = anchor(no, it)
            h = item_height(it, geo)
            out.append(f'<div class="{cls}" id="{aid}" data-text="{_e(search_text(sh, it))}">'
                       f'<a class="here" href="#{aid}" title="link to this rung">#</a>'
                       f'<svg xmlns="http://www.w3.org/2000/svg" class="lad" width="{geo.width}" '
                       f'height="{h}" viewBox="0 0 {geo.width} {h}">'
                       + "".join(item_svg(sh, it, geo)) + "</svg></div>")
        out.append("</section>")
    return "<nav>" + " ".join(nav) + "</nav>\n<main>\n" + "\n".join(out) + "\n</main>"


def page(title: str, body: str, extra_style: str = "", script: str = "", header_extra: str = "") -> str:
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        f"<title>{_e(title)}</title>\n<style>\n{PAGE_STYLE}\n{STYLE}\n{extra_style}\n</style>\n</head>\n"
        f"<body>\n<header><h1>{_e(title)}</h1>"
        '<input id="q" type="search" placeholder="search devices, symbols, comments" '
        'aria-label="search rungs"><span id="count"></span>'
        f"{header_extra}</header>\n{body}\n"
        f"<script>\n{SEARCH_SCRIPT}\n{script}\n</script>\n</body>\n</html>\n"
    )


def sheets_html(sheets: list[Sheet], title: str = "", comments: bool = False) -> str:
    title = title or "Ladder: " + ", ".join(sh.path for sh in sheets)
    return page(title, sheets_body(sheets, comments))

