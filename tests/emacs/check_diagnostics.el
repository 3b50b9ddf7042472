;;; check_diagnostics.el --- run by tests/emacs_lsp.rs  -*- lexical-binding: t; -*-
;; `emacs --batch -Q -l editors/emacs/mapc.el -l check_diagnostics.el' with MAP (the map)
;; and OUT (the result file) in the environment and mapc on PATH. Visits the map as a user
;; would (the set-up's hook starts eglot), waits for flymake to show mapc's diagnostics,
;; goes to a vertex's definition (M-.), deletes the self-loop lane (an incremental change)
;; and waits for the diagnostics to update.

(require 'flymake)

(defvar check--published 0 "How many publishDiagnostics eglot has handled.")
(advice-add 'eglot-handle-notification :after
            (lambda (_server method &rest _)
              (when (eq method 'textDocument/publishDiagnostics)
                (setq check--published (1+ check--published)))))

(defun check--code (d)
  "The LSP code of flymake diagnostic D."
  (let ((spec (alist-get 'eglot-lsp-diag (flymake-diagnostic-data d))))
    (or (plist-get spec :code) "?")))

(defun check--has (code)
  (seq-some (lambda (d) (equal (check--code d) code)) (flymake-diagnostics)))

(defun check--wait (pred)
  "Run the editor's loop (process output, timers, idle timers) until PRED or 20 s."
  (let ((start (float-time)) (idle-run nil) ok)
    (while (and (not (setq ok (funcall pred))) (< (float-time) (+ start 20)))
      (accept-process-output nil 0.05)
      ;; Batch Emacs reads no input, so it is never idle and runs no idle timer: run them
      ;; once, as the command loop does when the user has stopped typing for a while (eglot
      ;; sends the buffer's changes, flymake asks its backends, on idle timers).
      (when (and (not idle-run) (> (float-time) (+ start 0.6)))
        (setq idle-run t)
        (mapc #'timer-event-handler (copy-sequence timer-idle-list))))
    ok))

(defun check--record (tag)
  (sort
   (mapcar (lambda (d)
             (save-excursion
               (goto-char (flymake-diagnostic-beg d))
               (format "%s %d:%d %s %s" tag (line-number-at-pos) (1+ (current-column))
                       (check--code d)
                       (pcase (flymake-diagnostic-type d)
                         ('eglot-error "error") ('eglot-warning "warning") (x x)))))
           (flymake-diagnostics))
   #'string<))

(let ((result '()))
  (find-file (getenv "MAP"))
  ;; eglot-ensure connects when the command that opened the file ends.
  (run-hooks 'post-command-hook)
  (push (format "mode %s eglot %s" major-mode (if (eglot-current-server) "on" "off")) result)
  (if (not (check--wait (lambda () (check--has "E0201"))))
      (push "timeout waiting for diagnostics" result)
    (setq result (append (reverse (check--record "open")) result))
    ;; Go to the definition of the `4' of `[1, 4,' (M-.): the second `pantry' vertex.
    (goto-char (point-min))
    (search-forward "[1, 4,")
    (backward-char 2)
    (call-interactively #'xref-find-definitions)
    (push (format "definition %d:%d" (line-number-at-pos) (1+ (current-column))) result)
    (goto-char (point-min))
    (search-forward "[3, 3,")
    (delete-region (line-beginning-position) (1+ (line-end-position)))
    (run-hooks 'post-command-hook)
    ;; Flymake drops the deleted line's diagnostic at once; wait for the server's answer.
    (if (let ((before check--published))
          (check--wait (lambda () (and (> check--published before)
                                       (not (check--has "E0201"))))))
        (setq result (append (reverse (check--record "edited")) result))
      (push "timeout waiting for the edit's diagnostics" result)))
  (with-temp-file (getenv "OUT")
    (insert (mapconcat #'identity (nreverse result) "\n") "\n"))
  (set-buffer-modified-p nil)
  (ignore-errors (eglot-shutdown (eglot-current-server)))
  (kill-emacs 0))
