"""The live preview page as a person sees it beside the editor: the time from an edit
the editor sends to the page showing it, and the page's frame rate while it plays, on
the library's largest file and on a generated 5,000-line file.

Target: an edit on the page within 100 ms (p99).

    python benchmarks/preview.py [--edits 200] [--play 5] [--memory-edits 10000]

The editor is pygls's client (as benchmarks/lsp.py's), the server ``gestc lsp`` on a
pipe, the page the one its ``gest.preview`` command serves, read by headless chromium
(software WebGL, as the tests run it). Each edit retypes a value of the first step of
a gesture in the middle of the file, as VS Code sends a keystroke (an incremental
change, a new version), the editor's cursor on that line (``gest/cursor``): each edit
makes a new plan (the costly case; an edit elsewhere keeps the plan and its timeline).
Its time runs from the moment the change is written to the pipe to the moment the
page's DOM has the new step, timed by a MutationObserver in chromium, on the same clock
(the computer's, in ms); the diagnostics' arrival, on the same clock, is the analysis
the page waits for. The frame rate is the number of times the page's time changes in a
second while it plays at 1x (its button), counted in the page. Last, the server's
memory (VmRSS) over many edits of the library's largest file with the page open
(benchmarks/lsp.py's typist, every version fed to the page). The figures are a shared
machine's: compare the two files of one run, not runs of different days.
"""

from __future__ import annotations

import argparse
import asyncio
import functools
import json
import os
import re
import signal
import statistics
import sys
import tempfile
import time
from pathlib import Path

from common import ROOT
from lsp import Editor, generated, largest_library_file
from lsp import session as typed
from lsprotocol import types as lsp

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
SETTLE = 5.0  #: s the page is left to draw the robot before the first edit
NUMBER = re.compile(r"(?<=[A-Za-z_] )\d+")  #: a step's first value
#: when the page's first step came to show %s (the page's clock, ms): a promise, kept
#: by a MutationObserver (no polling: the page is left to its own work meanwhile)
SHOWN = """new Promise(resolve => {
  const want = %s, check = () => { const l = window.__gl.labels;
    if (l.length && l[l.length - 1][1].includes(want)) { resolve(l[l.length - 1][0]);
                                                         return true; }
    return false; };
  if (!check()) { const o = new MutationObserver(() => { if (check()) o.disconnect(); });
    o.observe(document.body, {subtree: true, childList: true, characterData: true,
                              attributes: true}); } })"""


def js(browser, expression: str):
    return browser.call("Runtime.evaluate", expression=expression,
                        returnByValue=True)["result"].get("value")


async def shown(browser, want: str) -> float:
    """When the page showed ``want`` as its first step (ms, the computer's clock), read
    in a thread of its own (the client's loop runs meanwhile)."""
    def call() -> float:
        return browser.call("Runtime.evaluate", expression=SHOWN % json.dumps(want),
                            awaitPromise=True, returnByValue=True)["result"]["value"]

    return await asyncio.wait_for(asyncio.get_running_loop().run_in_executor(None, call), 60)


async def wait(browser, expression: str, timeout: float = 120.0):
    """The value of ``expression`` once true, the client's loop running meanwhile."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if value := js(browser, expression):
            return value
        await asyncio.sleep(0.002)
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


async def session(browser, name: str, path: Path, text: str, edits: int, hide_3d: bool,
                  play: float) -> list[float]:
    """Edits of the middle gesture's first step, sent by the editor: each edit's ms to
    its diagnostics and to the page."""
    editor = Editor()
    await editor.start(path, text)
    answer = await editor.client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        "gest.preview", [editor.uri, {"open": False}]))
    lines = text.split("\n")
    gesture, k = middle_gesture(text)
    editor.client.protocol.notify("gest/cursor", {"textDocument": {"uri": editor.uri},
                                                  "position": {"line": k, "character": 4}})
    browser.navigate(answer["url"])
    wanted = lines[k].strip()[:20]
    await wait(browser, f"[...document.querySelectorAll('button')].some(b => "
                        f"b.textContent.includes({wanted!r}))")
    if hide_3d:
        js(browser, HIDE_3D)
    await asyncio.sleep(SETTLE)  # the robot's meshes loaded and drawn: edits, not a start
    js(browser, OBSERVE)
    value = int(NUMBER.search(lines[k])[0])
    times: dict[str, list[float]] = {"told": [], "page": []}
    for n in range(edits):
        new = max(0, min(180, value + (n % 40) - 20 + (n % 40 >= 20)))
        if str(new) == NUMBER.search(lines[k])[0]:
            new = new + 1 if new < 180 else new - 1
        number = NUMBER.search(lines[k])
        lines[k] = lines[k][:number.start()] + str(new) + lines[k][number.end():]
        change = lsp.TextDocumentContentChangePartial(
            range=lsp.Range(lsp.Position(k, number.start()), lsp.Position(k, number.end())),
            text=str(new))
        sent = time.time() * 1000
        times["told"].append((await editor.edit(change))[0] * 1000)
        seen = await shown(browser, lines[k].strip()[:20])
        times["page"].append(seen - sent)
    rate = await frame_rate(browser, play)
    await editor.stop()
    print(f"{name}: {text.count(chr(10)):,} lines, gesture '{gesture}'; {edits} edits, ms "
          "from the edit (p50 / p99 / worst):")
    for what, said in (("told", "its diagnostics at the editor (the analysis the page waits "
                                "for)"),
                       ("page", "in chromium's page (the DOM changed)")):
        q = statistics.quantiles(times[what], n=100)
        print(f"  {said}: {q[49]:.1f} / {q[98]:.1f} / {max(times[what]):.1f}")
    print(f"  playing at 1x, looping: {rate:.1f} frames a second shown in chromium")
    return times["page"]


CLICK = """(label => { const b = [...document.querySelectorAll('button')]
    .find(b => b.textContent.trim() === label); if (b) b.click(); return !!b; })"""
LOOP = """(() => { const l = [...document.querySelectorAll('label')]
    .find(l => l.textContent.trim() === 'Loop'); if (l) l.click(); return !!l; })()"""


async def frame_rate(browser, seconds: float) -> float:
    """Frames a second shown while playing at 1x, looping (the page's own buttons)."""
    js(browser, LOOP)
    js(browser, f"{CLICK}('Play')")
    await asyncio.sleep(0.5)
    before = js(browser, "window.__gl.times")
    await asyncio.sleep(seconds)
    after = js(browser, "window.__gl.times")
    js(browser, f"{CLICK}('Pause')")
    return (after - before) / seconds


HIDE_3D = "document.querySelectorAll('canvas').forEach(c => c.style.display = 'none'); true"


async def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--edits", type=int, default=200)
    parser.add_argument("--play", type=float, default=5.0, help="s of playing per file")
    parser.add_argument("--memory-edits", type=int, default=10_000,
                        help="edits of the memory session (0: none)")
    args = parser.parse_args()
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # the browser closed still
    import test_web
    from test_web import Browser, chromium

    # as docs/simulation.md has it: software compositing, the GPU process left to WebGL
    test_web.BROWSER_FLAGS += ("--disable-gpu-compositing",)
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory() as folder:
        big = Path(folder) / "generated.gest"
        big.write_text(generated(5000))
        largest = largest_library_file()
        for name, path in ((f"library's largest file ({largest.name})", largest),
                           ("generated file", big)):
            for hide in (False, True):
                browser = Browser(chromium(), str(Path(folder) / f"chromium-{path.stem}-{hide}"))
                try:
                    browser.call("Emulation.setDeviceMetricsOverride", width=1400,
                                 height=900, deviceScaleFactor=1, mobile=False)
                    shown = "the 3-D view hidden" if hide else "with the 3-D view"
                    await session(browser, f"{name}, {shown}", path, path.read_text(),
                                  args.edits, hide, args.play)
                finally:
                    browser.close()
    if args.memory_edits:
        largest = largest_library_file()
        await typed(f"memory ({largest.name}, the preview page open)", largest,
                    largest.read_text(), args.memory_edits, 2, memory_every=1000, preview=True)


if __name__ == "__main__":
    asyncio.run(main())
