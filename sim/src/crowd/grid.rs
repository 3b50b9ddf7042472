//! A dense uniform grid over the navmesh's bounding box, rebuilt per crowd step by a
//! counting sort (linear in people): the neighbour queries of the avoidance and the
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
    cell_of: Vec<u32>,
}

/// At most this many cells (the cell size grows on very large meshes).
const MAX_CELLS: f64 = 1_000_000.0;

impl Grid {
    /// A grid over `[lo, hi]` with cells of about `cell` metres.
    pub fn new(lo: Vec2, hi: Vec2, cell: f64) -> Grid {
        let (w, h) = ((hi.x - lo.x).max(1.0), (hi.y - lo.y).max(1.0));
        let cell = cell.max((w * h / MAX_CELLS).sqrt());
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
            cell_of: Vec::new(),
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

    /// Files point k of `pts` in its cell.
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
        let mut cursor = self.start.clone();
        for (k, &c) in self.cell_of.iter().enumerate() {
            let slot = &mut cursor[c as usize];
            self.items[*slot as usize] = k as u32;
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

    /// Items filed in the cells that the disc of radius `r` around `p` touches (each once
    /// for points; boxes may repeat across cells).
    pub fn visit(&self, p: Vec2, r: f64, mut f: impl FnMut(usize)) {
        let (x0, x1) = (self.ix(p.x - r), self.ix(p.x + r));
        let (y0, y1) = (self.iy(p.y - r), self.iy(p.y + r));
        for y in y0..=y1 {
            for x in x0..=x1 {
                let c = y * self.nx + x;
                let (s, e) = (self.start[c] as usize, self.start[c + 1] as usize);
                for &k in &self.items[s..e] {
                    f(k as usize);
                }
            }
        }
    }

    /// Items of the one cell holding `p`.
    pub fn cell(&self, p: Vec2) -> &[u32] {
        let c = self.iy(p.y) * self.nx + self.ix(p.x);
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }
}
