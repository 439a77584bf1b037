-- Gesture files in Neovim (0.7 and later): the gest filetype, and `gestc lsp` attached to
-- each gesture buffer. Put this file in ~/.config/nvim/lua/ and `require("gest")` from
-- init.lua, or copy its lines there (docs/editors.md).
local M = {}

-- settings sent to the server: { robot = "inmoov" } for files without a robot line
M.settings = {}
M.cmd = { "gestc", "lsp" }

function M.attach(buffer)
  local id = vim.lsp.start_client({
    name = "gestc",
    cmd = M.cmd,
    root_dir = vim.fn.fnamemodify(vim.api.nvim_buf_get_name(buffer), ":p:h"),
    init_options = { gest = M.settings },
  })
  if id then
    vim.lsp.buf_attach_client(buffer, id)
  end
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

return M
