//! A dense uniform grid over the navmesh's bounding box, rebuilt per crowd step by a
//! counting sort (linear in people and cells; positions copied in cell order, so that a
//! row of cells is one contiguous run): the neighbour queries of the avoidance and the
//! slotcars' "person in front" test. Points outside the box go to its border cells, so a
//! query still finds them (the border cells are only a little fuller).

use mapc_ir::Vec2;

pub(crate) struct Grid {
    x0: f64,
    y0: f64,
    inv: f64,
    nx: usize,
    ny: usize,
    /// Cell c holds `items[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
    /// For points: the position of `items[j]` at `pts[j]`, so that a query reads one
    /// contiguous run per cell instead of chasing every person's record.
    pts: Vec<Vec2>,
    cell_of: Vec<u32>,
    cursor: Vec<u32>,
}

impl Grid {
    /// A grid over `[lo, hi]` with cells of about `cell` metres, at most `max_cells` of
    /// them (the cells grow on large meshes: a rebuild costs one pass over the cells).
    pub fn new(lo: Vec2, hi: Vec2, cell: f64, max_cells: f64) -> Grid {
        let (w, h) = ((hi.x - lo.x).max(1.0), (hi.y - lo.y).max(1.0));
        let cell = cell.max((w * h / max_cells.max(1.0)).sqrt());
        let nx = ((w / cell).ceil() as usize).max(1);
        let ny = ((h / cell).ceil() as usize).max(1);
        Grid {
            x0: lo.x,
            y0: lo.y,
            inv: 1.0 / cell,
            nx,
            ny,
            start: vec![0; nx * ny + 1],
            items: Vec::new(),
            pts: Vec::new(),
            cell_of: Vec::new(),
            cursor: Vec::new(),
        }
    }

    fn ix(&self, x: f64) -> usize {
        let i = ((x - self.x0) * self.inv).floor();
        if i.is_nan() || i < 0.0 {
            0
        } else {
            (i as usize).min(self.nx - 1)
        }
    }

    fn iy(&self, y: f64) -> usize {
        let i = ((y - self.y0) * self.inv).floor();
        if i.is_nan() || i < 0.0 {
            0
        } else {
            (i as usize).min(self.ny - 1)
        }
    }

    /// Files point k of `pts` in its cell (stable: by cell, then by k).
    pub fn rebuild(&mut self, pts: impl ExactSizeIterator<Item = Vec2> + Clone) {
        let n = pts.len();
        self.start.fill(0);
        self.cell_of.clear();
        for p in pts.clone() {
            let c = self.iy(p.y) * self.nx + self.ix(p.x);
            self.cell_of.push(c as u32);
            self.start[c + 1] += 1;
        }
        for c in 0..self.nx * self.ny {
            self.start[c + 1] += self.start[c];
        }
        self.items.clear();
        self.items.resize(n, 0);
        self.pts.clear();
        self.pts.resize(n, Vec2::default());
        self.cursor.clear();
        self.cursor.extend_from_slice(&self.start);
        for (k, (p, &c)) in pts.zip(&self.cell_of).enumerate() {
            let slot = &mut self.cursor[c as usize];
            self.items[*slot as usize] = k as u32;
            self.pts[*slot as usize] = p;
            *slot += 1;
        }
    }

    /// Files item k in every cell its box `[lo, hi]` touches (for segments).
    pub fn rebuild_boxes(&mut self, boxes: &[(Vec2, Vec2)]) {
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        for (k, (lo, hi)) in boxes.iter().enumerate() {
            for y in self.iy(lo.y)..=self.iy(hi.y) {
                for x in self.ix(lo.x)..=self.ix(hi.x) {
                    pairs.push(((y * self.nx + x) as u32, k as u32));
                }
            }
        }
        pairs.sort_unstable();
        self.start.fill(0);
        for &(c, _) in &pairs {
            self.start[c as usize + 1] += 1;
        }
        for c in 0..self.nx * self.ny {
            self.start[c + 1] += self.start[c];
        }
        self.items = pairs.into_iter().map(|p| p.1).collect();
    }

    /// The cells that the disc of radius `r` around `p` touches: rows `y0..=y1`,
    /// columns `x0..=x1`.
    fn span(&self, p: Vec2, r: f64) -> (usize, usize, usize, usize) {
        (
            self.ix(p.x - r),
            self.ix(p.x + r),
            self.iy(p.y - r),
            self.iy(p.y + r),
        )
    }

    /// Points (index, position) filed in the cells that the disc of radius `r` around `p`
    /// touches, each once; only after `rebuild`.
    pub fn visit_points(&self, p: Vec2, r: f64, mut f: impl FnMut(usize, Vec2)) {
        let (x0, x1, y0, y1) = self.span(p, r);
        for y in y0..=y1 {
            // A row's cells are adjacent in the cell order: one run per row.
            let row = y * self.nx;
            let (s, e) = (
                self.start[row + x0] as usize,
                self.start[row + x1 + 1] as usize,
            );
            for (&k, &q) in self.items[s..e].iter().zip(&self.pts[s..e]) {
                f(k as usize, q);
            }
        }
    }

    /// Items of the one cell holding `p`.
    pub fn cell(&self, p: Vec2) -> &[u32] {
        let c = self.iy(p.y) * self.nx + self.ix(p.x);
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }
}

/// Lower bounds of distances are shrunk by this much (m), so that a point a rounding error
/// outside its nominal cell is never pruned.
const LB_MARGIN: f64 = 1e-6;

impl Grid {
    /// The `k` points nearest to `p` within `r` (squared distance, index), nearest first
    /// (ties by index), into `best`, leaving out `skip` and points closer than 1e-4 m;
    /// returns how many of the points within `r` are closer than `sqrt(count_r2)`. Exact:
    /// the same set and order as scanning every point within `r` and sorting them. Rows of
    /// cells are read nearest first, each as one run of cells as wide as the distance of
    /// the k-th point found so far allows, and the search stops at the first row that
    /// cannot hold a nearer point: in a crowd it reads about the cells of the k nearest.
    pub fn nearest(
        &self,
        p: Vec2,
        r: f64,
        k: usize,
        skip: usize,
        count_r2: f64,
        best: &mut Vec<(f64, usize)>,
    ) -> usize {
        best.clear();
        let r2 = r * r;
        let mut count = 0;
        let mut consider = |q: usize, pos: Vec2, best: &mut Vec<(f64, usize)>| {
            if q == skip {
                return;
            }
            let d = pos.minus(p);
            let d2 = d.x * d.x + d.y * d.y;
            // Coincident agents have no direction to avoid along (the avoidance crate
            // would divide by zero): only a guard, placement keeps people apart.
            if !(d2 < r2 && d2 > 1e-8) {
                return;
            }
            if d2 < count_r2 {
                count += 1;
            }
            let before = |a: (f64, usize), b: (f64, usize)| a.0 < b.0 || (a.0 == b.0 && a.1 < b.1);
            let item = (d2, q);
            if best.len() == k {
                match best.last() {
                    Some(&w) if before(item, w) => {
                        best.pop();
                    }
                    _ => return,
                }
            }
            // Insertion into a short sorted list.
            let mut at = best.len();
            while at > 0 && before(item, best[at - 1]) {
                at -= 1;
            }
            best.insert(at, item);
        };
        let fx = ((p.x - self.x0) * self.inv).floor();
        let fy = ((p.y - self.y0) * self.inv).floor();
        let inside = fx >= 0.0 && fy >= 0.0 && fx < self.nx as f64 && fy < self.ny as f64;
        if !inside || k == 0 || !r.is_finite() {
            // Outside the box the cells' bounds do not hold: every cell in reach.
            self.visit_points(p, r, |q, pos| consider(q, pos, best));
            return count;
        }
        let (cx, cy) = (fx as i64, fy as i64);
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        let cell = 1.0 / self.inv;
        // Rows beyond this many cells from p's cannot hold a point within r.
        let reach = ((r * self.inv).ceil() as i64 + 1).min(ny);
        for j in 0..=2 * reach {
            // 0, -1, 1, -2, 2, ...: the lower bound gy never decreases.
            let dy = if j % 2 == 1 { -(j + 1) / 2 } else { j / 2 };
            let gy = (((dy.abs() - 1).max(0)) as f64 * cell - LB_MARGIN).max(0.0);
            let gy2 = gy * gy;
            // Squared distance beyond which no point matters: r, or once k are found the
            // k-th (ties included) and the counting circle.
            let lim2 = match best.last() {
                Some(w) if best.len() == k => w.0.max(count_r2).min(r2),
                _ => r2,
            };
            if gy2 > lim2 || gy2 >= r2 {
                break;
            }
            let y = cy + dy;
            if y < 0 || y >= ny {
                continue;
            }
            let w = ((lim2 - gy2).sqrt() + LB_MARGIN) * self.inv;
            let dx = (w.floor() as i64 + 1).min(nx);
            let (x0, x1) = ((cx - dx).max(0), (cx + dx).min(nx - 1));
            let row = y as usize * self.nx;
            let s = self.start[row + x0 as usize] as usize;
            let e = self.start[row + x1 as usize + 1] as usize;
            for (&q, &pos) in self.items[s..e].iter().zip(&self.pts[s..e]) {
                consider(q as usize, pos, best);
            }
        }
        count
    }
}
