//! A spatial hash of axis-aligned boxes (Teschner et al. 2003): each box is listed in
//! every cell of a uniform grid it covers, the cells hashed into a table sorted by
//! counting, so building it and asking it for the boxes overlapping another box cost a
//! few passes over flat arrays and allocate nothing once its buffers have grown.
//!
//! A pair of overlapping boxes is reported once: in the cell holding the low corner of
//! their intersection. Boxes from different cells that share a bucket are filtered by
//! the overlap test and that rule.

use glam::Vec3;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub lo: Vec3,
    pub hi: Vec3,
}

impl Aabb {
    pub const EMPTY: Self = Self {
        lo: Vec3::splat(f32::INFINITY),
        hi: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn point(p: Vec3) -> Self {
        Self { lo: p, hi: p }
    }

    pub fn of(points: &[Vec3]) -> Self {
        points.iter().fold(Self::EMPTY, |b, &p| b.with(p))
    }

    pub fn with(self, p: Vec3) -> Self {
        Self {
            lo: self.lo.min(p),
            hi: self.hi.max(p),
        }
    }

    pub fn union(self, o: Self) -> Self {
        Self {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    pub fn grown(self, r: f32) -> Self {
        Self {
            lo: self.lo - Vec3::splat(r),
            hi: self.hi + Vec3::splat(r),
        }
    }

    pub fn overlaps(&self, o: &Self) -> bool {
        self.lo.cmple(o.hi).all() && o.lo.cmple(self.hi).all()
    }

    /// The least of `n . p` over the box.
    pub fn min_along(&self, n: Vec3) -> f32 {
        let a = n * self.lo;
        let b = n * self.hi;
        a.min(b).element_sum()
    }

    /// The most of `n . p` over the box.
    pub fn max_along(&self, n: Vec3) -> f32 {
        let a = n * self.lo;
        let b = n * self.hi;
        a.max(b).element_sum()
    }

    pub fn is_finite(&self) -> bool {
        self.lo.is_finite() && self.hi.is_finite()
    }
}

/// Most cells one box may cover before it is treated as covering the cells of its low
/// corner's neighbourhood only (a box that large is a bug upstream; capping it keeps a
/// query bounded). Callers keep boxes within a few cells.
const MAX_CELLS_PER_BOX: i64 = 4096;

/// The hash of boxes.
#[derive(Clone, Debug, Default)]
pub struct BoxGrid {
    cell: f32,
    inv_cell: f32,
    mask: usize,
    /// Bucket `b` lists `items[start[b]..start[b + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
    boxes: Vec<Aabb>,
}

fn cell_of(p: Vec3, inv: f32) -> [i32; 3] {
    let c = (p * inv).floor();
    [c.x as i32, c.y as i32, c.z as i32]
}

#[inline]
fn hash(c: [i32; 3]) -> usize {
    (c[0] as u32)
        .wrapping_mul(73_856_093)
        .wrapping_add((c[1] as u32).wrapping_mul(19_349_663))
        .wrapping_add((c[2] as u32).wrapping_mul(83_492_791)) as usize
}

/// Calls `f` with every cell of `b` (at most `MAX_CELLS_PER_BOX`).
#[inline]
fn cells(b: &Aabb, inv: f32, mut f: impl FnMut([i32; 3])) {
    let (lo, hi) = (cell_of(b.lo, inv), cell_of(b.hi, inv));
    // In i64 and saturating: far-flung boxes (cells at i32's ends) must neither overflow
    // nor loop over billions of cells.
    let count = (0..3)
        .map(|k| (hi[k] as i64 - lo[k] as i64 + 1).max(1))
        .fold(1i64, i64::saturating_mul);
    let hi = if count > MAX_CELLS_PER_BOX { lo } else { hi };
    for z in lo[2]..=hi[2] {
        for y in lo[1]..=hi[1] {
            for x in lo[0]..=hi[0] {
                f([x, y, z]);
            }
        }
    }
}

impl BoxGrid {
    /// Rebuilds the hash over `boxes` (ids are their indices) with cells of `cell` m.
    /// Boxes that are not finite are left out.
    pub fn build(&mut self, boxes: impl IntoIterator<Item = Aabb>, cell: f32) {
        self.boxes.clear();
        self.boxes.extend(boxes);
        self.cell = cell.max(1e-5);
        self.inv_cell = 1.0 / self.cell;
        let inv = self.inv_cell;
        let buckets = (2 * self.boxes.len()).next_power_of_two().max(64);
        self.mask = buckets - 1;
        self.start.clear();
        self.start.resize(buckets + 1, 0);
        for b in &self.boxes {
            if b.is_finite() {
                cells(b, inv, |c| self.start[(hash(c) & self.mask) + 1] += 1);
            }
        }
        for k in 0..buckets {
            self.start[k + 1] += self.start[k];
        }
        self.items.clear();
        self.items.resize(self.start[buckets] as usize, 0);
        // Fill from the back of each bucket, counting its start down.
        let mut fill = std::mem::take(&mut self.start);
        for (id, b) in self.boxes.iter().enumerate() {
            if b.is_finite() {
                cells(b, inv, |c| {
                    let k = (hash(c) & self.mask) + 1;
                    fill[k] -= 1;
                    self.items[fill[k] as usize] = id as u32;
                });
            }
        }
        // `fill[k + 1]` is now bucket k's start; shift back into place.
        fill.remove(0);
        fill.push(self.items.len() as u32);
        self.start = fill;
    }

    pub fn len(&self) -> usize {
        self.boxes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    pub fn box_of(&self, id: u32) -> &Aabb {
        &self.boxes[id as usize]
    }

    pub fn cell(&self) -> f32 {
        self.cell
    }

    /// Calls `f` once with every box id overlapping `q`.
    #[inline]
    pub fn query(&self, q: &Aabb, mut f: impl FnMut(u32)) {
        if self.boxes.is_empty() || !q.is_finite() {
            return;
        }
        let inv = self.inv_cell;
        cells(q, inv, |c| {
            let k = hash(c) & self.mask;
            // A box with several cells hashed to this bucket is in it several times, in a
            // row (`build` fills box by box): look at it once.
            let mut prev = u32::MAX;
            for &id in &self.items[self.start[k] as usize..self.start[k + 1] as usize] {
                if id == prev {
                    continue;
                }
                prev = id;
                let b = &self.boxes[id as usize];
                if b.overlaps(q) && cell_of(b.lo.max(q.lo), inv) == c {
                    f(id);
                }
            }
        });
    }
}

/// The edges of triangles `tris`, each once, as (low, high) vertex pairs in order.
pub fn unique_edges(tris: &[[u32; 3]]) -> Vec<[u32; 2]> {
    // Sorted as one u64 each (the same order as the pairs): the guard rebuilds these
    // at every edit of a 16k-vertex cloth.
    let mut keys: Vec<u64> = tris
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .map(|[a, b]| (a.min(b) as u64) << 32 | a.max(b) as u64)
        .collect();
    keys.sort_unstable();
    keys.dedup();
    keys.into_iter()
        .map(|k| [(k >> 32) as u32, k as u32])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn boxes(raw: &[(f32, f32, f32, f32)]) -> Vec<Aabb> {
        raw.iter()
            .map(|&(x, y, z, s)| Aabb {
                lo: Vec3::new(x, y, z),
                hi: Vec3::new(x, y, z) + Vec3::new(s, 0.5 * s, 0.25 * s),
            })
            .collect()
    }

    proptest! {
        /// Every overlapping pair is reported exactly once, and nothing else.
        #[test]
        fn query_finds_each_overlap_once(
            raw in prop::collection::vec((-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0, 0.0f32..0.4), 1..60),
            q in (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0, 0.0f32..0.6),
            cell in 0.05f32..0.5,
        ) {
            let bs = boxes(&raw);
            let mut g = BoxGrid::default();
            g.build(bs.iter().copied(), cell);
            let q = boxes(&[q])[0];
            let mut got = Vec::new();
            g.query(&q, |id| got.push(id));
            got.sort_unstable();
            let want: Vec<u32> = (0..bs.len() as u32).filter(|&i| bs[i as usize].overlaps(&q)).collect();
            prop_assert_eq!(got, want);
        }
    }

    /// Found by the property above: two of the box's cells share a bucket, and it was
    /// reported twice.
    #[test]
    fn a_box_whose_cells_share_a_bucket_is_found_once() {
        let bs = boxes(&[(-0.34849206, 0.83573365, -0.2644955, 0.36205113)]);
        let mut g = BoxGrid::default();
        g.build(bs.iter().copied(), 0.05);
        let q = boxes(&[(0.0, 0.79071057, -0.23401642, 0.3886301)])[0];
        let mut got = Vec::new();
        g.query(&q, |id| got.push(id));
        assert_eq!(got, [0]);
    }

    /// Found by the design fuzz target: a box spanning ±1e30 m (a damaged design's
    /// velocities) overflowed the cell count and, wrapped, walked billions of cells.
    #[test]
    fn a_far_flung_box_covers_few_cells_without_overflow() {
        let huge = Aabb {
            lo: Vec3::splat(-1e30),
            hi: Vec3::new(1e30, 2e30, 1e30),
        };
        let mut n = 0;
        cells(&huge, 100.0, |_| n += 1);
        assert_eq!(n, 1);
        let mut g = BoxGrid::default();
        g.build([huge, boxes(&[(0.0, 0.0, 0.0, 0.1)])[0]], 0.01);
        let mut got = Vec::new();
        g.query(&huge, |id| got.push(id));
        assert!(got.contains(&0), "{got:?}");
    }

    #[test]
    fn support_along_a_direction() {
        let b = Aabb {
            lo: Vec3::new(-1.0, 0.0, 2.0),
            hi: Vec3::new(1.0, 3.0, 4.0),
        };
        let n = Vec3::new(1.0, -1.0, 0.0);
        assert_eq!(b.min_along(n), -1.0 - 3.0);
        assert_eq!(b.max_along(n), 1.0);
    }
}
