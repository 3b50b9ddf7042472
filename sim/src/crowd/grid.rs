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

    // Truncation is the floor for the non-negative values it sees (a call to libm's
    // floor otherwise, on every query); NaN and negatives go to 0, overflow to the last.
    #[inline]
    fn ix(&self, x: f64) -> usize {
        let i = (x - self.x0) * self.inv;
        if i >= 0.0 {
            (i as usize).min(self.nx - 1)
        } else {
            0
        }
    }

    #[inline]
    fn iy(&self, y: f64) -> usize {
        let i = (y - self.y0) * self.inv;
        if i >= 0.0 {
            (i as usize).min(self.ny - 1)
        } else {
            0
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
    /// Entries (`items[s..e]`, `pts[s..e]`) of the points within the disc of radius `r`
    /// around `p` or near it: per row of cells, the run of cells that the disc reaches (a
    /// little more than the disc).
    #[inline]
    fn disc_runs(&self, p: Vec2, r: f64, mut f: impl FnMut(usize, usize)) {
        let cell = 1.0 / self.inv;
        let (y0, y1) = (self.iy(p.y - r), self.iy(p.y + r));
        // All the runs first, then their points: the rows' square roots overlap instead of
        // each waiting after the previous row's scan.
        let mut runs = [(0u32, 0u32); 32];
        let mut y = y0;
        while y <= y1 {
            let rows = (y1 + 1 - y).min(runs.len());
            for (j, run) in runs[..rows].iter_mut().enumerate() {
                let y = y + j;
                // The band of row y: [lo, lo + cell); its distance from p.
                let lo = self.y0 + y as f64 * cell;
                let gy = ((lo - p.y).max(p.y - (lo + cell)).max(0.0) - LB_MARGIN).max(0.0);
                // Rows outside the box hold the points beyond it: no bound, the whole width.
                let edge = y == 0 || y == self.ny - 1;
                let w = if edge || gy >= r {
                    r
                } else {
                    (r * r - gy * gy).sqrt() + LB_MARGIN
                };
                let (x0, x1) = (self.ix(p.x - w), self.ix(p.x + w));
                let row = y * self.nx;
                *run = (self.start[row + x0], self.start[row + x1 + 1]);
            }
            for &(s, e) in &runs[..rows] {
                f(s as usize, e as usize);
            }
            y += rows;
        }
    }

    /// The `k` points nearest to `p` within `r` as (squared distance, index), nearest
    /// first, ties by index, into `near`, leaving out `skip` and points closer than 1e-4 m;
    /// returns how many points within `r` are closer than `count_r`. Exact: the same as
    /// scanning every point within `r` and sorting them. The scan starts with the disc of
    /// radius `hint` (at least `count_r`; the caller's guess of the k-th distance, such as
    /// the last step's) and doubles it until it holds k points or reaches `r`: in a crowd
    /// it reads little more than the disc of the k nearest.
    #[allow(clippy::too_many_arguments)]
    pub fn nearest(
        &self,
        p: Vec2,
        r: f64,
        k: usize,
        skip: usize,
        count_r: f64,
        hint: f64,
        near: &mut Vec<(f64, usize)>,
    ) -> usize {
        let r2 = r * r;
        let mut rho = hint.max(count_r).min(r);
        loop {
            near.clear();
            let lim2 = (rho * rho).min(r2);
            let mut n = 0;
            self.disc_runs(p, rho, |s, e| {
                // Every entry is written and kept or not by its test, without a branch
                // (which half of a crowd passes is not predictable).
                if near.len() < n + (e - s) {
                    near.resize(n + (e - s), (0.0, 0));
                }
                for (&q, &pos) in self.items[s..e].iter().zip(&self.pts[s..e]) {
                    let d = pos.minus(p);
                    let d2 = d.x * d.x + d.y * d.y;
                    // Coincident agents have no direction to avoid along (the avoidance
                    // crate would divide by zero): only a guard, placement keeps people
                    // apart.
                    let keep = (q as usize != skip) & (d2 < lim2) & (d2 > 1e-8);
                    near[n] = (d2, q as usize);
                    n += usize::from(keep);
                }
            });
            near.truncate(n);
            if near.len() >= k || rho >= r || !rho.is_finite() {
                break;
            }
            rho = (rho * 2.0).min(r);
        }
        let count_r2 = count_r * count_r;
        let count = near.iter().filter(|n| n.0 < count_r2).count();
        let by = |a: &(f64, usize), b: &(f64, usize)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        if near.len() > k {
            if k > 0 {
                near.select_nth_unstable_by(k - 1, by);
            }
            near.truncate(k);
        }
        near.sort_unstable_by(by);
        count
    }
}
