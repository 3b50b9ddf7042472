//! Uniform grids: the spatial index of the rules that compare elements pairwise, so that
//! no rule is quadratic in the map. A uniform grid (rather than an R-tree) because every
//! query has a fixed radius or a bounding box of a map element, and the cell size can be
//! chosen from the tolerance or the elements' extent: insert and query are O(1 + hits),
//! with no dependency and no tree to balance.

use crate::Vec2;
use std::collections::HashMap;

/// The cell of `p` for cells of side `cell`. Coordinates are finite (an IR invariant);
/// far-away ones saturate, which only merges distant cells.
fn cell_of(p: Vec2, cell: f64) -> (i64, i64) {
    ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64)
}

/// Points in square cells of a fixed side, for "everything within r of p" queries with
/// r ≤ the side. Points can be removed lazily: a query first drops the points its
/// `keep` predicate rejects, so each point is dropped from its cell once.
pub(crate) struct PointGrid {
    cell: f64,
    cells: HashMap<(i64, i64), Vec<u32>>,
}

impl PointGrid {
    /// A grid of `points` (an id and a position each) in cells of side `cell` (> 0).
    pub(crate) fn new(cell: f64, points: impl IntoIterator<Item = (u32, Vec2)>) -> Self {
        let points = points.into_iter();
        let mut cells: HashMap<(i64, i64), Vec<u32>> = HashMap::with_capacity(points.size_hint().0);
        for (id, p) in points {
            cells.entry(cell_of(p, cell)).or_default().push(id);
        }
        PointGrid { cell, cells }
    }

    /// Calls `visit` with every kept point in the 3 × 3 cells around `p` (a superset of
    /// the points within `cell` of `p`), after dropping the points `keep` rejects.
    pub(crate) fn near(
        &mut self,
        p: Vec2,
        mut keep: impl FnMut(u32) -> bool,
        mut visit: impl FnMut(u32),
    ) {
        let (cx, cy) = cell_of(p, self.cell);
        for dx in -1..=1i64 {
            for dy in -1..=1i64 {
                let key = (cx.saturating_add(dx), cy.saturating_add(dy));
                let Some(ids) = self.cells.get_mut(&key) else {
                    continue;
                };
                ids.retain(|&id| keep(id));
                for &id in ids.iter() {
                    visit(id);
                }
            }
        }
    }
}

/// Axis-aligned boxes in square cells: each box is in every cell it overlaps, so a query
/// box finds every box that overlaps it. The cell side is the median box side (at least
/// `MIN_CELL`), so a typical box spans a few cells; only occupied cells are stored, and a
/// query box larger than the occupied area scans the occupied cells instead.
pub struct BoxGrid {
    cell: f64,
    cells: HashMap<(i64, i64), Vec<u32>>,
    /// Per id, the last query that returned it (deduplicates boxes in several cells).
    seen: Vec<u32>,
    query: u32,
}

/// At most this many cells are visited for one box; beyond it the box's cells are
/// scanned as a whole (every box), so a huge box costs O(boxes), not O(area / cell²).
const MAX_CELLS_PER_BOX: i64 = 4096;

/// The smallest cell side, metres (zero-length walls would make it 0).
const MIN_CELL: f64 = 0.05;

impl BoxGrid {
    /// A grid of the boxes `(min, max)`, ids `0..boxes.len()`.
    pub fn new(boxes: &[(Vec2, Vec2)]) -> Self {
        let mut sides: Vec<f64> = boxes
            .iter()
            .map(|(a, b)| (b.x - a.x).max(b.y - a.y))
            .collect();
        let typical = if sides.is_empty() {
            0.0
        } else {
            let mid = sides.len() / 2;
            *sides.select_nth_unstable_by(mid, f64::total_cmp).1
        };
        let cell = if typical.is_finite() {
            typical.max(MIN_CELL)
        } else {
            1.0
        };
        let mut grid = BoxGrid {
            cell,
            // A typical box spans a few cells: room for one each at least.
            cells: HashMap::with_capacity(boxes.len()),
            seen: vec![u32::MAX; boxes.len()],
            query: 0,
        };
        for (id, &(a, b)) in boxes.iter().enumerate() {
            let (x0, y0) = cell_of(a, cell);
            let (x1, y1) = cell_of(b, cell);
            if cells_in(x0, y0, x1, y1) > MAX_CELLS_PER_BOX {
                grid.cells
                    .entry((i64::MIN, i64::MIN))
                    .or_default()
                    .push(id as u32);
                continue;
            }
            for x in x0..=x1 {
                for y in y0..=y1 {
                    grid.cells.entry((x, y)).or_default().push(id as u32);
                }
            }
        }
        grid
    }

    /// The ids of the boxes that may overlap `(min, max)`, each once, in no set order.
    pub fn candidates(&mut self, min: Vec2, max: Vec2) -> Vec<u32> {
        self.query = self.query.wrapping_add(1);
        let q = self.query;
        let mut out = Vec::new();
        let mut take = |ids: &Vec<u32>, seen: &mut Vec<u32>| {
            for &id in ids {
                if seen[id as usize] != q {
                    seen[id as usize] = q;
                    out.push(id);
                }
            }
        };
        if let Some(huge) = self.cells.get(&(i64::MIN, i64::MIN)) {
            take(huge, &mut self.seen);
        }
        let (x0, y0) = cell_of(min, self.cell);
        let (x1, y1) = cell_of(max, self.cell);
        if cells_in(x0, y0, x1, y1) > self.cells.len() as i64 {
            // Fewer occupied cells than cells in the box: scan the occupied ones.
            for (&(x, y), ids) in &self.cells {
                if (x0..=x1).contains(&x) && (y0..=y1).contains(&y) {
                    take(ids, &mut self.seen);
                }
            }
        } else {
            for x in x0..=x1 {
                for y in y0..=y1 {
                    if let Some(ids) = self.cells.get(&(x, y)) {
                        take(ids, &mut self.seen);
                    }
                }
            }
        }
        out.sort_unstable();
        out
    }
}

/// The number of cells from (x0, y0) to (x1, y1), saturating.
fn cells_in(x0: i64, y0: i64, x1: i64, y1: i64) -> i64 {
    let w = x1.saturating_sub(x0).saturating_add(1).max(0);
    let h = y1.saturating_sub(y0).saturating_add(1).max(0);
    w.saturating_mul(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_near() {
        let pts = [
            (0, Vec2::new(0.0, 0.0)),
            (1, Vec2::new(0.05, 0.0)),
            (2, Vec2::new(0.5, 0.0)),
        ];
        let mut g = PointGrid::new(0.1, pts);
        let mut found = Vec::new();
        g.near(Vec2::new(0.0, 0.0), |_| true, |id| found.push(id));
        found.sort_unstable();
        assert_eq!(found, vec![0, 1]);
        // Dropped points stay dropped.
        g.near(Vec2::new(0.0, 0.0), |id| id != 1, |_| {});
        let mut again = Vec::new();
        g.near(Vec2::new(0.0, 0.0), |_| true, |id| again.push(id));
        assert_eq!(again, vec![0]);
    }

    #[test]
    fn boxes_overlapping() {
        // A 10 × 10 field of unit boxes 2 m apart, and one huge box.
        let mut boxes: Vec<(Vec2, Vec2)> = (0..100)
            .map(|i| {
                let p = Vec2::new(2.0 * (i % 10) as f64, 2.0 * (i / 10) as f64);
                (p, p.plus(Vec2::new(1.0, 1.0)))
            })
            .collect();
        boxes.push((Vec2::new(-1e12, 0.0), Vec2::new(1e12, 0.1)));
        let mut g = BoxGrid::new(&boxes);
        let c = g.candidates(Vec2::new(2.5, 2.5), Vec2::new(2.6, 2.6));
        assert!(c.contains(&11) && c.contains(&100), "{c:?}");
        assert!(c.len() < 20, "{c:?}");
        let all = g.candidates(Vec2::new(-10.0, -10.0), Vec2::new(30.0, 30.0));
        assert_eq!(all, (0..=100).collect::<Vec<u32>>());
    }
}
