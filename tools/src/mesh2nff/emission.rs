//! Emitting faces become NFF point lights, so a model lit by its own lamps
//! (a Cornell box's ceiling panel) renders lit by them.
//!
//! Each emitting face is cut into triangles; a triangle larger than an
//! eighth of the whole emitting area gives four lights (at the centroids of
//! its midpoint subdivision, for softer shadows), any other one light at its
//! centroid. A light sits a little off its face on the side the face's
//! normal points to: the file's normals where the face has them, else its
//! winding (counter-clockwise is the front).
//!
//! With more than [`MAX_LIGHTS`] lights, nearby ones are merged on a grid
//! whose cells grow until at most that many cells are occupied; a merged
//! light sits at the power-weighted mean position, off the surface along
//! the mean normal. The offset, taken after merging, is half the square
//! root of the area the light stands for, at most 5% of the model's
//! diagonal. Each light carries its
//! share of the emitted power (emission × area); [`Emission::lights`]
//! scales them to a chosen total.
//!
//! How much the emitters light the model, weighed against other lights
//! ([`Emission::irradiance`]), is physical: a small emitter of radiance L
//! and area A gives a point at distance r the irradiance
//! L·A·cosθ_e·cosθ_r / r², and a diffuse surface of albedo ρ then shows
//! ρ/π times that, where an NFF light of intensity I shows ρ·I·cosθ_r.
//!
//! NFF has no emission, so an emitting face is written in the colour and
//! Kd ([`Emission::face_look`]) with which its own lights make it render in
//! its emission colour, clamped to 1.

use glam::DVec3;
use nffkit_formats::mesh::{Face, Mesh};
use nffkit_formats::polygon::newell_normal;
use nffkit_formats::polygon::triangulate;
use nffkit_formats::Light;
use std::collections::BTreeMap;

/// The most lights emission turns into.
pub const MAX_LIGHTS: usize = 64;

/// A light's distance off its face, times the square root of the area it
/// stands for: half the spacing of neighbouring lights, so the face they
/// light shows no hot spots under them.
const OFFSET: f64 = 0.5;

/// The most a light stands off its face, times the model's diagonal.
const MAX_OFFSET: f64 = 0.05;

/// The most an emitting face's Kd is raised to show its colour.
const MAX_KD: f64 = 1000.0;

/// A point carrying part of the emitted power.
#[derive(Debug, Clone, Copy)]
struct Emitter {
    position: DVec3,
    /// Emission × area, per channel.
    power: DVec3,
    /// The power-weighted mean of the emitting faces' unit normals (shorter
    /// than 1 where faces facing different ways were merged).
    facing: DVec3,
    /// The emitting area.
    area: f64,
}

impl Emitter {
    fn weight(&self) -> f64 {
        self.power.element_sum().max(f64::MIN_POSITIVE)
    }
}

/// The emitting faces of a model, as at most [`MAX_LIGHTS`] emitters.
#[derive(Debug, Clone, Default)]
pub struct Emission {
    emitters: Vec<Emitter>,
    /// The brightest channel of the total power.
    brightest: f64,
}

impl Emission {
    /// The emitters of `mesh` at positions `pos` (already placed;
    /// `mirrored` when the placement reversed the winding); `bounds` is the
    /// model's box. Empty when nothing emits.
    pub fn of(mesh: &Mesh, pos: &[DVec3], mirrored: bool, bounds: (DVec3, DVec3)) -> Emission {
        let diag = (bounds.1 - bounds.0).length();
        let mut emitters = merge(emitters(mesh, pos, mirrored), MAX_LIGHTS);
        for e in &mut emitters {
            let offset = (OFFSET * e.area.sqrt()).min(MAX_OFFSET * diag);
            e.position += e.facing.normalize_or_zero() * offset;
        }
        let brightest = emitters.iter().map(|e| e.power).sum::<DVec3>().max_element();
        if !(brightest > 0.0 && brightest.is_finite()) {
            return Emission::default();
        }
        Emission { emitters, brightest }
    }

    /// Whether nothing emits.
    pub fn is_empty(&self) -> bool {
        self.emitters.is_empty()
    }

    /// How many lights the emitters make.
    pub fn len(&self) -> usize {
        self.emitters.len()
    }

    /// NFF lights whose colours add up to `total` in the brightest channel.
    pub fn lights(&self, total: f64) -> Vec<Light> {
        let scale = total / self.brightest;
        self.emitters
            .iter()
            .map(|e| Light { area: None, position: e.position, color: Some(e.power * scale) })
            .collect()
    }

    /// What the emitters give point `p` on a diffuse surface, in the units
    /// of an NFF light's intensity (module doc; the mean of the channels),
    /// where `reach[k]` is cosθ_r toward emitter `k`, or 0 when it is
    /// blocked or behind.
    pub fn irradiance(&self, p: DVec3, reach: &[f32]) -> f64 {
        self.emitters
            .iter()
            .zip(reach)
            .filter(|(_, r)| **r > 0.0)
            .map(|(e, r)| {
                let d = p - e.position;
                // Never closer than the emitter is wide: a point light's
                // 1/r² would grow without bound.
                let r2 = d.length_squared().max(e.area);
                let cos_e = e.facing.dot(d.normalize_or_zero()).max(0.0);
                e.power.element_sum() / 3.0 * cos_e * f64::from(*r) / (std::f64::consts::PI * r2)
            })
            .sum()
    }

    /// The colour and Kd with which an emitting face of emission `e` and
    /// unit normal `n` renders, lit by `lights` (as the renderer gives them
    /// intensity), in its emission clamped to 1 on average over the points
    /// `at`: Kd × colour × (Σ I·cosθ) = min(e, 1) per channel, the
    /// colour at most 1 and Kd as small as that allows. `None` when no
    /// light reaches the face's front.
    pub fn face_look(e: DVec3, at: &[DVec3], n: DVec3, lights: &[(DVec3, DVec3)]) -> Option<(DVec3, f64)> {
        let lit_at = |c: DVec3| -> DVec3 {
            lights.iter().map(|(p, i)| *i * n.dot((*p - c).normalize_or_zero()).max(0.0)).sum()
        };
        let lit = at.iter().map(|c| lit_at(*c)).sum::<DVec3>() / at.len().max(1) as f64;
        let want = e.clamp(DVec3::ZERO, DVec3::ONE);
        let ratio = DVec3::select(lit.cmpgt(DVec3::ZERO), want / lit, DVec3::ZERO);
        let kd = ratio.max_element();
        if !(kd > 0.0 && kd.is_finite()) {
            return None;
        }
        let kd = kd.min(MAX_KD);
        // A channel the lights do not carry at all cannot be shown; it gets
        // the most the colour allows.
        let color = DVec3::select(
            lit.cmpgt(DVec3::ZERO),
            ratio / kd,
            DVec3::select(want.cmpgt(DVec3::ZERO), DVec3::ONE, DVec3::ZERO),
        );
        Some((color.min(DVec3::ONE), kd))
    }
}

/// The unit normal of an emitting face with corners at `verts` (already
/// re-wound when mirrored): toward the side its file normals point to when
/// it has them, else its winding's. `None` for a face without area.
pub fn emitting_normal(mesh: &Mesh, f: &Face, verts: &[DVec3], mirrored: bool) -> Option<DVec3> {
    let n = newell_normal(verts);
    let length = n.length_squared();
    if length.is_nan() || length <= 0.0 {
        return None;
    }
    let corners = mesh.corners_of(f);
    let sign = if mirrored { -1.0 } else { 1.0 };
    let given: Option<DVec3> = corners.iter().map(|c| c.normal).sum();
    let n = n.normalize();
    Some(match given {
        Some(g) if (g * sign).dot(n) < 0.0 => -n,
        _ => n,
    })
}

/// The emitters of the faces, on them (the offset comes after merging).
fn emitters(mesh: &Mesh, pos: &[DVec3], mirrored: bool) -> Vec<Emitter> {
    let mut triangles = Vec::new();
    let mut verts = Vec::new();
    for f in &mesh.faces {
        let Some(e) = f.emission else { continue };
        super::placed_corners(mesh, f, pos, mirrored, &mut verts);
        let Some(n) = emitting_normal(mesh, f, &verts, mirrored) else { continue };
        let e = DVec3::from_array(e.map(f64::from));
        for t in triangulate(&verts) {
            triangles.push((t.map(|i| verts[i as usize]), e, n));
        }
    }
    let tri_area = |t: &[DVec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]).length() * 0.5;
    let total_area: f64 = triangles.iter().map(|(t, ..)| tri_area(t)).sum();
    let mut out = Vec::new();
    let mut push = |t: &[DVec3; 3], power: DVec3, facing: DVec3, area: f64| {
        out.push(Emitter { position: centroid(t), power, facing, area });
    };
    for (t, e, facing) in triangles {
        let a = tri_area(&t);
        if a > total_area / 8.0 {
            let m = [(t[0] + t[1]) * 0.5, (t[1] + t[2]) * 0.5, (t[2] + t[0]) * 0.5];
            for sub in [[t[0], m[0], m[2]], [m[0], t[1], m[1]], [m[2], m[1], t[2]], m] {
                push(&sub, e * a / 4.0, facing, a / 4.0);
            }
        } else {
            push(&t, e * a, facing, a);
        }
    }
    out
}

fn centroid(t: &[DVec3; 3]) -> DVec3 {
    (t[0] + t[1] + t[2]) / 3.0
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
        let mut cells: BTreeMap<[i64; 3], (Emitter, f64)> = BTreeMap::new();
        for e in &emitters {
            let k = ((e.position - lo) / cell).floor().as_i64vec3().to_array();
            let w = e.weight();
            let zero = Emitter { position: DVec3::ZERO, power: DVec3::ZERO, facing: DVec3::ZERO, area: 0.0 };
            let (sum, weight) = cells.entry(k).or_insert((zero, 0.0));
            sum.position += e.position * w;
            sum.facing += e.facing * w;
            sum.power += e.power;
            sum.area += e.area;
            *weight += w;
        }
        if cells.len() <= max {
            return cells
                .into_values()
                .map(|(e, w)| Emitter { position: e.position / w, facing: e.facing / w, ..e })
                .collect();
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
                facing: DVec3::Z,
                area: 1.0,
            })
            .collect();
        let merged = merge(emitters, MAX_LIGHTS);
        assert!(merged.len() <= MAX_LIGHTS && merged.len() > 8, "{}", merged.len());
        let total: DVec3 = merged.iter().map(|e| e.power).sum();
        assert!((total - DVec3::new(1000.0, 500.0, 250.0)).length() < 1e-9);
        assert!((merged.iter().map(|e| e.area).sum::<f64>() - 1000.0).abs() < 1e-9);
        for e in &merged {
            assert!(e.position.cmpge(DVec3::ZERO).all() && e.position.cmple(DVec3::splat(9.0)).all());
            assert!((e.facing - DVec3::Z).length() < 1e-12);
        }
    }

    #[test]
    fn a_face_look_renders_its_clamped_emission_under_its_lights() {
        let (c, n) = ([DVec3::ZERO], DVec3::Z);
        // Two lights, one warm head-on, one grey at 60 degrees.
        let lights = [
            (DVec3::new(0.0, 0.0, 1.0), DVec3::new(0.5, 0.25, 0.125)),
            (DVec3::new(0.0, 3f64.sqrt(), 1.0), DVec3::splat(0.5)),
        ];
        let lit = DVec3::new(0.5, 0.25, 0.125) + DVec3::splat(0.25);
        for e in [DVec3::new(17.0, 12.0, 4.0), DVec3::new(0.5, 0.2, 0.1)] {
            let (color, kd) = Emission::face_look(e, &c, n, &lights).unwrap();
            let shown = kd * color * lit;
            assert!((shown - e.min(DVec3::ONE)).abs().max_element() < 1e-9, "{e}: {shown}");
            assert!(color.max_element() <= 1.0 && (color.max_element() - 1.0).abs() < 1e-9);
        }
        // From behind, nothing reaches it.
        assert_eq!(Emission::face_look(DVec3::ONE, &c, -n, &lights), None);
    }
}
