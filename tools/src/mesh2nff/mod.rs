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
use nffkit_formats::polygon::{drop_repeats, triangulate};
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
    /// Triangles dropped from triangulated faces for repeating another of
    /// the same face.
    pub repeated: usize,
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

/// The corners of face `f` at positions `pos` into `verts`, re-wound when
/// the placement `mirrored` the model (so it keeps facing out).
fn placed_corners(mesh: &Mesh, f: &Face, pos: &[DVec3], mirrored: bool, verts: &mut Vec<DVec3>) {
    verts.clear();
    verts.extend(mesh.corners_of(f).iter().map(|c| pos[c.position as usize]));
    if mirrored {
        verts.reverse();
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

/// Planar (within 1e-6 of the size) and convex (all turns one way, once
/// round).
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
    // Every turn one way, and the turns adding up to one full turn (an
    // outline that winds round twice turns one way too).
    let mut turning = 0.0;
    for i in 0..v.len() {
        let (a, b, c) = (v[i], v[(i + 1) % v.len()], v[(i + 2) % v.len()]);
        let (d1, d2) = (b - a, c - b);
        let sin = d1.cross(d2).dot(nh);
        if sin <= 0.0 {
            return false;
        }
        turning += sin.atan2(d1.dot(d2));
    }
    (turning - std::f64::consts::TAU).abs() < 1e-6
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

/// A converted mesh: the NFF text, ready to write, and what was done.
pub struct Converted {
    /// The comment, background, view and lights.
    header: Vec<u8>,
    /// Materials and faces.
    body: Vec<u8>,
    /// What the conversion did.
    pub summary: Summary,
}

impl Converted {
    /// Write the NFF text to `out`: nothing but I/O can fail here.
    pub fn write_to<W: Write + ?Sized>(&self, out: &mut W) -> std::io::Result<()> {
        out.write_all(&self.header)?;
        out.write_all(&self.body)
    }
}

/// Write the mesh as NFF to `out` ([`convert`], then [`Converted::write_to`]).
pub fn write<W: Write>(mesh: &Mesh, o: &Options, mut out: W) -> Result<(W, Summary)> {
    let converted = convert(mesh, o)?;
    converted.write_to(&mut out)?;
    Ok((out, converted.summary))
}

/// Convert the mesh to NFF: a header (background, view, lights) unless
/// `--no-view`, then materials and faces.
pub fn convert(mesh: &Mesh, o: &Options) -> Result<Converted> {
    check(mesh)?;
    let place = Placement::of(mesh, o);
    let pos = place.positions(mesh);
    let b = bounds(written_corners(mesh).map(|p| pos[p as usize]));
    let mut summary = Summary { bounds: b, ..Default::default() };
    let emission =
        if o.view { emission::Emission::of(mesh, &pos, o.scale < 0.0, b) } else { Default::default() };
    let body = |total: f64, summary: &mut Summary| -> Result<(Vec<u8>, Vec<bool>)> {
        let mut w = NffWriter::new(Vec::new());
        *summary = Summary { bounds: b, notes: std::mem::take(&mut summary.notes), ..Default::default() };
        let emitting = write_faces(mesh, o, &pos, (&emission, total), &mut w, summary)?;
        Ok((w.into_inner(), emitting))
    };
    let (mut faces, emitting) = body(1.0, &mut summary)?;
    let mut w = NffWriter::new(Vec::new());
    w.comment("written by nffkit mesh2nff")?;
    if o.view {
        let staged = stage(mesh, o, place, b, &emission, (&faces, &emitting), &mut summary)?;
        if staged.emission_total != 1.0 {
            // The emitting faces' look depends on their lights' strength.
            faces = body(staged.emission_total, &mut summary)?.0;
        }
        summary.emission_lights = emission.len();
        w.background(nffkit_formats::SPD_SKY)?;
        w.view(&staged.view)?;
        for l in &staged.lights {
            w.light(l)?;
        }
    }
    Ok(Converted { header: w.into_inner(), body: faces, summary })
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

/// The view and lights chosen, and the strength (brightest channel, all
/// together) of the lights from emitting faces among them.
struct Staged {
    view: View,
    lights: Vec<Light>,
    emission_total: f64,
}

/// The share of the light on what the camera sees above which the emitting
/// faces light the model alone: a tenth, where they visibly light it on
/// their own (a Cornell box's ceiling panel gives its walls a sixth of what
/// framing lights shining in through its open side would; a label on a
/// model, well under 1%).
const EMISSION_ALONE: f64 = 0.1;

/// The least strength of emission lights kept beside framing lights, so an
/// emitting face still has lights of its own to show its colour by.
const EMISSION_LEAST: f64 = 0.02;

/// Choose the view and the lights (module doc). `body` is the written
/// geometry and, per `f` line, whether emitting faces use it.
fn stage(
    mesh: &Mesh,
    o: &Options,
    place: Placement,
    b: (DVec3, DVec3),
    emission: &emission::Emission,
    body: (&[u8], &[bool]),
    summary: &mut Summary,
) -> Result<Staged> {
    let centre = (b.0 + b.1) * 0.5;
    let camera = chosen_camera(mesh, o)?;
    let punctual = punctual::lights(mesh, |p| place.apply(p), b);
    if let Some(note) = punctual::note(mesh) {
        summary.notes.push(note);
    }
    let needs_probe = o.lights == Lights::Auto || !emission.is_empty();
    let mut probe = if needs_probe {
        Some(probe::Probe::new(body.0, &framing_view(b, o).0, body.1).context("test renders for the view")?)
    } else {
        None
    };
    // The views to choose from, each with its framing lights: the file's
    // camera, else framing views (several when the model lights itself).
    let candidates: Vec<(View, Vec<Light>)> = match camera {
        Some((i, cam)) => {
            let v = view::camera_view(cam, o, |p| place.apply(p), place.scale, centre);
            let name = cam.name.as_deref().map(|n| format!(" `{n}`")).unwrap_or_default();
            summary.notes.push(format!("view from the model's camera {i}{name}"));
            let (_, lights) = view::framing(b, o, (v.from - v.at).normalize_or(DVec3::Z));
            vec![(v, lights)]
        }
        None if !emission.is_empty() => {
            view::candidate_directions(o.up).into_iter().map(|d| view::framing(b, o, d)).collect()
        }
        None => vec![framing_view(b, o)],
    };
    let (mut staged, framing_lights) = match &mut probe {
        Some(p) if !emission.is_empty() => {
            lit_by_emission(p, candidates, o, emission, !punctual.is_empty(), summary)
        }
        _ => {
            let (view, lights) = candidates.into_iter().next().expect("one view at least");
            (Staged { view, lights: Vec::new(), emission_total: 1.0 }, lights)
        }
    };
    if !emission.is_empty() {
        staged.lights = emission.lights(staged.emission_total);
    }
    let has_own = !staged.lights.is_empty() || !punctual.is_empty();
    staged.lights.extend(punctual);
    if o.lights == Lights::Auto && (!has_own || staged.emission_total != 1.0) {
        staged.lights.splice(0..0, framing_lights);
    }
    let eye = match (o.lights, &mut probe) {
        (Lights::Eye, _) => Some("--lights eye".to_string()),
        (Lights::None, _) => None,
        (Lights::Auto, _) if view::inside(&staged.view, b) => {
            Some("the eye is inside the model's box".into())
        }
        (Lights::Auto, Some(p)) => {
            let seen = p.look(&staged.view, &staged.lights);
            (seen.covered > 0.0 && seen.lit < 0.5).then(|| {
                format!("only {:.0}% of what the camera sees is lit by the other lights", seen.lit * 100.0)
            })
        }
        (Lights::Auto, None) => None,
    };
    if let Some(why) = eye {
        // Beside coloured lights of the model's own a half-strength white
        // fill; alone or beside framing lights, the SPD's 1/sqrt(n).
        let color = has_own.then_some(DVec3::splat(0.5));
        staged.lights.push(view::eye_light(&staged.view, color));
        summary.notes.push(format!("a light at the eye: {why}"));
    }
    colour_plain_lights(&mut staged.lights);
    Ok(staged)
}

/// Beside coloured lights, give the lights without a colour the intensity
/// they would have among themselves (the renderer's 1/sqrt(n), where n
/// would otherwise count the coloured ones too).
fn colour_plain_lights(lights: &mut [Light]) {
    let plain = lights.iter().filter(|l| l.color.is_none()).count();
    if plain == lights.len() {
        return;
    }
    let each = DVec3::splat(1.0 / (plain as f64).sqrt());
    for l in lights.iter_mut().filter(|l| l.color.is_none()) {
        l.color = Some(each);
    }
}

/// For a model with emitting faces: the view among `candidates` and how
/// strong the emission lights are. Unless `--lights` says otherwise or
/// the file has lights of its own, the emitting faces light the model
/// alone where, from some candidate view, they give more than
/// [`EMISSION_ALONE`] of the light on what it sees, and the view is the
/// one they show best in (the first unless another is 10% brighter);
/// otherwise the first view keeps its framing lights and the emission
/// lights get the strength that gives its surfaces what the emitters
/// would. Returns the framing lights of the view chosen beside.
fn lit_by_emission(
    probe: &mut probe::Probe,
    candidates: Vec<(View, Vec<Light>)>,
    o: &Options,
    emission: &emission::Emission,
    has_punctual: bool,
    summary: &mut Summary,
) -> (Staged, Vec<Light>) {
    let weighed: Vec<probe::Weighing> = candidates.iter().map(|(v, l)| probe.weigh(v, emission, l)).collect();
    let alone = o.lights != Lights::Auto || has_punctual || weighed.iter().any(|w| w.share > EMISSION_ALONE);
    let n = emission.len();
    let what = format!("{n} light{} from emitting faces", plural(n));
    let (pick, total) = if alone {
        let mut best = 0;
        for (k, w) in weighed.iter().enumerate().skip(1) {
            if w.brightness > weighed[best].brightness && w.brightness > weighed[0].brightness * 1.1 {
                best = k;
            }
        }
        if best != 0 {
            let d = (candidates[best].0.from - candidates[best].0.at).normalize();
            summary.notes.push(format!(
                "view from direction ({:.2}, {:.2}, {:.2}), where the model's own lights show best",
                d.x, d.y, d.z
            ));
        }
        if o.lights == Lights::Auto && !has_punctual {
            let share = weighed.iter().map(|w| w.share).fold(0.0, f64::max);
            summary.notes.push(format!(
                "{what}, alone: they give {:.0}% of the light on what the camera sees",
                share * 100.0
            ));
        } else {
            summary.notes.push(what);
        }
        (best, 1.0)
    } else {
        let w = weighed[0];
        let total = w.total.clamp(EMISSION_LEAST, 1.0);
        summary.notes.push(format!(
            "{what}, at strength {total:.3} beside the framing lights: they give {:.0}% of the light on what \
             the camera sees",
            w.share * 100.0
        ));
        (0, total)
    };
    let (view, framing) = candidates.into_iter().nth(pick).expect("a candidate picked");
    (Staged { view, lights: Vec::new(), emission_total: total }, framing)
}

/// A face's colour quantised and, for an emitting face, its Kd's bits.
type ColorKey = (Option<[u16; 3]>, Option<u64>);

/// The ratio of neighbouring Kd values of emitting faces.
const KD_STEP: f64 = 1.05;

/// The colour key of a face: its own colour, quantised, and for an
/// emitting face the Kd (in [`KD_STEP`]s, as bits) that shows its emission under
/// emission lights of strength `total` ([`emission::Emission::face_look`]);
/// `None` for the material's.
fn color_key(mesh: &Mesh, f: &Face, verts: &[DVec3], mirrored: bool, lights: &[(DVec3, DVec3)]) -> ColorKey {
    let q = |x: f64| (x.clamp(0.0, 1.0) * COLOR_STEPS).round() as u16;
    let quantised = |c: DVec3| Some([q(c.x), q(c.y), q(c.z)]);
    match (f.emission, f.color) {
        (Some(e), _) => {
            let e = DVec3::from_array(e.map(f64::from));
            // A face small beside its distance to the lights is lit alike
            // all over: its centre tells. Otherwise the centre, the
            // corners, the edges' midpoints and the points halfway to them.
            let centre = verts.iter().sum::<DVec3>() / verts.len() as f64;
            let size = verts.iter().map(|v| v.distance_squared(centre)).fold(0.0, f64::max).sqrt();
            let near = lights.iter().map(|(p, _)| p.distance_squared(centre)).fold(f64::INFINITY, f64::min);
            let at: Vec<DVec3> = if size * size < 0.01 * near {
                vec![centre]
            } else {
                let edges = (0..verts.len()).map(|i| (verts[i] + verts[(i + 1) % verts.len()]) * 0.5);
                std::iter::once(centre)
                    .chain(verts.iter().copied().chain(edges).flat_map(|v| [v, (v + centre) * 0.5]))
                    .collect()
            };
            let look = emission::emitting_normal(mesh, f, verts, mirrored)
                .and_then(|n| emission::Emission::face_look(e, &at, n, lights));
            match look {
                Some((c, kd)) => {
                    // Kd in steps of 5%: faces lit alike share an `f` line.
                    let step = (kd.ln() / KD_STEP.ln()).round();
                    let kd = KD_STEP.powf(step);
                    (quantised(c), Some(kd.to_bits()))
                }
                None => (quantised(e), None),
            }
        }
        (None, Some(c)) => (quantised(DVec3::from_array(c.map(f64::from))), None),
        (None, None) => (None, None),
    }
}

/// Materials and faces, grouped by material (in file order within one),
/// with an `f` line whenever the material or the face colour changes.
fn write_faces<W: Write>(
    mesh: &Mesh,
    o: &Options,
    pos: &[DVec3],
    (emission, total): (&emission::Emission, f64),
    w: &mut NffWriter<W>,
    summary: &mut Summary,
) -> Result<Vec<bool>> {
    let smooth = (o.smooth && !o.flat).then(|| smooth_normals(mesh, pos));
    let lights: Vec<(DVec3, DVec3)> = if emission.is_empty() {
        Vec::new()
    } else {
        emission.lights(total).iter().map(|l| (l.position, l.color.unwrap_or_default())).collect()
    };
    // Emitting faces' keys come first, so faces lit alike can be written
    // together under one `f` line.
    let mut verts = Vec::new();
    let emitter_keys: Vec<Option<ColorKey>> = if lights.is_empty() {
        Vec::new()
    } else {
        let mirrored = o.scale < 0.0;
        let key = |f: &Face, verts: &mut Vec<DVec3>| {
            f.emission?;
            placed_corners(mesh, f, pos, mirrored, verts);
            Some(color_key(mesh, f, verts, mirrored, &lights))
        };
        mesh.faces.iter().map(|f| key(f, &mut verts)).collect()
    };
    let mut emitting = Vec::new();
    let mut current = None;
    let mut norms = Vec::new();
    let mut order: Vec<usize> = (0..mesh.faces.len()).collect();
    order.sort_by_key(|&i| (mesh.faces[i].material, emitter_keys.get(i).copied().flatten()));
    for i in order {
        let f = &mesh.faces[i];
        let corners = mesh.corners_of(f);
        placed_corners(mesh, f, pos, o.scale < 0.0, &mut verts);
        norms.clear();
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
            // A negative scale mirrors (all three axes): the corners are
            // re-wound above; their normals turn to keep facing out.
            norms.reverse();
            norms.iter_mut().for_each(|n| *n = -*n);
        }
        if newell_normal(&verts).length_squared() == 0.0 {
            summary.degenerate += 1;
            continue;
        }
        let look = match emitter_keys.get(i) {
            Some(Some(k)) => *k,
            _ => color_key(mesh, f, &verts, o.scale < 0.0, &lights),
        };
        let key = (f.material, f.emission.is_some(), look);
        if current != Some(key) {
            let mut m: Material = mesh.materials[f.material as usize].clone();
            if let Some(c) = key.2 .0 {
                m.color = DVec3::from_array(c.map(|x| x as f64 / COLOR_STEPS));
            }
            if let Some(kd) = key.2 .1 {
                m.kd = f64::from_bits(kd);
            }
            w.material(&m)?;
            summary.materials += 1;
            emitting.push(key.1);
            current = Some(key);
        }
        // NFF polygons have at most MAX_VERTICES corners; larger faces are
        // cut into triangles.
        let fits = verts.len() as u64 <= nffkit_formats::nff::MAX_VERTICES;
        if verts.len() == 3 || (fits && planar_convex(&verts)) {
            emit(w, &verts, with_normals.then_some(&norms[..]), summary)?;
        } else {
            summary.triangulated += 1;
            let mut triangles = triangulate(&verts);
            summary.repeated += drop_repeats(&verts, &mut triangles);
            for t in triangles {
                let tv = t.map(|i| verts[i as usize]);
                let tn = with_normals.then(|| t.map(|i| norms[i as usize]));
                emit(w, &tv, tn.as_ref().map(|n| &n[..]), summary)?;
            }
        }
    }
    Ok(emitting)
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
