//! Plane geometry shared by the door, lift and geometry rules: segment intersection,
//! point in polygon, polygon area and simplicity. Every test works in metres and uses
//! tolerances relative to the lengths involved, so it behaves the same at any scale
//! (unlike the reference generator's `|det| < 0.01`, which fails on degrees).

use crate::{Building, Handle, Polygon, Span, Vec2, Vertex};

/// Relative tolerance on the sine of an angle below which three points count as colinear.
const COLINEAR_SIN: f64 = 1e-10;

/// How two closed segments meet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Meet {
    /// Disjoint.
    None,
    /// They cross or touch at one point and are not parallel.
    Cross,
    /// Parallel and overlapping (colinear), or one of them has zero length and lies on
    /// the other.
    Overlap,
}

/// Sign of the turn a → b → c: 1 left, -1 right, 0 colinear (within a relative tolerance).
fn orient(a: Vec2, b: Vec2, c: Vec2) -> i8 {
    let u = b.minus(a);
    let v = c.minus(a);
    let cr = u.cross(v);
    // |cr| > COLINEAR_SIN * |u| * |v|, without square roots.
    if cr * cr <= COLINEAR_SIN * COLINEAR_SIN * u.dot(u) * v.dot(v) {
        0
    } else if cr > 0.0 {
        1
    } else {
        -1
    }
}

/// Is `p`, known to be colinear with segment `a`–`b`, within its bounding box?
fn within(a: Vec2, b: Vec2, p: Vec2) -> bool {
    let tol = 1e-12 * (1.0 + a.x.abs().max(a.y.abs()).max(b.x.abs()).max(b.y.abs()));
    p.x >= a.x.min(b.x) - tol
        && p.x <= a.x.max(b.x) + tol
        && p.y >= a.y.min(b.y) - tol
        && p.y <= a.y.max(b.y) + tol
}

/// How the closed segments `p1`–`p2` and `q1`–`q2` meet. Touching at an end point counts.
pub(crate) fn segments_meet(p1: Vec2, p2: Vec2, q1: Vec2, q2: Vec2) -> Meet {
    // Cheap rejection on bounding boxes (with the same slack as `within`).
    let tol = 1e-12
        * (1.0
            + [p1, p2, q1, q2]
                .iter()
                .fold(0.0_f64, |m, v| m.max(v.x.abs()).max(v.y.abs())));
    if p1.x.max(p2.x) + tol < q1.x.min(q2.x)
        || q1.x.max(q2.x) + tol < p1.x.min(p2.x)
        || p1.y.max(p2.y) + tol < q1.y.min(q2.y)
        || q1.y.max(q2.y) + tol < p1.y.min(p2.y)
    {
        return Meet::None;
    }
    let d1 = orient(q1, q2, p1);
    let d2 = orient(q1, q2, p2);
    let d3 = orient(p1, p2, q1);
    let d4 = orient(p1, p2, q2);
    if d1 == 0 && d2 == 0 && d3 == 0 && d4 == 0 {
        // Colinear (or degenerate): overlap of the projections.
        let overlap =
            within(p1, p2, q1) || within(p1, p2, q2) || within(q1, q2, p1) || within(q1, q2, p2);
        return if overlap { Meet::Overlap } else { Meet::None };
    }
    if d1 * d2 < 0 && d3 * d4 < 0 {
        return Meet::Cross;
    }
    let touch = (d1 == 0 && within(q1, q2, p1))
        || (d2 == 0 && within(q1, q2, p2))
        || (d3 == 0 && within(p1, p2, q1))
        || (d4 == 0 && within(p1, p2, q2));
    if touch {
        Meet::Cross
    } else {
        Meet::None
    }
}

/// Signed area (shoelace), positive for counter-clockwise rings.
pub(crate) fn signed_area(pts: &[Vec2]) -> f64 {
    if pts.len() < 3 {
        return 0.0;
    }
    let o = pts[0];
    let mut s = 0.0;
    for w in pts[1..].windows(2) {
        s += w[0].minus(o).cross(w[1].minus(o));
    }
    s / 2.0
}

/// Sum of the absolute areas of the fan triangles from the first point: zero exactly when
/// every point lies on one line (a flat ring), whatever the winding.
pub(crate) fn fan_extent(pts: &[Vec2]) -> f64 {
    if pts.len() < 3 {
        return 0.0;
    }
    let o = pts[0];
    pts[1..]
        .windows(2)
        .map(|w| w[0].minus(o).cross(w[1].minus(o)).abs() / 2.0)
        .sum()
}

/// Is `p` inside the ring `pts` or on its boundary?
pub(crate) fn point_in_polygon(p: Vec2, pts: &[Vec2]) -> bool {
    let n = pts.len();
    if n == 0 {
        return false;
    }
    let mut inside = false;
    for i in 0..n {
        let a = pts[i];
        let b = pts[(i + 1) % n];
        if within(a, b, p) && orient(a, b, p) == 0 {
            return true;
        }
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Axis-aligned bounding box (min, max).
pub(crate) fn bbox(pts: &[Vec2]) -> (Vec2, Vec2) {
    let mut lo = Vec2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    for p in pts {
        lo = Vec2::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Vec2::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    (lo, hi)
}

/// Do two rings share any area or boundary point (a vertex of one inside the other, or
/// crossing edges)?
pub(crate) fn rings_overlap(a: &[Vec2], b: &[Vec2]) -> bool {
    if a.is_empty() || b.is_empty() {
        return false;
    }
    let (alo, ahi) = bbox(a);
    let (blo, bhi) = bbox(b);
    if alo.x > bhi.x || blo.x > ahi.x || alo.y > bhi.y || blo.y > ahi.y {
        return false;
    }
    // Crossing or touching edges, found through a grid of b's edges (no na × nb loop).
    let (na, nb) = (a.len(), b.len());
    let edge_box = |p: Vec2, q: Vec2| {
        (
            Vec2::new(p.x.min(q.x), p.y.min(q.y)),
            Vec2::new(p.x.max(q.x), p.y.max(q.y)),
        )
    };
    let b_edges: Vec<(Vec2, Vec2)> = (0..nb).map(|j| edge_box(b[j], b[(j + 1) % nb])).collect();
    let mut grid = crate::validate::grid::BoxGrid::new(&b_edges);
    let crossing = (0..na).any(|i| {
        let (p, q) = (a[i], a[(i + 1) % na]);
        let (lo, hi) = edge_box(p, q);
        grid.candidates(lo, hi).into_iter().any(|j| {
            let j = j as usize;
            segments_meet(p, q, b[j], b[(j + 1) % nb]) != Meet::None
        })
    });
    if crossing {
        return true;
    }
    // No boundary point shared: one ring is inside the other or they are apart, which a
    // vertex of each tells.
    point_in_polygon(a[0], b) || point_in_polygon(b[0], a)
}

/// A floor or hole with a word for messages.
pub(crate) struct PolygonRef<'a> {
    pub kind: &'static str,
    pub poly: &'a Polygon,
    pub span: Span,
}

/// Every floor, then every hole, in document order.
pub(crate) fn polygons(b: &Building) -> impl Iterator<Item = PolygonRef<'_>> + '_ {
    let floors = b.floors.iter().map(move |(h, p)| PolygonRef {
        kind: "floor",
        poly: p,
        span: b.floors.span(h),
    });
    let holes = b.holes.iter().map(move |(h, p)| PolygonRef {
        kind: "hole",
        poly: p,
        span: b.holes.span(h),
    });
    floors.chain(holes)
}

/// Number of different vertices a polygon lists.
pub(crate) fn distinct_vertices(poly: &Polygon) -> usize {
    let mut v: Vec<usize> = poly.vertices.iter().map(|h| h.index()).collect();
    v.sort_unstable();
    v.dedup();
    v.len()
}

/// The polygon's ring: positions and vertices in order, without consecutive repeats
/// (same vertex or same position), the closing edge included in that rule.
pub(crate) fn ring(b: &Building, poly: &Polygon) -> (Vec<Vec2>, Vec<Handle<Vertex>>) {
    let mut pts: Vec<Vec2> = Vec::with_capacity(poly.vertices.len());
    let mut hs: Vec<Handle<Vertex>> = Vec::with_capacity(poly.vertices.len());
    for &h in &poly.vertices {
        let p = b.vertices[h].pos;
        if pts.last().is_some_and(|&q| same_point(p, q)) {
            continue;
        }
        pts.push(p);
        hs.push(h);
    }
    while pts.len() > 1 && same_point(pts[0], pts[pts.len() - 1]) {
        pts.pop();
        hs.pop();
    }
    (pts, hs)
}

/// Points closer than a nanometre are the same point.
pub(crate) fn same_point(a: Vec2, b: Vec2) -> bool {
    a.minus(b).norm() < 1e-9
}

/// Rings with more edges than this are checked only while the sweep below stays under
/// [`MAX_PAIR_TESTS`] segment tests.
pub(crate) const MAX_PAIR_TESTS: usize = 1_000_000;

/// Result of [`self_intersection`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Simplicity {
    Simple,
    /// Edges `i` (from point i to i+1) and `j` meet where they should not.
    Crossing(usize, usize),
    /// Too many candidate pairs: not decided.
    Unknown,
}

/// Finds two edges of the ring `pts` (closed, no consecutive repeats, at least 3 points)
/// that cross, touch, or (for neighbouring edges) fold back over each other. Sort and
/// sweep on x, so ordinary polygons cost about O(n log n).
pub(crate) fn self_intersection(pts: &[Vec2]) -> Simplicity {
    let n = pts.len();
    if n < 3 {
        return Simplicity::Simple;
    }
    let edge = |i: usize| (pts[i], pts[(i + 1) % n]);
    // Neighbouring edges share a vertex; they are wrong only when they fold back.
    for i in 0..n {
        let (a, b) = edge(i);
        let c = pts[(i + 2) % n];
        if orient(a, b, c) == 0 && b.minus(a).dot(c.minus(b)) < 0.0 {
            return Simplicity::Crossing(i, (i + 1) % n);
        }
    }
    if n == 3 {
        return Simplicity::Simple;
    }
    let mut order: Vec<(f64, f64, usize)> = (0..n)
        .map(|i| {
            let (a, b) = edge(i);
            (a.x.min(b.x), a.x.max(b.x), i)
        })
        .collect();
    order.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.2.cmp(&y.2)));
    let mut tests = 0usize;
    let mut found: Option<(usize, usize)> = None;
    for (k, &(_, xmax, i)) in order.iter().enumerate() {
        for &(xmin_j, _, j) in &order[k + 1..] {
            if xmin_j > xmax {
                break;
            }
            let adjacent = (i + 1) % n == j || (j + 1) % n == i;
            if adjacent {
                continue;
            }
            tests += 1;
            if tests > MAX_PAIR_TESTS {
                return Simplicity::Unknown;
            }
            let (a, b) = edge(i);
            let (c, d) = edge(j);
            if a.y.max(b.y) < c.y.min(d.y) || c.y.max(d.y) < a.y.min(b.y) {
                continue;
            }
            if segments_meet(a, b, c, d) != Meet::None {
                let pair = (i.min(j), i.max(j));
                if found.is_none_or(|f| pair < f) {
                    found = Some(pair);
                }
            }
        }
    }
    match found {
        Some((i, j)) => Simplicity::Crossing(i, j),
        None => Simplicity::Simple,
    }
}

/// Index of vertex `v` in its level's `vertices` list (the number written in the file).
pub(crate) fn level_index(b: &Building, v: Handle<Vertex>) -> usize {
    let level = &b.levels[b.vertices[v].level];
    level.vertices.iter().position(|&x| x == v).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    #[test]
    fn segments() {
        assert_eq!(
            segments_meet(v(0., 0.), v(2., 2.), v(0., 2.), v(2., 0.)),
            Meet::Cross
        );
        // Touching at an end point.
        assert_eq!(
            segments_meet(v(0., 0.), v(1., 0.), v(1., 0.), v(1., 1.)),
            Meet::Cross
        );
        assert_eq!(
            segments_meet(v(0., 0.), v(1., 0.), v(2., -1.), v(2., 1.)),
            Meet::None
        );
        assert_eq!(
            segments_meet(v(0., 0.), v(2., 0.), v(1., 0.), v(3., 0.)),
            Meet::Overlap
        );
        assert_eq!(
            segments_meet(v(0., 0.), v(1., 0.), v(2., 0.), v(3., 0.)),
            Meet::None
        );
        // Scale free: the same crossing at millimetre and kilometre scale.
        for k in [1e-3, 1.0, 1e3, 1e6] {
            assert_eq!(
                segments_meet(v(0., 0.), v(k, k), v(0., k), v(k, 0.)),
                Meet::Cross
            );
        }
    }

    #[test]
    fn polygons() {
        let sq = [v(0., 0.), v(1., 0.), v(1., 1.), v(0., 1.)];
        assert_eq!(signed_area(&sq), 1.0);
        assert!(point_in_polygon(v(0.5, 0.5), &sq));
        assert!(point_in_polygon(v(1.0, 0.5), &sq));
        assert!(!point_in_polygon(v(1.5, 0.5), &sq));
        assert_eq!(self_intersection(&sq), Simplicity::Simple);
        let bowtie = [v(0., 0.), v(1., 1.), v(1., 0.), v(0., 1.)];
        assert_eq!(self_intersection(&bowtie), Simplicity::Crossing(0, 2));
        let spike = [v(0., 0.), v(2., 0.), v(1., 0.), v(1., 1.)];
        assert!(matches!(
            self_intersection(&spike),
            Simplicity::Crossing(..)
        ));
        let flat = [v(0., 0.), v(1., 0.), v(2., 0.)];
        assert_eq!(fan_extent(&flat), 0.0);
        let plus_a = [v(-2., -1.), v(2., -1.), v(2., 1.), v(-2., 1.)];
        let plus_b = [v(-1., -2.), v(1., -2.), v(1., 2.), v(-1., 2.)];
        assert!(rings_overlap(&plus_a, &plus_b));
        let far = [v(5., 5.), v(6., 5.), v(6., 6.)];
        assert!(!rings_overlap(&plus_a, &far));
    }

    #[test]
    fn large_polygons_stay_fast() {
        // A 20,000-gon: the sweep tests only a few neighbours per edge.
        let n = 20_000;
        let circle: Vec<Vec2> = (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                v(100.0 * a.cos(), 100.0 * a.sin())
            })
            .collect();
        assert_eq!(self_intersection(&circle), Simplicity::Simple);
        // A comb whose long teeth all overlap in x: too many pairs, not decided.
        let mut comb = Vec::new();
        for i in 0..1500 {
            let y = 2.0 * i as f64;
            comb.extend([v(0., y), v(100., y), v(100., y + 1.), v(0.5, y + 1.)]);
        }
        comb.extend([v(-1., 3000.), v(-1., 0.)]);
        assert_eq!(self_intersection(&comb), Simplicity::Unknown);
    }

    #[test]
    fn ring_overlap_of_large_rings() {
        // 20,000-corner rings: an n × n edge loop would take minutes in a debug build.
        let circle = |r: f64, cx: f64| -> Vec<Vec2> {
            (0..20_000)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / 20_000.0;
                    v(cx + r * a.cos(), r * a.sin())
                })
                .collect()
        };
        let big = circle(10.0, 0.0);
        assert!(rings_overlap(&circle(5.0, 0.0), &big)); // inside
        assert!(rings_overlap(&big, &circle(5.0, 0.0))); // contains
        assert!(rings_overlap(&circle(5.0, 12.0), &big)); // crossing
        assert!(!rings_overlap(&circle(5.0, 16.0), &circle(5.0, 0.0))); // apart
        assert!(rings_overlap(&circle(5.0, 10.0), &circle(5.0, 0.0))); // touching
    }
}
