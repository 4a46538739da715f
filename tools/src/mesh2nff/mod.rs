//! `mesh2nff`: an imported mesh to NFF text that renders as it is.
//!
//! Faces with normals become `pp` patches, others `p` polygons. A face of
//! more than three corners stays one polygon when it is planar and convex;
//! otherwise it is ear-clipped into triangles (winding preserved). Faces
//! with their own colour (textures, vertex colours) get an `f` line whenever
//! the colour, quantised to [`COLOR_STEPS`] levels, changes; emitting faces
//! show their emitted colour and become lights ([`emission`]).
//!
//! Unless `--no-view`, a background, a view and lights follow
//! ([`view`]): the file's camera when it asks for one (or has exactly one),
//! else a framing view; lights per [`Lights`], checked by small test renders
//! ([`probe`]) so what the camera sees is lit.

pub mod emission;
pub mod probe;
mod punctual;
pub mod view;

use anyhow::{Context, Result};
use glam::DVec3;
use nffkit_formats::mesh::{Corner, Face, Mesh, MeshCamera};
use nffkit_formats::nff::NffWriter;
use nffkit_formats::polygon::newell_normal;
use nffkit_formats::polygon::triangulate;
use nffkit_formats::{plural, Light, Material, View};
use std::io::Write;

/// Levels per colour channel for per-face colours: finer than 8-bit output
/// cannot show, and equal colours share one `f` line.
pub const COLOR_STEPS: f64 = 255.0;

/// The up axis of the source, for the view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Up {
    /// +Y up (glTF, most OBJ).
    Y,
    /// +Z up.
    Z,
}

/// Which lights to add to the model's own (emission always becomes lights).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Lights {
    /// Framing lights when nothing emits; a light at the eye as well when
    /// the eye is inside the model's box or test renders find most of what
    /// the camera sees unlit.
    #[default]
    Auto,
    /// A light at the eye (a headlight) and no framing lights.
    Eye,
    /// None: only the model's emission.
    None,
}

/// Conversion options.
#[derive(Debug, Clone)]
pub struct Options {
    /// Write a view, lights and background.
    pub view: bool,
    /// Image size of the view (default 512 × 512, or 512 wide at a file
    /// camera's aspect ratio).
    pub resolution: Option<[u32; 2]>,
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
    /// Lights to add.
    pub lights: Lights,
    /// Use the file's perspective camera of this index (in the order met).
    pub camera: Option<usize>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            view: true,
            resolution: None,
            up: Up::Y,
            scale: 1.0,
            center: false,
            fit: false,
            flat: false,
            smooth: false,
            lights: Lights::Auto,
            camera: None,
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
    /// `f` lines written.
    pub materials: usize,
    /// Lights made from emitting faces.
    pub emission_lights: usize,
    /// Output bounds.
    pub bounds: (DVec3, DVec3),
    /// How the view and lights were chosen, for the user.
    pub notes: Vec<String>,
}

fn bounds(points: impl Iterator<Item = DVec3>) -> (DVec3, DVec3) {
    points.fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| {
        (lo.min(p), hi.max(p))
    })
}

/// What --center, --fit and --scale do to a point: `(p − shift) × scale`.
#[derive(Debug, Clone, Copy)]
struct Placement {
    shift: DVec3,
    scale: f64,
}

impl Placement {
    fn of(mesh: &Mesh, o: &Options) -> Placement {
        let used = bounds(written_corners(mesh).map(|p| mesh.positions[p as usize]));
        let shift = if o.center || o.fit { (used.0 + used.1) * 0.5 } else { DVec3::ZERO };
        let fit = if o.fit { 1.0 / (used.1 - used.0).max_element().max(f64::MIN_POSITIVE) } else { 1.0 };
        Placement { shift, scale: o.scale * fit }
    }

    fn apply(&self, p: DVec3) -> DVec3 {
        (p - self.shift) * self.scale
    }

    /// The positions the faces use, placed.
    fn positions(&self, mesh: &Mesh) -> Vec<DVec3> {
        if self.shift == DVec3::ZERO && self.scale == 1.0 {
            return mesh.positions.clone();
        }
        mesh.positions.iter().map(|p| self.apply(*p)).collect()
    }
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

/// The positions of the corners of faces with area, the ones written: a
/// stray degenerate face (`f 4 4 4` far away) must not move the framing.
/// (A uniform scale, shift or fit never gives a face area or takes it
/// away, so the source positions decide.)
fn written_corners(mesh: &Mesh) -> impl Iterator<Item = u32> + '_ {
    let mut verts = Vec::new();
    mesh.faces
        .iter()
        .filter(move |f| {
            verts.clear();
            verts.extend(mesh.corners_of(f).iter().map(|c| mesh.positions[c.position as usize]));
            newell_normal(&verts).length_squared() > 0.0
        })
        .flat_map(|f| mesh.corners_of(f).iter().map(|c| c.position))
}

/// The framing view for the output bounds, from the default direction.
pub fn framing_view(b: (DVec3, DVec3), o: &Options) -> (View, Vec<Light>) {
    view::framing(b, o, view::default_direction(o.up))
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

/// Write the mesh as NFF to `out`: a header (background, view, lights)
/// unless `--no-view`, then materials and faces.
pub fn write<W: Write>(mesh: &Mesh, o: &Options, out: W) -> Result<(W, Summary)> {
    check(mesh)?;
    let place = Placement::of(mesh, o);
    let pos = place.positions(mesh);
    let b = bounds(written_corners(mesh).map(|p| pos[p as usize]));
    let mut summary = Summary { bounds: b, ..Default::default() };
    let mut body = NffWriter::new(Vec::new());
    write_faces(mesh, o, &pos, &mut body, &mut summary)?;
    let body = body.into_inner();
    let mut w = NffWriter::new(out);
    w.comment("written by nffkit mesh2nff")?;
    if o.view {
        let (view, lights) = stage(mesh, o, place, &pos, b, &body, &mut summary)?;
        w.background(nffkit_formats::SPD_SKY)?;
        w.view(&view)?;
        for l in &lights {
            w.light(l)?;
        }
    }
    let mut out = w.into_inner();
    out.write_all(&body)?;
    Ok((out, summary))
}

/// The file camera the view comes from: the one asked for, else the only one.
fn chosen_camera<'m>(mesh: &'m Mesh, o: &Options) -> Result<Option<(usize, &'m MeshCamera)>> {
    match o.camera {
        Some(i) => match mesh.cameras.get(i) {
            Some(c) => Ok(Some((i, c))),
            None => anyhow::bail!(
                "--camera {i}: the model has {} perspective camera{} (numbered from 0)",
                mesh.cameras.len(),
                plural(mesh.cameras.len())
            ),
        },
        None if mesh.cameras.len() == 1 => Ok(Some((0, &mesh.cameras[0]))),
        None => Ok(None),
    }
}

/// Choose the view and the lights (module doc).
fn stage(
    mesh: &Mesh,
    o: &Options,
    place: Placement,
    pos: &[DVec3],
    b: (DVec3, DVec3),
    body: &[u8],
    summary: &mut Summary,
) -> Result<(View, Vec<Light>)> {
    let emission = emission::lights(mesh, pos, o.scale < 0.0, b);
    summary.emission_lights = emission.len();
    let centre = (b.0 + b.1) * 0.5;
    let camera = chosen_camera(mesh, o)?;
    let needs_probe = o.lights == Lights::Auto || (camera.is_none() && !emission.is_empty());
    let mut probe = if needs_probe {
        Some(probe::Probe::new(body, &framing_view(b, o).0).context("test renders for the view")?)
    } else {
        None
    };
    let (view, framing_lights) = match camera {
        Some((i, cam)) => {
            let v = view::camera_view(cam, o, |p| place.apply(p), place.scale, centre);
            let name = cam.name.as_deref().map(|n| format!(" `{n}`")).unwrap_or_default();
            summary.notes.push(format!("view from the model's camera {i}{name}"));
            let (_, lights) = view::framing(b, o, (v.from - v.at).normalize_or(DVec3::Z));
            (v, lights)
        }
        None => match (&mut probe, emission.is_empty()) {
            (Some(p), false) => brightest_framing(p, b, o, &emission, summary),
            _ => framing_view(b, o),
        },
    };
    // The model's own lights, from emitting faces and from the file.
    let mut own = emission.clone();
    own.extend(punctual::lights(mesh, |p| place.apply(p), b));
    if let Some(note) = punctual::note(mesh) {
        summary.notes.push(note);
    }
    let has_own = !own.is_empty();
    let mut lights = match o.lights {
        Lights::Auto if own.is_empty() => framing_lights,
        _ => own,
    };
    let eye = match (o.lights, &mut probe) {
        (Lights::Eye, _) => Some("--lights eye".to_string()),
        (Lights::None, _) => None,
        (Lights::Auto, _) if view::inside(&view, b) => Some("the eye is inside the model's box".into()),
        (Lights::Auto, Some(p)) => {
            let seen = p.look(&view, &lights);
            (seen.covered > 0.0 && seen.lit < 0.5).then(|| {
                format!("only {:.0}% of what the camera sees is lit by the other lights", seen.lit * 100.0)
            })
        }
        (Lights::Auto, None) => None,
    };
    if let Some(why) = eye {
        // Beside coloured emission lights (which total 1) a half-strength
        // white fill; alone or beside framing lights, the SPD's 1/sqrt(n).
        let color = has_own.then_some(DVec3::splat(0.5));
        lights.push(view::eye_light(&view, color));
        summary.notes.push(format!("a light at the eye: {why}"));
    }
    if !emission.is_empty() {
        summary.notes.push(format!("{} light{} from emitting faces", emission.len(), plural(emission.len())));
    }
    Ok((view, lights))
}

/// The framing view, among the candidate directions, in which the model's
/// own lights show the most (the default unless another is 10% brighter).
fn brightest_framing(
    probe: &mut probe::Probe,
    b: (DVec3, DVec3),
    o: &Options,
    emission: &[Light],
    summary: &mut Summary,
) -> (View, Vec<Light>) {
    let candidates = view::candidate_directions(o.up);
    let score =
        |probe: &mut probe::Probe, d: DVec3| probe.look(&view::framing(b, o, d).0, emission).brightness;
    let default = score(probe, candidates[0]);
    let (mut best, mut best_score) = (candidates[0], default);
    for &d in &candidates[1..] {
        let s = score(probe, d);
        if s > best_score && s > default * 1.1 {
            (best, best_score) = (d, s);
        }
    }
    if best != candidates[0] {
        summary.notes.push(format!(
            "view from direction ({:.2}, {:.2}, {:.2}), where the model's own lights show best",
            best.x, best.y, best.z
        ));
    }
    view::framing(b, o, best)
}

/// The colour key of a face: its own colour (an emitting face shows its
/// emitted colour at full strength), quantised; `None` for the material's.
fn color_key(f: &Face) -> Option<[u16; 3]> {
    let c = match (f.emission, f.color) {
        (Some(e), _) => {
            let e = DVec3::from_array(e.map(f64::from));
            e / e.max_element()
        }
        (None, Some(c)) => DVec3::from_array(c.map(f64::from)),
        (None, None) => return None,
    };
    let q = |x: f64| (x.clamp(0.0, 1.0) * COLOR_STEPS).round() as u16;
    Some([q(c.x), q(c.y), q(c.z)])
}

/// Materials and faces, grouped by material (in file order within one),
/// with an `f` line whenever the material or the face colour changes.
fn write_faces<W: Write>(
    mesh: &Mesh,
    o: &Options,
    pos: &[DVec3],
    w: &mut NffWriter<W>,
    summary: &mut Summary,
) -> Result<()> {
    let smooth = (o.smooth && !o.flat).then(|| smooth_normals(mesh, pos));
    let mut current = None;
    let mut verts = Vec::new();
    let mut norms = Vec::new();
    let mut order: Vec<&Face> = mesh.faces.iter().collect();
    order.sort_by_key(|f| f.material);
    for f in order {
        let key = (f.material, color_key(f));
        if current != Some(key) {
            let mut m: Material = mesh.materials[f.material as usize].clone();
            if let Some(c) = key.1 {
                m.color = DVec3::from_array(c.map(|x| x as f64 / COLOR_STEPS));
            }
            w.material(&m)?;
            summary.materials += 1;
            current = Some(key);
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
            emit(w, &verts, with_normals.then_some(&norms[..]), summary)?;
        } else {
            summary.triangulated += 1;
            for t in triangulate(&verts) {
                let tv = t.map(|i| verts[i as usize]);
                let tn = with_normals.then(|| t.map(|i| norms[i as usize]));
                emit(w, &tv, tn.as_ref().map(|n| &n[..]), summary)?;
            }
        }
    }
    Ok(())
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
