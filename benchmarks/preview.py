"""The live preview page (``gestc preview --live``, the page the language server will
open) as a person sees it: the time from an edit of the text to the page showing it,
and the page's frame rate while it plays, on the library's largest file and on a
generated 5,000-line file.

Target: an edit on the page within 100 ms.

    python benchmarks/preview.py [--edits 200] [--play 5]

Each edit retypes a value of the first step of the gesture the cursor is in (so each
makes a new plan: the costly case; an edit elsewhere keeps the plan and its timeline).
Its time runs from just before the text is analysed (``editor.analysis.analyse``, its
memo kept, as the language server does; ``gestc preview --live`` adds the time it takes
to see the file change, up to 20 ms) to the moment the page's DOM has the new step,
timed by a MutationObserver in headless chromium (software WebGL, as the tests run it),
on the same clock (the computer's, in ms). The frame rate is the number of times the
page's time changes in a second while it plays at 1x, counted in the page. The figures
are a shared machine's: compare the two files of one run, not runs of different days.
"""

from __future__ import annotations

import argparse
import functools
import os
import re
import signal
import statistics
import sys
import tempfile
import time
from pathlib import Path

from common import ROOT
from lsp import generated, largest_library_file

sys.path.insert(0, str(ROOT / "tests"))
print = functools.partial(print, flush=True)  # noqa: A001 (a long run: say as it goes)

OBSERVE = """(() => {
  window.__gl = {labels: [], times: 0, label: null, time: null};
  new MutationObserver(() => {
    const now = performance.timeOrigin + performance.now();
    const first = [...document.querySelectorAll('button')]
        .map(b => b.textContent.trim()).find(t => t.startsWith('1. '));
    if (first && first !== window.__gl.label) {
      window.__gl.label = first; window.__gl.labels.push([now, first]); }
    const t = document.getElementById('gl-time');
    if (t && t.textContent !== window.__gl.time) {
      window.__gl.time = t.textContent; window.__gl.times += 1; }
  }).observe(document.body, {subtree: true, childList: true, characterData: true,
                             attributes: true});
  return true; })()"""
NUMBER = re.compile(r"(?<=[A-Za-z_] )\d+")  #: a step's first value


def js(browser, expression: str):
    return browser.call("Runtime.evaluate", expression=expression,
                        returnByValue=True)["result"].get("value")


def wait(browser, expression: str, timeout: float = 120.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if value := js(browser, expression):
            return value
        time.sleep(0.005)
    raise SystemExit(f"the page did not show {expression!r} in {timeout} s")


def middle_gesture(text: str) -> tuple[str, int]:
    """The gesture in the middle of ``text`` whose first step has a value, and that
    step's line (0-based)."""
    lines = text.split("\n")
    starts = [k for k, row in enumerate(lines) if re.match(r"[a-z_0-9]+:\s*$", row)]
    for k in starts[len(starts) // 2:]:
        if re.match(r"\s+(?!repeat |wait |hold |say )[A-Za-z_]\w* \d", lines[k + 1]):
            return lines[k].rstrip(":"), k + 1
    raise SystemExit("no gesture with a value in its first step")


def session(browser, page, name: str, path: Path, text: str, edits: int) -> list[float]:
    """Edits of the middle gesture's first step: each edit's ms to the page."""
    from inmoov_dsl.editor.analysis import analyse
    from inmoov_dsl.editor.memo import Memo
    from inmoov_dsl.editor.preview_view import view_of

    memo, lines = Memo(), text.split("\n")
    gesture, k = middle_gesture(text)
    value = int(NUMBER.search(lines[k])[0])
    view = view_of(analyse(text, str(path), memo=memo), k, previous=page.view)
    page.show(view)
    wait(browser, f"window.__gl.label && window.__gl.label.includes({lines[k].strip()[:20]!r})")
    times: dict[str, list[float]] = {"analysis": [], "view": [], "drawn": [], "page": []}
    for n in range(edits):
        new = max(0, min(180, value + (n % 40) - 20 + (n % 40 >= 20)))
        if str(new) == NUMBER.search(lines[k])[0]:
            new = new + 1 if new < 180 else new - 1
        lines[k] = NUMBER.sub(str(new), lines[k], count=1)
        sent, frames = time.time() * 1000, page.frames
        found = analyse("\n".join(lines), str(path), memo=memo)
        times["analysis"].append(time.time() * 1000 - sent)
        view = view_of(found, k, 4, page.view)
        times["view"].append(time.time() * 1000 - sent)
        page.show(view)
        deadline = time.monotonic() + 30
        while (page.view is None or page.view.plan is not view.plan
               or page.frames == frames) and time.monotonic() < deadline:
            time.sleep(0.0005)  # (its contacts, found later, make it another view)
        times["drawn"].append(time.time() * 1000 - sent)
        want = lines[k].strip()[:20]
        seen = wait(browser, f"(l => l.length && l[l.length - 1][1].includes({want!r}) && "
                             f"l[l.length - 1][0])(window.__gl.labels)", 30)
        times["page"].append(seen - sent)
    print(f"{name}: {text.count(chr(10)):,} lines, gesture '{gesture}' on "
          f"{view.profile.name}; {edits} edits, ms from the edit (p50 / p99 / worst):")
    for what, said in (("analysis", "the text analysed (editor.analysis, as gestc lsp)"),
                       ("view", "the view made (the gesture's steps, timeline)"),
                       ("drawn", "the page's thread has sent it (viser)"),
                       ("page", "in chromium's page (the DOM changed)")):
        q = statistics.quantiles(times[what], n=100)
        print(f"  {said}: {q[49]:.1f} / {q[98]:.1f} / {max(times[what]):.1f}")
    return times["page"]


def frame_rate(browser, page, seconds: float) -> tuple[float, float]:
    """Frames a second while playing at 1x (looping): drawn by the page's thread, and
    the page's time shown in chromium."""
    page.set_loop(True)
    page.play()
    time.sleep(0.5)
    before, frames = js(browser, "window.__gl.times"), page.frames
    time.sleep(seconds)
    after, drawn = js(browser, "window.__gl.times"), page.frames
    page.pause()
    return (drawn - frames) / seconds, (after - before) / seconds


HIDE_3D = "document.querySelectorAll('canvas').forEach(c => c.style.display = 'none'); true"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--edits", type=int, default=200)
    parser.add_argument("--play", type=float, default=5.0, help="s of playing per file")
    args = parser.parse_args()
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # the browser closed still
    import test_web
    from test_web import Browser, chromium

    from inmoov_dsl.model.livepage import LivePage

    # as docs/simulation.md has it: software compositing, the GPU process left to WebGL
    test_web.BROWSER_FLAGS += ("--disable-gpu-compositing",)
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory() as folder:
        big = Path(folder) / "generated.gest"
        big.write_text(generated(5000))
        largest = largest_library_file()
        for name, path in ((f"library's largest file ({largest.name})", largest),
                           ("generated file", big)):
            page = LivePage(0)
            browser = Browser(chromium(), str(Path(folder) / f"chromium-{path.stem}"))
            try:
                browser.call("Emulation.setDeviceMetricsOverride", width=1400, height=900,
                             deviceScaleFactor=1, mobile=False)
                browser.navigate(page.url)
                wait(browser, "document.querySelector('button') !== null")
                js(browser, OBSERVE)
                for shown in ("with the 3-D view", "the 3-D view hidden"):
                    if shown != "with the 3-D view":
                        js(browser, HIDE_3D)
                    session(browser, page, f"{name}, {shown}", path, path.read_text(),
                            args.edits)
                    drawn, seen = frame_rate(browser, page, args.play)
                    print(f"  playing at 1x: {drawn:.1f} frames a second sent, {seen:.1f} "
                          "shown in chromium")
            finally:
                browser.close()
                page.close()


if __name__ == "__main__":
    main()
