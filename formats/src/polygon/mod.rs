//! Geometry of polygons shared by the reader's checks, the tracer and the
//! mesh converter: normals, projection, orientation, and triangulation.

mod monotone;
mod triangulate;

pub use triangulate::{drop_repeats, triangulate};

use glam::{DVec2, DVec3};

/// The polygon's area-weighted normal by Newell's method (robust for concave
/// and slightly non-planar polygons); its length is twice the area, and it
/// points the way the vertices turn counter-clockwise.
pub fn newell_normal(v: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (i, a) in v.iter().enumerate() {
        let b = v[(i + 1) % v.len()];
        n += DVec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    n
}

/// The polygon in 2D: its vertices projected onto the axis plane its normal
/// `n` faces most, keeping orientation (a polygon counter-clockwise about
/// `n` stays counter-clockwise).
pub fn project(v: &[DVec3], n: DVec3) -> Vec<DVec2> {
    let a = n.abs();
    let (i, j, s) = if a.x >= a.y && a.x >= a.z {
        (1, 2, n.x)
    } else if a.y >= a.z {
        (2, 0, n.y)
    } else {
        (0, 1, n.z)
    };
    let flip = if s < 0.0 { -1.0 } else { 1.0 };
    v.iter().map(|p| DVec2::new(p[i] * flip, p[j])).collect()
}

/// Signed area of a 2D outline (shoelace): positive when counter-clockwise.
pub fn signed_area(p: &[DVec2]) -> f64 {
    (0..p.len()).map(|i| p[i].perp_dot(p[(i + 1) % p.len()])).sum::<f64>() * 0.5
}

/// Twice the signed area of triangle `abc`: positive when it turns left.
pub fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_keeps_orientation_whichever_way_the_normal_points() {
        let square = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)];
        for (axis, sign) in [(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0), (2, 1.0), (2, -1.0)] {
            // The square counter-clockwise about `sign * axis`.
            let v: Vec<DVec3> = square
                .iter()
                .map(|&(x, y)| {
                    let (x, y) = if sign > 0.0 { (x, y) } else { (y, x) };
                    let mut p = [0.0; 3];
                    p[(axis + 1) % 3] = x;
                    p[(axis + 2) % 3] = y;
                    DVec3::from_array(p)
                })
                .collect();
            let n = newell_normal(&v);
            assert!(n[axis] * sign > 0.0);
            assert!((signed_area(&project(&v, n)) - 1.0).abs() < 1e-12, "axis {axis} sign {sign}");
        }
        assert!(orient(DVec2::ZERO, DVec2::X, DVec2::Y) > 0.0);
    }
}
