-- Gesture files in Neovim (0.7 and later): the gest filetype, and `gestc lsp` attached to
-- each gesture buffer (one server for the gesture files of a folder). Put this file in
-- ~/.config/nvim/lua/ and `require("gest")` from init.lua, or copy its lines there
-- (docs/editors.md).
--
-- The preview: :GestPreview asks the server for the page of the buffer's gestures
-- (workspace/executeCommand gest.preview {uri, {open = false}}, answered {url}) and opens
-- it in the browser (vim.ui.open, Neovim 0.10 and later; before, the URL is echoed to be
-- opened by hand); the cursor of every gesture buffer is told to the server as it moves
-- (gest/cursor), which marks the step under it on the page. A click on a step of the page
-- comes back as window/showDocument: Neovim 0.8 and later show it themselves, this file
-- does on 0.7.
local M = {}

-- settings sent to the server: { robot = "inmoov" } for files without a robot line
M.settings = {}
M.cmd = { "gestc", "lsp" }
-- ms: the cursor is told to the server once it has stopped this long
M.cursor_delay = 50

local NAME = "gestc"
local clients = {} -- before Neovim 0.10: the client of each folder, by its path
local group = vim.api.nvim_create_augroup("gest_cursor", { clear = true })
local timer

local function has(version)
  return vim.fn.has("nvim-" .. version) == 1
end

-- a client's request and notification: methods from Neovim 0.11, functions before
local function request(client, method, params, handler, buffer)
  if has("0.11") then
    return client:request(method, params, handler, buffer)
  end
  return client.request(method, params, handler, buffer)
end

local function notify(client, method, params)
  if has("0.11") then
    return client:notify(method, params)
  end
  return client.notify(method, params)
end

local function echo(text)
  vim.api.nvim_echo({ { text } }, true, {})
end

local function fail(text)
  vim.notify(text, vim.log.levels.ERROR)
end

-- Open `url` in the browser (vim.ui.open, Neovim 0.10 and later), else echo it to be
-- opened by hand. Opened?
local function open_url(url)
  if vim.ui.open then
    local _, err = vim.ui.open(url)
    if not err then
      return true
    end
    echo("Gest preview: " .. url .. " (" .. tostring(err) .. ")")
    return false
  end
  echo("Gest preview: " .. url)
  return false
end

-- window/showDocument where Neovim has no handler of its own (0.7): a page in the
-- browser, or a file with the selection's start under the cursor.
local function show_document(_, params, ctx)
  if params.external then
    return { success = open_url(params.uri) }
  end
  local client = vim.lsp.get_client_by_id(ctx.client_id)
  local encoding = client and client.offset_encoding or "utf-16"
  local buffer = vim.uri_to_bufnr(params.uri)
  local location = { uri = params.uri, range = params.selection }
  if params.takeFocus ~= false then
    if params.selection then
      vim.lsp.util.jump_to_location(location, encoding)
    else
      vim.api.nvim_win_set_buf(0, buffer)
    end
  elseif params.selection and vim.fn.bufwinid(buffer) ~= -1 then
    vim.api.nvim_win_call(vim.fn.bufwinid(buffer), function()
      vim.lsp.util.jump_to_location(location, encoding)
    end)
  end
  vim.bo[buffer].buflisted = true
  return { success = true }
end

local function config(root)
  local settings = {
    name = NAME,
    cmd = M.cmd,
    root_dir = root,
    init_options = { gest = M.settings },
  }
  if not vim.lsp.handlers["window/showDocument"] then
    settings.handlers = { ["window/showDocument"] = show_document }
    settings.capabilities = vim.tbl_deep_extend("force",
      vim.lsp.protocol.make_client_capabilities(),
      { window = { showDocument = { support = true } } })
  end
  return settings
end

-- The gest client attached to `buffer` (0: the current one), if any.
function M.client(buffer)
  if buffer == nil or buffer == 0 then
    buffer = vim.api.nvim_get_current_buf()
  end
  local attached = vim.lsp.get_clients and vim.lsp.get_clients({ bufnr = buffer, name = NAME })
    or vim.tbl_values(vim.lsp.buf_get_clients(buffer))
  for _, client in ipairs(attached) do
    if client.name == NAME then
      return client
    end
  end
end

-- Tell the server where the cursor of the current window is, when it shows a gesture
-- buffer its client is attached to.
function M.send_cursor()
  local client = M.client(0)
  if client and client.initialized then
    notify(client, "gest/cursor", vim.lsp.util.make_position_params(0, client.offset_encoding))
  end
end

local function cursor_moved()
  timer = timer or (vim.uv or vim.loop).new_timer()
  timer:stop()
  timer:start(M.cursor_delay, 0, vim.schedule_wrap(M.send_cursor))
end

-- :GestPreview: the page of the current buffer's gestures, in the browser.
function M.preview()
  local buffer = vim.api.nvim_get_current_buf()
  local client = M.client(buffer)
  if not client or not client.initialized then
    fail("GestPreview: no gest language server runs for this buffer (a .gest file)")
    return
  end
  local cursor = vim.lsp.util.make_position_params(0, client.offset_encoding)
  local params = {
    command = "gest.preview",
    arguments = { vim.uri_from_bufnr(buffer), { open = false } },
  }
  request(client, "workspace/executeCommand", params, function(err, result)
    if err or type(result) ~= "table" or type(result.url) ~= "string" then
      fail("GestPreview: no preview (" .. (err and err.message or vim.inspect(result)) .. ")")
      return
    end
    open_url(result.url)
    if client.initialized then
      notify(client, "gest/cursor", cursor)
    end
  end, buffer)
end

function M.attach(buffer)
  local root = vim.fn.fnamemodify(vim.api.nvim_buf_get_name(buffer), ":p:h")
  local id
  if vim.lsp.start and has("0.10") then
    id = vim.lsp.start(config(root), { bufnr = buffer }) -- the folder's client, or a new one
  else
    id = clients[root]
    if not (id and vim.lsp.get_client_by_id(id)) then
      id = vim.lsp.start_client(config(root))
      clients[root] = id
    end
    if id then
      vim.lsp.buf_attach_client(buffer, id)
    end
  end
  vim.api.nvim_clear_autocmds({ group = group, buffer = buffer })
  vim.api.nvim_create_autocmd({ "CursorMoved", "CursorMovedI" }, {
    group = group,
    buffer = buffer,
    callback = cursor_moved,
  })
  return id
end

vim.api.nvim_create_autocmd({ "BufRead", "BufNewFile" }, {
  pattern = "*.gest",
  command = "setfiletype gest",
})
vim.api.nvim_create_autocmd("FileType", {
  pattern = "gest",
  callback = function(args)
    vim.bo[args.buf].commentstring = "# %s"
    M.attach(args.buf)
  end,
})
vim.api.nvim_create_user_command("GestPreview", M.preview, {
  desc = "Open the page of the buffer's gestures (the step under the cursor) in the browser",
})

return M
