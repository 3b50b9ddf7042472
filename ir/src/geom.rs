//! Plane geometry that several stages need to agree on (the nav backend names the door a
//! lane crosses; validation rules warn about the same crossings).

use crate::{Building, Door, Handle, Level, Vec2};

/// Parameter along `a→b` where it meets segment `p→q` (endpoints included); `None` for
/// parallel, colinear or degenerate segments. Scale-free (the parallel test is relative to
/// the segments' lengths), so it works in metres and in degrees alike.
pub fn segment_intersection(a: Vec2, b: Vec2, p: Vec2, q: Vec2) -> Option<f64> {
    let r = b.minus(a);
    let s = q.minus(p);
    let denom = r.cross(s);
    if denom.abs() <= 1e-12 * r.norm() * s.norm() || denom == 0.0 {
        return None;
    }
    let ap = p.minus(a);
    let t = ap.cross(s) / denom;
    let u = ap.cross(r) / denom;
    let eps = 1e-9;
    ((-eps..=1.0 + eps).contains(&t) && (-eps..=1.0 + eps).contains(&u)).then_some(t)
}

impl Building {
    /// The door of level `level` that a robot going from `a` to `z` meets first, if any.
    /// (The reference generator used raw file coordinates with an absolute threshold and
    /// kept the last door in file order.)
    pub fn crossed_door(&self, level: Handle<Level>, a: Vec2, z: Vec2) -> Option<Handle<Door>> {
        let mut best: Option<(f64, Handle<Door>)> = None;
        for &dh in &self.levels[level].doors {
            let d = &self.doors[dh];
            let (p, q) = (self.vertices[d.start].pos, self.vertices[d.end].pos);
            if let Some(t) = segment_intersection(a, z, p, q) {
                if best.is_none_or(|(bt, _)| t < bt) {
                    best = Some((t, dh));
                }
            }
        }
        best.map(|(_, h)| h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intersection_cases() {
        let v = Vec2::new;
        // Crossing at the middle.
        assert_eq!(
            segment_intersection(v(0., 0.), v(2., 0.), v(1., -1.), v(1., 1.)),
            Some(0.5)
        );
        // Touching at an endpoint counts.
        assert!(segment_intersection(v(0., 0.), v(1., 0.), v(1., 0.), v(1., 1.)).is_some());
        // Parallel and colinear never intersect.
        assert_eq!(
            segment_intersection(v(0., 0.), v(1., 0.), v(0., 1.), v(1., 1.)),
            None
        );
        assert_eq!(
            segment_intersection(v(0., 0.), v(2., 0.), v(1., 0.), v(3., 0.)),
            None
        );
        // Missing by a little.
        assert_eq!(
            segment_intersection(v(0., 0.), v(1., 0.), v(1.1, -1.), v(1.1, 1.)),
            None
        );
        // Scale-free: tiny (degree-sized) segments work.
        assert!(
            segment_intersection(v(0., 0.), v(2e-5, 0.), v(1e-5, -1e-5), v(1e-5, 1e-5)).is_some()
        );
    }
}
