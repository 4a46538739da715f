//! The P3D report's uniform grid (§3), with mailboxes (§4.2)
//! made safe for many threads.
//!
//! - World box: the union of the primitives' boxes. Infinite planes (`pl`)
//!   have none: they stay out of the grid, which covers only the bounded
//!   primitives, and the [`Intersector`] tests them beside the walk.
//! - Cells per axis, formula (1): `size × M × cbrt(n / volume) + 1`, floored;
//!   M = 0 gives a single cell.
//! - Filling, Algorithm 2: each primitive goes into every cell its box
//!   touches, border cells included (indices clamped to the grid).
//! - Storage: compressed rows, one offset array and one index array.
//! - Traversal: 3D-DDA (Amanatides and Woo, 1987), stopping at the first cell
//!   whose nearest hit lies inside that cell.
//! - Mailboxes: a primitive spanning several cells is tested once per ray.
//!   The stamp array and the ray counter belong to each render thread
//!   ([`Mailbox`], the intersector's scratch), never to the shared grid.

use super::{test_prim, AccelInfo, Intersector, Query, Tracer};
use crate::aabb::{Aabb, ENTRY_SLACK};
use crate::geometry::{Geometry, Hit};
use crate::math::RayQuery;
use crate::stats::Counters;
use crate::stopwatch::Stopwatch;
use glam::Vec3A;

/// Cap on the number of cells, whatever M asks for.
const MAX_CELLS: u64 = 1 << 26;

/// Most cells and references together (4 bytes each: 256 MB). Formula (1)
/// multiplies cells by objects, and a primitive goes into every cell its
/// box touches, so one huge polygon's triangles can ask for billions of
/// references; past this the grid is made coarser until it fits.
const MAX_ENTRIES: u64 = 1 << 26;

/// The grid.
#[derive(Debug, Clone)]
pub(crate) struct Grid {
    bounds: Aabb,
    /// Cells per axis.
    pub(crate) dims: [u32; 3],
    cell_size: Vec3A,
    inv_cell_size: Vec3A,
    /// `offsets[c]..offsets[c + 1]` are cell `c`'s entries in `items`.
    offsets: Vec<u32>,
    items: Vec<u32>,
    mailbox: bool,
    prim_count: usize,
    build_seconds: f64,
    /// Why the grid is coarser than formula (1) asks, if it is.
    coarsened: Option<String>,
}

/// Per-thread mailbox: the last ray id that tested each primitive.
#[derive(Debug, Clone)]
pub(crate) struct Mailbox {
    stamps: Vec<u32>,
    ray: u32,
}

impl Mailbox {
    /// A mailbox for `n` primitives (empty when mailboxes are off).
    pub fn new(n: usize) -> Mailbox {
        Mailbox { stamps: vec![0; n], ray: 0 }
    }

    /// Start a new ray: a new id, clearing the stamps when ids wrap.
    #[inline]
    fn next_ray(&mut self) {
        self.ray = self.ray.wrapping_add(1);
        if self.ray == 0 {
            self.stamps.fill(0);
            self.ray = 1;
        }
    }

    /// True if `id` was already tested by this ray; marks it tested.
    #[inline]
    fn seen(&mut self, id: u32) -> bool {
        let s = &mut self.stamps[id as usize];
        let seen = *s == self.ray;
        *s = self.ray;
        seen
    }
}

/// Cells per axis by formula (1) of the P3D report (§3.2.2).
pub(crate) fn cell_counts(bounds: &Aabb, n: usize, m: f32) -> [u32; 3] {
    let size = bounds.size().max(Vec3A::ZERO);
    // A flat world (an axis-aligned polygon) has no volume: give thin axes a
    // token thickness so the density stays finite; they still get one cell.
    let floor = size.max_element().max(f32::MIN_POSITIVE) * 1e-3;
    let s = size.max(Vec3A::splat(floor));
    let density = (n as f32 / (s.x * s.y * s.z)).cbrt();
    let mut dims = [0u32; 3];
    for i in 0..3 {
        let c = size[i] * m * density;
        dims[i] = if c.is_finite() { (c as u32).saturating_add(1) } else { 1 };
    }
    // Keep absurd M values from exhausting memory.
    while dims.iter().map(|&d| d as u64).product::<u64>() > MAX_CELLS {
        for d in &mut dims {
            *d = (*d / 2).max(1);
        }
    }
    dims
}

impl Grid {
    /// Build with density multiplier `m`: formula (1)'s cells, or fewer
    /// when its references would not fit in [`MAX_ENTRIES`].
    pub(crate) fn build(geom: &Geometry, m: f32, mailbox: bool) -> Grid {
        let t0 = Stopwatch::start();
        let n = geom.bounded_len();
        let boxes: Vec<Aabb> = (0..n as u32).map(|id| geom.bounds(id)).collect();
        let bounds = boxes.iter().fold(Aabb::EMPTY, |a, b| a.union(*b));
        let bounds = if n == 0 { Aabb::new(Vec3A::ZERO, Vec3A::ZERO) } else { bounds };
        let asked = cell_counts(&bounds, n, m.max(0.0));
        let mut grid = Grid::empty(bounds, asked, mailbox, n);
        let mut refs = grid.references(&boxes);
        while grid.cells() + refs > MAX_ENTRIES && grid.dims != [1, 1, 1] {
            grid = Grid::empty(bounds, grid.dims.map(|d| d.div_ceil(2)), mailbox, n);
            refs = grid.references(&boxes);
        }
        if grid.dims != asked {
            let [x, y, z] = asked;
            let [a, b, c] = grid.dims;
            grid.coarsened = Some(format!(
                "formula (1) asks for {x}x{y}x{z} cells, whose references would not fit in memory \
                 (the primitives' boxes overlap that many cells); using {a}x{b}x{c} cells with {refs} references"
            ));
        }
        grid.fill(&boxes);
        grid.build_seconds = t0.seconds();
        grid
    }

    /// A grid of `dims` cells over `bounds`, not yet filled.
    fn empty(bounds: Aabb, dims: [u32; 3], mailbox: bool, prim_count: usize) -> Grid {
        let dimv = Vec3A::new(dims[0] as f32, dims[1] as f32, dims[2] as f32);
        let size = bounds.size();
        Grid {
            bounds,
            dims,
            cell_size: size / dimv,
            inv_cell_size: Vec3A::select(size.cmpgt(Vec3A::ZERO), dimv / size, Vec3A::ZERO),
            offsets: Vec::new(),
            items: Vec::new(),
            mailbox,
            prim_count,
            build_seconds: 0.0,
            coarsened: None,
        }
    }

    /// Number of cells.
    fn cells(&self) -> u64 {
        self.dims.iter().map(|&d| d as u64).product()
    }

    /// How many references filling the grid with `boxes` would make,
    /// counted without allocating (saturating).
    fn references(&self, boxes: &[Aabb]) -> u64 {
        boxes.iter().fold(0u64, |sum, b| {
            let (lo, hi) = self.cell_ranges(b);
            let n = (0..3).map(|i| (hi[i] - lo[i]) as u64 + 1).product::<u64>();
            sum.saturating_add(n)
        })
    }

    /// Algorithm 2 of the P3D report (§3.2.3): a world position to clamped cell indices.
    fn world_to_cell(&self, p: Vec3A) -> [u32; 3] {
        let rel = (p - self.bounds.min) * self.inv_cell_size;
        let mut c = [0u32; 3];
        for i in 0..3 {
            c[i] = (rel[i].max(0.0) as u32).min(self.dims[i] - 1);
        }
        c
    }

    #[inline]
    fn cell_index(&self, c: [u32; 3]) -> usize {
        (c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])) as usize
    }

    fn cell_ranges(&self, b: &Aabb) -> ([u32; 3], [u32; 3]) {
        (self.world_to_cell(b.min), self.world_to_cell(b.max))
    }

    /// Two passes: count entries per cell, then place them (compressed rows).
    fn fill(&mut self, boxes: &[Aabb]) {
        let cells = self.dims.iter().map(|&d| d as usize).product::<usize>();
        let mut counts = vec![0u32; cells + 1];
        let each_cell = |g: &Grid, b: &Aabb, f: &mut dyn FnMut(usize)| {
            let (lo, hi) = g.cell_ranges(b);
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        f(g.cell_index([x, y, z]));
                    }
                }
            }
        };
        for b in boxes {
            each_cell(self, b, &mut |c| counts[c + 1] += 1);
        }
        for i in 0..cells {
            counts[i + 1] += counts[i];
        }
        let mut cursor = counts.clone();
        let mut items = vec![0u32; counts[cells] as usize];
        for (id, b) in boxes.iter().enumerate() {
            each_cell(self, b, &mut |c| {
                items[cursor[c] as usize] = id as u32;
                cursor[c] += 1;
            });
        }
        self.offsets = counts;
        self.items = items;
    }

    /// Size and build time.
    pub fn info(&self) -> AccelInfo {
        AccelInfo {
            build_seconds: self.build_seconds,
            bytes: (self.offsets.len() + self.items.len()) * 4,
            nodes: self.offsets.len() - 1,
            summary: if self.mailbox { "uniform grid with mailboxes" } else { "uniform grid, no mailboxes" },
            unit: "cells",
            warning: self.coarsened.clone(),
            sah_cost: None,
        }
    }

    /// The primitives listed in cell `c`.
    #[inline]
    fn cell(&self, c: usize) -> &[u32] {
        &self.items[self.offsets[c] as usize..self.offsets[c + 1] as usize]
    }

    /// 3D-DDA: calls `visit(cell, t_exit)` for each cell the ray crosses
    /// within `(q.t_min, t_max)`, in order, until `visit` returns false.
    #[inline]
    pub fn walk(&self, q: &RayQuery, t_max: f32, mut visit: impl FnMut(usize, f32) -> bool) {
        let Some((t0, t1)) = self.bounds.hit(q, q.t_min, t_max * ENTRY_SLACK) else { return };
        // The bounds are finite, so only a ray with a NaN origin or direction
        // leaves them at no finite distance; it hits nothing (as in every
        // other accelerator) instead of stepping in place for ever.
        if !t1.is_finite() {
            return;
        }
        let (o, d) = (q.ray.o, q.ray.d);
        let mut cell = self.world_to_cell(o + d * t0);
        let mut next = [f32::INFINITY; 3];
        let mut delta = [f32::INFINITY; 3];
        let mut step = [0i32; 3];
        for i in 0..3 {
            if d[i] > 0.0 {
                step[i] = 1;
                let edge = self.bounds.min[i] + (cell[i] + 1) as f32 * self.cell_size[i];
                next[i] = (edge - o[i]) / d[i];
                delta[i] = self.cell_size[i] / d[i];
            } else if d[i] < 0.0 {
                step[i] = -1;
                let edge = self.bounds.min[i] + cell[i] as f32 * self.cell_size[i];
                next[i] = (edge - o[i]) / d[i];
                delta[i] = -self.cell_size[i] / d[i];
            }
        }
        loop {
            let axis = if next[0] < next[1] {
                if next[0] < next[2] {
                    0
                } else {
                    2
                }
            } else if next[1] < next[2] {
                1
            } else {
                2
            };
            let t_exit = next[axis].min(t1);
            if !visit(self.cell_index(cell), t_exit) || next[axis] > t1 {
                return;
            }
            let c = cell[axis] as i32 + step[axis];
            if c < 0 || c >= self.dims[axis] as i32 {
                return;
            }
            cell[axis] = c as u32;
            next[axis] += delta[axis];
        }
    }

    /// Cell coordinates the DDA visits, in order.
    #[cfg(test)]
    fn cells_along(&self, q: &RayQuery, t_max: f32) -> Vec<[u32; 3]> {
        let mut out = Vec::new();
        let (dx, dy) = (self.dims[0] as usize, self.dims[1] as usize);
        self.walk(q, t_max, |c, _| {
            out.push([(c % dx) as u32, ((c / dx) % dy) as u32, (c / (dx * dy)) as u32]);
            true
        });
        out
    }

    /// The cell holding point `p` (clamped), as the builder computes it.
    #[cfg(test)]
    fn cell_of(&self, p: Vec3A) -> [u32; 3] {
        self.world_to_cell(p)
    }
}

impl Intersector for Grid {
    type Scratch = Mailbox;

    fn scratch(&self, _: &Geometry) -> Mailbox {
        Mailbox::new(if self.mailbox { self.prim_count } else { 0 })
    }

    fn trace_bounded<Q: Query>(
        tr: &mut Tracer<'_, Self>,
        q: &RayQuery,
        t_max: f32,
        mut best: Option<Hit>,
    ) -> Option<Hit> {
        let (grid, geom) = (tr.accel, tr.geom);
        grid.walk_candidates(q, t_max, &mut tr.scratch, &mut tr.counters, |id, t_exit, c| match id {
            // Any hit stops the walk at once.
            Some(id) => !test_prim::<Q>(geom, id, q, &mut best, t_max, c),
            // At the end of a cell: the nearest hit stops the walk once it
            // lies within the cell (by a margin: a tied primitive may start
            // only in the next), as no later cell can hold a nearer one.
            None => Q::ANY_HIT || !best.is_some_and(|h| h.t * ENTRY_SLACK <= t_exit),
        });
        best
    }
}

impl Grid {
    /// Walk the cells along the ray and call `visit(Some(id), t_exit, c)` for
    /// each primitive the mailbox has not seen this ray, then
    /// `visit(None, t_exit, c)` at the end of each cell; `visit` returns
    /// false to stop.
    #[inline]
    fn walk_candidates(
        &self,
        q: &RayQuery,
        t_max: f32,
        mb: &mut Mailbox,
        c: &mut Counters,
        mut visit: impl FnMut(Option<u32>, f32, &mut Counters) -> bool,
    ) {
        let use_mailbox = self.mailbox;
        if use_mailbox {
            mb.next_ray();
        }
        self.walk(q, t_max, |cell, t_exit| {
            c.visits += 1;
            for &id in self.cell(cell) {
                if use_mailbox && mb.seen(id) {
                    c.mailbox_hits += 1;
                } else if !visit(Some(id), t_exit, c) {
                    return false;
                }
            }
            visit(None, t_exit, c)
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Ray;
    use crate::testing::{spheres, uniform};

    /// 500 spheres scattered in [-5, 5]^3 by a fixed xorshift.
    fn scattered_spheres() -> Geometry {
        let mut rnd = uniform(0x9e37_79b9_7f4a_7c15);
        spheres(500, |_| (Vec3A::new(rnd(), rnd(), rnd()) * 10.0 - 5.0, 0.1 + rnd() * 0.5))
    }

    #[test]
    fn dda_visits_every_crossed_cell_in_order() {
        let g = scattered_spheres();
        let grid = Grid::build(&g, 2.0, false);
        let (lo, hi) = (grid.bounds.min, grid.bounds.max);
        for i in 0..300 {
            let a = i as f32 * 0.618;
            let o = Vec3A::new(a.sin() * 9.0, (a * 1.7).cos() * 9.0, (a * 0.3).sin() * 9.0);
            let d = Vec3A::new(-o.x + (a * 5.0).sin(), -o.y + (a * 3.0).cos(), -o.z + 0.5);
            let q = RayQuery::new(Ray::new(o, d), 0.0);
            let visited = grid.cells_along(&q, f32::INFINITY);
            // Brute-force walk: sample the ray densely inside the grid; every
            // cell met must appear among the visited ones, in the same order.
            let mut walk: Vec<[u32; 3]> = Vec::new();
            for k in 0..20000 {
                let p = q.ray.at(k as f32 * 0.002);
                if (0..3).any(|j| p[j] < lo[j] + 1e-3 || p[j] > hi[j] - 1e-3) {
                    continue;
                }
                let c = grid.cell_of(p);
                if walk.last() != Some(&c) {
                    walk.push(c);
                }
            }
            let mut pos = 0;
            for c in &walk {
                match visited[pos..].iter().position(|v| v == c) {
                    Some(k) => pos += k,
                    None => panic!("ray {i}: cell {c:?} crossed but not visited (visited {visited:?})"),
                }
            }
            // Consecutive visited cells are face neighbours.
            for w in visited.windows(2) {
                let dist: i32 = (0..3).map(|j| (w[0][j] as i32 - w[1][j] as i32).abs()).sum();
                assert_eq!(dist, 1);
            }
        }
    }

    #[test]
    fn a_nan_ray_ends_its_walk() {
        // A ray computed far from a tiny sphere can carry NaN (before the
        // surface record's fallback normal); the walk stepped in place for
        // ever on it.
        let grid = Grid::build(&scattered_spheres(), 2.0, false);
        for (o, d) in [(Vec3A::NAN, Vec3A::NAN), (Vec3A::ZERO, Vec3A::NAN), (Vec3A::NAN, Vec3A::X)] {
            let q = RayQuery::new(Ray { o, d }, 0.0);
            let cells = grid.dims.iter().map(|&d| d as usize).sum::<usize>();
            assert!(grid.cells_along(&q, f32::INFINITY).len() <= cells);
        }
    }

    #[test]
    fn a_huge_polygon_coarsens_the_grid_within_its_memory_bound() {
        // One convex 20,000-gon: its triangles are slivers from one vertex
        // across the whole disc, so each box covers most of formula (1)'s
        // cells (about 2.4 billion references at 307x307x1).
        use nffkit_formats::{Primitive, Scene, Shape, SourceLine};
        let n = 20_000;
        let vertices = (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                glam::DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let scene = Scene {
            primitives: vec![Primitive {
                shape: Shape::Polygon { vertices },
                material: None,
                line: SourceLine(1),
            }],
            ..Default::default()
        };
        let g = crate::testing::geometry_of(&scene, false);
        let grid = Grid::build(&g, 2.0, true);
        assert!(
            grid.cells() + grid.items.len() as u64 <= MAX_ENTRIES,
            "{:?}, {} refs",
            grid.dims,
            grid.items.len()
        );
        let warning = grid.info().warning.expect("the user is told");
        assert!(warning.contains("would not fit in memory"), "{warning}");
        // Still the brute-force answers.
        let (mut tg, mut tb) = (Tracer::new(&grid, &g), Tracer::new(&super::super::BruteForce, &g));
        for i in 0..50 {
            let a = i as f32 * 0.7;
            let q = RayQuery::new(Ray::new(Vec3A::new(a.sin() * 0.9, a.cos() * 0.9, 2.0), -Vec3A::Z), 0.0);
            assert_eq!(tg.nearest(&q, f32::INFINITY), tb.nearest(&q, f32::INFINITY));
        }
    }

    #[test]
    fn formula_one_and_m_zero() {
        let b = Aabb::new(Vec3A::ZERO, Vec3A::new(2.0, 1.0, 1.0));
        assert_eq!(cell_counts(&b, 1000, 0.0), [1, 1, 1]);
        // n/V = 500, cbrt = 7.937; x: 2 * 2 * 7.937 + 1 = 32.7 -> 32
        assert_eq!(cell_counts(&b, 1000, 2.0), [32, 16, 16]);
        // A flat world still works.
        let flat = Aabb::new(Vec3A::ZERO, Vec3A::new(1.0, 1.0, 0.0));
        let d = cell_counts(&flat, 100, 2.0);
        assert_eq!(d[2], 1);
        assert!(d[0] > 1);
    }
}
