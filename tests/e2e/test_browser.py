"""The 3-D page in a real browser: headless Chromium (Debian package, installed by .ci/run)
opens each `sg3d show --out *.html` page with the network cut off, takes a screenshot and the
console; the page must draw (coloured pixels across the plot, WebGL canvases), fit the window
and log no error, at the largest allowed point count too."""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess

import cv2
import numpy as np
import pytest

from sg3d.render.style import RELATION_COLOURS
from tests.scenes import build_show_room as build
from tests.scenes import run_show as show

WINDOW = (1400, 900)
# Before the page's own scripts: console.error and uncaught errors get a marker we look for.
HOOK = ("<script>(function(){var e=console.error.bind(console);"
        "console.error=function(){e.apply(null,['SG3D-CONSOLE-ERROR'].concat([].slice.call(arguments)))};"
        "addEventListener('error',function(ev){e('SG3D-CONSOLE-ERROR uncaught '+ev.message)});})();</script>")
# After them: what the page looks like once plotly has drawn.
PROBE = ("<script>setTimeout(function(){var gd=document.getElementById('sg3d-view');"
         "var el=document.documentElement;var s=gd&&gd._fullLayout&&gd._fullLayout.scene;"
         "console.log('SG3D-PROBE canvases='+(gd?gd.querySelectorAll('canvas').length:0)"
         "+' webgl='+!!(s&&s._scene&&s._scene.glplot)"
         "+' fits='+(el.scrollHeight<=innerHeight&&el.scrollWidth<=innerWidth)"
         "+' height='+(gd?Math.round(gd.getBoundingClientRect().height):0)+' inner='+innerHeight);"
         # the legends as drawn (each entry's text, the box each takes) and the axis titles
         "var out={axes:[],legends:{}};if(s){out.axes=['xaxis','yaxis','zaxis'].map(function(a){return s[a].title.text})}"
         "['legend','legend2'].forEach(function(k){var g=gd&&gd.querySelector('g.'+k);if(!g)return;"
         "var r=g.querySelector('rect.bg').getBoundingClientRect();out.legends[k]={box:[r.left,r.top,r.right,r.bottom],"
         "title:(g.querySelector('.'+k+'titletext')||{}).textContent||'',"
         "entries:Array.from(g.querySelectorAll('.'+k+'text')).map(function(t){return t.textContent})}});"
         "console.log('SG3D-LEGENDS '+JSON.stringify(out));},4000);</script>")


def chromium() -> str:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    if os.environ.get("CI") == "true":
        pytest.fail("chromium is not installed: .ci/run installs the Debian package `chromium`")
    pytest.skip("headless Chromium not found (apt-get install -y chromium); CI installs it")


def open_in_browser(page, tmp_path, budget_ms: int = 15000):
    """(screenshot as BGR, console lines) of `page` with a hook and a probe added to a copy."""
    exe = chromium()
    text = page.read_text(encoding="utf-8")
    probed = tmp_path / f"probed-{page.name}"
    probed.write_text(text.replace("<head>", "<head>" + HOOK, 1).replace("</body>", PROBE + "</body>", 1),
                      encoding="utf-8")
    shot = tmp_path / f"{page.stem}.png"
    proc = subprocess.run(
        [exe, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader", "--disable-quic",
         "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync",
         f"--user-data-dir={tmp_path / ('profile-' + page.stem)}",
         # offline: a name lookup or a proxied fetch fails, so a page that draws needed no network
         "--host-resolver-rules=MAP * ~NOTFOUND", "--proxy-server=127.0.0.1:9",
         f"--window-size={WINDOW[0]},{WINDOW[1]}", f"--virtual-time-budget={budget_ms}",
         "--enable-logging=stderr", "--v=0", f"--screenshot={shot}", probed.as_uri()],
        capture_output=True, text=True, timeout=600)
    console = [ln for ln in proc.stderr.splitlines() if ":CONSOLE" in ln]
    img = cv2.imread(str(shot))
    assert img is not None, proc.stderr[-2000:]
    return img, console


def legends(console) -> dict:
    """{"axes": [3 axis titles], "legends": {id: {"box", "title", "entries"}}} as the page drew them."""
    line = next((ln for ln in console if "SG3D-LEGENDS" in ln), None)
    assert line is not None, console
    text = line.split("SG3D-LEGENDS ", 1)[1]
    return json.JSONDecoder().raw_decode(text.replace('\\"', '"'))[0]


def check_page(img, console, min_drawn: float, colour=None, min_colour_px: int = 0):
    errors = [ln for ln in console if "SG3D-CONSOLE-ERROR" in ln or "Uncaught" in ln]
    assert not errors, errors
    probe = next((ln for ln in console if "SG3D-PROBE" in ln), None)
    assert probe is not None, console
    got = dict(re.findall(r"(\w+)=(\w+)", probe.split("SG3D-PROBE", 1)[1]))
    assert int(got["canvases"]) >= 1 and got["webgl"] == "true", probe
    assert got["fits"] == "true" and abs(int(got["height"]) - int(got["inner"])) <= 2, probe   # no scrollbars
    assert img.shape[:2] == (WINDOW[1], WINDOW[0])
    # the plot area (left of the legend, below the title): drawn pixels (coloured or dark; the
    # empty scene is white and light grey), spread over the window
    plot = img[40:, : int(WINDOW[0] * 0.82)]
    hsv = cv2.cvtColor(plot, cv2.COLOR_BGR2HSV)
    drawn = (hsv[..., 1] > 60) | (hsv[..., 2] < 150)
    assert drawn.mean() > min_drawn, drawn.mean()
    if colour is not None:       # a colour only the page's WebGL traces use
        near = (np.abs(plot.astype(int) - np.array(colour[::-1])).max(axis=-1) < 40).sum()
        assert near >= min_colour_px, near
    ys, xs = np.nonzero(drawn)
    # the first view is framed on the room: what is drawn spans a good part of the window
    assert xs.max() - xs.min() > 0.4 * plot.shape[1] and ys.max() - ys.min() > 0.3 * plot.shape[0]


def test_graph_page_renders_in_chromium(store, embedded_home, tmp_path):
    chromium()
    build(store)
    page = tmp_path / "graph.html"
    r = show(embedded_home, "--out", str(page))
    assert r.exit_code == 0, r.output
    img, console = open_in_browser(page, tmp_path)
    # the ON lines' colour (vermillion), drawn by WebGL
    on = tuple(int(RELATION_COLOURS["ON"][i:i + 2], 16) for i in (1, 3, 5))
    check_page(img, console, min_drawn=0.003, colour=on, min_colour_px=150)
    # two legends, apart, as drawn: the objects' categories and names, then one entry per
    # relation type (size statements listed, though hidden); the axes titled in metres
    drawn = legends(console)
    assert drawn["axes"] == ["x (m)", "y (m)", "up (m)"]
    objects, relations = drawn["legends"]["legend"], drawn["legends"]["legend2"]
    assert objects["title"].startswith("objects") and relations["title"].startswith("relations")
    assert "names" in objects["entries"] and "furniture" in objects["entries"]
    assert relations["entries"] == ["bigger than (2)", "next to (1)", "on (2)", "smaller than (2)"]
    a, b = objects["box"], relations["box"]
    assert a[3] <= b[1] or b[3] <= a[1], (a, b)                  # one above the other, not overlapping
    assert max(a[2], b[2]) <= WINDOW[0] and max(a[3], b[3]) <= WINDOW[1]


def test_largest_point_cloud_renders_in_chromium(store, embedded_home, tmp_path, kitchen_dir):
    """--max-points 200000, the most `sg3d show` allows: the old canvas viewer showed a blank page
    ("Maximum call stack size exceeded") from 130,000 points."""
    chromium()
    build(store)
    page = tmp_path / "cloud.html"
    r = show(embedded_home, "--out", str(page), "--sequence", str(kitchen_dir), "--frames", "24",
             "--max-points", "200000")
    assert r.exit_code == 0, r.output
    assert "point cloud (200,000)" in page.read_text(encoding="utf-8")
    img, console = open_in_browser(page, tmp_path, budget_ms=30000)
    check_page(img, console, min_drawn=0.04)
