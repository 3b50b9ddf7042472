-- Run by tests/nvim_lsp.rs: `nvim --headless --clean MAP -c 'luafile check_diagnostics.lua'`
-- with MAPC (the binary) and OUT (the result file) in the environment. Starts `mapc lsp`
-- with Neovim's built-in client (as docs/editors.md configures it), waits for diagnostics,
-- deletes the self-loop lane (an incremental change) and waits for them to update.
local bin, out = os.getenv("MAPC"), os.getenv("OUT")
local buf = vim.api.nvim_get_current_buf()
local config = { name = "mapc", cmd = { bin, "lsp" }, root_dir = vim.fn.getcwd() }
if vim.lsp.start then
  vim.lsp.start(config) -- Neovim 0.8 and later
else
  local id = vim.lsp.start_client(config) -- Neovim 0.7 (Debian 12)
  vim.lsp.buf_attach_client(buf, id)
end

local result = {}
local function code(d)
  return d.code or (d.user_data and d.user_data.lsp and d.user_data.lsp.code) or "?"
end
local function record(tag)
  local lines = {}
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    table.insert(lines, string.format("%s %d:%d %s %d", tag, d.lnum + 1, d.col + 1, code(d), d.severity))
  end
  table.sort(lines)
  vim.list_extend(result, lines)
end
local function has(c)
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    if code(d) == c then return true end
  end
  return false
end

if vim.wait(20000, function() return has("E0201") end, 20) then
  record("open")
  -- Delete the self-loop lane, as a user would.
  for i, line in ipairs(vim.api.nvim_buf_get_lines(buf, 0, -1, false)) do
    if line:find("[3, 3,", 1, true) then
      vim.api.nvim_buf_set_lines(buf, i - 1, i, false, {})
      break
    end
  end
  if vim.wait(20000, function() return not has("E0201") end, 20) then
    record("edited")
  else
    table.insert(result, "timeout waiting for the edit's diagnostics")
  end
else
  table.insert(result, "timeout waiting for diagnostics")
end
vim.fn.writefile(result, out)
vim.cmd("qa!")
