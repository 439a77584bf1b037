"""Helix's configuration, editors/helix/languages.toml (docs/editors.md): TOML that gives
the gest language to the project's file type, `.gest`, and starts the language server
the project installs, `gestc lsp`, as Neovim's (editors/neovim/gest.lua) and VS Code's
(editors/vscode) configurations start it; the preview is the same command in the three
editors, and the docs tell how each opens it. Helix itself is not run: it is not in
Debian 12.
"""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

import pytest

from inmoov_dsl.language.load import GEST_SUFFIX

ROOT = Path(__file__).resolve().parent.parent
HELIX = ROOT / "editors" / "helix" / "languages.toml"
NEOVIM = ROOT / "editors" / "neovim" / "gest.lua"
VSCODE = ROOT / "editors" / "vscode" / "package.json"
DOCS = ROOT / "docs" / "editors.md"


def helix() -> tuple[dict, dict]:
    """The file's gest language and the language server it names."""
    config = tomllib.loads(HELIX.read_text(encoding="utf-8"))
    language, = config["language"]
    name, = language["language-servers"]
    return language, config["language-server"][name]


def test_the_helix_file_is_a_language_and_its_server():
    """Valid TOML (tomllib), one language, gest, for the .gest files, with the comments
    and the scope the VS Code grammar has, and one server."""
    config = tomllib.loads(HELIX.read_text(encoding="utf-8"))
    assert set(config) == {"language", "language-server"}
    language, server = helix()
    assert language["name"] == "gest"
    assert [f".{t}" for t in language["file-types"]] == [GEST_SUFFIX]
    assert language["comment-token"] == "#"
    grammar, = json.loads(VSCODE.read_text(encoding="utf-8"))["contributes"]["grammars"]
    assert language["scope"] == grammar["scopeName"] == "source.gest"
    assert list(config["language-server"]) == language["language-servers"] == ["gestc"]
    assert set(server) == {"command", "args", "config"}


def test_its_command_is_the_projects_language_server():
    """`gestc` is the project's console script, and `gestc lsp` is its language server."""
    from inmoov_dsl.cli import gestc
    from inmoov_dsl.cli.gestc import lsp

    _, server = helix()
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert server["command"] in pyproject["project"]["scripts"]
    assert server["command"] == gestc.PROG
    args = gestc.parser(server["args"][0]).parse_args(server["args"])
    assert args.func is lsp.run


def test_its_config_is_what_the_server_reads():
    """`config` is sent as the initialization options: the server takes its robot."""
    pytest.importorskip("pygls")
    from inmoov_dsl.editor.documents import GestServer

    _, server = helix()
    assert set(server["config"]) <= {"robot", "library"}
    gest = GestServer()
    gest.configure({"robot": "inmoov"})
    gest.configure(server["config"])
    assert gest.robot == server["config"]["robot"]


def test_every_editor_starts_the_server_the_same_way():
    """Helix, Neovim and VS Code: the same command for the same language on the same
    files."""
    language, server = helix()
    lua = NEOVIM.read_text(encoding="utf-8")
    neovim_cmd = re.search(r"^M\.cmd = \{(.*)\}$", lua, re.M)
    assert neovim_cmd, "gest.lua sets M.cmd"
    neovim_pattern, = re.findall(r'pattern = "\*(\.[^"]+)"', lua)
    neovim_filetype, = re.findall(r'pattern = "(\w+)"', lua)
    manifest = json.loads(VSCODE.read_text(encoding="utf-8"))["contributes"]
    vscode_language, = manifest["languages"]
    commands = {
        "helix": [server["command"], *server["args"]],
        "neovim": re.findall(r'"([^"]*)"', neovim_cmd[1]),
        "vscode": manifest["configuration"]["properties"]["gest.server.command"]["default"],
    }
    assert commands == dict.fromkeys(commands, ["gestc", "lsp"])
    assert {language["name"], neovim_filetype, vscode_language["id"]} == {"gest"}
    suffixes = [*(f".{t}" for t in language["file-types"]), neovim_pattern,
                *vscode_language["extensions"]]
    assert suffixes == [GEST_SUFFIX] * 3


def test_the_docs_point_to_the_file():
    """docs/editors.md names the file and how to use it, and keeps no copy of it."""
    text = DOCS.read_text(encoding="utf-8")
    section = text[text.index("## Helix"):text.index("## ", text.index("## Helix") + 3)]
    assert "editors/helix/languages.toml" in section
    assert "~/.config/helix/languages.toml" in section
    assert "[language-server" not in re.sub(r"`[^`\n]*`", "", section)


def test_every_editor_asks_for_the_same_preview():
    """VS Code and Neovim send the server's command gest.preview, not opened by the
    server, and the cursor as gest/cursor; the docs tell how the three editors open the
    preview (Helix: the same command, by its name), in a subsection of their own."""
    extension = (ROOT / "editors" / "vscode" / "extension.js").read_text(encoding="utf-8")
    lua = NEOVIM.read_text(encoding="utf-8")
    for client in (extension, lua):
        assert re.search(r'"gest\.preview"', client)
        assert re.search(r'"gest/cursor"', client)
        assert re.search(r"\{ ?open ?[:=] ?false ?\}", client)
    assert "nvim_create_user_command(\"GestPreview\"" in lua
    text = DOCS.read_text(encoding="utf-8")
    start = text.index("### Opening the preview from an editor")
    section = text[start:text.index("\n## ", start)]
    for words in ("Gest: Open Preview to the Side", "`:GestPreview`",
                  "`:lsp-workspace-command gest.preview`", "`gest/cursor`",
                  "`window/showDocument`"):
        assert words in section
    assert "gest.preview" in HELIX.read_text(encoding="utf-8")
