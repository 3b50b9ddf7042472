//! The reader's primitives: diagnostics (capped at `MAX_DIAGNOSTICS`), a mapping's entries
//! with unknown and duplicate keys reported, and typed values (names, numbers, durations),
//! each problem located.

use super::*;

impl P<'_> {
    pub(super) fn push(&mut self, d: Diagnostic) -> &mut Diagnostic {
        self.had_error |= d.is_error();
        if self.diags.len() >= MAX_DIAGNOSTICS {
            self.suppressed += 1;
            self.scratch = d;
            return &mut self.scratch;
        }
        self.diags.push(d);
        let last = self.diags.len() - 1;
        &mut self.diags[last]
    }

    pub(super) fn full(&self) -> bool {
        self.diags.len() >= MAX_DIAGNOSTICS
    }

    pub(super) fn error(
        &mut self,
        code: Code,
        span: Span,
        msg: impl Into<String>,
    ) -> &mut Diagnostic {
        self.push(Diagnostic::error(code.code, span, msg))
    }

    pub(super) fn warning(
        &mut self,
        code: Code,
        span: Span,
        msg: impl Into<String>,
    ) -> &mut Diagnostic {
        self.push(Diagnostic::warning(code.code, span, msg))
    }

    /// Sets the help of the diagnostic just reported.
    pub(super) fn help(&mut self, help: impl Into<String>) {
        if self.suppressed > 0 {
            self.scratch.help = Some(help.into());
        } else if let Some(d) = self.diags.last_mut() {
            d.help = Some(help.into());
        }
    }

    pub(super) fn wrong_type(&mut self, v: &Node, what: &str, expected: &str) {
        self.error(
            codes::WRONG_TYPE,
            v.span,
            format!("{what} must be {expected}, found {}", v.type_name()),
        );
    }

    /// Reads a mapping; warns about duplicate keys and, when `known` is given, unknown
    /// ones (`unknown_code` picks the warning).
    pub(super) fn entries<'n, 'a>(
        &mut self,
        v: &'n Node<'a>,
        what: &str,
        known: Option<(&[&str], Code)>,
    ) -> Option<Entries<'n, 'a>> {
        let Some(m) = v.as_map() else {
            self.wrong_type(v, what, "a mapping");
            return None;
        };
        let mut items: Vec<(&'n str, &'n Node<'a>, &'n Node<'a>)> = Vec::with_capacity(m.len());
        // First span of each key: duplicates in O(n log n) even for huge mappings.
        let mut seen: BTreeMap<&'n str, Span> = BTreeMap::new();
        for (k, val) in m {
            let Some(key) = k.key_text() else {
                self.wrong_type(k, &format!("a key of {what}"), "a string");
                continue;
            };
            if let Some(&first_span) = seen.get(key) {
                self.warning(
                    codes::DUPLICATE_KEY,
                    k.span,
                    format!("duplicate key `{key}` in {what}; the last one is used"),
                )
                .labels
                .push(mapc_ir::Label {
                    span: first_span,
                    message: "first defined here".into(),
                });
                self.help("remove one of the two");
            }
            seen.entry(key).or_insert(k.span);
            items.push((key, k, val));
        }
        if let Some((names, code)) = known {
            for (key, k, _) in &items {
                if !names.contains(key) {
                    self.warning(
                        code,
                        k.span,
                        format!("unknown key `{key}` in {what}; it is ignored"),
                    );
                    match closest(key, names.iter().copied()) {
                        Some(c) => self.help(format!("did you mean `{c}`?")),
                        None => self.help(format!("known keys: {}", list(names))),
                    }
                }
            }
        }
        Some(Entries {
            span: v.span,
            items,
        })
    }

    pub(super) fn required<'n, 'a>(
        &mut self,
        e: &Entries<'n, 'a>,
        key: &str,
        what: &str,
    ) -> Option<&'n Node<'a>> {
        let v = e.get(key);
        if v.is_none() {
            self.error(codes::MISSING_KEY, e.span, format!("{what} has no `{key}`"));
        }
        v
    }

    /// A name: any non-empty scalar but null (`1` is the name "1").
    pub(super) fn name(&mut self, v: &Node, what: &str) -> Option<String> {
        match v.key_text() {
            Some(t) if !t.trim().is_empty() && v.as_seq().is_none() => Some(t.to_string()),
            _ => {
                self.wrong_type(v, what, "a non-empty name");
                None
            }
        }
    }

    pub(super) fn number(&mut self, v: &Node, what: &str) -> Option<f64> {
        let Some(x) = v.as_f64() else {
            self.wrong_type(v, what, "a number");
            return None;
        };
        if !x.is_finite() {
            self.error(
                codes::OUT_OF_RANGE,
                v.span,
                format!("{what} must be finite"),
            );
            return None;
        }
        Some(x)
    }

    /// An integer; integral floats beyond i64 are clamped so range checks report them.
    pub(super) fn int(&mut self, v: &Node, what: &str) -> Option<i64> {
        if let Some(i) = v.as_i64() {
            return Some(i);
        }
        match v.as_f64() {
            Some(f) if f.is_finite() && f.fract() == 0.0 => {
                Some(if f > 0.0 { i64::MAX } else { i64::MIN })
            }
            _ => {
                self.wrong_type(v, what, "an integer");
                None
            }
        }
    }

    pub(super) fn bool(&mut self, v: &Node, what: &str) -> Option<bool> {
        let b = v.as_bool();
        if b.is_none() {
            self.wrong_type(v, what, "true or false");
        }
        b
    }

    /// A time: seconds as a number, or a duration string. Never negative.
    pub(super) fn duration(&mut self, v: &Node, what: &str) -> Option<f64> {
        let x = match v.scalar() {
            Some(Scalar::Int(i)) => i as f64,
            Some(Scalar::Float(f)) => f,
            Some(Scalar::Str(s)) => match parse_duration(s) {
                Ok(x) => x,
                Err(e) => {
                    self.error(
                        codes::BAD_DURATION,
                        v.span,
                        format!("{what} `{s}` is not a duration: {e}"),
                    );
                    self.help("write seconds as a number, or a duration such as `90s`, `15min`, `8h`, `1h30min`");
                    return None;
                }
            },
            _ => {
                self.error(
                    codes::BAD_DURATION,
                    v.span,
                    format!("{what} must be a duration, found {}", v.type_name()),
                );
                self.help("write seconds as a number, or a duration such as `90s`, `15min`, `8h`, `1h30min`");
                return None;
            }
        };
        if !x.is_finite() || x < 0.0 {
            self.error(
                codes::BAD_DURATION,
                v.span,
                format!("{what} must be a finite time of 0 s or more"),
            );
            return None;
        }
        Some(x)
    }

    pub(super) fn positive(&mut self, v: &Node, x: f64, what: &str) -> Option<f64> {
        if x > 0.0 {
            Some(x)
        } else {
            self.error(
                codes::NOT_POSITIVE,
                v.span,
                format!("{what} must be greater than 0"),
            );
            None
        }
    }

    /// Reads every element of a sequence (all of them, even after a bad one).
    pub(super) fn seq<T>(
        &mut self,
        v: &Node,
        what: &str,
        mut one: impl FnMut(&mut Self, &Node) -> Option<T>,
    ) -> Option<Vec<T>> {
        let Some(items) = v.as_seq() else {
            self.wrong_type(v, what, "a list");
            return None;
        };
        let mut out = Vec::with_capacity(items.len());
        let mut ok = true;
        for n in items {
            match one(self, n) {
                Some(x) => out.push(x),
                None => ok = false,
            }
        }
        ok.then_some(out)
    }
}
