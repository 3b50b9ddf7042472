" Run by tests/vim_lsp.rs: Vim with editors/vim/mapc.vim sourced, the map opened, then
" `-S check_diagnostics.vim`, with OUT (the result file) in the environment and mapc on
" PATH. Waits for ALE to show mapc's diagnostics, goes to a vertex's definition
" (:ALEGoToDefinition), deletes the self-loop lane (ALE sends the change) and waits for the
" diagnostics to update.
let s:result = ['filetype ' . &filetype]

" mapc's items only (ALE may run other YAML linters too).
function! s:items() abort
  return filter(copy(ale#engine#GetLoclist(bufnr(''))),
        \ {_, d -> get(d, 'linter_name', '') ==# 'mapc'})
endfunction
function! s:has(code) abort
  return len(filter(copy(s:items()), {_, d -> get(d, 'code', '') ==# a:code})) > 0
endfunction
function! s:wait(cond) abort
  let l:start = reltime()
  while !eval(a:cond) && reltimefloat(reltime(l:start)) < 20
    sleep 20m
  endwhile
  return eval(a:cond)
endfunction
function! s:record(tag) abort
  let l:sev = {'E': 'error', 'W': 'warning', 'I': 'info'}
  let l:lines = map(s:items(), {_, d -> printf('%s %d:%d %s %s', a:tag,
        \ d.lnum, d.col, get(d, 'code', '?'), get(l:sev, d.type, d.type))})
  call extend(s:result, sort(l:lines))
endfunction

" How many times ALE has shown new results.
let s:published = 0
augroup check
  autocmd User ALELintPost let s:published += 1
augroup END

" ALE lints the buffer it entered on its own (a timer after BufEnter).
if s:wait('s:has("E0201")')
  call s:record('open')
  " Go to the definition of the `4' of `[1, 4,': the second `pantry' vertex.
  call search('\V[1, 4,')
  normal! 4l
  let s:from = line('.')
  ALEGoToDefinition
  if s:wait('line(".") != s:from')
    call add(s:result, printf('definition %d:%d', line('.'), col('.')))
  else
    call add(s:result, 'timeout waiting for the definition')
  endif
  " Delete the self-loop lane, as a user would. Ex mode fires no TextChanged (Normal mode
  " does after each change), so fire it here; ALE sends the text after it, on a timer.
  call search('\V[3, 3,')
  delete
  let s:before = s:published
  doautocmd TextChanged
  if s:wait('s:published > s:before && !s:has("E0201")')
    call s:record('edited')
  else
    call add(s:result, "timeout waiting for the edit's diagnostics")
  endif
else
  call add(s:result, 'timeout waiting for diagnostics')
endif
call writefile(s:result, $OUT)
qa!
