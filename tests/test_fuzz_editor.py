"""The editor's side of the compiler never fails on what is typed: the gesture fuzzer's
seeded mutants of the library, each analysed and asked every question an editor asks
(hover and completion everywhere on a line, definition, references, outline, inlay
hints, fixes, semantic tokens), and fed to a running ``gestc lsp`` as edits: diagnostics
each time, never an exception, a hang or a dead server. Random keystrokes (characters
Python takes for line ends among them) keep the server's text the editor's: its
diagnostics are those of the same text opened whole; and the protocol's lines
(``editor/lines.py``) agree with a walk over the characters on random texts."""

import asyncio
import random

import pytest
from lsprotocol import types as lsp
from mutate import mutate, seeds, within
from pytest_lsp import LanguageClient

from inmoov_dsl.editor.actions import fixes
from inmoov_dsl.editor.analysis import analyse
from inmoov_dsl.editor.knowledge import completions, definition, hover, outline, references
from inmoov_dsl.editor.lines import compiler_line, index, place, rows
from inmoov_dsl.editor.timing import step_times
from inmoov_dsl.editor.tokens import encoded, tokens

MUTANTS = 20  #: analysed and asked everything (about 4 s)
EDITS = 8  #: fed to the server (about 3 s)
LIMIT = 30.0  #: s per mutant, which a loaded machine meets (most take milliseconds; a
#: mutant of 3,000 lines whose 1,000 gestures call each other takes 6 s on an idle one)


@pytest.fixture(scope="module")
def library():
    return seeds()["gest"]


def ask_everything(text: str, path: str, rng: random.Random) -> None:
    found = analyse(text, path)
    for d in found.diagnostics:
        assert d.severity in ("error", "warning") and d.message
    lines = text.split("\n")
    for _ in range(4):
        line = rng.randrange(len(lines))
        column = rng.randrange(len(lines[line]) + 1)
        hover(found, line, column)
        completions(found, line, column)
        definition(found, line, column)
        fixes(found, line)
        references(text, "index")
    outline(found)
    step_times(found)
    data = encoded(tokens(found))
    assert len(data) % 5 == 0 and min(data, default=0) >= 0


def test_every_question_on_mutants_has_an_answer(library, tmp_path):
    problems = []
    for n in range(MUTANTS):
        rng = random.Random(f"editor:{n}")
        seed = rng.choice(library)
        text = mutate(seed.data, rng, "gest").decode("utf-8", "replace")
        path = str(tmp_path / seed.name.split("/")[-1])
        try:
            within(LIMIT, lambda text=text, path=path, rng=rng: ask_everything(text, path,
                                                                               rng))
        except BaseException as exc:  # noqa: BLE001 - what we are looking for
            problems.append(f"mutant {n} of {seed.name}: {type(exc).__name__}: {exc}"[:300])
    assert not problems, "\n".join(problems[:5])




@pytest.mark.asyncio
async def test_the_server_takes_mutants_as_edits(client, library, tmp_path):
    uri = (tmp_path / "typed.gest").as_uri()
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(
        uri=uri, language_id="gest", version=1, text="")))
    await asyncio.wait_for(client.wait_for_notification(
        lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS), LIMIT * 4)
    told = 0
    for n in range(EDITS):
        rng = random.Random(f"edits:{n}")
        text = mutate(rng.choice(library).data, rng, "gest").decode("utf-8", "replace")
        client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(uri=uri, version=n + 2),
            [lsp.TextDocumentContentChangeWholeDocument(text=text)]))
        await asyncio.wait_for(client.wait_for_notification(
            lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS), LIMIT * 4)
        told += len(client.diagnostics[uri])
        last = len(text.split("\n")) - 1
        where = lsp.Range(lsp.Position(0, 0), lsp.Position(last, 0))
        ident = lsp.TextDocumentIdentifier(uri=uri)
        for request in (
                client.text_document_hover_async(lsp.HoverParams(ident, lsp.Position(
                    rng.randrange(last + 1), rng.randrange(12)))),
                client.text_document_inlay_hint_async(lsp.InlayHintParams(ident, where)),
                client.text_document_code_action_async(lsp.CodeActionParams(
                    ident, where, lsp.CodeActionContext(diagnostics=[]))),
                client.text_document_semantic_tokens_full_async(
                    lsp.SemanticTokensParams(ident))):
            await asyncio.wait_for(request, LIMIT * 4)  # an answer, not an error
    assert told > 0  # the mutants do have problems, and the server told them
    assert not client.error



ODD = "ab 9:#\n\r\u2028\u2029\f\v\x85\x1c\x1d\x1e\t\U0001f600"  #: and line ends


def walk(text: str) -> list[tuple[int, int, int, int, int]]:
    """(protocol line, UTF-16 column, column, compiler line, its column) of each
    character of ``text`` and of its end, by walking it: the protocol's line ends are
    \\n, \\r\\n and \\r; the compiler's, \\n (lines from 1, its columns too)."""
    out, line, units, column, compiled, at = [], 0, 0, 0, 1, 1
    for k, char in enumerate(text + "$"):
        out.append((line, units, column, compiled, at))
        if char == "\n" or (char == "\r" and text[k + 1:k + 2] != "\n"):
            line, units, column = line + 1, 0, 0
        elif char != "\r":
            units, column = units + (2 if ord(char) > 0xFFFF else 1), column + 1
        compiled, at = (compiled + 1, 1) if char == "\n" else (compiled, at + 1)
    return out


def test_the_protocol_s_lines_on_random_texts():
    rng = random.Random("lines")
    for _ in range(3000):
        text = "".join(rng.choice(ODD) for _ in range(rng.randrange(40)))
        seen = walk(text)
        assert len(rows(text)) == seen[-1][0] + 1
        for k, (line, units, column, compiled, at) in enumerate(seen):
            if k == len(text) or text[k] not in "\r\n":
                assert index(text, line, units) == k, (text, k)
                assert index(text, line, column, "utf-32") == k, (text, k)
                assert place(text, compiled, at) == (line, column), (text, k)
                assert compiler_line(text, line) == compiled, (text, k)


def recorded(client: LanguageClient) -> list:
    """Every publishDiagnostics from now on, in order (pytest-lsp keeps the last)."""
    published: list = []
    method = lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS
    handler = client.protocol.fm.features[method]

    def both(params: lsp.PublishDiagnosticsParams) -> None:
        published.append(params)
        handler(params)

    client.protocol.fm.features[method] = both
    return published


def keystroke(text: str, rng: random.Random) -> tuple[str, lsp.TextDocumentContentChangePartial]:
    """``text`` changed at random, and the change as an editor sends it (a range of
    protocol lines and UTF-16 columns, its end past the text's now and then)."""
    seen = walk(text)
    a = rng.randrange(len(seen))
    if 0 < a < len(text) and text[a - 1:a + 1] == "\r\n":
        a -= 1  # nor start between them
    b = min(len(seen) - 1, a + rng.randrange(6))
    while b > a and text[b - 1] == "\r" and text[b:b + 1] == "\n":
        b += 1  # a range does not end between the two characters of \r\n
    new = "".join(rng.choice(ODD + "index 90\n") for _ in range(rng.randrange(5)))
    (la, ua), (lb, ub) = seen[a][:2], seen[b][:2]
    if b == len(text) and rng.random() < 0.2:
        lb, ub = lb + rng.randrange(3), ub + rng.randrange(9)  # past the end: its end
    return text[:a] + new + text[b:], lsp.TextDocumentContentChangePartial(
        range=lsp.Range(lsp.Position(la, ua), lsp.Position(lb, ub)), text=new)


async def told(published: list, wanted: set[tuple[str, int]]) -> dict[str, list[tuple]]:
    """Uri -> (line, start, end, message) of each diagnostic published for each of the
    ``wanted`` (uri, version), once all are."""
    shown: dict[str, list[tuple]] = {}
    while len(shown) < len(wanted):
        for params in published:
            if (params.uri, params.version) in wanted:
                shown[params.uri] = [(d.range.start.line, d.range.start.character,
                                      d.range.end.character, d.message)
                                     for d in params.diagnostics]
        await asyncio.sleep(0.01)
    return shown


@pytest.mark.asyncio
async def test_keystrokes_keep_the_editor_s_text(client, library, tmp_path):
    published = recorded(client)
    rng = random.Random("keystrokes")
    for n in range(3):
        uri, whole = (tmp_path / f"{n}.gest").as_uri(), (tmp_path / f"{n}w.gest").as_uri()
        text = rng.choice(library).data.decode()
        client.text_document_did_open(lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(
            uri=uri, language_id="gest", version=1, text=text)))
        for version in range(2, 40):
            text, change = keystroke(text, rng)
            client.text_document_did_change(lsp.DidChangeTextDocumentParams(
                lsp.VersionedTextDocumentIdentifier(uri=uri, version=version), [change]))
        client.text_document_did_open(lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(
            uri=whole, language_id="gest", version=1, text=text)))
        shown = await asyncio.wait_for(told(published, {(uri, 39), (whole, 1)}), LIMIT * 4)
        assert shown[uri] == [(*d[:3], d[3].replace(f"{n}w.gest", f"{n}.gest"))
                              for d in shown[whole]], repr(text)
