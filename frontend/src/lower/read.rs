//! The lowering's primitives: located diagnostics, unknown and misspelled keys, and typed
//! fields (required or with the format's defaults), parameters checked by type.

use super::*;

impl Lower<'_> {
    pub(crate) fn err(
        &mut self,
        code: &'static str,
        span: Span,
        msg: impl Into<String>,
        help: &str,
    ) {
        self.diags
            .push(Diagnostic::error(code, span, msg).with_help(help));
    }

    pub(crate) fn warn(
        &mut self,
        code: &'static str,
        span: Span,
        msg: impl Into<String>,
        help: &str,
    ) {
        self.diags
            .push(Diagnostic::warning(code, span, msg).with_help(help));
    }

    pub(crate) fn wrong_type(&mut self, node: &Node, what: &str, expected: &str) {
        self.err(
            "E0101",
            node.span,
            format!("{what} must be {expected}, found {}", node.type_name()),
            &format!("write {what} as {expected}"),
        );
    }

    /// Entries of a mapping, warning about duplicate keys. `null` is an empty mapping
    /// (with a warning); other types are an error.
    pub fn map<'n, 's>(
        &mut self,
        node: &'n Node<'s>,
        what: impl Display + Copy,
    ) -> Option<&'n [(Node<'s>, Node<'s>)]> {
        match &node.kind {
            Kind::Map(m) => {
                if m.len() > 1 {
                    // Most mappings are small parameter maps: compare pairwise there and
                    // hash only large ones.
                    let small = m.len() <= 16;
                    let mut seen = HashSet::new();
                    for (i, (k, _)) in m.iter().enumerate() {
                        if let Some(t) = k.key_text() {
                            let dup = if small {
                                m[..i].iter().any(|(p, _)| p.key_text() == Some(t))
                            } else {
                                !seen.insert(t)
                            };
                            if dup {
                                self.warn(
                                    "W0102",
                                    k.span,
                                    format!("duplicate key `{t}` in {what}; the last one is used"),
                                    "remove or rename one of the duplicates",
                                );
                            }
                        }
                    }
                }
                Some(m)
            }
            _ if node.is_null() => {
                self.warn(
                    "W0101",
                    node.span,
                    format!("{what} is null; treated as empty"),
                    "write `{}` for an empty mapping, or remove the key",
                );
                Some(&[])
            }
            _ => {
                self.wrong_type(node, &what.to_string(), "a mapping");
                None
            }
        }
    }

    pub fn seq<'n, 's>(
        &mut self,
        node: &'n Node<'s>,
        what: impl Display + Copy,
    ) -> Option<&'n [Node<'s>]> {
        match &node.kind {
            Kind::Seq(s) => Some(s),
            _ if node.is_null() => {
                self.warn(
                    "W0101",
                    node.span,
                    format!("{what} is null; treated as empty"),
                    "write `[]` for an empty list, or remove the key",
                );
                Some(&[])
            }
            // The reference iterates it as an empty list, and public maps have `walls: {}`.
            Kind::Map(m) if m.is_empty() => {
                self.warn(
                    "W0101",
                    node.span,
                    format!("{what} is an empty mapping `{{}}`; treated as an empty list"),
                    "write `[]` for an empty list, or remove the key",
                );
                Some(&[])
            }
            _ => {
                self.wrong_type(node, &what.to_string(), "a sequence");
                None
            }
        }
    }

    pub fn f64(&mut self, node: &Node, what: impl Display) -> Option<f64> {
        match node.as_f64() {
            Some(v) if v.is_finite() => Some(v),
            Some(_) => {
                self.err(
                    "E0104",
                    node.span,
                    format!("{what} is not a finite number"),
                    "use a finite number",
                );
                None
            }
            None => {
                self.wrong_type(node, &what.to_string(), "a number");
                None
            }
        }
    }

    pub fn i64(&mut self, node: &Node, what: impl Display) -> Option<i64> {
        let v = node.as_i64();
        if v.is_none() {
            self.wrong_type(node, &what.to_string(), "an integer");
        }
        v
    }

    pub fn bool(&mut self, node: &Node, what: impl Display) -> Option<bool> {
        // Old files and crowd_sim write 0/1 for booleans.
        match node.scalar() {
            Some(Scalar::Bool(b)) => Some(b),
            Some(Scalar::Int(i)) if i == 0 || i == 1 => Some(i == 1),
            _ => {
                self.wrong_type(node, &what.to_string(), "a boolean");
                None
            }
        }
    }

    pub fn string(&mut self, node: &Node, what: impl Display) -> Option<String> {
        match &node.kind {
            Kind::Scalar { text, .. } if !node.is_null() => Some(text.to_string()),
            _ if node.is_null() => Some(String::new()),
            _ => {
                self.wrong_type(node, &what.to_string(), "a string");
                None
            }
        }
    }

    /// A `{name: [type_code, value], ...}` map.
    pub fn params(&mut self, node: &Node, what: impl Display + Copy) -> Params {
        self.params_checked(node, what).0
    }

    pub(super) fn unknown_keys(&mut self, entries: &[(Node, Node)], known: &[&str], what: &str) {
        for (k, _) in entries {
            if let Some(t) = k.key_text() {
                if known.contains(&t) {
                    continue;
                }
                // Close to a known key: a typo whose value would be silently lost. Far from
                // every known key: a tool-specific extension, which maps may carry.
                match crate::spelling::closest(t, known) {
                    Some(m) => self.err(
                        "E0112",
                        k.span,
                        format!("unknown key `{t}` in {what}; did you mean `{m}`?"),
                        &format!("rename it to `{m}`; as written it is ignored"),
                    ),
                    None => self.warn(
                        "W0103",
                        k.span,
                        format!("unknown key `{t}` in {what}; it is ignored"),
                        "check the spelling against the .building.yaml format",
                    ),
                }
            }
        }
    }

    /// Vertex parameters close to a known one (`is_chargr`): errors, since the role would
    /// silently disappear. Others are free-form and stay quiet.
    pub(super) fn misspelled_params(&mut self, node: &Node, what: impl Display) {
        let Some(entries) = node.as_map() else {
            return;
        };
        for (k, _) in entries {
            let Some(t) = k.key_text() else { continue };
            if VERTEX_PARAMS.contains(&t) {
                continue;
            }
            if let Some(m) = crate::spelling::closest(t, VERTEX_PARAMS) {
                self.err(
                    "E0112",
                    k.span,
                    format!("unknown parameter `{t}` of {what}; did you mean `{m}`?"),
                    &format!("rename it to `{m}`; as written it is ignored"),
                );
            }
        }
    }

    /// A `graphs` key: an integer, or an integer written as a string (traffic-editor-js
    /// and serde-based exporters write `'0':`, which the reference's Python reads too).
    pub(super) fn graph_key(&mut self, node: &Node) -> Option<i64> {
        if let Some(i) = node.as_i64() {
            return Some(i);
        }
        let text = node.key_text().map(str::trim);
        if let Some(i) = text.and_then(|t| t.parse::<i64>().ok()) {
            return Some(i);
        }
        self.wrong_type(
            node,
            "a graph index",
            "an integer (or an integer in quotes)",
        );
        None
    }

    pub(super) fn require<'n, 's>(
        &mut self,
        parent: &'n Node<'s>,
        key: &str,
        what: &str,
    ) -> Option<&'n Node<'s>> {
        let v = parent.get(key);
        if v.is_none() {
            self.err(
                "E0102",
                parent.span,
                format!("{what} has no `{key}`"),
                &format!("add `{key}` to {what}"),
            );
        }
        v
    }

    pub(super) fn opt_f64(&mut self, parent: &Node, key: &str, what: &str, default: f64) -> f64 {
        match parent.get(key) {
            Some(n) => self.f64(n, Field(what, key)).unwrap_or(default),
            None => default,
        }
    }

    pub(super) fn opt_i64(&mut self, parent: &Node, key: &str, what: &str, default: i64) -> i64 {
        match parent.get(key) {
            Some(n) => self.i64(n, Field(what, key)).unwrap_or(default),
            None => default,
        }
    }

    pub(super) fn opt_string(&mut self, parent: &Node, key: &str, what: &str) -> String {
        match parent.get(key) {
            Some(n) => self.string(n, Field(what, key)).unwrap_or_default(),
            None => String::new(),
        }
    }

    pub(super) fn opt_bool(&mut self, parent: &Node, key: &str, what: &str, default: bool) -> bool {
        match parent.get(key) {
            Some(n) => self.bool(n, Field(what, key)).unwrap_or(default),
            None => default,
        }
    }

    pub(super) fn req_f64(&mut self, parent: &Node, key: &str, what: &str) -> Option<f64> {
        let n = self.require(parent, key, what)?;
        self.f64(n, Field(what, key))
    }

    pub(super) fn req_string(&mut self, parent: &Node, key: &str, what: &str) -> Option<String> {
        let n = self.require(parent, key, what)?;
        self.string(n, Field(what, key))
    }

    /// [`Self::params`], plus the names of the parameters that are present but malformed
    /// (reported here, and left out of the `Params`).
    pub(super) fn params_checked(
        &mut self,
        node: &Node,
        what: impl Display + Copy,
    ) -> (Params, Vec<String>) {
        let mut out = Params::default();
        let mut invalid = Vec::new();
        let Some(entries) = self.map(node, format_args!("the parameters of {what}")) else {
            return (out, invalid);
        };
        // A later duplicate replaces the earlier one in place. Name -> position in `out`
        // for long lists, without a scan per parameter (maps are untrusted: a lane may have
        // 10^5 of them); the few of a usual element are scanned (a hash map per vertex was
        // a tenth of lowering).
        let mut position: Option<std::collections::HashMap<&str, usize>> =
            (entries.len() > 16).then(std::collections::HashMap::new);
        out.0.reserve_exact(entries.len());
        for (k, v) in entries {
            let Some(name) = k.key_text() else {
                self.wrong_type(k, "a parameter name", "a string");
                continue;
            };
            match self.param_value(v, name) {
                Some(value) => {
                    let p = Param {
                        name: name.to_string(),
                        value,
                        span: v.span,
                    };
                    let earlier = match &position {
                        Some(m) => m.get(name).copied(),
                        None => out.0.iter().position(|q| q.name == name),
                    };
                    match earlier {
                        Some(i) => out.0[i] = p,
                        None => {
                            if let Some(m) = &mut position {
                                m.insert(name, out.0.len());
                            }
                            out.0.push(p);
                        }
                    }
                }
                None => invalid.push(name.to_string()),
            }
        }
        out.0.shrink_to_fit();
        (out, invalid)
    }

    pub(super) fn param_value(&mut self, v: &Node, name: &str) -> Option<ParamValue> {
        let help = "write parameters as `[type_code, value]` with type_code 1 string, 2 int, 3 double, 4 bool";
        let Some([code, value]) = v.as_seq() else {
            self.err(
                "E0105",
                v.span,
                format!(
                    "parameter `{name}` must be a `[type_code, value]` pair, found {}",
                    v.type_name()
                ),
                help,
            );
            return None;
        };
        let bad = |l: &mut Self, expected: &str| {
            l.err(
                "E0105",
                value.span,
                format!(
                    "parameter `{name}` has type code {} ({expected}) but its value is {}",
                    code.as_i64().unwrap_or(0),
                    value.type_name()
                ),
                help,
            );
            None
        };
        match code.as_i64() {
            Some(1) => match &value.kind {
                Kind::Scalar { text, .. } => Some(ParamValue::String(if value.is_null() {
                    String::new()
                } else {
                    text.to_string()
                })),
                _ => bad(self, "string"),
            },
            Some(2) => match value.scalar() {
                Some(Scalar::Int(i)) => Some(ParamValue::Int(i)),
                _ => bad(self, "int"),
            },
            Some(3) => match value.as_f64() {
                Some(f) if f.is_finite() => Some(ParamValue::Double(f)),
                Some(_) => {
                    self.err(
                        "E0104",
                        value.span,
                        format!("parameter `{name}` is not a finite number"),
                        "use a finite number",
                    );
                    None
                }
                None => bad(self, "double"),
            },
            Some(4) => match value.as_bool() {
                Some(b) => Some(ParamValue::Bool(b)),
                _ => bad(self, "bool"),
            },
            _ => {
                self.err(
                    "E0105",
                    code.span,
                    format!("parameter `{name}` has an unknown type code"),
                    help,
                );
                None
            }
        }
    }
}
