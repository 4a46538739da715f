//! Any scene as triangles, one group per material, for the formats that
//! hold nothing else (OBJ, glTF): polygons triangulated as `render` does
//! them, `pp` patches with their normals, boxes as twelve triangles,
//! spheres and cones tessellated as the SPD library does (`--tessellate N`:
//! a sphere is six faces of N x N quadrilaterals, a cone 4N sides, each
//! corner with its true normal). An infinite plane becomes a square around
//! the scene a hundred times its size, said as lost.

use crate::spd::tessellate;
use glam::DVec3;
use nffkit_formats::polygon::{newell_normal, triangulate};
use nffkit_formats::{box_faces, Scene, Shape};

/// The triangles of one material.
#[derive(Debug, Clone, Default)]
pub struct Group {
    /// The material: 0 the default (before any `f`), `i + 1` the file's
    /// `i`-th.
    pub material: usize,
    /// Corner positions.
    pub positions: Vec<DVec3>,
    /// A unit normal per position (a flat polygon's at each of its corners).
    pub normals: Vec<DVec3>,
    /// Triangles as indices into `positions`, counter-clockwise seen from
    /// the front.
    pub triangles: Vec<[u32; 3]>,
}

impl Group {
    fn corner(&mut self, p: DVec3, n: DVec3) -> u32 {
        self.positions.push(p);
        self.normals.push(n);
        (self.positions.len() - 1) as u32
    }

    fn polygon(&mut self, vertices: &[DVec3], normals: Option<&[DVec3]>) {
        let flat = newell_normal(vertices).normalize_or_zero();
        let base = self.positions.len() as u32;
        for (i, v) in vertices.iter().enumerate() {
            let n = normals.map_or(flat, |n| n[i].normalize_or_zero());
            self.corner(*v, n);
        }
        self.triangles.extend(triangulate(vertices).into_iter().map(|t| t.map(|i| base + i)));
    }

    fn patch(&mut self, (corners, normals): tessellate::Patch) {
        let t = [0, 1, 2].map(|k| self.corner(corners[k], normals[k].normalize_or_zero()));
        self.triangles.push(t);
    }
}

/// The scene's shapes as triangle groups, in the order their materials
/// first appear, and what was approximated.
pub fn groups(scene: &Scene, tessellate_at: u32) -> (Vec<Group>, Vec<String>) {
    let mut groups: Vec<Group> = Vec::new();
    let mut lost = Vec::new();
    let (lo, hi) = scene.bounds().unwrap_or((DVec3::splat(-1.0), DVec3::splat(1.0)));
    let reach = 100.0 * (hi - lo).max_element().max(1.0);
    let res = tessellate_at.max(1);
    let mut planes = 0;
    for p in &scene.primitives {
        let material = p.material.map_or(0, |m| m as usize + 1);
        let g = match groups.iter().position(|g| g.material == material) {
            Some(i) => &mut groups[i],
            None => {
                groups.push(Group { material, ..Group::default() });
                groups.last_mut().expect("just pushed")
            }
        };
        match &p.shape {
            Shape::Sphere { center, radius } if *radius != 0.0 => {
                tessellate::sphere(*center, radius.abs(), res, |t| g.patch(t))
            }
            Shape::Sphere { .. } => {}
            Shape::Cone(cone) => {
                let nffkit_formats::Cone { base, base_radius, apex, apex_radius } = &**cone;
                tessellate::cone(*base, base_radius.abs(), *apex, apex_radius.abs(), res, |t| g.patch(t))
            }
            Shape::Polygon { vertices } => g.polygon(vertices, None),
            Shape::Patch(p) => g.polygon(&p.vertices, Some(&p.normals)),
            Shape::Box(aabb) => {
                let nffkit_formats::AxisBox { min, max } = &**aabb;
                for face in box_faces(*min, *max) {
                    g.polygon(&face, None);
                }
            }
            Shape::Plane { points } => {
                let [a, b, c] = &**points;
                let n = (*b - *a).cross(*c - *a).normalize();
                if !n.is_finite() {
                    continue;
                }
                let u = (*b - *a).normalize() * reach;
                let v = n.cross(u);
                let middle = (lo + hi) * 0.5;
                let centre = middle - n * n.dot(middle - *a);
                g.polygon(&[centre - u - v, centre + u - v, centre + u + v, centre - u + v], None);
                planes += 1;
            }
        }
    }
    if planes > 0 {
        lost.push(format!(
            "{planes} infinite plane{}: each is a square {} across around the scene",
            nffkit_formats::plural(planes),
            super::num(2.0 * reach)
        ));
    }
    if scene.primitives.iter().any(|p| matches!(p.shape, Shape::Sphere { .. } | Shape::Cone { .. })) {
        lost.push(format!(
            "exact spheres and cones: tessellated at {res} (--tessellate), with their true normals at the corners"
        ));
    }
    (groups, lost)
}
