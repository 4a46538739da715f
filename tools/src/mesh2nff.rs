//! `mesh2nff`: an imported mesh to NFF text that renders as it is.
//!
//! Faces with normals become `pp` patches, others `p` polygons. A face of
//! more than three corners stays one polygon when it is planar and convex;
//! otherwise it is ear-clipped into triangles (winding preserved). Unless
//! `--no-view`, a view, two lights and a background frame the model.

use anyhow::Result;
use glam::DVec3;
use nffkit_formats::mesh::{Corner, Face, Mesh};
use nffkit_formats::nff::NffWriter;
use nffkit_formats::polygon::newell_normal;
use nffkit_formats::{Light, View};
use nffkit_tracer::triangulate::triangulate;
use std::io::Write;

/// The up axis of the source, for the view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Up {
    /// +Y up (glTF, most OBJ).
    Y,
    /// +Z up.
    Z,
}

/// Conversion options.
#[derive(Debug, Clone)]
pub struct Options {
    /// Write a view, lights and background.
    pub view: bool,
    /// Image size of the view.
    pub resolution: [u32; 2],
    /// Up axis for the view.
    pub up: Up,
    /// Uniform scale applied to positions.
    pub scale: f64,
    /// Move the bounding box centre to the origin (before scaling).
    pub center: bool,
    /// Scale so the largest side of the bounding box is 1.
    pub fit: bool,
    /// Force flat polygons, dropping normals.
    pub flat: bool,
    /// Compute area-weighted vertex normals for faces without normals.
    pub smooth: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            view: true,
            resolution: [512, 512],
            up: Up::Y,
            scale: 1.0,
            center: false,
            fit: false,
            flat: false,
            smooth: false,
        }
    }
}

/// What the conversion did, for the user.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Summary {
    /// `p` entities written.
    pub polygons: usize,
    /// `pp` entities written.
    pub patches: usize,
    /// Faces split into triangles by ear clipping.
    pub triangulated: usize,
    /// Faces dropped for having no area.
    pub degenerate: usize,
    /// Output bounds.
    pub bounds: (DVec3, DVec3),
}

fn bounds(points: impl Iterator<Item = DVec3>) -> (DVec3, DVec3) {
    points.fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| {
        (lo.min(p), hi.max(p))
    })
}

/// Apply --center, --fit and --scale to the positions the faces use.
fn transform(mesh: &Mesh, o: &Options) -> Vec<DVec3> {
    let used = bounds(mesh.corners.iter().map(|c| mesh.positions[c.position as usize]));
    let shift = if o.center || o.fit { (used.0 + used.1) * 0.5 } else { DVec3::ZERO };
    let fit = if o.fit { 1.0 / (used.1 - used.0).max_element().max(f64::MIN_POSITIVE) } else { 1.0 };
    let s = o.scale * fit;
    if shift == DVec3::ZERO && s == 1.0 {
        return mesh.positions.clone();
    }
    mesh.positions.iter().map(|p| (*p - shift) * s).collect()
}

/// Area-weighted normals per position, from the faces that lack normals.
fn smooth_normals(mesh: &Mesh, pos: &[DVec3]) -> Vec<DVec3> {
    let mut n = vec![DVec3::ZERO; pos.len()];
    let mut verts = Vec::new();
    for f in &mesh.faces {
        let c = mesh.corners_of(f);
        verts.clear();
        verts.extend(c.iter().map(|c| pos[c.position as usize]));
        let face_n = newell_normal(&verts);
        for corner in c {
            n[corner.position as usize] += face_n; // Newell's length is twice the area
        }
    }
    n.iter().map(|v| v.normalize_or_zero()).collect()
}

/// Planar (within 1e-6 of the size) and convex (all turns one way).
fn planar_convex(v: &[DVec3]) -> bool {
    let n = newell_normal(v);
    let size = bounds(v.iter().copied());
    let extent = (size.1 - size.0).length();
    if n.length() == 0.0 {
        return false;
    }
    let nh = n.normalize();
    if v.iter().any(|p| (*p - v[0]).dot(nh).abs() > 1e-6 * extent) {
        return false;
    }
    (0..v.len()).all(|i| {
        let (a, b, c) = (v[i], v[(i + 1) % v.len()], v[(i + 2) % v.len()]);
        (b - a).cross(c - b).dot(nh) > 0.0
    })
}

/// The framing view for the output bounds.
pub fn framing_view(b: (DVec3, DVec3), o: &Options) -> (View, Vec<Light>) {
    let center = (b.0 + b.1) * 0.5;
    let radius = ((b.1 - b.0).length() * 0.5).max(1e-9);
    let angle: f64 = 40.0;
    let dist = radius / (angle.to_radians() * 0.5).sin() * 1.05;
    let (up, dir) = match o.up {
        Up::Y => (DVec3::Y, DVec3::new(0.55, 0.45, 0.95).normalize()),
        Up::Z => (DVec3::Z, DVec3::new(0.55, -0.95, 0.45).normalize()),
    };
    let from = center + dir * dist;
    let right = (-dir).cross(up).normalize();
    let view = View { from, at: center, up, angle, hither: dist * 1e-3, resolution: o.resolution };
    let lights = vec![
        Light { position: from + (up * 1.5 + right * 1.0) * radius * 2.0, color: None },
        Light { position: center + (up * 1.0 - right * 2.0 + dir * 0.5) * radius * 3.0, color: None },
    ];
    (view, lights)
}

/// Refuse a mesh whose faces all have zero area, as an empty mesh is:
/// before anything is written. (A uniform scale, shift or fit never gives
/// a face area or takes it away, so the source positions decide.)
pub fn check(mesh: &Mesh) -> Result<()> {
    let mut verts = Vec::new();
    let has_area = |f: &Face| {
        verts.clear();
        verts.extend(mesh.corners_of(f).iter().map(|c| mesh.positions[c.position as usize]));
        newell_normal(&verts).length_squared() > 0.0
    };
    if !mesh.faces.iter().any(has_area) {
        anyhow::bail!("the mesh has no faces with any area (all {} are degenerate)", mesh.faces.len());
    }
    Ok(())
}

/// Write the mesh as NFF to `out`, streaming faces.
pub fn write<W: Write>(mesh: &Mesh, o: &Options, out: W) -> Result<(W, Summary)> {
    check(mesh)?;
    let pos = transform(mesh, o);
    let smooth = (o.smooth && !o.flat).then(|| smooth_normals(mesh, &pos));
    let b = bounds(mesh.corners.iter().map(|c| pos[c.position as usize]));
    let mut w = NffWriter::new(out);
    w.comment("written by nffkit mesh2nff")?;
    if o.view {
        let (view, lights) = framing_view(b, o);
        w.background(nffkit_formats::SPD_SKY)?;
        w.view(&view)?;
        for l in &lights {
            w.light(l)?;
        }
    }
    let mut summary = Summary { bounds: b, ..Default::default() };
    let mut current = None;
    let mut verts = Vec::new();
    let mut norms = Vec::new();
    // Faces grouped by material so each `f` line is written once.
    let mut order: Vec<&Face> = mesh.faces.iter().collect();
    order.sort_by_key(|f| f.material);
    for f in order {
        if current != Some(f.material) {
            w.material(&mesh.materials[f.material as usize])?;
            current = Some(f.material);
        }
        let corners = mesh.corners_of(f);
        verts.clear();
        norms.clear();
        verts.extend(corners.iter().map(|c| pos[c.position as usize]));
        let normal_of = |c: &Corner| -> Option<DVec3> {
            if o.flat {
                None
            } else {
                c.normal.or_else(|| smooth.as_ref().map(|s| s[c.position as usize]))
            }
        };
        let with_normals = corners.iter().all(|c| normal_of(c).is_some_and(|n| n != DVec3::ZERO));
        if with_normals {
            norms.extend(corners.iter().map(|c| normal_of(c).unwrap()));
        }
        if o.scale < 0.0 {
            // A negative scale mirrors (all three axes): re-wind the face and
            // turn its normals so it keeps facing out.
            verts.reverse();
            norms.reverse();
            norms.iter_mut().for_each(|n| *n = -*n);
        }
        if newell_normal(&verts).length_squared() == 0.0 {
            summary.degenerate += 1;
            continue;
        }
        if verts.len() == 3 || planar_convex(&verts) {
            emit(&mut w, &verts, with_normals.then_some(&norms[..]), &mut summary)?;
        } else {
            summary.triangulated += 1;
            for t in triangulate(&verts) {
                let tv = t.map(|i| verts[i as usize]);
                let tn = with_normals.then(|| t.map(|i| norms[i as usize]));
                emit(&mut w, &tv, tn.as_ref().map(|n| &n[..]), &mut summary)?;
            }
        }
    }
    Ok((w.into_inner(), summary))
}

fn emit<W: Write>(
    w: &mut NffWriter<W>,
    v: &[DVec3],
    n: Option<&[DVec3]>,
    s: &mut Summary,
) -> std::io::Result<()> {
    match n {
        Some(n) => {
            s.patches += 1;
            w.patch(v, n)
        }
        None => {
            s.polygons += 1;
            w.polygon(v)
        }
    }
}
