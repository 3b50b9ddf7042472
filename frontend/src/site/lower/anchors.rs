//! Anchors to IR vertices: an element's two anchors (its level's or site anchors), the
//! vertex made of each on its level, and the file coordinates mapc's extension keeps.

use super::*;

impl<'d, 'n, 's> SiteLower<'d, 'n, 's> {
    /// The file coordinates (pixels, y down) of map position `pos` on level `lh` of a
    /// reference_image map: those mapc's extension kept, while they still land on `pos`
    /// (an element moved in rmf_site gets them from the level's drawing instead).
    pub(super) fn pixel_raw(
        &self,
        b: &Building,
        lh: Handle<Level>,
        pos: Vec2,
        kept: Option<Vec2>,
    ) -> Vec2 {
        let t = b.levels[lh].transform;
        match kept {
            Some(r) if t.apply(flip(r)).minus(pos).norm() < 1e-6 => r,
            _ => flip(t.invert(pos)),
        }
    }

    /// What mapc's extension keeps under `key` for element `id` of level `lh`.
    pub(super) fn ext_level_point(&self, key: &str, lh: Handle<Level>, id: u32) -> Option<Vec2> {
        let level = self.level_ids.get(&lh)?;
        ext_point(
            self.ext?
                .get(key)?
                .get(&level.to_string())?
                .get(&id.to_string()),
        )
    }

    /// The two anchor ids of an edge (`anchors: [start, end]`), or E0102 on `span`.
    pub(super) fn anchor_pair<'a, 't>(
        &mut self,
        n: &'a Node<'t>,
        span: Span,
        what: &str,
    ) -> Option<&'a [Node<'t>]> {
        let a = n
            .get("anchors")
            .and_then(|a| a.as_seq())
            .filter(|s| s.len() == 2);
        if a.is_none() {
            self.l.err(
                "E0102",
                span,
                format!("{what} needs `anchors: [start, end]`"),
                "give the two anchor ids",
            );
        }
        a
    }

    /// The two anchors of a wall or door on level `lh` (its own anchors or site anchors).
    pub(super) fn edge(
        &mut self,
        b: &mut Building,
        n: &Node,
        span: Span,
        lh: Handle<Level>,
        what: &str,
    ) -> Option<(Handle<Vertex>, Handle<Vertex>)> {
        let a = self.anchor_pair(n, span, what)?;
        let mut out = [None, None];
        for (i, node) in a.iter().enumerate() {
            let Some(id) = ref_of(node) else {
                self.l
                    .wrong_type(node, "an anchor id", "an unsigned integer");
                return None;
            };
            out[i] = Some(self.level_anchor(b, id, lh, node.span, what)?);
        }
        Some((out[0]?, out[1]?))
    }

    /// The vertex on level `lh` of anchor `id`, named by an element of that level (`what`,
    /// the reference at `at`). rmf_site's loader resolves a level's walls, floors and doors
    /// against the site's anchors and the level's own (site anchors first, then each
    /// level's anchors before its elements), so both are accepted; a site anchor is where
    /// the site says, on every level that uses it. Another level's anchor or a lift's cabin
    /// anchor is an error: rmf_site's loader finds the first only when that level's id is
    /// lower (it reads levels in id order) and the second never (lifts come after levels),
    /// so a site using them opens in rmf_site by accident of numbering, or not at all.
    pub(super) fn level_anchor(
        &mut self,
        b: &mut Building,
        id: u32,
        lh: Handle<Level>,
        at: Span,
        what: &str,
    ) -> Option<Handle<Vertex>> {
        let level = |b: &Building, l: Handle<Level>| b.levels[l].name.clone();
        match self.anchors.get(&id).copied() {
            Some(Anchor::Level(l2, v)) if l2 == lh => Some(v),
            Some(Anchor::Site(p, def)) => Some(self.site_vertex(b, id, p, lh, def)),
            Some(Anchor::Level(l2, _)) => {
                self.l.err(
                    "E0121",
                    at,
                    format!(
                        "{what} of level `{}` uses anchor {id}, which is an anchor of level `{}`",
                        level(b, lh),
                        level(b, l2)
                    ),
                    &format!(
                        "use an anchor of level `{}` or a site anchor (the site's `anchors`, shared by all levels)",
                        level(b, lh)
                    ),
                );
                None
            }
            Some(Anchor::Cabin(..)) => {
                self.l.err(
                    "E0121",
                    at,
                    format!("{what} uses anchor {id}, which is a lift's cabin anchor"),
                    &format!(
                        "use an anchor of level `{}` or a site anchor; cabin anchors are for lanes and locations",
                        level(b, lh)
                    ),
                );
                None
            }
            None => {
                self.dangling(at, what, id);
                None
            }
        }
    }

    /// The vertex of site anchor `id` (at map position `pos`, defined at `span`) on level
    /// `lh`, made on first use: one per level, as the IR's elements join vertices of their
    /// own level.
    pub(super) fn site_vertex(
        &mut self,
        b: &mut Building,
        id: u32,
        pos: Vec2,
        lh: Handle<Level>,
        span: Span,
    ) -> Handle<Vertex> {
        if let Some(v) = self.site_vertices.get(&(id, lh)) {
            return *v;
        }
        let raw = if b.coordinate_system == CoordinateSystem::ReferenceImage {
            let kept = self.ext_level_point("raw_vertices", lh, id);
            self.pixel_raw(b, lh, pos, kept)
        } else {
            pos.minus(b.offset)
        };
        let vh = b.vertices.append(
            Vertex {
                level: lh,
                name: String::new(),
                pos,
                raw,
                params: Params::default(),
                roles: Default::default(),
            },
            span,
        );
        b.levels[lh].vertices.push(vh);
        self.site_vertices.insert((id, lh), vh);
        vh
    }
}
