//! Polygons to triangles by ear clipping in the polygon's own plane, so
//! concave polygons (SPD gears: 144-vertex faces) come out right and the
//! winding is preserved. A naive fan would cover the notches of a concave
//! polygon.

use super::{newell_normal, orient, project, signed_area};
use glam::{DVec2, DVec3};

/// Triangles as index triples into `v`, wound like the polygon. Triangles of
/// zero area are dropped. Self-intersecting outlines, which have no proper
/// ears, are finished with a fan from the remaining first vertex.
pub fn triangulate(v: &[DVec3]) -> Vec<[u32; 3]> {
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
    let mut out = Vec::with_capacity(n - 2);
    let mut guard = 0;
    while idx.len() > 3 && guard < 2 * n * n {
        guard += 1;
        let m = idx.len();
        let ear = (0..m).find(|&i| is_ear(&pts, &idx, i));
        let Some(i) = ear else { break };
        let (a, b, c) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
        out.push([a, b, c]);
        idx.remove(i);
    }
    // Whatever is left (a triangle, or a knot with no ears) becomes a fan.
    for k in 1..idx.len().saturating_sub(1) {
        out.push([idx[0], idx[k], idx[k + 1]]);
    }
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

    #[test]
    fn degenerate_input_does_not_panic() {
        let v = vec![DVec3::ZERO; 5];
        assert!(triangulate(&v).is_empty());
        let bow: Vec<DVec3> =
            [(0., 0.), (1., 1.), (1., 0.), (0., 1.)].iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect();
        assert!(!triangulate(&bow).is_empty());
    }
}
