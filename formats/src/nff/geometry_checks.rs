//! Warnings for polygons that render but break the spec's assumptions:
//! planarity, a convex first corner, simple (non-self-intersecting) outlines,
//! and unit patch normals that agree with the winding.

use crate::polygon::{newell_normal, orient, project};
use glam::{DVec2, DVec3};

/// Polygons with more vertices than this skip the quadratic
/// self-intersection check.
const MAX_SELF_INTERSECTION_CHECK: usize = 1024;

/// Messages for everything suspicious about one polygon (or patch, when
/// `normals` is given).
pub fn polygon(v: &[DVec3], normals: Option<&[DVec3]>) -> Vec<String> {
    let mut out = Vec::new();
    let n = newell_normal(v);
    let (lo, hi) = v.iter().fold((v[0], v[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let extent = (hi - lo).length();
    let scale = lo.abs().max(hi.abs()).max_element();
    let degenerate = extent == 0.0 || n.length() <= 1e-12 * extent * extent;
    // A bow tie has zero net area; find its plane from any proper corner.
    let plane = if degenerate { corner_normal(v) } else { Some(n.normalize()) };
    let crosses =
        v.len() > 3 && v.len() <= MAX_SELF_INTERSECTION_CHECK && plane.is_some_and(|p| self_intersects(v, p));
    if crosses {
        out.push("polygon outline crosses itself".into());
    }
    if degenerate {
        if !crosses {
            out.push("degenerate polygon: its area is zero".into());
        }
        return out;
    }
    let nh = n.normalize();
    if v.len() > 3 {
        out.extend(planarity(v, nh, extent, scale));
        out.extend(first_corner(v, nh));
    }
    if let Some(normals) = normals {
        out.extend(patch_normals(normals, nh));
    }
    out
}

fn corner_normal(v: &[DVec3]) -> Option<DVec3> {
    (0..v.len()).find_map(|i| {
        let c = (v[(i + 1) % v.len()] - v[i]).cross(v[(i + 2) % v.len()] - v[(i + 1) % v.len()]);
        (c.length() > 0.0).then(|| c.normalize())
    })
}

fn planarity(v: &[DVec3], nh: DVec3, extent: f64, scale: f64) -> Option<String> {
    let centroid = v.iter().copied().sum::<DVec3>() / v.len() as f64;
    // SPD prints 6 significant digits: allow for that rounding as well.
    let tol = (1e-4 * extent).max(1e-5 * scale);
    let (k, d) = v.iter().map(|p| (p - centroid).dot(nh).abs()).enumerate().fold((0, 0.0), |best, (i, d)| {
        if d > best.1 {
            (i, d)
        } else {
            best
        }
    });
    (d > tol).then(|| format!("polygon is not planar: vertex {} is {d:.3e} off its plane", k + 1))
}

fn first_corner(v: &[DVec3], nh: DVec3) -> Option<String> {
    let (e1, e2) = (v[1] - v[0], v[2] - v[1]);
    let c = e1.cross(e2);
    if c.length() <= 1e-9 * e1.length() * e2.length() {
        Some("the first three vertices are collinear; the spec uses them to find the normal".into())
    } else if c.dot(nh) < 0.0 {
        Some("the first corner is concave; the spec requires a convex first angle".into())
    } else {
        None
    }
}

/// Projects onto the plane most facing the normal and tests every pair of
/// non-adjacent edges for a proper crossing.
fn self_intersects(v: &[DVec3], nh: DVec3) -> bool {
    let pts = project(v, nh);
    let m = pts.len();
    for i in 0..m {
        let (a, b) = (pts[i], pts[(i + 1) % m]);
        for j in i + 2..m {
            if i == 0 && j == m - 1 {
                continue; // adjacent through the closing edge
            }
            let (c, d) = (pts[j], pts[(j + 1) % m]);
            if segments_cross(a, b, c, d) {
                return true;
            }
        }
    }
    false
}

fn segments_cross(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let (d1, d2) = (orient(a, b, c), orient(a, b, d));
    let (d3, d4) = (orient(c, d, a), orient(c, d, b));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

fn patch_normals(normals: &[DVec3], nh: DVec3) -> Vec<String> {
    let mut out = Vec::new();
    if let Some((k, len)) =
        normals.iter().map(|n| n.length()).enumerate().find(|(_, l)| (l - 1.0).abs() > 1e-3)
    {
        out.push(format!("patch normal of vertex {} has length {len:.4}, not 1", k + 1));
    }
    if let Some(k) = normals.iter().position(|n| n.dot(nh) < 0.0) {
        out.push(format!("patch normal of vertex {} points against the polygon's winding", k + 1));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<DVec3> {
        vec![DVec3::new(0., 0., 0.), DVec3::new(1., 0., 0.), DVec3::new(1., 1., 0.), DVec3::new(0., 1., 0.)]
    }

    #[test]
    fn clean_square_has_no_warnings() {
        assert!(polygon(&square(), None).is_empty());
        assert!(newell_normal(&square()).z > 0.0);
    }

    #[test]
    fn bow_tie_crosses_itself() {
        let mut v = square();
        v.swap(2, 3);
        assert!(polygon(&v, None).iter().any(|w| w.contains("crosses itself")));
    }

    #[test]
    fn lifted_corner_is_not_planar() {
        let mut v = square();
        v[2].z = 0.5;
        assert!(polygon(&v, None).iter().any(|w| w.contains("not planar")));
    }

    #[test]
    fn collinear_start_is_reported() {
        let v = vec![
            DVec3::new(0., 0., 0.),
            DVec3::new(1., 0., 0.),
            DVec3::new(2., 0., 0.),
            DVec3::new(2., 1., 0.),
            DVec3::new(0., 1., 0.),
        ];
        assert!(polygon(&v, None).iter().any(|w| w.contains("collinear")));
    }

    #[test]
    fn patch_normals_checked() {
        let n = vec![DVec3::Z, DVec3::Z * 2.0, -DVec3::Z, DVec3::Z];
        let w = polygon(&square(), Some(&n));
        assert!(w.iter().any(|w| w.contains("length 2")));
        assert!(w.iter().any(|w| w.contains("against")));
    }
}
