//! Geometry of polygons shared by the reader's checks, the triangulator and
//! the mesh converter.

use glam::DVec3;

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
