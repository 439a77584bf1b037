"""The language server on a file near the largest it reads (~990,000 characters, about
16,000 one-line gestures: the library's renamed, over and over): the time from didOpen
to the first diagnostics, the time a hover sent right after didOpen takes to be
answered meanwhile, formatting (and a hover of another document sent meanwhile), and
two edits sent while the first is analysed (the diagnostics of the newer; the older's,
told or not).

    python benchmarks/lsp_large.py [--size 990000]

The client is pygls's, started as an editor starts the server (``gestc lsp`` on a
pipe); times run from the moment a message is written to the moment its answer (or the
diagnostics of its version) arrives.
"""

from __future__ import annotations

import argparse
import asyncio
import re
import sys
import tempfile
import time
from pathlib import Path

from common import ROOT
from lsprotocol import types as lsp
from pygls.lsp.client import LanguageClient

SERVER = [sys.executable, "-m", "inmoov_dsl.cli.gestc", "lsp"]
LIMIT = 600.0  #: s for any answer


def huge(size: int = 990_000) -> str:
    """A legal file of at most ``size`` characters: every one-line gesture of the
    library, its name numbered (``peace_12``), over and over."""
    rows = [row for path in sorted((ROOT / "gestures").glob("*.gest"))
            for row in path.read_text().split("\n") if re.match(r"^\w+: \w+ \d", row)]
    out: list[str] = []
    total = n = 0
    while True:
        for row in rows:
            name, rest = row.split(":", 1)
            line = f"{name}_{n}:{rest}\n"
            if total + len(line) > size:
                return "".join(out)
            out.append(line)
            total += len(line)
        n += 1


class Editor:
    """A pygls client and the server it started; each version's diagnostics as they
    arrive."""

    def __init__(self) -> None:
        self.client = LanguageClient("benchmark", "1")
        self.told: dict[int | None, tuple[float, int]] = {}
        self.arrived = asyncio.Event()

        @self.client.feature(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def told(params: lsp.PublishDiagnosticsParams) -> None:
            self.told[params.version] = (time.perf_counter(), len(params.diagnostics))
            self.arrived.set()

    async def start(self) -> None:
        await self.client.start_io(*SERVER)
        await self.client.initialize_async(lsp.InitializeParams(
            capabilities=lsp.ClientCapabilities()))
        self.client.initialized(lsp.InitializedParams())

    async def diagnostics(self, version: int) -> tuple[float, int]:
        """When the diagnostics of ``version`` arrived, and how many there were."""
        while version not in self.told:
            self.arrived.clear()
            await asyncio.wait_for(self.arrived.wait(), LIMIT)
        return self.told[version]

    async def stop(self) -> None:
        await self.client.shutdown_async(None)
        self.client.exit(None)
        await self.client.stop()


async def opening(path: Path, text: str) -> None:
    """didOpen, a hover at once, then an edit while the first version is analysed."""
    editor = Editor()
    await editor.start()
    uri = path.as_uri()
    ident = lsp.TextDocumentIdentifier(uri)
    t0 = time.perf_counter()
    editor.client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(uri, "gest", 1, text)))
    said = await asyncio.wait_for(editor.client.text_document_hover_async(
        lsp.HoverParams(ident, lsp.Position(0, 1))), LIMIT)
    hovered = time.perf_counter() - t0
    at, count = await editor.diagnostics(1)
    print(f"- didOpen to its diagnostics: {at - t0:.2f} s ({count} told)")
    print(f"- a hover sent right after didOpen: answered in {hovered:.2f} s "
          f"({'an answer' if said else 'no hover'})")
    small = path.with_name("small.gest").as_uri()
    editor.client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(small, "gest", 1, "s: index 90\n")))
    await asyncio.wait_for(editor.client.text_document_hover_async(
        lsp.HoverParams(lsp.TextDocumentIdentifier(small), lsp.Position(0, 4))), LIMIT)
    t0 = time.perf_counter()
    formatting = asyncio.ensure_future(editor.client.text_document_formatting_async(
        lsp.DocumentFormattingParams(ident, lsp.FormattingOptions(4, True))))
    await asyncio.sleep(0.05)  # the formatting under way
    t1 = time.perf_counter()
    await asyncio.wait_for(editor.client.text_document_hover_async(
        lsp.HoverParams(lsp.TextDocumentIdentifier(small), lsp.Position(0, 4))), LIMIT)
    meanwhile = time.perf_counter() - t1
    edits = await asyncio.wait_for(formatting, LIMIT)
    print(f"- formatting: {time.perf_counter() - t0:.2f} s ({len(edits or [])} edits); a "
          f"hover of another document sent meanwhile: answered in {meanwhile:.2f} s")
    lines = text.split("\n")
    t0 = time.perf_counter()
    for version in (2, 3):  # a new line typed twice, the first superseded at once
        editor.client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(version=version, uri=uri),
            [lsp.TextDocumentContentChangePartial(
                range=lsp.Range(lsp.Position(len(lines) - 1, 0),
                                lsp.Position(len(lines) - 1, 0)), text="x: wait 1s\n")]))
    at, count = await editor.diagnostics(3)
    print(f"- two edits in a row, to the diagnostics of the second: {at - t0:.2f} s "
          f"({count} told; the first's {'told too' if 2 in editor.told else 'never told'})")
    await editor.stop()


async def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--size", type=int, default=990_000)
    args = parser.parse_args()
    text = huge(args.size)
    gestures = text.count("\n")
    print(f"a file of {len(text):,} characters, {gestures:,} gestures:")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "huge.gest"
        path.write_text(text)
        await opening(path, text)


if __name__ == "__main__":
    asyncio.run(main())
