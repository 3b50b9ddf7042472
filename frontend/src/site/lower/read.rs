//! The site reader's primitives: a mapping's entries with unknown and unused keys
//! reported, names, points, anchor values and poses, dangling references, the format version.

use super::*;

impl<'d, 'n, 's> SiteLower<'d, 'n, 's> {
    pub(super) fn entries<'a, 'b>(
        &mut self,
        parent: &'a Node<'b>,
        key: &str,
        what: &str,
    ) -> Vec<(u32, &'a Node<'b>, Span)> {
        let Some(n) = parent.get(key) else {
            return Vec::new();
        };
        let Some(m) = self.l.map(n, format_args!("{what} `{key}`")) else {
            return Vec::new();
        };
        let mut out = Vec::with_capacity(m.len());
        for (k, v) in m {
            match id_of(k) {
                Some(id) => out.push((id, v, k.span)),
                None => self
                    .l
                    .wrong_type(k, "a site id", "an unsigned integer in quotes"),
            }
        }
        // rmf_site keeps every map as a BTreeMap<u32, _>: numeric id order.
        out.sort_by_key(|(id, _, _)| *id);
        out
    }

    pub(super) fn unknown(&mut self, node: &Node, known: &[&str], what: &str) {
        let Some(m) = node.as_map() else { return };
        for (k, _) in m {
            let Some(t) = k.key_text() else { continue };
            if !known.contains(&t) {
                self.l.warn(
                    "W0121",
                    k.span,
                    format!("unknown field `{t}` in {what}; it is ignored"),
                    "rmf_site_format 0.0.2 has no such field; check the spelling",
                );
            }
        }
    }

    pub(super) fn unused(&mut self, node: &Node, keys: &[&str], what: &str) {
        for key in keys {
            if let Some(v) = node.get(key) {
                let non_empty = v.as_map().is_some_and(|m| !m.is_empty())
                    || v.as_seq().is_some_and(|s| !s.is_empty());
                if non_empty {
                    self.l.warn(
                        "W0121",
                        v.span,
                        format!("mapc does not use the `{key}` of {what}; they are ignored"),
                        "nothing to do unless an output should have them",
                    );
                }
            }
        }
    }

    pub(super) fn name(&mut self, n: &Node, what: &str) -> String {
        match n.get("name") {
            Some(v) => self
                .l
                .string(v, format_args!("the name of {what}"))
                .unwrap_or_default(),
            None => String::new(),
        }
    }

    pub(super) fn point(&mut self, n: &Node, what: &str) -> Option<Vec2> {
        let s = n.as_seq().filter(|s| s.len() >= 2);
        let Some(s) = s else {
            self.l.wrong_type(n, what, "a list [x, y]");
            return None;
        };
        let x = self.l.f64(&s[0], format_args!("the x of {what}"))?;
        let y = self.l.f64(&s[1], format_args!("the y of {what}"))?;
        Some(Vec2::new(x, y))
    }

    /// An anchor value: `Translate2D`, `CategorizedTranslate2D` (its `General` point) or
    /// `Pose3D` (its x, y).
    pub(super) fn anchor_pos(&mut self, n: &Node) -> Option<Vec2> {
        match variant(n) {
            Some(("Translate2D", Some(v))) => self.point(v, "an anchor"),
            Some(("CategorizedTranslate2D", Some(v))) => match v.get("General") {
                Some(g) => self.point(g, "an anchor"),
                None => {
                    self.l.err(
                        "E0102",
                        v.span,
                        "categorized anchor has no `General` point",
                        "add `General: [x, y]`",
                    );
                    None
                }
            },
            Some(("Pose3D", Some(v))) => v.get("trans").and_then(|t| self.point(t, "an anchor")),
            _ => {
                self.l.wrong_type(
                    n,
                    "an anchor",
                    "Translate2D, CategorizedTranslate2D or Pose3D",
                );
                None
            }
        }
    }

    /// Translation and yaw of a `Pose` (`rot` as yaw, or a quaternion's yaw).
    pub(super) fn pose(&mut self, pose: Option<&Node>) -> (Vec2, f64) {
        let Some(p) = pose else {
            return (Vec2::default(), 0.0);
        };
        let t = p
            .get("trans")
            .and_then(|t| self.point(t, "a pose translation"))
            .unwrap_or_default();
        let yaw = match p.get("rot").and_then(variant) {
            Some(("yaw", Some(a))) => angle_rad(a).unwrap_or(0.0),
            Some(("quat", Some(q))) => {
                let q: Vec<f64> = q
                    .as_seq()
                    .unwrap_or(&[])
                    .iter()
                    .filter_map(|v| v.as_f64())
                    .collect();
                if let [x, y, z, w] = q[..] {
                    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
                } else {
                    0.0
                }
            }
            _ => 0.0,
        };
        (t, yaw)
    }

    pub(super) fn dangling(&mut self, span: Span, what: &str, id: u32) {
        self.l.err(
            "E0121",
            span,
            format!("{what} refers to id {id}, which the site does not have"),
            "point it at an existing element, or delete it",
        );
    }

    pub(super) fn format_version(&mut self, root: &Node) -> bool {
        let Some(v) = root.get("format_version") else {
            self.l.err(
                "E0120",
                root.span,
                "the site has no `format_version`",
                "rmf_site writes `\"format_version\": \"0.1\"`",
            );
            return false;
        };
        let major = v
            .key_text()
            .and_then(|t| t.split('.').next())
            .and_then(|m| m.trim().parse::<u32>().ok());
        match major {
            Some(m) if m == FORMAT_MAJOR => true,
            Some(m) => {
                self.l.err(
                    "E0120",
                    v.span,
                    format!("site format_version major {m} is newer than the {FORMAT_MAJOR}.x mapc reads"),
                    "save the site with an rmf_site that writes format 0.x, or update mapc",
                );
                false
            }
            None => {
                self.l.err(
                    "E0120",
                    v.span,
                    "`format_version` must be \"MAJOR.MINOR\"",
                    "write `\"format_version\": \"0.1\"`",
                );
                false
            }
        }
    }
}
