"""gestc lsp, driven by a client we did not write (pytest-lsp) with the capabilities of
VS Code and of Neovim: diagnostics as the text changes, with gestc check's wording,
places and hints; formatting by gestc fmt's rules; hover, completion, definition,
references, outline, inlay hints, code actions applied, semantic tokens, settings. Every
answer is awaited with a time limit (``soon``): a broken request fails, never hangs."""

import asyncio
import functools
from pathlib import Path

import pytest
import pytest_lsp
from lsp_client import SERVER
from lsprotocol import types as lsp
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

#: one server a module and an editor (each test's documents are its own files): a
#: server's start is 1.7 s of CPU, paid once, not for each of a hundred tests
pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER),
                    params=["visual-studio-code", "neovim"], scope="module")
async def client(request, lsp_client: LanguageClient):
    result = await lsp_client.initialize_session(
        lsp.InitializeParams(capabilities=client_capabilities(request.param)))
    lsp_client.server_legend = result.capabilities.semantic_tokens_provider.legend
    yield
    await lsp_client.shutdown_session()


LIMIT = 60.0  #: s for any answer, which a loaded machine meets (most take milliseconds)


async def soon(awaited):
    """``awaited``'s result, or a failure after LIMIT seconds (never a hang)."""
    return await asyncio.wait_for(awaited, LIMIT)


async def opened(client: LanguageClient, uri: str, text: str) -> list[lsp.Diagnostic]:
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(
        lsp.TextDocumentItem(uri=uri, language_id="gest", version=1, text=text)))
    await soon(client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS))
    return client.diagnostics[uri]


async def hovered(client: LanguageClient, uri: str, line: int, character: int) -> str:
    said = await soon(client.text_document_hover_async(lsp.HoverParams(
        lsp.TextDocumentIdentifier(uri=uri), lsp.Position(line, character))))
    return said.contents.value


async def changed(client: LanguageClient, uri: str, version: int, text: str
                  ) -> list[lsp.Diagnostic]:
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        lsp.VersionedTextDocumentIdentifier(uri=uri, version=version),
        [lsp.TextDocumentContentChangeWholeDocument(text=text)]))
    await soon(client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS))
    return client.diagnostics[uri]


async def test_every_error_as_it_is_typed_and_gone_once_fixed(client, tmp_path):
    uri = (tmp_path / "typos.gest").as_uri()
    found = await opened(client, uri, "a: indx 90, midle 90\nb: thum 90\nc: ring 90\n")
    assert [(d.range.start.line, d.range.start.character, d.range.end.character,
             d.severity) for d in found] == [(0, 3, 7, lsp.DiagnosticSeverity.Error),
                                             (0, 12, 17, lsp.DiagnosticSeverity.Error),
                                             (1, 3, 7, lsp.DiagnosticSeverity.Error)]
    assert found[0].message == ("unknown servo or group 'indx'\nhint: did you mean "
                                "'index'?")
    # typed, not saved: the first line fixed
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        lsp.VersionedTextDocumentIdentifier(uri=uri, version=2),
        [lsp.TextDocumentContentChangeWholeDocument(
            text="a: index 90, middle 90\nb: thum 90\nc: ring 90\n")]))
    await soon(client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS))
    assert [d.range.start.line for d in client.diagnostics[uri]] == [1]
    # a syntax error in one gesture does not hide another's
    found = await opened(client, (tmp_path / "syntax.gest").as_uri(),
                         "a: index 90 ove 1s\nb: index 9x\n")
    assert [(d.range.start.line, d.range.start.character) for d in found] == [(0, 12),
                                                                              (1, 10)]
    assert found[0].message.endswith("hint: did you mean 'over'?")


async def test_formatting_is_gestc_fmt(client, tmp_path):
    uri = (tmp_path / "f.gest").as_uri()
    assert not await opened(client, uri, "g:\n  index   90  over 1s\n")
    edits = await soon(client.text_document_formatting_async(lsp.DocumentFormattingParams(
        lsp.TextDocumentIdentifier(uri=uri), lsp.FormattingOptions(tab_size=4,
                                                                   insert_spaces=True))))
    assert [e.new_text for e in edits] == ["g:\n    index 90 over 1s\n"]


async def test_hover_and_completion_know_the_robot(client, tmp_path):
    uri = (tmp_path / "h.gest").as_uri()
    text = "pose half: fingers 90\ng: half, wrist 30 over 1s\n"
    assert not await opened(client, uri, text)
    hover_at = functools.partial(hovered, client, uri)

    assert (await hover_at(1, 10)).startswith("**servo wrist** (profile rhand): board 181 "
                                             "(right hand), pin 2; values 0..180, rest 0")
    assert await hover_at(0, 12) == "**group fingers**: thumb, index, middle, ring, pinky"
    for robot, place in (("rhand-maestro", "channel 0"), ("rhand-pca9685", "channel 0"),
                         ("rhand-mrlcomm", "pin 7")):  # a controller's servo: a channel
        other = (tmp_path / f"{robot}.gest").as_uri()
        await opened(client, other, f"robot {robot}\ng: wrist 30 over 1s\n")
        said = await hovered(client, other, 1, 4)
        assert f"), {place}; values" in said, said
    assert (await hover_at(1, 4)).startswith("**pose half**: fingers 90\n\n**step of g**")
    assert await hover_at(1, 0) == "**gesture g**: 1 step, 1.00 s as planned"
    listed = await soon(client.text_document_completion_async(lsp.CompletionParams(
        lsp.TextDocumentIdentifier(uri=uri), lsp.Position(1, 3))))
    items = {i.label: i.detail for i in listed.items}
    assert {"wrist": "servo", "fingers": "group", "half": "pose",
            "wait": "keyword"}.items() <= items.items()
    assert not {"g", "over", "ms", "pose"} & items.keys()  # g is the gesture defined
    peace = next(i for i in listed.items if i.label == "peace")  # not in scope yet
    assert peace.detail.startswith("library gesture, in peace.gest: ")
    assert apply(text, peace.additional_text_edits) == 'use "peace.gest"\n' + text


async def test_definition_references_and_outline(client, tmp_path):
    (tmp_path / "moves.gest").write_text("pose half: fingers 90\n")
    uri = (tmp_path / "main.gest").as_uri()
    text = ('use "moves.gest"\ngroup two: index, middle\ng: half, two 30 over 1s\n'
            'h:\n    g  # g again\n    half\n')
    assert not await opened(client, uri, text)

    async def defined(line, character):
        return await soon(client.text_document_definition_async(lsp.DefinitionParams(
            lsp.TextDocumentIdentifier(uri=uri), lsp.Position(line, character))))

    there = await defined(2, 4)  # 'half', in the file main uses
    assert there.uri == (tmp_path / "moves.gest").as_uri()
    assert (there.range.start.line, there.range.start.character) == (0, 5)
    here = await defined(4, 4)  # 'g', in this file
    assert here.uri == uri and here.range.start.line == 2
    found = await soon(client.text_document_references_async(lsp.ReferenceParams(
        context=lsp.ReferenceContext(include_declaration=True),
        text_document=lsp.TextDocumentIdentifier(uri=uri), position=lsp.Position(2, 4))))
    moves = (tmp_path / "moves.gest").as_uri()
    assert sorted((r.uri, r.range.start.line, r.range.start.character) for r in found) == [
        (uri, 2, 3), (uri, 5, 4), (moves, 0, 5)]  # across use; not in the comment
    found = await soon(client.text_document_references_async(lsp.ReferenceParams(
        context=lsp.ReferenceContext(include_declaration=True),
        text_document=lsp.TextDocumentIdentifier(uri=uri), position=lsp.Position(4, 4))))
    assert sorted((r.uri, r.range.start.line) for r in found) == [(uri, 2), (uri, 4)]
    symbols = await soon(client.text_document_document_symbol_async(
        lsp.DocumentSymbolParams(lsp.TextDocumentIdentifier(uri=uri))))
    assert [(s.name, s.detail) for s in symbols] == [("two", "group"), ("g", "gesture"),
                                                     ("h", "gesture")]


def apply(text: str, edits: list[lsp.TextEdit]) -> str:
    """``text`` with ``edits`` (each on one line) made, as an editor makes them."""
    lines = text.split("\n")
    for e in sorted(edits, key=lambda e: (e.range.start.line, e.range.start.character),
                    reverse=True):
        start, end = e.range.start, e.range.end
        assert start.line == end.line
        row = lines[start.line]
        lines[start.line:start.line + 1] = (row[:start.character] + e.new_text +
                                            row[end.character:]).split("\n")
    return "\n".join(lines)


async def test_inlay_hints_time_each_step_and_hover_tells_a_stretched_move(client, tmp_path):
    uri = (tmp_path / "t.gest").as_uri()
    text = "g:\n    index 180 over 0.6s\n    index 0 over 0.05s  # too fast\n    wait 1s\n"
    found = await opened(client, uri, text)
    assert [(d.range.start.line, d.severity) for d in found] == [
        (2, lsp.DiagnosticSeverity.Warning)]
    hints = await soon(client.text_document_inlay_hint_async(lsp.InlayHintParams(
        text_document=lsp.TextDocumentIdentifier(uri=uri),
        range=lsp.Range(lsp.Position(0, 0), lsp.Position(4, 0)))))
    said = {h.position.line: (h.position.character, h.label) for h in hints}
    assert said[1] == (23, "# at 0.00 s, 0.60 s")
    assert said[2][0] == 22 and said[2][1].startswith("# at 0.60 s, 0.")
    assert said[2][1].endswith("(stretched: asked 0.05 s)")
    stretched = float(said[2][1].split(", ")[1].split(" ")[0])
    assert stretched > 0.5
    assert said[3] == (11, f"# at {0.6 + stretched:.2f} s, 1.00 s")  # after the stretch
    assert text.split("\n")[1] == "    index 180 over 0.6s"  # a hint, not text
    said = await hovered(client, uri, 2, 14)
    assert "**step of g**: at 0.60 s" in said
    assert "stretched: asked 0.05 s" in said


async def test_code_actions_from_the_hints_fix_the_file(client, tmp_path):
    uri = (tmp_path / "fix.gest").as_uri()
    text = "robot rhand\n\na: indx 90\nb: peace\nc: index 180 over 0.05s\n"
    found = await opened(client, uri, text)
    assert len(found) == 3
    for version, (start, title) in enumerate((("a:", "Change to 'index'"),
                                              ("b:", "Add 'use \"peace.gest\"'"),
                                              ("c:", "Ask for 0.52 s, the time the limits "
                                                     "need")), 2):
        line = [row[:2] for row in text.split("\n")].index(start)
        actions = await soon(client.text_document_code_action_async(lsp.CodeActionParams(
            text_document=lsp.TextDocumentIdentifier(uri=uri),
            range=lsp.Range(lsp.Position(line, 0), lsp.Position(line, 0)),
            context=lsp.CodeActionContext(diagnostics=[]))))
        assert [a.title for a in actions] == [title]
        assert actions[0].kind == lsp.CodeActionKind.QuickFix and actions[0].is_preferred
        text = apply(text, actions[0].edit.changes[uri])
        found = await changed(client, uri, version, text)
    assert text == ('robot rhand\nuse "peace.gest"\n\na: index 90\nb: peace\n'
                    'c: index 180 over 0.52s\n')
    assert not found  # every problem gone


async def test_semantic_tokens_say_what_each_name_resolves_to(client, tmp_path):
    uri = (tmp_path / "s.gest").as_uri()
    text = 'pose half: fingers 90\ng: half, wrist 30 over 1s # done\nh: g & say "hi"\n'
    await opened(client, uri, text)
    answer = await soon(client.text_document_semantic_tokens_full_async(
        lsp.SemanticTokensParams(lsp.TextDocumentIdentifier(uri=uri))))
    types = client.server_legend.token_types  # as the server told it at initialize
    data, line, column, seen = answer.data, 0, 0, []
    rows = text.split("\n")
    for k in range(0, len(data), 5):
        line += data[k]
        column = data[k + 1] + (column if data[k] == 0 else 0)
        seen.append((rows[line][column:column + data[k + 2]], types[data[k + 3]],
                     data[k + 4]))
    assert seen == [("pose", "keyword", 0), ("half", "enumMember", 1),
                    ("fingers", "enum", 2), ("90", "number", 0),
                    ("g", "function", 1), ("half", "enumMember", 0), ("wrist", "variable", 2),
                    ("30", "number", 0), ("over", "keyword", 0), ("1", "number", 0),
                    ("s", "keyword", 0), ("# done", "comment", 0),
                    ("h", "function", 1), ("g", "function", 0), ("say", "keyword", 0),
                    ('"hi"', "string", 0)]


async def test_completion_in_use_and_say_lists_the_files(client, tmp_path):
    (tmp_path / "mine.gest").write_text("pose p: index 9\n")
    (tmp_path / "hello.wav").write_bytes(b"")
    uri = (tmp_path / "c.gest").as_uri()
    text = 'use "\ng: say "\n'
    await opened(client, uri, text)

    async def listed(line, character):
        got = await soon(client.text_document_completion_async(lsp.CompletionParams(
            lsp.TextDocumentIdentifier(uri=uri), lsp.Position(line, character))))
        return {i.label: i.detail for i in got.items}

    files = await listed(0, 5)
    assert files["mine.gest"] == files["peace.gest"] == "gesture file"  # beside, library
    assert "c.gest" not in files and "index" not in files
    assert await listed(1, 8) == {"hello.wav": "sound file"}


ROBOT = ClientServerConfig(server_command=SERVER)


@pytest_lsp.fixture(config=ROBOT, scope="module")
async def inmoov_client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(lsp.InitializeParams(
        capabilities=client_capabilities("visual-studio-code"),
        initialization_options={"gest": {"robot": "inmoov"}}))
    yield
    await lsp_client.shutdown_session()


async def test_the_robot_is_the_file_s_line_else_the_setting(inmoov_client, tmp_path):
    client = inmoov_client
    uri = (tmp_path / "head.gest").as_uri()
    assert not await opened(client, uri, "n: neck 120 over 1s\n")  # the setting: inmoov
    found = await changed(client, uri, 2, "robot rhand\nn: neck 120 over 1s\n")
    assert [d.message.split("\n")[0] for d in found] == ["unknown servo or group 'neck'"]
    client.workspace_did_change_configuration(lsp.DidChangeConfigurationParams(
        settings={"gest": {"robot": "rhand"}}))
    await soon(client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS))
    found = await changed(client, uri, 3, "n: neck 120 over 1s\n")
    assert found[0].message.startswith("unknown servo or group 'neck'")
    assert "robot inmoov" in found[0].message  # the hint names the robot that has it


async def test_hover_on_a_use_path_and_a_say(client, tmp_path):
    import wave

    with wave.open(str(tmp_path / "hi.wav"), "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(16000)
        w.writeframes(b"\0\1" * 12000)  # 0.75 s
    (tmp_path / "moves.gest").write_text("robot inmoov\npose up: neck 120\n")
    uri = (tmp_path / "talk.gest").as_uri()
    text = 'robot inmoov\nuse "moves.gest"\ng: say "hi.wav" & up\n'
    assert not await opened(client, uri, text)
    hover_at = functools.partial(hovered, client, uri)

    assert await hover_at(1, 8) == f"**use**: {tmp_path / 'moves.gest'}"
    assert (await hover_at(2, 11)).startswith("**say**: 0.75 s of sound (")


HAND = ["all", "fingers", "hand", "index", "middle", "pinky", "ring", "thumb", "wrist"]
MINE = 'pose half: fingers 90\nw: index 90\n'  #: a pose and a gesture of the file's own


async def offered(client: LanguageClient, uri: str, marked: str) -> list[lsp.CompletionItem]:
    """The completion items at the ``|`` of ``marked``, opened as ``uri``."""
    text = marked.replace("|", "")
    before = marked[:marked.index("|")].split("\n")
    await opened(client, uri, text)
    got = await soon(client.text_document_completion_async(lsp.CompletionParams(
        lsp.TextDocumentIdentifier(uri=uri), lsp.Position(len(before) - 1, len(before[-1])))))
    return got.items


def own(items: list[lsp.CompletionItem]) -> list[str]:
    """The labels but the library's gestures not in scope (which the library decides)."""
    return [i.label for i in items if not (i.detail or "").startswith("library gesture")]


STEP = sorted([*HAND, "half", "w"]) + ["hold", "repeat", "wait"]  #: rhand: no left, say
TIMING = ["over", "stagger", "through"]


@pytest.mark.parametrize("cases", [
    pytest.param([(MINE + "g: |", STEP, True),  # the gesture defined left out
                  (MINE + "g:\n    index 90\n    |", STEP, True),
                  (MINE + "g:\n    repeat 2: mi|", STEP, True),
                  (MINE + "g: index 90, |", sorted([*HAND, "half"]), False),  # no call
                  (MINE + "pose p: fingers 0, |", sorted([*HAND, "half"]), False),
                  ("group two: index, |", HAND[3:], False)], id="where a target starts"),
    pytest.param([("g: index 90 |", TIMING, False),
                  (MINE + "g: half st|", TIMING, False),  # a pose takes no value
                  ("g: index 90 over 2s |", ["stagger", "through"], False),
                  ("g: index 90 through |", ["over"], False),
                  ("g: index |", [], False)], id="after a target"),  # a servo: a value
    pytest.param([("g: index 90 over 2|", ["s", "ms"], False),
                  ("g: index 90 stagger 2 |", ["s", "ms"], False),
                  ("g:\n    hold 0.5|", ["s", "ms"], False)], id="after a duration"),
    pytest.param([("|\ng: index 90\n", ["group", "place", "pose", "robot", "use"], False),
                  ("# a comment\n\n|", ["group", "place", "pose", "robot", "use"], False),
                  ("g: index 90\n|", ["group", "place", "pose", "use"], False),
                  ("g: index 90\npo|", ["group", "place", "pose", "use"], False)],
                 id="a top-level line"),
    pytest.param([("g: index 90  # in|", [], False), ('robot "my|', [], False),
                  ("pose |", [], False), ("g: wait 1s |", [], False)], id="nothing"),
])
async def test_completion_offers_what_the_grammar_allows_there(client, tmp_path, cases):
    for k, (marked, labels, library) in enumerate(cases):
        items = await offered(client, (tmp_path / f"c{k}.gest").as_uri(), marked)
        assert own(items) == labels, marked
        assert ("peace" in [i.label for i in items]) == library, marked
        assert "&" not in [i.label for i in items]


async def test_completion_on_the_whole_robot(client, tmp_path):
    uri = (tmp_path / "r.gest").as_uri()
    profiles = own(await offered(client, uri, "robot |"))
    assert {"inmoov", "rhand", "rhand-maestro"} <= set(profiles) and "index" not in profiles
    part = own(await offered(client, uri, 'robot inmoov\ng: jaw 40 & |'))
    assert {"neck", "r_index", "fingers", "left", "right", "say"} <= set(part)
    assert not {"wait", "hold", "repeat", "over", "use", "g"} & set(part)
    step = own(await offered(client, uri, 'robot inmoov\nuse "peace.gest"\ng: |'))
    assert {"left", "right", "say", "wait", "peace", "neck"} <= set(step)
    called = own(await offered(client, uri, 'robot inmoov\nuse "peace.gest"\ng: left |'))
    assert "peace" in called and not {"neck", "r_index", "fingers", "g"} & set(called)
    assert not {"left", "right", "say"} & set(own(await offered(client, uri, "g: |")))


async def test_a_completion_replaces_the_word_typed(client, tmp_path):
    uri = (tmp_path / "w.gest").as_uri()
    text = "g: index 90 over 2"
    unit = next(i for i in await offered(client, uri, text + "|") if i.label == "ms")
    assert apply(text, [unit.text_edit]) == "g: index 90 over 2ms"  # right after the 2
    text = "g: ind"
    index = next(i for i in await offered(client, uri, text + "|") if i.label == "index")
    assert apply(text, [index.text_edit]) == "g: index"


async def test_a_call_is_timed_as_the_steps_it_plays(client, tmp_path):
    uri = (tmp_path / "calls.gest").as_uri()
    text = ("a:\n    index 90 over 1s\n    index 0 over 0.5s\nb: a\n"
            "c:\n    wait 1s\n    repeat 2: a\n    a & wrist 90 over 1s\n")
    assert not await opened(client, uri, text)

    async def hints(uri, lines):
        got = await soon(client.text_document_inlay_hint_async(lsp.InlayHintParams(
            text_document=lsp.TextDocumentIdentifier(uri=uri),
            range=lsp.Range(lsp.Position(0, 0), lsp.Position(lines, 0)))))
        return {h.position.line: (h.position.character, h.label) for h in got}

    said = await hints(uri, 8)
    assert said[3] == (4, "# at 0.00 s, 1.50 s")  # b: a
    assert said[6] == (15, "# at 1.00 s, 1.50 s, 2 times")  # repeat 2: a
    assert said[7] == (24, "# at 4.00 s, 1.50 s")  # a & wrist 90 over 1s, as before
    assert (await hovered(client, uri, 3, 3)).endswith("**step of b**: at 0.00 s, 1.50 s")
    # the library's demo: each call of another file's gesture, one after the other
    demo = (tmp_path / "demo.gest").as_uri()
    lines = (Path(__file__).parent.parent / "gestures" / "demo.gest").read_text().split("\n")
    assert not await opened(client, demo, "\n".join(lines))
    said = await hints(demo, len(lines))
    calls = [k for k, row in enumerate(lines) if row.strip() in ("peace", "ok", "rockon")]
    assert len(calls) == 3 and all(said[k][0] == len(lines[k]) for k in calls)
    times = [tuple(float(x.split()[-2]) for x in said[k][1].split(", ")) for k in sorted(said)]
    assert times[0][0] == 0.0 and len(times) == 11  # every step of demo, calls too
    for (start, length), (after, _) in zip(times[:-1], times[1:], strict=True):
        assert after == pytest.approx(start + length, abs=0.011)
