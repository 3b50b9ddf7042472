" Open-RMF maps in Vim with ALE (Debian's vim-ale, or ALE installed as you like) and
" `mapc lsp`. Source it from your vimrc (after `filetype on`), or copy it there:
"   source /path/to/mapc/editors/vim/mapc.vim
" tests/vim_lsp.rs loads this very file in Vim and checks the diagnostics that arrive.

" Debian's vim-ale is an optional package; ignored when ALE is not there that way.
silent! packadd! ale

" Map files are YAML; the second file type lets mapc serve them and no other YAML.
augroup mapc_maps
  autocmd!
  autocmd BufRead,BufNewFile *.building.yaml,*.project.yaml,*.scenario.yaml
        \ set filetype=yaml.rmfmap
augroup END

" ALE's autoload functions are found once ALE is on 'runtimepath' (the packadd above).
try
  call ale#linter#Define('rmfmap', {
        \ 'name': 'mapc',
        \ 'lsp': 'stdio',
        \ 'executable': 'mapc',
        \ 'command': '%e lsp',
        \ 'project_root': {buffer -> fnamemodify(bufname(buffer), ':p:h')},
        \ })
catch /^Vim\%((\a\+)\)\=:E117:/
  echomsg 'mapc.vim: ALE not found; mapc lsp is not set up'
endtry
