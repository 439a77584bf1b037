"""Debian's Neovim, headless, with the project's editors/neovim/gest.lua: it opens a
gesture file, starts ``gestc lsp`` itself, and reads back the diagnostics the server
published (a client we did not write, as a user's editor runs it)."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

from toolchain import need

ROOT = Path(__file__).resolve().parents[1]
INIT = """
vim.opt.runtimepath:prepend({lua_dir!r})
local gest = require("gest")
gest.cmd = {cmd}
gest.settings = {{ robot = "inmoov" }}
vim.cmd("edit " .. vim.env.GEST_FILE)
local ok = vim.wait(60000, function() return #vim.diagnostic.get(0) >= 2 end, 50)
local lines = {{ vim.bo.filetype .. " " .. tostring(ok) }}
for _, d in ipairs(vim.diagnostic.get(0)) do
  table.insert(lines, string.format("%d:%d:%d:%s", d.lnum, d.col, d.severity,
    (d.message:gsub("\\n", " | "))))
end
vim.fn.writefile(lines, vim.env.GEST_OUT)
vim.cmd("qa!")
"""


def test_neovim_attaches_gestc_lsp_and_shows_its_diagnostics(tmp_path):
    need("nvim", packages="neovim")
    lua = tmp_path / "lua"
    lua.mkdir()
    shutil.copy(ROOT / "editors" / "neovim" / "gest.lua", lua / "gest.lua")
    cmd = "{ " + ", ".join(f'"{a}"' for a in (sys.executable, "-m",
                                                "inmoov_dsl.cli.gestc", "lsp")) + " }"
    (tmp_path / "init.lua").write_text(INIT.format(lua_dir=str(tmp_path), cmd=cmd))
    gesture = tmp_path / "head.gest"
    gesture.write_text("a: nek 90\nb: neck 120 over 0.05s\n")  # neck: the setting's robot
    out = tmp_path / "out.txt"
    env = {**os.environ, "GEST_FILE": str(gesture), "GEST_OUT": str(out),
           "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    subprocess.run(["nvim", "--headless", "--clean", "-u", str(tmp_path / "init.lua")],
                   env=env, cwd=tmp_path, timeout=120, check=True, capture_output=True)
    head, *found = out.read_text().splitlines()
    assert head == "gest true"
    assert found == [
        "0:3:1:unknown servo or group 'nek' | hint: did you mean 'neck'?",
        found[1]]
    assert found[1].startswith("1:17:2:move stretched: needs ")
