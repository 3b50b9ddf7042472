//! Segment geometry in metres for the lane rules.

use crate::Vec2;

/// Below this distance, in metres, two points touch or a point lies on a line.
pub(super) const TOUCH: f64 = 1e-3;

/// Axis-aligned bounding box of a segment, grown by [`TOUCH`].
#[derive(Debug, Clone, Copy)]
pub(super) struct Bbox {
    pub(super) lo: Vec2,
    pub(super) hi: Vec2,
}

impl Bbox {
    pub(super) fn of(a: Vec2, b: Vec2) -> Bbox {
        Bbox {
            lo: Vec2::new(a.x.min(b.x) - TOUCH, a.y.min(b.y) - TOUCH),
            hi: Vec2::new(a.x.max(b.x) + TOUCH, a.y.max(b.y) + TOUCH),
        }
    }
    pub(super) fn overlaps(&self, o: &Bbox) -> bool {
        self.lo.x <= o.hi.x && o.lo.x <= self.hi.x && self.lo.y <= o.hi.y && o.lo.y <= self.hi.y
    }
}

/// Signed distance in metres of `p` from the line through `a` and `b` (positive on the
/// left of `a→b`). `a` and `b` must be distinct.
pub(super) fn side(a: Vec2, b: Vec2, p: Vec2) -> f64 {
    let d = b.minus(a);
    d.cross(p.minus(a)) / d.norm()
}

/// Distance in metres from `p` to the segment `a`–`b`.
pub(super) fn point_segment_distance(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let d = b.minus(a);
    let len2 = d.dot(d);
    let t = if len2 > 0.0 {
        (p.minus(a).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.minus(a.plus(d.scale(t))).norm()
}

/// The same crossing test the nav backend uses to name a lane's door, so door rules agree
/// with the output.
pub(super) use crate::segment_intersection;

/// `|sin|` of the angle between the directions `a→b` and `p→q` (both non-degenerate).
pub(super) fn abs_sin(a: Vec2, b: Vec2, p: Vec2, q: Vec2) -> f64 {
    let r = b.minus(a);
    let s = q.minus(p);
    (r.cross(s) / (r.norm() * s.norm())).abs()
}

/// Do segments `a`–`b` and `p`–`q` lie on one line (within [`TOUCH`]) and share a stretch
/// longer than [`TOUCH`]? Both must be longer than [`TOUCH`].
pub(super) fn colinear_overlap(a: Vec2, b: Vec2, p: Vec2, q: Vec2) -> bool {
    if side(a, b, p).abs() > TOUCH || side(a, b, q).abs() > TOUCH {
        return false;
    }
    let d = b.minus(a);
    let len = d.norm();
    let (tp, tq) = (p.minus(a).dot(d) / len, q.minus(a).dot(d) / len);
    let (lo, hi) = (tp.min(tq).max(0.0), tp.max(tq).min(len));
    hi - lo > TOUCH
}

/// How a lane `a→b` meets a wall `c`–`d`, decided with distances in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Meet {
    /// No contact, or contact only at one of the lane's own endpoints, or colinear.
    Apart,
    /// The wall passes from one side of the lane to the other, strictly inside both.
    Cross(Vec2),
    /// One end of the wall lies on the lane's interior; `side` is the sign (+1 left, -1
    /// right of the lane) of the wall's other end. Whether the lane crosses the wall line
    /// there depends on the other walls that end at the same point.
    EndOnLane { end_is_start: bool, side: i8 },
}

/// Classifies the contact between lane `a→b` and segment `c`–`d` (both longer than
/// [`TOUCH`]).
pub(super) fn meet(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> Meet {
    let (sc, sd) = (side(a, b, c), side(a, b, d));
    let (sa, sb) = (side(c, d, a), side(c, d, b));
    // The lane's endpoints must be strictly on opposite sides of the wall's line: a lane
    // ending on a wall (a waypoint drawn on it) touches but does not cross.
    if !(sa.abs() > TOUCH && sb.abs() > TOUCH && (sa > 0.0) != (sb > 0.0)) {
        return Meet::Apart;
    }
    let (c_on, d_on) = (sc.abs() <= TOUCH, sd.abs() <= TOUCH);
    match (c_on, d_on) {
        (false, false) if (sc > 0.0) != (sd > 0.0) => {
            let k = sc / (sc - sd);
            Meet::Cross(c.plus(d.minus(c).scale(k)))
        }
        (true, false) => Meet::EndOnLane {
            end_is_start: true,
            side: if sd > 0.0 { 1 } else { -1 },
        },
        (false, true) => Meet::EndOnLane {
            end_is_start: false,
            side: if sc > 0.0 { 1 } else { -1 },
        },
        _ => Meet::Apart,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    #[test]
    fn meet_cases() {
        // A proper crossing, at (1, 0).
        assert_eq!(
            meet(v(0., 0.), v(2., 0.), v(1., -1.), v(1., 1.)),
            Meet::Cross(v(1., 0.))
        );
        // The lane ends on the wall: not a crossing.
        assert_eq!(
            meet(v(0., 0.), v(1., 0.), v(1., -1.), v(1., 1.)),
            Meet::Apart
        );
        // The wall ends on the lane, reaching to the left.
        assert_eq!(
            meet(v(0., 0.), v(2., 0.), v(1., 0.), v(1., 1.)),
            Meet::EndOnLane {
                end_is_start: true,
                side: 1
            }
        );
        // Colinear, parallel and far apart.
        assert_eq!(
            meet(v(0., 0.), v(2., 0.), v(1., 0.), v(3., 0.)),
            Meet::Apart
        );
        assert_eq!(
            meet(v(0., 0.), v(2., 0.), v(0., 1.), v(2., 1.)),
            Meet::Apart
        );
        assert_eq!(
            meet(v(0., 0.), v(2., 0.), v(5., -1.), v(5., 1.)),
            Meet::Apart
        );
    }

    #[test]
    fn scale_free() {
        // Projected coordinates far from the origin, centimetre-sized features.
        let o = v(370_000.0, 140_000.0);
        let m = meet(
            o,
            o.plus(v(0.04, 0.0)),
            o.plus(v(0.02, -0.01)),
            o.plus(v(0.02, 0.01)),
        );
        assert!(matches!(m, Meet::Cross(_)));
        assert!(segment_intersection(
            o,
            o.plus(v(0.04, 0.0)),
            o.plus(v(0.02, -0.01)),
            o.plus(v(0.02, 0.01))
        )
        .is_some());
    }

    #[test]
    fn colinear_and_distance() {
        assert!(colinear_overlap(v(0., 0.), v(2., 0.), v(1., 0.), v(3., 0.)));
        assert!(!colinear_overlap(
            v(0., 0.),
            v(2., 0.),
            v(2., 0.),
            v(3., 0.)
        ));
        assert!(!colinear_overlap(
            v(0., 0.),
            v(2., 0.),
            v(1., 1.),
            v(3., 1.)
        ));
        assert_eq!(point_segment_distance(v(1., 1.), v(0., 0.), v(2., 0.)), 1.0);
        assert_eq!(point_segment_distance(v(3., 0.), v(0., 0.), v(2., 0.)), 1.0);
        assert!(
            (abs_sin(v(0., 0.), v(1., 0.), v(0., 0.), v(1., 1.)) - 0.5f64.sqrt()).abs() < 1e-12
        );
    }
}
