//! Emitting faces become NFF point lights, so a model lit by its own lamps
//! (a Cornell box's ceiling panel) renders lit by them.
//!
//! Each emitting face is cut into triangles; a triangle larger than an
//! eighth of the whole emitting area gives four lights (at the centroids of
//! its midpoint subdivision, for softer shadows), any other one light at its
//! centroid. A light sits a little off its face, on the side the light goes
//! to: the face's front (counter-clockwise) side, except that a face lying
//! on the model's bounding box shines inward, whatever its winding (a
//! ceiling panel lights the room, not the sky). The offset is a fifth of the
//! square root of the face's area, at most 2% of the model's diagonal, so
//! the face itself is lit by its own lights and shows in its colour.
//!
//! With more than [`MAX_LIGHTS`] lights, nearby ones are merged on a grid
//! whose cells grow until at most that many cells are occupied; a merged
//! light sits at the power-weighted mean position. Intensities: each light
//! carries its share of the emitted power (emission × area), scaled so the
//! brightest channel of all of them together is 1 — the total is that of
//! one full-intensity NFF light, split by where the power is.

use glam::DVec3;
use nffkit_formats::mesh::Mesh;
use nffkit_formats::polygon::newell_normal;
use nffkit_formats::polygon::triangulate;
use nffkit_formats::Light;
use std::collections::BTreeMap;

/// The most lights emission turns into.
pub const MAX_LIGHTS: usize = 64;

/// A point carrying part of the emitted power.
#[derive(Debug, Clone, Copy)]
struct Emitter {
    position: DVec3,
    power: DVec3,
}

/// Lights for the emitting faces of `mesh` at positions `pos` (already
/// transformed; `mirrored` when the transform reversed the winding);
/// `bounds` is the model's box. Empty when nothing emits.
pub fn lights(mesh: &Mesh, pos: &[DVec3], mirrored: bool, bounds: (DVec3, DVec3)) -> Vec<Light> {
    let emitters = emitters(mesh, pos, mirrored, bounds);
    let total = emitters.iter().map(|e| e.power).sum::<DVec3>();
    let scale = total.max_element();
    if emitters.is_empty() || !(scale > 0.0 && scale.is_finite()) {
        return Vec::new();
    }
    merge(emitters, MAX_LIGHTS)
        .into_iter()
        .map(|e| Light { position: e.position, color: Some(e.power / scale) })
        .collect()
}

fn emitters(mesh: &Mesh, pos: &[DVec3], mirrored: bool, bounds: (DVec3, DVec3)) -> Vec<Emitter> {
    let diag = (bounds.1 - bounds.0).length();
    let centre = (bounds.0 + bounds.1) * 0.5;
    let mut triangles = Vec::new();
    let mut verts = Vec::new();
    for f in &mesh.faces {
        let Some(e) = f.emission else { continue };
        verts.clear();
        verts.extend(mesh.corners_of(f).iter().map(|c| pos[c.position as usize]));
        if mirrored {
            verts.reverse();
        }
        let n = newell_normal(&verts);
        let area = n.length() * 0.5;
        if area.is_nan() || area <= 0.0 {
            continue;
        }
        let mut n = n.normalize();
        let on_box = verts.iter().all(|v| on_box_side(*v, verts[0], bounds, diag));
        if on_box && n.dot(centre - verts[0]) < 0.0 {
            n = -n;
        }
        let offset = n * (0.2 * area.sqrt()).min(0.02 * diag);
        let e = DVec3::from_array(e.map(f64::from));
        for t in triangulate(&verts) {
            triangles.push((t.map(|i| verts[i as usize]), e, offset));
        }
    }
    let tri_area = |t: &[DVec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]).length() * 0.5;
    let total_area: f64 = triangles.iter().map(|(t, _, _)| tri_area(t)).sum();
    let mut out = Vec::new();
    for (t, e, offset) in triangles {
        let a = tri_area(&t);
        if a > total_area / 8.0 {
            let m = [(t[0] + t[1]) * 0.5, (t[1] + t[2]) * 0.5, (t[2] + t[0]) * 0.5];
            for sub in [[t[0], m[0], m[2]], [m[0], t[1], m[1]], [m[2], m[1], t[2]], m] {
                out.push(Emitter { position: centroid(&sub) + offset, power: e * a / 4.0 });
            }
        } else {
            out.push(Emitter { position: centroid(&t) + offset, power: e * a });
        }
    }
    out
}

fn centroid(t: &[DVec3; 3]) -> DVec3 {
    (t[0] + t[1] + t[2]) / 3.0
}

/// Whether `v` and `first` lie on the same side of the box (within 1% of
/// its diagonal).
fn on_box_side(v: DVec3, first: DVec3, b: (DVec3, DVec3), diag: f64) -> bool {
    let eps = 0.01 * diag;
    (0..3).any(|k| {
        let near = |p: DVec3, side: f64| (p[k] - side).abs() <= eps;
        (near(v, b.0[k]) && near(first, b.0[k])) || (near(v, b.1[k]) && near(first, b.1[k]))
    })
}

/// Merge emitters on a grid until at most `max` remain (module doc).
fn merge(emitters: Vec<Emitter>, max: usize) -> Vec<Emitter> {
    if emitters.len() <= max {
        return emitters;
    }
    let (lo, hi) = emitters
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), e| (lo.min(e.position), hi.max(e.position)));
    let extent = (hi - lo).max_element().max(f64::MIN_POSITIVE);
    let mut cell = extent / 64.0;
    loop {
        // Cells keyed in a BTreeMap so the lights come out in a fixed order.
        let mut cells: BTreeMap<[i64; 3], (DVec3, DVec3, f64)> = BTreeMap::new();
        for e in &emitters {
            let k = ((e.position - lo) / cell).floor().as_i64vec3().to_array();
            let w = e.power.element_sum().max(f64::MIN_POSITIVE);
            let entry = cells.entry(k).or_insert((DVec3::ZERO, DVec3::ZERO, 0.0));
            entry.0 += e.position * w;
            entry.1 += e.power;
            entry.2 += w;
        }
        if cells.len() <= max {
            return cells.into_values().map(|(p, power, w)| Emitter { position: p / w, power }).collect();
        }
        cell *= 1.25;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merging_keeps_the_total_power_and_the_cap() {
        let emitters: Vec<Emitter> = (0..1000)
            .map(|i| Emitter {
                position: DVec3::new((i % 10) as f64, (i / 10 % 10) as f64, (i / 100) as f64),
                power: DVec3::new(1.0, 0.5, 0.25),
            })
            .collect();
        let merged = merge(emitters, MAX_LIGHTS);
        assert!(merged.len() <= MAX_LIGHTS && merged.len() > 8, "{}", merged.len());
        let total: DVec3 = merged.iter().map(|e| e.power).sum();
        assert!((total - DVec3::new(1000.0, 500.0, 250.0)).length() < 1e-9);
        for e in &merged {
            assert!(e.position.cmpge(DVec3::ZERO).all() && e.position.cmple(DVec3::splat(9.0)).all());
        }
    }
}
