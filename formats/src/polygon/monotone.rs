//! Triangulation of a large simple polygon in O(n log n): a sweep from top
//! to bottom adds the diagonals that cut it into y-monotone pieces, and each
//! piece is triangulated in linear time with a stack (de Berg, Cheong, van
//! Kreveld and Overmars, "Computational Geometry", chapter 3).
//!
//! The result is checked (n − 2 triangles whose areas sum to the
//! polygon's); `None` where it is not right, as for an outline that crosses
//! itself, and the caller falls back to ear clipping.

use super::orient;
use glam::DVec2;

/// Triangles (positions in `idx`, counter-clockwise) of the simple
/// counter-clockwise outline `idx` over `pts`, or `None`.
pub(super) fn triangulate(pts: &[DVec2], idx: &[u32], work: &mut u64) -> Option<Vec<[u32; 3]>> {
    let n = idx.len();
    let p: Vec<DVec2> = idx.iter().map(|&i| pts[i as usize]).collect();
    if n < 4 || p.iter().any(|q| !q.is_finite()) {
        return None;
    }
    let mut sweep = Sweep::new(&p);
    let diagonals = sweep.run();
    *work += sweep.scanned + n as u64;
    let diagonals = diagonals?;
    let mut out = Vec::with_capacity(n - 2);
    for face in faces(&p, &diagonals)? {
        triangulate_monotone(&p, &face, &mut out)?;
    }
    let area = |t: &[usize; 3]| orient(p[t[0]], p[t[1]], p[t[2]]);
    let outline: f64 = (0..n).map(|k| p[k].perp_dot(p[(k + 1) % n])).sum();
    let covered: f64 = out.iter().map(area).sum();
    let sound = out.len() == n - 2
        && out.iter().all(|t| area(t) >= 0.0)
        && (covered - outline).abs() <= 1e-9 * outline.abs().max(f64::MIN_POSITIVE);
    sound.then(|| out.into_iter().map(|t| t.map(|k| k as u32)).collect())
}

/// Status entries the sweep may look at per vertex, and in all besides,
/// before it gives up ([`Sweep::over_budget`]).
const SCAN_BUDGET_PER_VERTEX: u64 = 256;
const SCAN_BUDGET: u64 = 1 << 24;

/// Whether `a` comes before `b` in the sweep: higher, or as high and to
/// the left (so no two vertices are at the same height, in effect).
fn above(a: DVec2, b: DVec2) -> bool {
    a.y > b.y || (a.y == b.y && a.x < b.x)
}

/// The sweep's order, as [`above`].
fn sweep_order(a: DVec2, b: DVec2) -> std::cmp::Ordering {
    b.y.total_cmp(&a.y).then(a.x.total_cmp(&b.x))
}

/// The sweep that finds the diagonals.
struct Sweep<'a> {
    p: &'a [DVec2],
    /// Edges `k → k + 1` crossing the sweep line with the interior to their
    /// right, each with its helper vertex.
    status: Vec<(usize, usize)>,
    merge: Vec<bool>,
    diagonals: Vec<(usize, usize)>,
    /// Status entries looked at, for tests of the time taken.
    scanned: u64,
}

impl<'a> Sweep<'a> {
    fn new(p: &'a [DVec2]) -> Sweep<'a> {
        Sweep { p, status: Vec::new(), merge: vec![false; p.len()], diagonals: Vec::new(), scanned: 0 }
    }

    fn prev(&self, k: usize) -> usize {
        (k + self.p.len() - 1) % self.p.len()
    }

    fn next(&self, k: usize) -> usize {
        (k + 1) % self.p.len()
    }

    /// The x of edge `e` at the height of `v` (an endpoint's x where it is
    /// level with the sweep, or the edge is).
    fn x_at(&self, e: usize, v: DVec2) -> f64 {
        let (a, b) = (self.p[e], self.p[self.next(e)]);
        if a.y == b.y {
            a.x.min(b.x)
        } else {
            a.x + (v.y - a.y) * (b.x - a.x) / (b.y - a.y)
        }
    }

    /// The status entry of the edge directly left of vertex `v`.
    fn left_of(&mut self, v: usize) -> Option<usize> {
        self.scanned += self.status.len() as u64;
        let q = self.p[v];
        let mut best: Option<(usize, f64)> = None;
        for (slot, &(e, _)) in self.status.iter().enumerate() {
            if e == v || self.next(e) == v {
                continue;
            }
            let x = self.x_at(e, q);
            if x <= q.x && best.is_none_or(|(_, bx)| x > bx) {
                best = Some((slot, x));
            }
        }
        best.map(|(slot, _)| slot)
    }

    fn slot_of(&mut self, e: usize) -> Option<usize> {
        self.scanned += self.status.len() as u64;
        self.status.iter().position(|&(edge, _)| edge == e)
    }

    /// Whether the sweep has looked at more status entries than a simple
    /// outline needs: the status is a list, fine while few edges cross
    /// the sweep line; an outline that doubles back on itself millions of
    /// times would make the sweep quadratic, and is left to the caller.
    fn over_budget(&self) -> bool {
        self.scanned > SCAN_BUDGET_PER_VERTEX * self.p.len() as u64 + SCAN_BUDGET
    }

    /// Remove edge `e`, first joining `v` to its helper if that is a merge
    /// vertex.
    fn end_edge(&mut self, e: usize, v: usize) -> Option<()> {
        let slot = self.slot_of(e)?;
        let helper = self.status[slot].1;
        if self.merge[helper] {
            self.diagonals.push((v, helper));
        }
        self.status.swap_remove(slot);
        Some(())
    }

    /// Make `v` the helper of the edge left of it, first joining them if
    /// the old helper is a merge vertex (or always, for a split vertex).
    fn help_left(&mut self, v: usize, always: bool) -> Option<()> {
        let slot = self.left_of(v)?;
        let helper = self.status[slot].1;
        if always || self.merge[helper] {
            self.diagonals.push((v, helper));
        }
        self.status[slot].1 = v;
        Some(())
    }

    fn run(&mut self) -> Option<Vec<(usize, usize)>> {
        let n = self.p.len();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| sweep_order(self.p[a], self.p[b]));
        for v in order {
            if self.over_budget() {
                return None;
            }
            let (a, b) = (self.prev(v), self.next(v));
            let (q, pa, pb) = (self.p[v], self.p[a], self.p[b]);
            let convex = orient(pa, q, pb) > 0.0;
            match (above(q, pa), above(q, pb)) {
                // Start or split: both neighbours below.
                (true, true) => {
                    if !convex {
                        self.help_left(v, true)?;
                    }
                    self.status.push((v, v));
                }
                // End or merge: both neighbours above.
                (false, false) => {
                    self.end_edge(a, v)?;
                    if !convex {
                        self.merge[v] = true;
                        self.help_left(v, false)?;
                    }
                }
                // On a left chain going down: the interior is to the right.
                (false, true) => {
                    self.end_edge(a, v)?;
                    self.status.push((v, v));
                }
                (true, false) => self.help_left(v, false)?,
            }
        }
        self.status.is_empty().then(|| std::mem::take(&mut self.diagonals))
    }
}

/// The pieces the diagonals cut the outline into, each counter-clockwise:
/// walk each unused directed edge, at every vertex taking the sharpest
/// left turn.
fn faces(p: &[DVec2], diagonals: &[(usize, usize)]) -> Option<Vec<Vec<usize>>> {
    let n = p.len();
    // Outgoing edges per vertex: the outline's, then the diagonals' both ways.
    let mut out: Vec<Vec<(usize, bool)>> = (0..n).map(|k| vec![((k + 1) % n, false)]).collect();
    for &(a, b) in diagonals {
        if a == b || a >= n || b >= n {
            return None;
        }
        out[a].push((b, false));
        out[b].push((a, false));
    }
    let mut faces = Vec::new();
    for start in 0..n {
        for e in 0..out[start].len() {
            if out[start][e].1 {
                continue;
            }
            let mut face = Vec::new();
            let (mut u, mut slot) = (start, e);
            loop {
                out[u][slot].1 = true;
                face.push(u);
                let v = out[u][slot].0;
                if face.len() > n {
                    return None;
                }
                // At `v`, the outgoing edge first clockwise from v → u.
                let back = p[u] - p[v];
                let turn = |w: usize| {
                    let d = p[w] - p[v];
                    let a = back.perp_dot(d).atan2(back.dot(d));
                    // Clockwise angle from `back` in (0, 2π]; straight back last.
                    if a < 0.0 {
                        -a
                    } else {
                        std::f64::consts::TAU - a
                    }
                };
                let next = (0..out[v].len())
                    .filter(|&s| out[v][s].0 != u || out[v].len() == 1)
                    .min_by(|&s, &t| turn(out[v][s].0).total_cmp(&turn(out[v][t].0)))?;
                if out[v][next].1 {
                    break;
                }
                (u, slot) = (v, next);
            }
            if face.len() >= 3 {
                faces.push(face);
            }
        }
    }
    Some(faces)
}

/// Triangulate the y-monotone counter-clockwise piece `face` (positions in
/// `p`) with a stack, adding counter-clockwise triangles to `out`.
fn triangulate_monotone(p: &[DVec2], face: &[usize], out: &mut Vec<[usize; 3]>) -> Option<()> {
    let m = face.len();
    if m == 3 {
        out.push([face[0], face[1], face[2]]);
        return Some(());
    }
    let key = |k: usize| p[face[k]];
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| sweep_order(key(a), key(b)));
    let (top, bottom) = (order[0], order[m - 1]);
    // Counter-clockwise from the top runs down the left chain.
    let mut left = vec![false; m];
    let mut k = top;
    while k != bottom {
        left[k] = true;
        k = (k + 1) % m;
    }
    let emit = |a: usize, b: usize, c: usize, out: &mut Vec<[usize; 3]>| {
        let t = [face[a], face[b], face[c]];
        out.push(if orient(p[t[0]], p[t[1]], p[t[2]]) < 0.0 { [t[0], t[2], t[1]] } else { t });
    };
    let mut stack = vec![order[0], order[1]];
    for &u in &order[2..m - 1] {
        let top_of = *stack.last()?;
        if left[u] != left[top_of] {
            while stack.len() > 1 {
                let s = stack.pop()?;
                emit(u, s, *stack.last()?, out);
            }
            stack.clear();
            stack.extend([top_of, u]);
        } else {
            let mut last = stack.pop()?;
            let side = if left[u] { 1.0 } else { -1.0 };
            while let Some(&s) = stack.last() {
                if orient(key(s), key(last), key(u)) * side <= 0.0 {
                    break;
                }
                emit(u, last, s, out);
                last = stack.pop()?;
            }
            stack.extend([last, u]);
        }
    }
    let u = order[m - 1];
    while stack.len() > 1 {
        let s = stack.pop()?;
        emit(u, s, *stack.last()?, out);
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn check(p: &[DVec2]) -> Option<Vec<[u32; 3]>> {
        let idx: Vec<u32> = (0..p.len() as u32).collect();
        triangulate(p, &idx, &mut 0)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

        /// Star-shaped outlines (any radius at each of n rising angles) are
        /// simple: each is triangulated, and checked by the function itself
        /// (n − 2 triangles covering exactly its area).
        #[test]
        fn star_shaped_outlines(radii in prop::collection::vec(0.05f64..2.0, 4..400), grid in any::<bool>()) {
            let n = radii.len();
            let p: Vec<DVec2> = radii
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let a = std::f64::consts::TAU * i as f64 / n as f64;
                    let q = DVec2::new(a.cos(), a.sin()) * *r;
                    // On a coarse grid: many vertices level with each other.
                    if grid { (q * 8.0).round() / 8.0 } else { q }
                })
                .collect();
            let simple = !grid || (0..n).all(|k| p[k] != p[(k + 1) % n]);
            let t = check(&p);
            if !grid {
                prop_assert!(t.is_some(), "refused a simple outline of {} vertices", n);
            } else if simple {
                // Rounding may fold it onto itself; when accepted it is right.
                prop_assert!(t.is_none_or(|t| t.len() == n - 2));
            }
        }
    }

    #[test]
    fn rectilinear_combs_and_stairs() {
        // Level edges and vertices everywhere: a comb of 300 teeth and a
        // staircase, both counter-clockwise.
        let mut comb = vec![DVec2::new(0.0, 0.0), DVec2::new(600.0, 0.0)];
        for k in (0..300).rev() {
            let x = 2.0 * k as f64;
            comb.extend([
                DVec2::new(x + 2.0, 10.0),
                DVec2::new(x + 1.0, 10.0),
                DVec2::new(x + 1.0, 1.0),
                DVec2::new(x, 1.0),
            ]);
        }
        comb.pop();
        let mut stairs = vec![DVec2::new(0.0, 0.0), DVec2::new(100.0, 0.0)];
        for k in (0..100).rev() {
            stairs.extend([
                DVec2::new(k as f64 + 1.0, 100.0 - k as f64),
                DVec2::new(k as f64, 100.0 - k as f64),
            ]);
        }
        stairs.pop();
        for (name, p) in [("comb", comb), ("stairs", stairs)] {
            let t = check(&p).unwrap_or_else(|| panic!("{name} refused"));
            assert_eq!(t.len(), p.len() - 2, "{name}");
        }
    }

    #[test]
    fn a_self_crossing_outline_is_left_to_the_caller() {
        let bow = [DVec2::new(0.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0)];
        assert!(check(&bow).is_none());
        assert!(check(&[DVec2::ZERO, DVec2::X, DVec2::NAN, DVec2::Y]).is_none());
    }
}
