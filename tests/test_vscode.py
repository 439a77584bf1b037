"""The VS Code extension (editors/vscode). Its TextMate grammar gives every token of
every library file the scope the project's own lexer (Lark, grammar/gest.lark) says it
has, checked by a tool we did not write (vscode-tmgrammar-test) on test files made here
from the lexer's tokens; `npm ci` and the packager (vsce) print no warning, and the .vsix
carries what VS Code needs and nothing else: one JavaScript file that esbuild bundles
(the client and the language client library, no node_modules), which loads in Node with
nothing beside it but VS Code's own module; the client starts the configured command and
tells it the robot. The preview (Gest: Open Preview to the Side): the server's page asked
for and shown in a panel beside, one per document, the cursor told, a click on the page
shown in the document's column; in a stand-in for VS Code (tests/vscode_host.js), and the
packaged bundle with its real language client against a stand-in server.

The tests that run node skip without node and npm, except under CI=true, where that
fails."""

from __future__ import annotations

import functools
import json
import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest
from lark import Lark, Token
from test_neovim import received, stand_in_server
from toolchain import need

from inmoov_dsl.language.indent import GestIndenter
from inmoov_dsl.language.syntax import KEYWORDS

ROOT = Path(__file__).resolve().parent.parent
EXTENSION = ROOT / "editors" / "vscode"
BUNDLE = "dist/extension.js"  #: what esbuild writes and the manifest's main names
PREVIEW = "gest.openPreviewToSide"  #: the command that opens the preview beside
GRAMMAR = EXTENSION / "syntaxes" / "gest.tmLanguage.json"
LIBRARY = sorted((ROOT / "gestures").glob("*.gest"))

KEYWORD = "keyword.control.gest"
NAME = "variable.other.gest"
DEFINED = "entity.name.function.gest"  #: the name a gesture, pose or group line defines
COMMENT = "comment.line.number-sign.gest"
#: the scope of each other kind of token (Lark's terminal); a keyword is one of KEYWORDS
SCOPES = {
    "NUMBER": "constant.numeric.gest",
    "UNIT": "keyword.other.unit.gest",
    "STRING": "string.quoted.double.gest",
    "ROBOT_NAME": NAME,  # robot rhand-maestro
    "COLON": "punctuation.separator.colon.gest",
    "COMMA": "punctuation.separator.comma.gest",
    "AMPERSAND": "punctuation.separator.together.gest",
    "HAND": "keyword.other.place.gest",  # right hand to (350, -200, 300) mm, look at cup
    "TO": "keyword.other.place.gest",
    "AT": "keyword.other.place.gest",
    "LPAR": "punctuation.section.parens.begin.gest",
    "RPAR": "punctuation.section.parens.end.gest",
}
#: what the library does not write: a robot with a dash, a group, left and right,
#: through, &, a unit after a space, a line continued (its backslash is no token)
SAMPLES = {
    "sample_robot.gest": """\
robot rhand-maestro   # a built-in profile
use "peace.gest"
group wave_order: pinky, ring, middle, index
pose half: index 90, middle 90
sweep:
    wrist 90 over 1 s through
    left peace & right peace
    wave_order 90 stagger 80ms
    half, thumb 0, index 90, \\
        middle 90 over .5s
    hold 0.5 ms
    repeat 2: half
""",
    "sample_file.gest": """\
robot "my_hand.toml"
hello: say "Hello" & index 90
""",
}
#: a source line the tool would take for an assertion (and drop from the source)
LOOKS_LIKE_ASSERTION = re.compile(r"#\s*(\^|<~*-+)")


class _Tap(GestIndenter):
    """The project's indenter, keeping every token the lexer gives it (comments are in
    the newline tokens; whitespace and line continuations are ignored by the lexer)."""

    def process(self, stream):
        self.seen: list[Token] = []
        return super().process(self._keep(stream))

    def _keep(self, stream):
        for tok in stream:
            self.seen.append(tok)
            yield tok


@functools.cache
def _lexer() -> tuple[Lark, _Tap]:
    tap = _Tap()
    grammar = (ROOT / "grammar" / "gest.lark").read_text(encoding="utf-8")
    return Lark(grammar, parser="lalr", lexer="contextual", postlex=tap,
                maybe_placeholders=False), tap


def expected(text: str) -> dict[int, list[tuple[int, int, str]]]:
    """Line (1-based) -> (column (0-based), width, scope) of each token of ``text``, from
    the project's lexer and parse tree, not from the TextMate grammar."""
    lark, tap = _lexer()
    tree = lark.parse(text)
    defined = {(t.children[0].line, t.children[0].column) for t in tree.iter_subtrees()
               if t.data in ("gesture_line", "gesture_block", "pose_def", "group_def")}
    marks: dict[int, list[tuple[int, int, str]]] = {}
    for tok in tap.seen:
        if tok.type == "_NL":  # newlines, indentation and comments
            for comment in re.finditer(r"#[^\r\n]*", str(tok)):
                before = str(tok)[:comment.start()]
                line = tok.line + before.count("\n")
                column = (tok.column - 1 if "\n" not in before
                          else len(before) - before.rindex("\n") - 1)
                marks.setdefault(line, []).append((column, len(comment[0]), COMMENT))
            continue
        if tok.type == "NAME":
            scope = DEFINED if (tok.line, tok.column) in defined else NAME
        elif str(tok) in KEYWORDS:
            scope = KEYWORD
        else:
            assert tok.type in SCOPES, f"no scope expected for a {tok.type} ({tok!r})"
            scope = SCOPES[tok.type]
        marks.setdefault(tok.line, []).append((tok.column - 1, len(tok), scope))
    return marks


def annotated(text: str, title: str) -> str:
    """``text`` as vscode-tmgrammar-test's test case: a header, then each line followed
    by an assertion line per token (``<---`` for one at the start of the line)."""
    marks = expected(text)
    out = [f'# SYNTAX TEST "source.gest" "{title}"']
    for number, line in enumerate(text.removesuffix("\n").split("\n"), 1):
        assert not LOOKS_LIKE_ASSERTION.match(line), f"{title}:{number} reads as an assertion"
        out.append(line)
        for column, width, scope in sorted(marks.get(number, [])):
            out.append(f"#<{'-' * width} {scope}" if column == 0
                       else f"#{' ' * (column - 1)}{'^' * width} {scope}")
    return "\n".join(out) + "\n"


def cases_texts() -> dict[str, str]:
    """Every library file, and the samples: name -> text."""
    return {p.name: p.read_text(encoding="utf-8") for p in LIBRARY} | SAMPLES


@pytest.mark.parametrize("name", list(cases_texts()))
def test_every_character_gets_an_expected_scope(name):
    """The expectations are complete: every character of every line but blanks (and a
    continuing backslash) is in a token given a scope."""
    text = cases_texts()[name]
    marks = expected(text)
    for number, line in enumerate(text.split("\n"), 1):
        covered = {c for column, width, _ in marks.get(number, [])
                   for c in range(column, column + width)}
        bare = [c for c, char in enumerate(line) if not char.isspace() and c not in covered
                and line[c:].rstrip() != "\\"]
        assert not bare, f"{name}:{number}: no token at columns {bare}: {line!r}"


def test_the_grammar_knows_the_languages_keywords():
    """One rule of the TextMate grammar lists the keywords, exactly KEYWORDS, and it alone
    gives a keyword's scope."""
    grammar = json.loads(GRAMMAR.read_text(encoding="utf-8"))
    rule = grammar["repository"]["keywords"]
    listed = re.fullmatch(r"\(\?<!\[A-Za-z0-9_\]\)\(\?:([a-z|]+)\)\(\?!\[A-Za-z0-9_\]\)",
                          rule["match"])
    assert listed, rule["match"]
    assert sorted(listed[1].split("|")) == sorted(KEYWORDS)
    assert rule["name"] == KEYWORD
    assert json.dumps(grammar).count(f'"{KEYWORD}"') == 1


def _run(args: list, cwd: Path, timeout: float = 300) -> subprocess.CompletedProcess:
    env = {**os.environ, "FORCE_COLOR": "0", "npm_config_update_notifier": "false"}
    return subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=timeout)


def warnings(done: subprocess.CompletedProcess) -> list[str]:
    """The lines of a command's output, standard error too, that warn: npm's `npm warn`
    (`npm WARN` before npm 9), vsce's ` WARNING `, esbuild's `[WARNING]`; not npm's
    echo of a script it runs (`> esbuild ... --log-level=warning`)."""
    return [line for line in (done.stdout + done.stderr).splitlines()
            if re.search(r"warn", line, re.I) and not line.startswith("> ")]


@pytest.fixture(scope="session")
def npm_ci(tmp_path_factory) -> tuple[Path, subprocess.CompletedProcess]:
    """A copy of the extension (no node_modules, no build output) and what `npm ci` did
    in it, as the docs run it (no audit: not a warning, and a registry call), once a
    session."""
    need("node", "npm", packages="nodejs npm")
    work = tmp_path_factory.mktemp("vscode") / "vscode"
    shutil.copytree(EXTENSION, work,
                    ignore=shutil.ignore_patterns("node_modules", "*.vsix", "dist"))
    done = _run(["npm", "ci", "--no-audit", "--no-fund", "--prefer-offline"], work,
                timeout=600)
    return work, done


@pytest.fixture(scope="session")
def installed(npm_ci) -> Path:
    """The copy of the extension with its locked node modules."""
    work, done = npm_ci
    assert done.returncode == 0, done.stdout + done.stderr
    return work


@pytest.fixture(scope="session")
def packaged(installed) -> tuple[subprocess.CompletedProcess, Path]:
    """`npm run package` (vsce, which bundles first) and the .vsix it made, once."""
    done = _run(["npm", "run", "package"], installed)
    assert done.returncode == 0, done.stdout + done.stderr
    version = json.loads((installed / "package.json").read_text())["version"]
    return done, installed / f"inmoov-gest-{version}.vsix"


def test_npm_ci_prints_no_warning(npm_ci):
    """No deprecated package, no install script left undecided (package.json's
    allowScripts declines vsce-sign's and esbuild's), nothing else to warn of."""
    _, done = npm_ci
    assert done.returncode == 0, done.stdout + done.stderr
    assert warnings(done) == [], done.stdout + done.stderr
    assert re.search(r"added \d+ packages", done.stdout), done.stdout


@pytest.fixture(scope="session")
def cases(tmp_path_factory) -> Path:
    """The test cases, one file each, in a folder of their own (no package.json there:
    the tool would load that one's grammar too)."""
    folder = tmp_path_factory.mktemp("tmgrammar")
    for name, text in cases_texts().items():
        (folder / name).write_text(annotated(text, name), encoding="utf-8")
    return folder


def grammar_test(installed: Path, cases: Path, grammar: Path) -> subprocess.CompletedProcess:
    tool = installed / "node_modules" / ".bin" / "vscode-tmgrammar-test"
    return _run([tool, "--compact", "-g", grammar, *sorted(p.name for p in cases.iterdir())],
                cases)


def test_the_grammar_scopes_every_token_of_the_library(installed, cases):
    done = grammar_test(installed, cases, GRAMMAR)
    assert done.returncode == 0, done.stdout + done.stderr
    passed = set(re.findall(r"(\S+\.gest) run successfuly", done.stdout))
    assert passed == set(cases_texts()), done.stdout
    asserted = sum(line.startswith("#<") or line.lstrip("#").lstrip().startswith("^")
                   for p in cases.iterdir() for line in p.read_text().splitlines()[1:])
    assert asserted > 1000  # every token of 13 files, not a handful


def test_a_grammar_without_its_keyword_rule_fails(installed, cases, tmp_path):
    grammar = json.loads(GRAMMAR.read_text(encoding="utf-8"))
    del grammar["repository"]["keywords"]
    grammar["patterns"].remove({"include": "#keywords"})
    broken = tmp_path / "broken.tmLanguage.json"
    broken.write_text(json.dumps(grammar), encoding="utf-8")
    done = grammar_test(installed, cases, broken)
    assert done.returncode != 0
    errors = re.findall(r"^ERROR (\S+?\.gest):\d+:\d+:\d+ (.*)", done.stdout, re.M)
    assert errors, done.stdout
    assert {why for _, why in errors} == {
        f"Missing required scopes: [ {KEYWORD} ] actual scopes: [source.gest {NAME}]"}
    with_keywords = {name for name, text in cases_texts().items()
                     if any(scope == KEYWORD for marks in expected(text).values()
                            for *_, scope in marks)}
    assert {name for name, _ in errors} == with_keywords


def test_the_bundle_is_built_not_kept():
    """`npm run bundle` (esbuild) writes dist/extension.js from extension.js, vsce runs
    it before it packages, the manifest's main is it, and git ignores it."""
    manifest = json.loads((EXTENSION / "package.json").read_text(encoding="utf-8"))
    assert manifest["main"] == f"./{BUNDLE}"
    bundle = manifest["scripts"]["bundle"].split()
    assert bundle[:3] == ["esbuild", "extension.js", "--bundle"]
    assert {f"--outfile={BUNDLE}", "--external:vscode", "--platform=node",
            "--format=cjs"} <= set(bundle)
    assert manifest["scripts"]["vscode:prepublish"] == "npm run bundle"
    assert "esbuild" in manifest["devDependencies"]
    lock = json.loads((EXTENSION / "package-lock.json").read_text(encoding="utf-8"))
    assert lock["packages"][""]["devDependencies"] == manifest["devDependencies"]
    assert lock["packages"][""]["dependencies"] == manifest["dependencies"]
    assert "dist/" in (EXTENSION / ".gitignore").read_text(encoding="utf-8").split()


def test_the_extension_packages(packaged):
    done, path = packaged
    assert warnings(done) == [], done.stdout + done.stderr
    with zipfile.ZipFile(path) as vsix:
        names = set(vsix.namelist())
        manifest = json.loads(vsix.read("extension/package.json"))
        grammar = vsix.read("extension/syntaxes/gest.tmLanguage.json")
    # what VS Code reads, and one JavaScript file: no node_modules, no source, no tools
    assert names == {"extension.vsixmanifest", "[Content_Types].xml",
                     "extension/package.json", "extension/readme.md", "extension/LICENSE.txt",
                     "extension/language-configuration.json",
                     "extension/syntaxes/gest.tmLanguage.json", f"extension/{BUNDLE}"}
    assert not [n for n in names if "node_modules" in n]
    assert [n for n in names if n.endswith(".js")] == [f"extension/{BUNDLE}"]
    assert grammar == GRAMMAR.read_bytes()
    language, = manifest["contributes"]["languages"]
    assert (language["id"], language["extensions"]) == ("gest", [".gest"])
    assert f"extension/{language['configuration'].removeprefix('./')}" in names
    grammar_entry, = manifest["contributes"]["grammars"]
    assert (grammar_entry["language"], grammar_entry["scopeName"]) == ("gest", "source.gest")
    settings = manifest["contributes"]["configuration"]["properties"]
    assert " ".join(settings["gest.server.command"]["default"]) == "gestc lsp"
    assert settings["gest.robot"]["default"] == ""
    assert "onLanguage:gest" in manifest["activationEvents"]
    assert manifest["main"] == f"./{BUNDLE}"
    # the preview's command: in the palette and the editor's title bar of gest files, on
    # a key, as Markdown's "Open Preview to the Side" is
    command, = manifest["contributes"]["commands"]
    assert command == {"command": PREVIEW, "title": "Open Preview to the Side",
                       "category": "Gest", "icon": "$(open-preview)"}
    menus = manifest["contributes"]["menus"]
    assert menus["editor/title"] == [{"command": PREVIEW, "when": "editorLangId == gest",
                                      "group": "navigation"}]
    assert menus["commandPalette"] == [{"command": PREVIEW, "when": "editorLangId == gest"}]
    key, = manifest["contributes"]["keybindings"]
    assert key == {"command": PREVIEW, "key": "ctrl+k v", "mac": "cmd+k v",
                   "when": "editorLangId == gest"}


#: Node: load the bundle (argv[2]) as VS Code does, with a stand-in for the vscode module
#: that answers whatever the bundled language client reads of it as it loads; activate
#: it with a command setting that is no command (the extension says so and starts
#: nothing), deactivate it; print what the bundle required and showed, as JSON.
LOAD_BUNDLE = r"""
"use strict";
const Module = require("module");
const bundle = require("path").resolve(process.argv[2]);
const required = new Set();
const errors = [];
const settings = { "server.command": [], robot: "" };

/** What the stand-in answers for a name it does not know: a class, whose members are
 * more of them (the client extends some of VS Code's classes as it loads). */
function anything() {
    return new Proxy(function () {}, {
        get: (target, key) => (key in target ? target[key] : (target[key] = anything())),
    });
}

/** ``members``, and more of anything() for the names it does not have. */
function namespace(members) {
    return new Proxy(members, {
        get: (target, key) => (key in target ? target[key] : (target[key] = anything())),
    });
}

const vscode = namespace({
    workspace: namespace({
        getConfiguration: () => ({ get: (key) => settings[key] }),
        onDidChangeConfiguration: () => ({ dispose() {} }),
    }),
    window: namespace({ showErrorMessage: (message) => errors.push(message) }),
});

const load = Module._load;
Module._load = function (request, parent, ...rest) {
    if (parent && parent.filename === bundle) {
        required.add(request);
    }
    return request === "vscode" ? vscode : load.call(this, request, parent, ...rest);
};

(async () => {
    const extension = require(bundle);
    await extension.activate({ subscriptions: [] });
    await extension.deactivate();
    console.log(JSON.stringify({
        exports: Object.keys(extension).sort(),
        required: [...required].filter((r) => r !== "vscode" && !Module.isBuiltin(r)),
        errors,
    }));
})();
"""


def test_the_bundle_loads_alone(packaged, tmp_path):
    """The .vsix's dist/extension.js, alone in a folder (no node_modules anywhere
    above it), loads in Node with a stand-in for VS Code's module: it requires nothing
    else but Node's own modules, exports activate and deactivate, and runs the
    extension's code (a command setting that is no command is told, and nothing
    starts)."""
    _, path = packaged
    with zipfile.ZipFile(path) as vsix:
        code = vsix.read(f"extension/{BUNDLE}")
    alone = tmp_path / "extension.js"
    alone.write_bytes(code)
    loader = tmp_path / "load_bundle.js"
    loader.write_text(LOAD_BUNDLE, encoding="utf-8")
    done = _run(["node", loader, alone], tmp_path, timeout=60)
    assert done.returncode == 0, done.stderr[-4000:]
    seen = json.loads(done.stdout)
    assert seen["exports"] == ["activate", "deactivate"]
    assert seen["required"] == [], "the bundle requires only vscode and Node's modules"
    error, = seen["errors"]
    assert error.startswith("Gest: gest.server.command must be a list of strings"), error
    assert b"inmoov-dsl[lsp]" in code  # the extension's own text, bundled


def host(settings: dict, scenario: str = "settings") -> dict:
    """What extension.js asked of the stand-in for VS Code (tests/vscode_host.js) in
    ``scenario``, activated with ``settings``."""
    need("node", packages="nodejs npm")
    done = _run(["node", ROOT / "tests" / "vscode_host.js", EXTENSION / "extension.js",
                 json.dumps(settings), scenario], ROOT, timeout=180)
    assert done.returncode == 0, done.stdout + done.stderr
    return json.loads(done.stdout)


def test_the_client_starts_the_command_and_tells_it_the_robot():
    """extension.js in a stand-in for VS Code (tests/vscode_host.js): the configured
    command on stdio as it is (no --stdio added), the robot at start and on change, and a
    new command restarts the server."""
    seen = host({"gest.server.command": ["gestc", "lsp"], "gest.robot": "inmoov"})
    assert seen["errors"] == []
    first, second = seen["clients"]
    assert first["serverOptions"] == {"command": "gestc", "args": ["lsp"]}
    assert {s["language"] for s in first["clientOptions"]["documentSelector"]} == {"gest"}
    assert first["clientOptions"]["initializationOptions"] == {"robot": "inmoov"}
    assert first["notifications"] == [{"method": "workspace/didChangeConfiguration",
                                       "params": {"settings": {"gest": {
                                           "robot": "rhand-maestro"}}}}]
    assert first["started"] and first["stopped"]
    assert second["serverOptions"] == {"command": "/opt/venv/bin/gestc", "args": ["lsp"]}
    assert second["clientOptions"]["initializationOptions"] == {"robot": "rhand-maestro"}
    assert second["started"] and second["stopped"]


#: what VS Code's ViewColumn.Beside is
BESIDE = -2
#: the page the stand-in's server answers gest.preview with, by the client's number
PAGE = "http://127.0.0.1:{}/preview"
HAND, OTHER, BROKEN, README = (f"file:///work/{name}" for name in (
    "hand.gest", "other%20hand.gest", "broken.gest", "README.md"))


def asked(uri: str) -> dict:
    """The request for ``uri``'s page, as the contract has it."""
    return {"method": "workspace/executeCommand",
            "params": {"command": "gest.preview", "arguments": [uri, {"open": False}]}}


def cursor(uri: str, line: int, character: int) -> dict:
    return {"method": "gest/cursor", "params": {"textDocument": {"uri": uri},
                                                "position": {"line": line,
                                                             "character": character}}}


def framed(html: str) -> tuple[dict[str, list[str]], list[str]]:
    """The Content-Security-Policy of a webview's page (directive -> sources) and the
    addresses of its frames."""
    policy, = re.findall(r'<meta http-equiv="Content-Security-Policy" content="([^"]*)">',
                         html)
    directives = {name: sources for name, *sources in
                  (part.split() for part in policy.split(";") if part.strip())}
    return directives, re.findall(r'<iframe src="([^"]*)"', html)


@pytest.fixture(scope="module")
def previewed() -> dict:
    """The stand-in's preview scenario: previews opened, shown again, closed, refused;
    cursors moved; clicks on the page; the server's command changed."""
    return host({"gest.server.command": ["gestc", "lsp"], "gest.robot": ""}, "preview")


def test_the_preview_opens_beside_on_the_servers_page(previewed):
    """Gest: Open Preview to the Side asks the server for the document's page
    (gest.preview, not opened by the server) and shows it in a panel beside the editor,
    in an iframe that the page's policy lets in, and nothing else; the cursor is told."""
    assert previewed["commands"] == [PREVIEW]
    client = previewed["clients"][0]
    opened = previewed["steps"]["opened"]
    assert client["requests"][:opened["requests"]] == [asked(HAND)]
    assert client["notifications"][:opened["notifications"]] == [cursor(HAND, 2, 4)]
    assert opened["panels"] == 1
    panel = previewed["panels"][0]
    assert panel["viewType"] == "gest.previewPanel"
    assert panel["title"] == "Preview: hand.gest"
    assert panel["showOptions"] == {"viewColumn": BESIDE, "preserveFocus": True}
    assert panel["options"]["enableScripts"] is True  # the page's own scripts, in its frame
    policy, frames = framed(panel["htmls"][0])
    assert frames == [PAGE.format(8000)]
    assert policy["default-src"] == ["'none'"]
    assert policy["frame-src"] == ["http://127.0.0.1:*"]
    style, = policy.pop("style-src")
    assert re.fullmatch(r"'nonce-[A-Za-z0-9+/]+={0,2}'", style)
    assert set(policy) == {"default-src", "frame-src"}  # no script, nothing remote
    assert "<script" not in panel["htmls"][0]


def test_the_cursor_is_told_for_gest_files_once_it_stops(previewed):
    """gest/cursor for the cursor of a gest file as it moves (its last place always;
    maybe not the places it only went through) and for the editor that becomes the active
    one; never for another language's file."""
    notifications = previewed["clients"][0]["notifications"]
    moved = previewed["steps"]["moved"]["notifications"]
    again = previewed["steps"]["again"]["notifications"]
    assert all(n["method"] == "gest/cursor" for n in notifications)
    assert not [n for n in notifications if n["params"]["textDocument"]["uri"] == README]
    while_moving = notifications[again:moved]
    assert while_moving[-1] == cursor(HAND, 5, 1)
    assert {(p["line"], p["character"]) for n in while_moving
            for p in [n["params"]["position"]]} <= {(3, 0), (4, 2), (5, 1)}
    assert cursor(OTHER, 9, 3) in notifications[moved:]


def test_a_click_on_the_page_shows_the_step_in_the_editor_not_over_the_preview(previewed):
    """window/showDocument (a click on a step of the page) goes to the column that shows
    the document, or, from the preview, to its document's column; a page for the browser,
    or a document neither shows, is the language client's own (next)."""
    selection = {"start": {"line": 1, "character": 4}, "end": {"line": 1, "character": 9}}
    assert previewed["shown"] == [
        {"uri": HAND, "options": {"viewColumn": 1, "preserveFocus": False,
                                  "selection": {"converted": selection}}},
        {"uri": "file:///work/third.gest",
         "options": {"viewColumn": 1, "preserveFocus": True,
                     "selection": {"converted": selection}}}]
    assert previewed["next"] == [
        {"uri": "http://127.0.0.1:8000/", "external": True},
        {"uri": "file:///work/third.gest", "selection": selection}]
    assert previewed["clicks"] == [{"success": True}] * 4


def test_a_preview_per_document_closed_cleanly(previewed):
    """Shown again while open (asked again: the page may have moved), made again once
    closed; another document has its own; a document the server has no page for, or a
    file that is no gesture file, is told and gets none; all closed with the extension."""
    again, reopened, refused = (previewed["steps"][s] for s in ("again", "reopened",
                                                                 "refused"))
    first, second, third = previewed["panels"]
    assert again["panels"] == 1 and again["requests"] == 2
    assert first["reveals"] == [{"column": 2, "preserveFocus": True}]
    assert first["htmls"][1:] == []  # the same page: not loaded again
    assert reopened["panels"] == 2 and second["title"] == "Preview: hand.gest"
    assert third["title"] == "Preview: other hand.gest"
    assert framed(third["htmls"][0])[1] == [PAGE.format(8000)]
    client = previewed["clients"][0]
    assert client["requests"][reopened["requests"]:] == [asked(OTHER), asked(BROKEN)]
    assert refused["panels"] == 3
    assert previewed["errors"] == ["Gest: no preview (no page for you).",
                                   "Gest: the preview is of a .gest file: open one first."]
    assert all(panel["disposed"] for panel in previewed["panels"])


def test_a_new_server_gives_the_open_previews_its_page(previewed):
    """The server's command changed: the open previews ask the new server for their
    pages and show them."""
    _, second, third = previewed["panels"]
    restarted = previewed["clients"][1]
    assert sorted(r["params"]["arguments"][0] for r in restarted["requests"]) == [
        HAND, OTHER]
    assert all(r == asked(r["params"]["arguments"][0]) for r in restarted["requests"])
    for panel in (second, third):
        assert framed(panel["htmls"][-1])[1] == [PAGE.format(8001)]


def test_the_packaged_extension_previews_through_the_language_client(packaged, tmp_path):
    """The .vsix's dist/extension.js, with the language client bundled in it, in the
    stand-in for VS Code, talking to a stand-in server (tests/test_neovim.py's) over
    stdio: the preview asked with the document's URI and {open: false} and shown beside
    on the page answered, the cursor told as it moves, and a click on the page
    (window/showDocument) shown in the document's column with its selection, answered
    {success: true}."""
    _, path = packaged
    with zipfile.ZipFile(path) as vsix:
        bundle = tmp_path / "extension.js"
        bundle.write_bytes(vsix.read(f"extension/{BUNDLE}"))
    command, log = stand_in_server(tmp_path, port=8766)
    gesture = tmp_path / "hand.gest"
    gesture.write_text("a: index 90\nb: index 0 over 0.5s\nc: thumb 9\n", encoding="utf-8")
    done = _run(["node", ROOT / "tests" / "vscode_host.js", bundle,
                 json.dumps({"gest.server.command": command, "gest.robot": ""}), "live",
                 log, gesture], tmp_path, timeout=180)
    assert done.returncode == 0, done.stdout + done.stderr
    seen = json.loads(done.stdout)
    assert seen["errors"] == []
    uri = gesture.as_uri()
    messages = received(log)
    methods = [m.get("method") for m in messages]
    assert methods[:3] == ["initialize", "initialized", "textDocument/didOpen"]
    assert methods[-2:] == ["shutdown", "exit"]
    assert [m["params"] for m in messages if m.get("method") == "workspace/executeCommand"
            and m["params"]["command"] == "gest.preview"] == [
        {"command": "gest.preview", "arguments": [uri, {"open": False}]}]
    panel, = seen["panels"]
    assert panel["title"] == "Preview: hand.gest"
    assert panel["showOptions"] == {"viewColumn": BESIDE, "preserveFocus": True}
    assert framed(panel["htmls"][0])[1] == ["http://127.0.0.1:8766/preview"]
    cursors = [m for m in messages if m.get("method") == "gest/cursor"]
    assert cursors[0] == {"jsonrpc": "2.0", **cursor(uri, 0, 0)}  # as the preview opened
    assert {"jsonrpc": "2.0", **cursor(uri, 1, 3)} in cursors[1:]
    selection = {"start": {"line": 2, "character": 1}, "end": {"line": 2, "character": 4}}
    assert seen["shown"] == [{"uri": uri, "options": {"viewColumn": 1, "preserveFocus": False,
                                                      "selection": selection}}]
    assert [m.get("result") for m in messages if m.get("id") == "click-1"] == [
        {"success": True}]
    assert panel["disposed"]
