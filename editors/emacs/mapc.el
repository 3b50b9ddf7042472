;;; mapc.el --- Open-RMF maps in Emacs with eglot and `mapc lsp'  -*- lexical-binding: t; -*-

;; Load it from your init file, or copy it there:
;;   (load "/path/to/mapc/editors/emacs/mapc.el")
;; Needs eglot (built into Emacs 29 and later; on Emacs 28, Debian's elpa-eglot or
;; `M-x package-install RET eglot') and `mapc' on `exec-path'.
;; tests/emacs_lsp.rs loads this very file in Emacs and checks the diagnostics that arrive.

;;; Code:

(require 'eglot)

;; A mode of its own, so that mapc serves map files and no other YAML. It is based on a
;; YAML mode when one is there (yaml-ts-mode in Emacs 29+, or the yaml-mode package).
(defalias 'mapc-map-parent-mode
  (cond ((and (fboundp 'yaml-ts-mode) (fboundp 'treesit-ready-p)
              (treesit-ready-p 'yaml t))
         #'yaml-ts-mode)
        ((fboundp 'yaml-mode) #'yaml-mode)
        (t #'prog-mode)))

(define-derived-mode mapc-map-mode mapc-map-parent-mode "RMF-map"
  "Major mode for Open-RMF map files, checked by `mapc lsp'.")

(add-to-list 'auto-mode-alist
             '("\\.\\(building\\|project\\|scenario\\)\\.yaml\\'" . mapc-map-mode))
;; Add e.g. "--deny" "warnings" after "lsp".
(add-to-list 'eglot-server-programs '(mapc-map-mode . ("mapc" "lsp")))
(add-hook 'mapc-map-mode-hook #'eglot-ensure)

(provide 'mapc)
;;; mapc.el ends here
