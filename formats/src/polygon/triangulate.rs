//! Polygons to triangles in the polygon's own plane, winding preserved, so
//! concave polygons (SPD gears: 144-vertex faces) come out right. A naive
//! fan would cover the notches of a concave polygon.
//!
//! Up to [`SMALL`] vertices, ear clipping searched from the outline's
//! start (quadratic, and what every scene's images were made with). Past
//! it, in O(n log n): a strictly convex outline is the fan that ear clipping
//! gives it, written out directly; any other simple one is cut into
//! monotone pieces ([`super::monotone`]); one that crosses itself is ear
//! clipped along a linked list, the "no vertex inside the ear" test asking
//! only the reflex vertices near the ear, found in z-order.

use super::{monotone, newell_normal, orient, project, signed_area};
use glam::{DVec2, DVec3};

/// Polygons up to this many vertices are clipped the quadratic way.
const SMALL: usize = 1024;

/// Triangles as index triples into `v`, wound like the polygon. Triangles of
/// zero area are dropped. Self-intersecting outlines, which have no proper
/// ears, are finished with a fan from the remaining first vertex.
pub fn triangulate(v: &[DVec3]) -> Vec<[u32; 3]> {
    triangulate_counting(v, &mut 0)
}

/// [`triangulate`], adding to `work` the vertices and ears it looked at
/// (for tests that the time is near-linear).
pub(crate) fn triangulate_counting(v: &[DVec3], work: &mut u64) -> Vec<[u32; 3]> {
    let n = v.len();
    if n < 3 {
        return Vec::new();
    }
    if n == 3 {
        return vec![[0, 1, 2]];
    }
    let normal = newell_normal(v);
    let pts = project(v, normal);
    // Work on a counter-clockwise 2D outline; remember to flip back.
    let ccw = signed_area(&pts) >= 0.0;
    let mut idx: Vec<u32> = (0..n as u32).collect();
    if !ccw {
        idx.reverse();
    }
    *work += n as u64;
    let mut out = if n <= SMALL {
        clip_from_start(&pts, idx)
    } else if strictly_convex(&pts, &idx) {
        convex_fan(&idx)
    } else if let Some(t) = monotone::triangulate(&pts, &idx, work) {
        t.into_iter().map(|t| t.map(|k| idx[k as usize])).collect()
    } else {
        clip_along_list(&pts, &idx, work)
    };
    if !ccw {
        for t in &mut out {
            t.swap(1, 2);
        }
    }
    out.retain(|t| {
        let a = (v[t[1] as usize] - v[t[0] as usize]).cross(v[t[2] as usize] - v[t[0] as usize]);
        a.length_squared() > 0.0
    });
    out
}

/// Leave out of `triangles` (of the polygon `v`) each triangle with the
/// same three corner positions as one before it, returning how many went:
/// an outline that runs over itself repeats triangles, and a million
/// copies of one triangle would make every ray through it test them all.
pub fn drop_repeats(v: &[DVec3], triangles: &mut Vec<[u32; 3]>) -> usize {
    if triangles.len() < 2 {
        return 0;
    }
    let key = |t: &[u32; 3]| {
        let mut key = t.map(|i| v[i as usize].to_array().map(f64::to_bits));
        key.sort_unstable();
        key
    };
    let before = triangles.len();
    // Most polygons are small: their keys fit on the stack, no table.
    const SMALL: usize = 16;
    if before <= SMALL {
        let (mut seen, mut count) = ([[[0u64; 3]; 3]; SMALL], 0);
        triangles.retain(|t| {
            let k = key(t);
            let new = !seen[..count].contains(&k);
            if new {
                seen[count] = k;
                count += 1;
            }
            new
        });
    } else {
        let mut seen = std::collections::HashSet::with_capacity(before);
        triangles.retain(|t| seen.insert(key(t)));
    }
    before - triangles.len()
}

/// Ear clipping, each ear searched from the outline's start (the first
/// ear found is clipped); whatever is left (a triangle, or a knot with no
/// ears) becomes a fan.
fn clip_from_start(pts: &[DVec2], mut idx: Vec<u32>) -> Vec<[u32; 3]> {
    let n = idx.len();
    let mut out = Vec::with_capacity(n - 2);
    let mut guard = 0;
    while idx.len() > 3 && guard < 2 * n * n {
        guard += 1;
        let m = idx.len();
        let ear = (0..m).find(|&i| is_ear(pts, &idx, i));
        let Some(i) = ear else { break };
        let (a, b, c) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
        out.push([a, b, c]);
        idx.remove(i);
    }
    fan(&idx, &mut out);
    out
}

/// The rest of an outline as a fan from its first vertex.
fn fan(rest: &[u32], out: &mut Vec<[u32; 3]>) {
    for k in 1..rest.len().saturating_sub(1) {
        out.push([rest[0], rest[k], rest[k + 1]]);
    }
}

/// Whether the counter-clockwise outline `idx` turns strictly left at every
/// vertex and winds once (a pentagram turns left everywhere but twice
/// round).
fn strictly_convex(pts: &[DVec2], idx: &[u32]) -> bool {
    let n = idx.len();
    let p = |k: usize| pts[idx[k % n] as usize];
    let mut turning = 0.0;
    for k in 0..n {
        let (a, b, c) = (p(k), p(k + 1), p(k + 2));
        let (e1, e2) = (b - a, c - b);
        let cross = e1.perp_dot(e2);
        if orient(a, b, c) <= 0.0 || !cross.is_finite() {
            return false;
        }
        turning += cross.atan2(e1.dot(e2));
    }
    (turning - std::f64::consts::TAU).abs() < std::f64::consts::PI
}

/// What [`clip_from_start`] makes of a strictly convex outline, without
/// the search: its first vertex is always an ear, so the ears are clipped
/// in order, a fan about the last vertex, and the last triangle is the
/// three vertices left.
fn convex_fan(idx: &[u32]) -> Vec<[u32; 3]> {
    let n = idx.len();
    let mut out: Vec<[u32; 3]> = (0..n - 3).map(|k| [idx[n - 1], idx[k], idx[k + 1]]).collect();
    out.push([idx[n - 3], idx[n - 2], idx[n - 1]]);
    out
}

/// Ear clipping along a doubly linked outline: the search goes on past
/// the last ear instead of restarting, and the "no vertex inside" test asks
/// only the reflex vertices (no other kind can lie inside an ear of a
/// simple outline) near the ear ([`ReflexIndex`]). Near-linear for smooth
/// outlines, however fine; an outline whose teeth are deep against its
/// vertex spacing costs more, each ear's box holding many vertices. A knot
/// with no ears left is finished with a fan.
fn clip_along_list(pts: &[DVec2], idx: &[u32], work: &mut u64) -> Vec<[u32; 3]> {
    let n = idx.len();
    let at = |k: usize| pts[idx[k] as usize];
    let mut next: Vec<usize> = (0..n).map(|k| (k + 1) % n).collect();
    let mut prev: Vec<usize> = (0..n).map(|k| (k + n - 1) % n).collect();
    let turns_left = |a: usize, b: usize, c: usize| orient(at(a), at(b), at(c)) > 0.0;
    let mut reflex: Vec<bool> = (0..n).map(|k| !turns_left(prev[k], k, next[k])).collect();
    let mut index = ReflexIndex::new(pts, idx, &reflex);
    let mut out = Vec::with_capacity(n - 2);
    let (mut left, mut k, mut tried) = (n, 0, 0);
    while left > 3 && tried < left {
        let (a, c) = (prev[k], next[k]);
        *work += 1;
        let ear = !reflex[k]
            && index.none_inside(at(a), at(k), at(c), work, |r| {
                r != a && r != k && r != c && reflex[r] && ![at(a), at(k), at(c)].contains(&at(r))
            });
        if !ear {
            (k, tried) = (c, tried + 1);
            continue;
        }
        out.push([idx[a], idx[k], idx[c]]);
        (next[a], prev[c]) = (c, a);
        reflex[k] = false;
        left -= 1;
        // Clipping an ear only makes its neighbours more convex.
        for (v, convex) in [(a, turns_left(prev[a], a, c)), (c, turns_left(a, c, next[c]))] {
            if reflex[v] && convex {
                reflex[v] = false;
                index.drop_one();
            }
        }
        // Go on past the next vertex, not at it: ears taken one after the
        // other would fan out from `a`, each larger than the last.
        (k, tried) = (next[c], 0);
    }
    let mut rest = Vec::with_capacity(left);
    let mut r = k;
    for _ in 0..left {
        rest.push(idx[r]);
        r = next[r];
    }
    fan(&rest, &mut out);
    out
}

/// The reflex vertices of an outline in z-order (Morton order of their
/// coordinates, as mapbox's earcut orders them): the vertices inside a box
/// all lie between the keys of its corners, a run that is short for a
/// small box whatever the outline's density. A vertex that stops being
/// reflex is dropped from the count; its entry stays, skipped by the
/// caller's test.
struct ReflexIndex {
    lo: DVec2,
    scale: DVec2,
    /// (key, position in the outline), by key.
    sorted: Vec<(u64, u32)>,
    points: Vec<DVec2>,
    /// How many listed vertices are still reflex.
    reflex: usize,
}

impl ReflexIndex {
    fn new(pts: &[DVec2], idx: &[u32], reflex: &[bool]) -> ReflexIndex {
        let points: Vec<DVec2> = idx.iter().map(|&i| pts[i as usize]).collect();
        let (lo, hi) = points.iter().fold((points[0], points[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        let scale = DVec2::splat(65535.0) / (hi - lo).max(DVec2::splat(f64::MIN_POSITIVE));
        let mut index = ReflexIndex { lo, scale, sorted: Vec::new(), points, reflex: 0 };
        index.sorted = (0..reflex.len())
            .filter(|&k| reflex[k])
            .map(|k| (index.key(index.points[k]), k as u32))
            .collect();
        index.sorted.sort_unstable();
        index.reflex = index.sorted.len();
        index
    }

    /// The Morton key of `p`: its 16-bit grid coordinates interleaved.
    fn key(&self, p: DVec2) -> u64 {
        let q = ((p - self.lo) * self.scale).clamp(DVec2::ZERO, DVec2::splat(65535.0));
        let spread = |v: u64| {
            let v = (v | (v << 8)) & 0x00ff_00ff;
            let v = (v | (v << 4)) & 0x0f0f_0f0f;
            let v = (v | (v << 2)) & 0x3333_3333;
            (v | (v << 1)) & 0x5555_5555
        };
        spread(q.x as u64) | (spread(q.y as u64) << 1)
    }

    /// One listed vertex is no longer reflex.
    fn drop_one(&mut self) {
        self.reflex -= 1;
    }

    /// Whether no listed vertex that `counts` lies inside or on triangle
    /// `abc` (counter-clockwise).
    fn none_inside(
        &self,
        a: DVec2,
        b: DVec2,
        c: DVec2,
        work: &mut u64,
        counts: impl Fn(usize) -> bool,
    ) -> bool {
        if self.reflex == 0 {
            return true;
        }
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        let (z0, z1) = (self.key(lo), self.key(hi));
        let start = self.sorted.partition_point(|&(z, _)| z < z0);
        for &(z, r) in &self.sorted[start..] {
            if z > z1 {
                break;
            }
            *work += 1;
            let q = self.points[r as usize];
            let in_box = q.cmpge(lo).all() && q.cmple(hi).all();
            if in_box
                && orient(a, b, q) >= 0.0
                && orient(b, c, q) >= 0.0
                && orient(c, a, q) >= 0.0
                && counts(r as usize)
            {
                return false;
            }
        }
        true
    }
}

fn is_ear(p: &[DVec2], idx: &[u32], i: usize) -> bool {
    let m = idx.len();
    let (ia, ib, ic) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
    let (a, b, c) = (p[ia as usize], p[ib as usize], p[ic as usize]);
    if orient(a, b, c) <= 0.0 {
        return false; // reflex or flat corner
    }
    // No other vertex may lie inside or on the candidate triangle.
    idx.iter().all(|&k| {
        if k == ia || k == ib || k == ic {
            return true;
        }
        let q = p[k as usize];
        if q == a || q == b || q == c {
            return true; // a repeated vertex (bridge) does not block the ear
        }
        !(orient(a, b, q) >= 0.0 && orient(b, c, q) >= 0.0 && orient(c, a, q) >= 0.0)
    })
}

#[cfg(test)]
mod tests {

    #[test]
    fn an_outline_running_round_twice_keeps_each_triangle_once() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let v: Vec<DVec3> = (0..2000).map(|k| t[k % 3]).collect();
        let mut tris = triangulate(&v);
        assert!(!tris.is_empty());
        let dropped = drop_repeats(&v, &mut tris);
        assert_eq!(tris.len(), 1, "{dropped} dropped");
        // Three times round: few enough triangles for the table on the stack.
        let v: Vec<DVec3> = (0..9).map(|k| t[k % 3]).collect();
        let mut tris = triangulate(&v);
        assert!((2..=16).contains(&tris.len()), "{}", tris.len());
        drop_repeats(&v, &mut tris);
        assert_eq!(tris.len(), 1);
        let square = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let mut tris = triangulate(&square);
        assert_eq!((drop_repeats(&square, &mut tris), tris.len()), (0, 2));
    }

    use super::*;

    fn area3(v: &[DVec3], tris: &[[u32; 3]]) -> (f64, DVec3) {
        let mut total = 0.0;
        let mut n = DVec3::ZERO;
        for t in tris {
            let c = (v[t[1] as usize] - v[t[0] as usize]).cross(v[t[2] as usize] - v[t[0] as usize]);
            total += c.length() * 0.5;
            n += c;
        }
        (total, n)
    }

    #[test]
    fn concave_polygon_covers_exactly_its_area() {
        // An L shape, counter-clockwise about +z, area 3.
        let v: Vec<DVec3> = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .iter()
            .map(|&(x, y)| DVec3::new(x, y, 0.0))
            .collect();
        let t = triangulate(&v);
        assert_eq!(t.len(), 4);
        let (area, n) = area3(&v, &t);
        assert!((area - 3.0).abs() < 1e-12);
        assert!(n.z > 0.0, "winding preserved");
    }

    #[test]
    fn star_shaped_gear_tooth_profile() {
        // A 12-pointed star in the plane x = 1, clockwise about +x: winding
        // must stay clockwise and the area must match the shoelace area.
        let mut v = Vec::new();
        for k in 0..24 {
            let a = -(k as f64) * std::f64::consts::PI / 12.0;
            let r = if k % 2 == 0 { 2.0 } else { 1.0 };
            v.push(DVec3::new(1.0, r * a.cos(), r * a.sin()));
        }
        let t = triangulate(&v);
        assert_eq!(t.len(), 22);
        let (area, n) = area3(&v, &t);
        let expect = newell_normal(&v).length() * 0.5;
        assert!((area - expect).abs() < 1e-9, "{area} vs {expect}");
        assert!(n.x < 0.0);
    }

    /// A closed outline of `n` points at radius `r(i)`, counter-clockwise.
    fn ring(n: usize, r: impl Fn(usize) -> f64) -> Vec<DVec3> {
        (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                DVec3::new(r(i) * a.cos(), r(i) * a.sin(), 0.0)
            })
            .collect()
    }

    #[test]
    fn huge_polygons_take_near_linear_work_and_cover_their_area() {
        // A convex 200,000-gon; a 100,000-vertex flower (five deep
        // notches: a third of its vertices reflex), and the same clockwise;
        // a fine zigzag (every other vertex reflex, teeth shallow against
        // the spacing). Work counted stays a small multiple of the vertex
        // count (quadratic would be 10^10).
        let tau = std::f64::consts::TAU;
        let convex = ring(200_000, |_| 1.0);
        let flower = ring(100_000, |i| 1.0 + 0.4 * (5.0 * tau * i as f64 / 100_000.0).sin());
        let clockwise: Vec<DVec3> = flower.iter().rev().copied().collect();
        let zigzag = ring(100_000, |i| if i % 2 == 0 { 1.0 } else { 1.0 - 2e-5 });
        for (name, v) in
            [("convex", &convex), ("flower", &flower), ("clockwise flower", &clockwise), ("zigzag", &zigzag)]
        {
            let mut work = 0;
            let t = triangulate_counting(v, &mut work);
            assert!(work < 40 * v.len() as u64, "{name}: {work} steps for {} vertices", v.len());
            assert_eq!(t.len(), v.len() - 2, "{name}");
            let (area, n) = area3(v, &t);
            let expect = newell_normal(v).length() * 0.5;
            assert!((area - expect).abs() < 1e-9 * expect.max(1.0), "{name}: area {area} vs {expect}");
            assert!(n.z * newell_normal(v).z > 0.0, "{name}: winding kept");
        }
    }

    #[test]
    fn an_outline_winding_round_many_times_takes_bounded_work() {
        // A triangle gone round 100,000 times: the sweep's status fills
        // with edges (quadratic: 10^10 steps) until its budget stops it.
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let v: Vec<DVec3> = (0..300_000).map(|k| t[k % 3]).collect();
        let mut work = 0;
        let tris = triangulate_counting(&v, &mut work);
        assert!(work < 400 * v.len() as u64, "{work} steps for {} vertices", v.len());
        assert!(!tris.is_empty());
    }

    #[test]
    fn small_convex_polygons_are_the_fan_ear_clipping_makes() {
        // The fan written out for large convex outlines is what clipping
        // from the start makes of them.
        let v = ring(40, |_| 2.0);
        let pts = project(&v, newell_normal(&v));
        let idx: Vec<u32> = (0..40).collect();
        assert!(strictly_convex(&pts, &idx));
        assert_eq!(convex_fan(&idx), clip_from_start(&pts, idx.clone()));
        let pentagram: Vec<u32> = (0..5).map(|k| (k * 2 % 5) as u32).collect();
        let five = ring(5, |_| 1.0);
        assert!(!strictly_convex(&project(&five, DVec3::Z), &pentagram), "winds twice");
    }

    #[test]
    fn degenerate_input_does_not_panic() {
        let v = vec![DVec3::ZERO; 5];
        assert!(triangulate(&v).is_empty());
        let bow: Vec<DVec3> =
            [(0., 0.), (1., 1.), (1., 0.), (0., 1.)].iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect();
        assert!(!triangulate(&bow).is_empty());
    }
}
