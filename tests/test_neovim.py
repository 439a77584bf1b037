"""Debian's Neovim, headless, with the project's editors/neovim/gest.lua: it opens a
gesture file, starts ``gestc lsp`` itself, and reads back the diagnostics the server
published (a client we did not write, as a user's editor runs it)."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

from test_cli import EVERY_ERROR
from toolchain import need

ROOT = Path(__file__).resolve().parents[1]
INIT = """
vim.opt.runtimepath:prepend({lua_dir!r})
local gest = require("gest")
gest.cmd = {cmd}
gest.settings = {{ robot = "inmoov" }}
vim.cmd("edit " .. vim.env.GEST_FILE)
local want = tonumber(vim.env.GEST_COUNT)
local ok = vim.wait(60000, function() return #vim.diagnostic.get(0) >= want end, 50)
local lines = {{ vim.bo.filetype .. " " .. tostring(ok) }}
for _, d in ipairs(vim.diagnostic.get(0)) do
  table.insert(lines, string.format("%d:%d:%d:%s", d.lnum, d.col, d.severity,
    (d.message:gsub("\\n", " | "))))
end
vim.fn.writefile(lines, vim.env.GEST_OUT)
vim.cmd("qa!")
"""


def neovim_diagnostics(tmp_path: Path, gesture: Path, count: int) -> tuple[str, list[str]]:
    """The diagnostics headless Neovim shows for ``gesture`` once it has ``count`` (as
    ``line:col:severity:message``, from 0), and its first line (filetype, waited)."""
    need("nvim", packages="neovim")
    lua = tmp_path / "lua"
    lua.mkdir(exist_ok=True)
    shutil.copy(ROOT / "editors" / "neovim" / "gest.lua", lua / "gest.lua")
    cmd = "{ " + ", ".join(f'"{a}"' for a in (sys.executable, "-m",
                                                "inmoov_dsl.cli.gestc", "lsp")) + " }"
    (tmp_path / "init.lua").write_text(INIT.format(lua_dir=str(tmp_path), cmd=cmd))
    out = tmp_path / "out.txt"
    env = {**os.environ, "GEST_FILE": str(gesture), "GEST_OUT": str(out),
           "GEST_COUNT": str(count),
           "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    subprocess.run(["nvim", "--headless", "--clean", "-u", str(tmp_path / "init.lua")],
                   env=env, cwd=tmp_path, timeout=120, check=True, capture_output=True)
    head, *found = out.read_text().splitlines()
    return head, found


def test_neovim_attaches_gestc_lsp_and_shows_its_diagnostics(tmp_path):
    gesture = tmp_path / "head.gest"
    gesture.write_text("a: nek 90\nb: neck 120 over 0.05s\n")  # neck: the setting's robot
    head, found = neovim_diagnostics(tmp_path, gesture, 2)
    assert head == "gest true"
    assert found == [
        "0:3:1:unknown servo or group 'nek' | hint: did you mean 'neck'?",
        found[1]]
    assert found[1].startswith("1:17:2:move stretched: needs ")


def test_neovim_shows_every_error_gestc_check_tells(tmp_path):
    """The file with a mistake of every kind, several to a step: Neovim lists what
    ``gestc check`` tells, at the same places."""
    gesture = tmp_path / "every_error.gest"
    shutil.copy(ROOT / "tests" / "data" / "every_error.gest", gesture)
    head, found = neovim_diagnostics(tmp_path, gesture, len(EVERY_ERROR))
    assert head == "gest true"
    assert [(f"{int(line) + 1}", f"{int(col) + 1}", message.split(" | ")[0])
            for line, col, _, message in (d.split(":", 3) for d in found)] == EVERY_ERROR
