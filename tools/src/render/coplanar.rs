//! Polygons that overlap in one plane: where both cover a pixel, rounding
//! picks which one a ray hits, so the picture speckles between them
//! ("z-fighting"), as a board appended in a floor's own plane does. The
//! file reads cleanly; `render` and `--check` say so.
//!
//! Polygons are grouped by plane (normal and offset, quantised), and within
//! a plane the convex ones whose boxes meet are tested for overlapping
//! interiors by separating axes; edges that only touch (a checkerboard's
//! squares) do not count. A grid of cells keeps the pairs tested near
//! linear in the number of polygons.

use super::scene_warnings::SceneWarning;
use glam::{DVec2, DVec3};
use nffkit_formats::polygon::{newell_normal, project};
use nffkit_formats::Primitive;
use std::collections::HashMap;

/// Pair tests at most, so that a huge flat mesh costs bounded time.
const MAX_TESTS: usize = 1 << 24;
/// Cells a polygon may cover before it is tested against its whole plane.
const MAX_CELLS: i64 = 64;

/// A convex polygon in its plane's 2D projection: its outline is
/// `points[start..start + len]` of its [`Plane`].
struct Flat {
    line: u32,
    start: u32,
    len: u32,
    min: DVec2,
    max: DVec2,
}

/// The convex polygons of one plane, their outlines in one list.
#[derive(Default)]
struct Plane {
    flats: Vec<Flat>,
    points: Vec<DVec2>,
}

impl Plane {
    fn outline(&self, f: &Flat) -> &[DVec2] {
        &self.points[f.start as usize..(f.start + f.len) as usize]
    }
}

/// The warning when polygons among `flats` (the file's flat surfaces,
/// [`flat_surfaces`](super::scene_warnings::flat_surfaces)) overlap in one
/// plane: the first pair's lines and how many pairs there are.
pub fn coplanar_overlaps(flats: &[&Primitive]) -> Option<SceneWarning> {
    let scale = flats
        .iter()
        .filter_map(|p| p.shape.vertices())
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs().max_element()));
    let mut planes: HashMap<[i64; 4], Plane> = HashMap::new();
    let mut outline = Vec::new();
    for prim in flats {
        let Some(vertices) = prim.shape.vertices() else { continue };
        if let Some(key) = flat(vertices, scale, &mut outline) {
            let plane = planes.entry(key).or_default();
            let min = outline.iter().fold(DVec2::INFINITY, |m, p| m.min(*p));
            let max = outline.iter().fold(DVec2::NEG_INFINITY, |m, p| m.max(*p));
            let (start, len) = (plane.points.len() as u32, outline.len() as u32);
            plane.points.append(&mut outline);
            plane.flats.push(Flat { line: prim.line.0, start, len, min, max });
        }
    }
    let mut found: Option<(u32, u32)> = None;
    let mut pairs = 0usize;
    let mut tests = 0usize;
    let mut groups: Vec<&Plane> = planes.values().filter(|g| g.flats.len() > 1).collect();
    groups.sort_by_key(|g| g.flats.iter().map(|f| f.line).min());
    for group in groups {
        overlaps_in(group, scale, &mut tests, &mut |a, b| {
            pairs += 1;
            let pair = (a.min(b), a.max(b));
            if found.is_none_or(|f| pair < f) {
                found = Some(pair);
            }
        });
    }
    let (a, b) = found?;
    let more = if pairs > 1 { format!(" (and {} more pairs)", pairs - 1) } else { String::new() };
    Some(SceneWarning {
        message: format!(
            "the polygons on lines {a} and {b} overlap in one plane{more}: where both cover a pixel, \
             rounding picks which one is seen, and the image speckles between them; move one off \
             the plane (planegen --z) or remove the overlap"
        ),
        line: Some(b),
    })
}

/// The plane key of a convex polygon, its 2D outline (counter-clockwise)
/// left in `points`; `None` for a degenerate or concave one.
fn flat(vertices: &[DVec3], scale: f64, points: &mut Vec<DVec2>) -> Option<[i64; 4]> {
    let n = newell_normal(vertices).try_normalize()?;
    // One sign per plane: its largest component positive.
    let big = n.abs().max_element();
    let n = if n.to_array().iter().find(|c| c.abs() == big).is_some_and(|c| *c < 0.0) { -n } else { n };
    let d = n.dot(vertices[0]);
    let q = |x: f64, step: f64| (x / step).round() as i64;
    let key = [q(n.x, 1e-6), q(n.y, 1e-6), q(n.z, 1e-6), q(d, 1e-9 * scale.max(f64::MIN_POSITIVE))];
    // Projected along the plane's quantised normal, so that every polygon
    // of a plane drops the same axis (a tie between two components must
    // not go one way for one and the other way for the next).
    *points = project(vertices, DVec3::new(key[0] as f64, key[1] as f64, key[2] as f64));
    let k = points.len();
    let area: f64 = (0..k).map(|i| points[i].perp_dot(points[(i + 1) % k])).sum();
    if area < 0.0 {
        points.reverse();
    }
    let convex = (0..k).all(|i| {
        let (a, b, c) = (points[i], points[(i + 1) % k], points[(i + 2) % k]);
        (b - a).perp_dot(c - b) >= 0.0
    });
    (convex && area != 0.0).then_some(key)
}

/// Call `found(line_a, line_b)` for each pair of `plane`'s polygons whose
/// interiors overlap, testing neighbours through a grid of cells.
fn overlaps_in(plane: &Plane, scale: f64, tests: &mut usize, found: &mut impl FnMut(u32, u32)) {
    let group = &plane.flats;
    let size = group.iter().map(|f| (f.max - f.min).max_element()).sum::<f64>() / group.len() as f64;
    let cell = if size > 0.0 { size } else { return };
    let cell_of = |p: DVec2| (p / cell).floor().as_i64vec2();
    // (cell, polygon) for each cell a small polygon covers, sorted by cell.
    let mut members: Vec<(glam::I64Vec2, u32)> = Vec::with_capacity(group.len() * 4);
    let mut big = Vec::new();
    for (i, f) in group.iter().enumerate() {
        let (lo, hi) = (cell_of(f.min), cell_of(f.max));
        if (hi.x - lo.x + 1).saturating_mul(hi.y - lo.y + 1) > MAX_CELLS {
            big.push(i);
            continue;
        }
        for x in lo.x..=hi.x {
            for y in lo.y..=hi.y {
                members.push((glam::I64Vec2::new(x, y), i as u32));
            }
        }
    }
    members.sort_unstable_by_key(|&(c, i)| (c.x, c.y, i));
    let eps = 1e-9 * scale.max(f64::MIN_POSITIVE);
    let mut test = |i: usize, j: usize, tests: &mut usize| {
        *tests += 1;
        let (a, b) = (&group[i], &group[j]);
        if overlap(plane.outline(a), a, plane.outline(b), b, eps) {
            found(a.line, b.line);
        }
    };
    // Big polygons against every other (each pair once: a big one meets
    // the big ones after it in the list, and every small one).
    let mut is_big = vec![false; group.len()];
    big.iter().for_each(|&i| is_big[i] = true);
    for &i in &big {
        for j in (0..group.len()).filter(|&j| !is_big[j] || j > i) {
            if *tests >= MAX_TESTS {
                return;
            }
            test(i, j, tests);
        }
    }
    // Small ones by cell; a pair is tested in the cell holding the corner
    // where their boxes start to meet, so once.
    for run in members.chunk_by(|a, b| a.0 == b.0) {
        for (k, &(c, i)) in run.iter().enumerate() {
            for &(_, j) in &run[k + 1..] {
                let (i, j) = (i as usize, j as usize);
                if cell_of(group[i].min.max(group[j].min)) != c {
                    continue;
                }
                if *tests >= MAX_TESTS {
                    return;
                }
                test(i, j, tests);
            }
        }
    }
}

/// Whether two convex outlines (counter-clockwise) share interior: no edge
/// direction of either separates them by more than `eps`.
fn overlap(pa: &[DVec2], a: &Flat, pb: &[DVec2], b: &Flat, eps: f64) -> bool {
    let boxes_meet = a.min.x < b.max.x - eps && b.min.x < a.max.x - eps;
    if !(boxes_meet && a.min.y < b.max.y - eps && b.min.y < a.max.y - eps) {
        return false;
    }
    let separated_by = |p: &[DVec2]| {
        (0..p.len()).any(|i| {
            let edge = p[(i + 1) % p.len()] - p[i];
            let axis = edge.perp().normalize_or_zero();
            if axis == DVec2::ZERO {
                return false;
            }
            let range = |q: &[DVec2]| {
                q.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    let t = axis.dot(*v);
                    (lo.min(t), hi.max(t))
                })
            };
            let ((a0, a1), (b0, b1)) = (range(pa), range(pb));
            a1.min(b1) - a0.max(b0) <= eps
        })
    };
    !separated_by(pa) && !separated_by(pb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nffkit_formats::nff::{parse, ParseOptions};

    fn warning(src: &str) -> Option<String> {
        let scene =
            parse(src.as_bytes(), &ParseOptions { fragment: true, ..Default::default() }).unwrap().scene;
        coplanar_overlaps(&super::super::scene_warnings::flat_surfaces(&scene)).map(|w| w.message)
    }

    const FLOOR: &str = "p 4\n-2 -2 0\n2 -2 0\n2 2 0\n-2 2 0\n";

    #[test]
    fn overlapping_polygons_in_one_plane_are_found_touching_ones_are_not() {
        // A square on the floor, in its plane: warned.
        let w = warning(&format!("{FLOOR}p 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n")).unwrap();
        assert!(w.contains("lines 1 and 6 overlap in one plane"), "{w}");
        // The same square a little above: fine.
        assert!(warning(&format!("{FLOOR}p 4\n0 0 0.01\n1 0 0.01\n1 1 0.01\n0 1 0.01\n")).is_none());
        // A checkerboard's squares share edges only; a quad split into two
        // triangles shares a diagonal.
        let mut board = String::new();
        for x in 0..20 {
            for y in 0..20 {
                let (x, y) = (x as f64, y as f64);
                board += &format!(
                    "p 4\n{x} {y} 0\n{} {y} 0\n{} {} 0\n{x} {} 0\n",
                    x + 1.0,
                    x + 1.0,
                    y + 1.0,
                    y + 1.0
                );
            }
        }
        assert!(warning(&board).is_none());
        assert!(warning("p 3\n0 0 0\n1 0 0\n1 1 0\np 3\n0 0 0\n1 1 0\n0 1 0\n").is_none());
        // The board and the floor under it: every square overlaps it.
        let w = warning(&format!("{board}{FLOOR}")).unwrap();
        assert!(w.contains("(and 3 more pairs)"), "{w}");
        // Facing the other way, the same plane.
        assert!(warning(&format!("{FLOOR}p 3\n0 0 0\n0 1 0\n1 0 0\n")).is_some());
    }
}
