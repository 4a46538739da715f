//! The SPD library's tessellation of curved primitives (libply.c), for
//! `--tessellate`: spheres as six cube faces of res × res quadrilaterals
//! projected onto the sphere, cylinders and cones as 4·res sides, each
//! quadrilateral two smooth-shaded triangles, in the library's order and
//! arithmetic.

use super::matrix::{
    axis_rotate, invert, normalize, rotate, transform_normal, transform_point, transform_vector, Axis,
};
use glam::DVec3;
use std::f64::consts::PI;

/// A smooth-shaded triangle: corners and their normals.
pub type Patch = ([DVec3; 3], [DVec3; 3]);

/// libply.c `lib_output_polygon_sphere` at resolution `res`.
pub fn sphere(centre: DVec3, radius: f64, res: u32, mut emit: impl FnMut(Patch)) {
    let n = res as usize;
    let axis_at = |k: usize, mid: DVec3, about: Axis| {
        let angle = (PI / 4.0) * (2.0 * k as f64 / f64::from(res) - 1.0);
        transform_vector(mid, &rotate(about, angle))
    };
    let x_axis: Vec<DVec3> = (0..=n).map(|k| axis_at(k, DVec3::X, Axis::Y)).collect();
    let y_axis: Vec<DVec3> = (0..=n).map(|k| axis_at(k, DVec3::Y, Axis::X)).collect();
    // The grid on the +Z face: x_axis[u] × y_axis[v], normalised.
    let mut pt: Vec<Vec<DVec3>> =
        (0..=n).map(|u| (0..=n).map(|v| normalize(x_axis[u].cross(y_axis[v]))).collect()).collect();
    for face in 0..6 {
        // libvec.c `lib_rotate_cube_face` about Z (its axis 2): each face
        // turns the previous face's grid.
        for row in &mut pt {
            for p in row.iter_mut() {
                *p = match (face + 2) % 3 {
                    0 => DVec3::new(-p.y, p.x, p.z),
                    1 => DVec3::new(p.x, -p.z, p.y),
                    _ => DVec3::new(-p.z, p.y, p.x),
                };
            }
        }
        for u in 0..n {
            for v in 0..n {
                for tri in 0..2 {
                    let mut corners = [DVec3::ZERO; 3];
                    let mut normals = [DVec3::ZERO; 3];
                    for edge in 0..3 {
                        let p = match (tri * 2 + edge) % 4 {
                            0 => pt[u][v],
                            1 => pt[u][v + 1],
                            2 => pt[u + 1][v + 1],
                            _ => pt[u + 1][v],
                        };
                        normals[edge] = p;
                        corners[edge] = DVec3::new(
                            p.x * radius + centre.x,
                            p.y * radius + centre.y,
                            p.z * radius + centre.z,
                        );
                    }
                    emit((corners, normals));
                }
            }
        }
    }
}

/// libply.c `lib_output_polygon_cylcone` at resolution `res`: 4·res sides
/// around the axis, two triangles each.
pub fn cone(
    base: DVec3,
    base_radius: f64,
    apex: DVec3,
    apex_radius: f64,
    res: u32,
    mut emit: impl FnMut(Patch),
) {
    let axis = apex - base;
    let height = axis.dot(axis).sqrt();
    let norm_axis = normalize(axis);
    let start = axis.cross(DVec3::Z);
    let start_dir =
        if start.dot(start).sqrt() < 1.0e-6 { normalize(axis.cross(DVec3::X)) } else { normalize(start) };
    let radius = [start_dir * base_radius, start_dir * apex_radius];
    let mut vert = [DVec3::ZERO; 3];
    vert[2] = base + radius[0];
    vert[1] = apex + radius[1];
    let start_norm = if base_radius == apex_radius {
        start_dir
    } else {
        let ba = base_radius - apex_radius;
        normalize(DVec3::new(
            start_dir.x * height + norm_axis.x * ba,
            start_dir.y * height + norm_axis.y * ba,
            start_dir.z * height + norm_axis.z * ba,
        ))
    };
    let mut norm = [DVec3::ZERO, start_norm, start_norm];
    let steps = 4 * res;
    let delta = 2.0 * PI / f64::from(steps);
    let mut angle = delta;
    for _ in 0..steps {
        let mx = axis_rotate(norm_axis, angle);
        let nmx = invert(&mx);
        vert[0] = transform_point(radius[1], &mx) + apex;
        norm[0] = transform_normal(start_norm, &nmx);
        emit((vert, norm));
        vert[1] = vert[0];
        norm[1] = norm[0];
        vert[0] = transform_point(radius[0], &mx) + base;
        emit((vert, norm));
        vert[2] = vert[0];
        norm[2] = norm[0];
        angle += delta;
    }
}
