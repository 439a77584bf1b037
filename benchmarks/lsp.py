"""The language server as an editor feels it: the time from an edit to its diagnostics,
over typing sessions on the library's largest file and on a generated 5,000-line file;
and the server's memory over many edits.

Target: p99 <= 50 ms on the library's largest file, <= 250 ms on the 5,000-line file;
the server's resident memory flat (the last edits' within 10% of the first's after a
warm-up) over 10,000 edits.

    python benchmarks/lsp.py [--edits 1000] [--memory-edits 10000] [--seed 1]

The client is pygls's (a client library, not the server's code), started as an editor
starts the server (``gestc lsp`` on a pipe); every edit is sent as VS Code sends a
keystroke (an incremental change with its range and a new version), and its time runs
from the moment it is written to the pipe to the moment the diagnostics of that version
arrive. The memory is the server process's VmRSS, read from /proc.
"""

from __future__ import annotations

import argparse
import asyncio
import random
import re
import statistics
import sys
import tempfile
import time
from pathlib import Path

from common import ROOT
from lsprotocol import types as lsp
from pygls.lsp.client import LanguageClient

SERVER = [sys.executable, "-m", "inmoov_dsl.cli.gestc", "lsp"]
STEP = "    index 90, middle 120 over 0.5s"  #: a step typed and taken back, key by key


def largest_library_file() -> Path:
    files = sorted((ROOT / "gestures").glob("*.gest"), key=lambda p: len(p.read_text()))
    return files[-1]


def generated(lines: int) -> str:
    """A file of ``lines`` lines: the library's hand files, their names numbered, over
    and over (gestures that call each other, poses, repeats, comments)."""
    parts = [p.read_text() for p in sorted((ROOT / "gestures").glob("*.gest"))
             if "robot" not in p.read_text() and "use " not in p.read_text()]
    defined = {d for part in parts for d in re.findall(r"^(?:pose |group )?(\w+):", part,
                                                       flags=re.M)}
    out: list[str] = []
    n = 0
    while len(out) < lines:
        for part in parts:
            out += re.sub(r"\b(\w+)\b", lambda m, n=n: f"{m[1]}_{n}" if m[1] in defined
                          else m[1], part).split("\n")
        n += 1
    cut = len(out[:lines]) - 1
    while cut > 0 and out[cut].startswith((" ", "#")):  # end on a whole gesture
        cut -= 1
    return "\n".join(out[:cut]) + "\n"


class Typist:
    """Edits as a person makes them: a number retyped, a step typed under a gesture and
    taken back, a name misspelt and put right, one key at a time."""

    def __init__(self, text: str, rng: random.Random):
        self.lines = text.split("\n")
        self.rng = rng

    def sessions(self):
        """Edits forever: (line, column, end column, new text) on one line, or a new
        line (``"\\n"`` typed at the end of a line)."""
        while True:
            yield from self.rng.choice((self._number, self._step, self._name))()

    def _step_lines(self) -> list[int]:
        return [k for k, row in enumerate(self.lines) if row.startswith("    ")
                and not row.lstrip().startswith("#")]

    def _number(self):
        k = self.rng.choice(self._step_lines())
        found = list(re.finditer(r"(?<![\d.])\d+(?![\d.sm])", self.lines[k]))
        if not found:
            return
        m = self.rng.choice(found)
        for i in range(len(m[0])):  # backspace the number
            end = m.end() - i
            yield self._replace(k, end - 1, end, "")
        for i, c in enumerate(str(self.rng.randrange(181))):
            yield self._replace(k, m.start() + i, m.start() + i, c)

    def _step(self):
        k = self.rng.choice(self._step_lines())
        yield self._newline(k)
        for i, c in enumerate(STEP):
            yield self._replace(k + 1, i, i, c)
        for i in range(len(STEP), 0, -1):
            yield self._replace(k + 1, i - 1, i, "")
        yield self._join(k)

    def _name(self):
        k = self.rng.choice(self._step_lines())
        m = self.rng.choice(list(re.finditer(r"[a-z_]+", self.lines[k])))
        yield self._replace(k, m.end() - 1, m.end(), "")
        yield self._replace(k, m.end() - 1, m.end() - 1, m[0][-1])

    def _replace(self, k: int, start: int, end: int, new: str):
        row = self.lines[k]
        self.lines[k] = row[:start] + new + row[end:]
        return lsp.TextDocumentContentChangePartial(
            range=lsp.Range(lsp.Position(k, start), lsp.Position(k, end)), text=new)

    def _newline(self, k: int):
        end = len(self.lines[k])
        self.lines.insert(k + 1, "")
        return lsp.TextDocumentContentChangePartial(
            range=lsp.Range(lsp.Position(k, end), lsp.Position(k, end)), text="\n")

    def _join(self, k: int):
        end = len(self.lines[k])
        self.lines[k:k + 2] = [self.lines[k] + self.lines[k + 1]]
        return lsp.TextDocumentContentChangePartial(
            range=lsp.Range(lsp.Position(k, end), lsp.Position(k + 1, 0)), text="")


class Editor:
    """A pygls client with one document open in ``gestc lsp``."""

    def __init__(self):
        self.client = LanguageClient("benchmark", "1")
        self.told: dict[int, asyncio.Future] = {}
        self.version = 1

        @self.client.feature(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def told(params: lsp.PublishDiagnosticsParams) -> None:
            waiting = self.told.pop(params.version, None)
            if waiting is not None and not waiting.done():
                waiting.set_result((time.perf_counter(), len(params.diagnostics)))

    async def start(self, path: Path, text: str, preview: bool = False) -> None:
        await self.client.start_io(*SERVER)
        await self.client.initialize_async(lsp.InitializeParams(
            capabilities=lsp.ClientCapabilities()))
        self.client.initialized(lsp.InitializedParams())
        self.uri = path.resolve().as_uri()
        done = self._expect(1)
        self.client.text_document_did_open(lsp.DidOpenTextDocumentParams(
            lsp.TextDocumentItem(self.uri, "gest", 1, text)))
        await asyncio.wait_for(done, 600)
        if preview:  # the live page fed each version too (no browser: viser's own work)
            await self.client.workspace_execute_command_async(lsp.ExecuteCommandParams(
                "gest.preview", [self.uri, {"open": False}]))

    def _expect(self, version: int) -> asyncio.Future:
        self.told[version] = asyncio.get_running_loop().create_future()
        return self.told[version]

    async def edit(self, change) -> tuple[float, int]:
        """Send one change; (seconds to its diagnostics, how many there were)."""
        self.version += 1
        done = self._expect(self.version)
        t0 = time.perf_counter()
        self.client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(version=self.version, uri=self.uri), [change]))
        at, count = await asyncio.wait_for(done, 60)
        return at - t0, count

    def rss_kb(self) -> int:
        status = Path(f"/proc/{self.client._server.pid}/status").read_text()
        return int(re.search(r"VmRSS:\s+(\d+)", status)[1])

    async def stop(self) -> None:
        await self.client.shutdown_async(None)
        self.client.exit(None)
        await self.client.stop()


async def session(name: str, path: Path, text: str, edits: int, seed: int,
                  memory_every: int = 0, preview: bool = False) -> list[float]:
    editor = Editor()
    t0 = time.perf_counter()
    await editor.start(path, text, preview)
    opened = time.perf_counter() - t0
    typist = Typist(text, random.Random(seed))
    times, told, rss = [], 0, []
    for n, change in zip(range(edits), typist.sessions(), strict=False):
        seconds, count = await editor.edit(change)
        times.append(seconds)
        told += count > 0
        if memory_every and n % memory_every == 0:
            rss.append((n, editor.rss_kb()))
    await editor.stop()
    q = statistics.quantiles(times, n=100)
    print(f"{name}: {text.count(chr(10)):,} lines, opened in {opened * 1000:.0f} ms; "
          f"{len(times):,} edits: p50 {q[49] * 1000:.1f} ms, p99 {q[98] * 1000:.1f} ms, "
          f"worst {max(times) * 1000:.1f} ms; {told:,} edits had diagnostics")
    if rss:
        print("  server memory (VmRSS) by edit: " + ", ".join(
            f"{n:,}: {kb / 1024:.1f} MB" for n, kb in rss))
    return times


async def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--edits", type=int, default=1000)
    parser.add_argument("--memory-edits", type=int, default=10_000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--preview", action="store_true",
                        help="the memory session with the live preview page open (fed "
                        "every version: gest.preview)")
    args = parser.parse_args()
    largest = largest_library_file()
    await session(f"library's largest file ({largest.name})", largest,
                  largest.read_text(), args.edits, args.seed)
    with tempfile.TemporaryDirectory() as folder:
        big = Path(folder) / "generated.gest"
        big.write_text(generated(5000))
        await session("generated file", big, big.read_text(), args.edits, args.seed)
    if args.memory_edits:
        await session(f"memory ({largest.name}"
                      f"{', the preview page open' if args.preview else ''})", largest,
                      largest.read_text(), args.memory_edits, args.seed + 1,
                      memory_every=1000, preview=args.preview)


if __name__ == "__main__":
    asyncio.run(main())
