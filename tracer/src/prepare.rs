//! From the file's [`Scene`] to what the renderer needs: camera, lights,
//! materials and flat primitive arrays, plus the accelerator over them.

use crate::accel::{Accel, AccelInfo, AccelOptions};
use crate::camera::Camera;
use crate::environment::CubeMap;
use crate::geometry::{Cone, Cull, Geometry, Kind, Plane, PrimInfo, Sphere, Triangle};
use crate::light::{LightRect, PointLight};
use crate::material::WhittedMaterial;
use crate::stats::PerKind;
use glam::{DVec3, Vec3A};
use nffkit_formats::polygon::{drop_repeats, triangulate};
use nffkit_formats::scene::{Primitive, MAX_COORDINATE};
use nffkit_formats::{box_faces, Dialect, Scene, Shape, View};
use rayon::prelude::*;
use std::sync::Arc;
use strum::EnumCount;
use thiserror::Error;

/// How to turn the file into a renderable scene.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PrepareOptions {
    /// Image width overriding the file's (the field of view is kept).
    pub width: Option<u32>,
    /// Image height overriding the file's.
    pub height: Option<u32>,
    /// The spec's one-sided rule for opaque objects (default: two-sided).
    pub one_sided: bool,
    /// Lens radius for depth of field (0: pinhole). Default: the file's
    /// lens (a P3F view's `aperture`), else a pinhole.
    pub aperture: Option<f32>,
    /// Focal distance. Default: the file's (a P3F view's `focal`), else
    /// the from-at distance.
    pub focus: Option<f32>,
    /// Weigh transmitters' reflection and transmission by Fresnel's
    /// equations, as P3F scenes always do.
    pub fresnel: bool,
    /// The accelerator to build.
    pub accel: AccelOptions,
    /// Ambient light.
    pub ambient: Ambient,
}

/// Ambient light: `ambient × colour × Kd` added at every hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ambient {
    /// A fixed intensity (0, the default, is the classic image).
    Value(f32),
    /// The SPD Readme's lighting: the ambient and every light that has no
    /// colour of its own at `sqrt(n) / (2 n)` = `1 / (2 sqrt(n))` for `n`
    /// lights (`n` taken as 1 when there are none).
    Spd,
}

impl Ambient {
    /// Whether it lights anything: what [`RenderScene::ambient`] `> 0`
    /// will say once prepared (for any number of lights: the SPD's level
    /// only scales with it).
    pub fn lights(&self) -> bool {
        self.levels(1).1 > 0.0
    }

    /// The intensity of a light that gives none, and the ambient level,
    /// for `lights` point lights.
    fn levels(self, lights: usize) -> (f32, f32) {
        let root_n = (lights.max(1) as f32).sqrt();
        match self {
            Ambient::Value(a) => (1.0 / root_n, a),
            Ambient::Spd => (0.5 / root_n, 0.5 / root_n),
        }
    }
}

impl Default for Ambient {
    /// None: the classic image.
    fn default() -> Self {
        Ambient::Value(0.0)
    }
}

impl std::fmt::Display for Ambient {
    /// As `render --ambient` takes it: the number, or `spd`.
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Ambient::Value(v) => write!(f, "{v}"),
            Ambient::Spd => f.write_str("spd"),
        }
    }
}

/// Why a scene cannot be rendered.
#[derive(Debug, Error)]
pub enum PrepareError {
    /// A fragment has no camera.
    #[error("the scene has no view (`v` block); a fragment cannot be rendered on its own")]
    NoView,
    /// Zero or absurd image size.
    #[error("image size {0}x{1} is not renderable (each side 1 to 65536, at most 2^27 pixels)")]
    BadSize(u32, u32),
}

/// Everything the renderer reads.
#[derive(Debug, Clone)]
pub struct RenderScene {
    /// The camera.
    pub camera: Camera,
    /// Lights with their intensities.
    pub lights: Vec<PointLight>,
    /// Materials; index 0 is the default for primitives before any `f`.
    pub materials: Vec<WhittedMaterial>,
    /// Background colour.
    pub background: Vec3A,
    /// The cube map rays that leave the scene see instead of the
    /// background (P3F's `env`, loaded by the caller).
    pub environment: Option<Arc<CubeMap>>,
    /// Ambient intensity (0: none).
    pub ambient: f32,
    /// The primitives.
    pub(crate) geometry: Geometry,
    /// The accelerator over them.
    pub(crate) accel: Accel,
}

impl RenderScene {
    /// What a ray in direction `d` that hits nothing sees.
    #[inline]
    pub(crate) fn miss(&self, d: Vec3A) -> Vec3A {
        match &self.environment {
            Some(map) => map.lookup(d),
            None => self.background,
        }
    }

    /// How many primitives of each kind the renderer made of the file's
    /// (polygons become triangles).
    pub fn primitive_counts(&self) -> PerKind {
        let mut n = PerKind::default();
        for &k in <Kind as strum::VariantArray>::VARIANTS {
            n[k] = self.geometry.count(k) as u64;
        }
        n
    }

    /// The accelerator's size and build time.
    pub fn accel_info(&self) -> AccelInfo {
        self.accel.info()
    }

    /// The scene's dynamic range: its span (the largest coordinate of any
    /// bounded primitive, the eye or a light) over the size of its smallest
    /// primitive (the longest side of its box). Single precision resolves
    /// about one part in 2^24 of a coordinate, so past
    /// [`PRECISION_RANGE`] the smallest primitives are hit or missed by
    /// rounding, which accelerators, culling rays at different boxes, may
    /// settle differently.
    pub fn dynamic_range(&self) -> f32 {
        let g = &self.geometry;
        let mut span = self.camera.eye.abs().max_element();
        for l in &self.lights {
            span = span.max(l.position.abs().max_element());
        }
        // Per primitive, its largest coordinate and its size; the largest
        // and the smallest of those (on all cores: max and min do not
        // depend on the order).
        let (far, smallest) = (0..g.info.len() as u32)
            .into_par_iter()
            .map(|id| {
                let b = g.bounds(id);
                if !(b.min.is_finite() && b.max.is_finite()) {
                    return (0.0, f32::INFINITY); // an infinite plane
                }
                let size = (b.max - b.min).max_element();
                // A triangle with all three corners at one point is never hit.
                let counts = size > 0.0 || g.locate(id).0 != Kind::Triangle;
                (b.min.abs().max(b.max.abs()).max_element(), if counts { size } else { f32::INFINITY })
            })
            .reduce(|| (0.0, f32::INFINITY), |a, b| (a.0.max(b.0), a.1.min(b.1)));
        let span = span.max(far);
        if smallest == f32::INFINITY {
            1.0
        } else {
            span / smallest
        }
    }
}

/// The dynamic range ([`RenderScene::dynamic_range`]) past which small
/// primitives are at the mercy of rounding: 2^20, a sixteenth of single
/// precision's 2^24 (sphereflake level 7 and the SPD tessellations are
/// below 2^13).
pub const PRECISION_RANGE: f32 = 1_048_576.0;

fn v3(v: DVec3) -> Vec3A {
    Vec3A::new(v.x as f32, v.y as f32, v.z as f32)
}

/// Prepare `scene` for rendering.
pub fn prepare(scene: &Scene, opts: &PrepareOptions) -> Result<RenderScene, PrepareError> {
    Ok(Flat::new(scene, opts)?.build(&opts.accel))
}

/// [`prepare`] for a caller done with the file's primitives: they are
/// taken from `scene` (left empty) and freed once flattened, before the
/// accelerator is built. The build's arrays then reuse their memory
/// instead of fresh pages, each of which costs a fault on first touch,
/// and the peak is the lower. (The rest of `scene` is kept: lights, view,
/// materials.)
pub fn prepare_freeing(scene: &mut Scene, opts: &PrepareOptions) -> Result<RenderScene, PrepareError> {
    let flat = Flat::new(scene, opts)?;
    drop(std::mem::take(&mut scene.primitives));
    Ok(flat.build(&opts.accel))
}

/// A scene flattened for rendering, all but its accelerator.
struct Flat {
    camera: Camera,
    lights: Vec<PointLight>,
    materials: Vec<WhittedMaterial>,
    background: Vec3A,
    ambient: f32,
    geometry: Geometry,
}

impl Flat {
    /// Camera, lights, materials and flat primitive arrays of `scene`.
    fn new(scene: &Scene, opts: &PrepareOptions) -> Result<Flat, PrepareError> {
        let view = scene.view.as_ref().ok_or(PrepareError::NoView)?;
        let w = opts.width.unwrap_or(view.resolution[0]);
        let h = opts.height.unwrap_or(view.resolution[1]);
        // The film holds 16 bytes a pixel: 2^27 pixels is 2 GiB, the most a
        // render may ask for before memory, not the renderer, gives out.
        if w == 0 || h == 0 || w > 65536 || h > 65536 || w as u64 * h as u64 > 1 << 27 {
            return Err(PrepareError::BadSize(w, h));
        }
        let (aperture, focus) = lens(view, scene.dialect, opts);
        let camera = Camera::in_dialect(view, scene.dialect, w, h).with_lens(aperture, focus);
        let (lights, ambient) = point_lights(&scene.lights, opts.ambient);
        let default = nffkit_formats::Material::default();
        let fresnel = opts.fresnel || scene.dialect == Dialect::P3f;
        let materials = std::iter::once(&default)
            .chain(&scene.materials)
            .map(|m| WhittedMaterial::new(m, fresnel))
            .collect::<Vec<_>>();
        let geometry = build_geometry(scene, &materials, opts.one_sided);
        Ok(Flat {
            camera,
            lights,
            materials,
            background: scene.background.map(v3).unwrap_or(Vec3A::ZERO),
            ambient,
            geometry,
        })
    }

    /// The render scene, with the accelerator `opts` asks for.
    fn build(self, opts: &AccelOptions) -> RenderScene {
        let accel = Accel::build(&self.geometry, opts);
        let Flat { camera, lights, materials, background, ambient, geometry } = self;
        RenderScene { camera, lights, materials, background, environment: None, ambient, geometry, accel }
    }
}

/// The lens radius and focal distance: the options', else the file's lens
/// (P3F's `aperture`, a multiple of the pixel size on the view plane at its
/// own resolution, and `focal`, a multiple of the view-plane distance),
/// else a pinhole focused on `at`.
fn lens(view: &View, dialect: Dialect, opts: &PrepareOptions) -> (f32, Option<f32>) {
    let d = (view.at - view.from).length();
    let file = view.lens.map(|l| {
        let [w, h] = view.resolution;
        ((l.aperture * view.pixel_size(dialect, w, h) * d) as f32, (l.focal * d) as f32)
    });
    let aperture = opts.aperture.or(file.map(|f| f.0)).unwrap_or(0.0);
    (aperture, opts.focus.or(file.map(|f| f.1)))
}

/// The file's lights with their intensities resolved, and the ambient
/// intensity. SPD's convention for lights without a colour: each gets
/// 1/sqrt(n), or 1/(2 sqrt(n)) with the SPD Readme's ambient term beside them.
pub fn point_lights(lights: &[nffkit_formats::Light], ambient: Ambient) -> (Vec<PointLight>, f32) {
    // Lights too far for single precision are left out (the reader warns).
    let lights: Vec<_> = lights.iter().filter(|l| l.position.abs().max_element() <= MAX_COORDINATE).collect();
    let (default_i, ambient) = ambient.levels(lights.len());
    let lights = lights
        .iter()
        .map(|l| PointLight {
            position: v3(l.position),
            intensity: l.color.map(v3).unwrap_or(Vec3A::splat(default_i)),
            rect: l.area.map(|a| {
                let n = v3(a.facing - l.position).normalize_or_zero();
                LightRect::facing(n, a.size[0] as f32, a.size[1] as f32)
            }),
        })
        .collect();
    (lights, ambient)
}

/// The triangles of a polygon, each place once (an outline that runs
/// over itself repeats them; a small one's repeats cost little).
fn triangles_of(vertices: &[DVec3]) -> Vec<[u32; 3]> {
    let mut t = triangulate(vertices);
    if vertices.len() > 16 {
        drop_repeats(vertices, &mut t);
    }
    t
}

/// A run of spheres at least this long that ends the primitive list is
/// converted on all cores.
const PARALLEL_SPHERES: usize = 1 << 14;

/// How a primitive's per-primitive record is made: its material (0 is the
/// default, before the file's first `f`) and which side it culls.
struct Records<'a> {
    materials: &'a [WhittedMaterial],
    one_sided: bool,
}

impl Records<'_> {
    /// The record of `prim`, which shows only its inside when
    /// `inside_only`, with patch normals `patch`.
    #[inline]
    fn of(&self, prim: &Primitive, inside_only: bool, patch: Option<u32>) -> PrimInfo {
        let material = prim.material.map_or(0, |m| m + 1);
        let transmissive = self.materials[material as usize].t > 0.0;
        let cull = if inside_only {
            Cull::Front
        } else if self.one_sided && !transmissive {
            Cull::Back
        } else {
            Cull::None
        };
        PrimInfo::new(material, cull, patch, prim.line.0)
    }

    /// A kept sphere ([`kept_sphere`]) and its record.
    #[inline]
    fn sphere(&self, prim: &Primitive, center: DVec3, radius: f64) -> (Sphere, PrimInfo) {
        (Sphere::new(v3(center), radius.abs() as f32), self.of(prim, radius < 0.0, None))
    }
}

/// Whether `prim` is a sphere the geometry keeps: of some size and not
/// too large for single precision (the reader warns of those).
#[inline]
fn kept_sphere(prim: &Primitive) -> bool {
    matches!(prim.shape, Shape::Sphere { radius, .. } if radius != 0.0)
        && prim.shape.magnitude() <= MAX_COORDINATE
}

/// Flatten the file's primitives into typed arrays, numbered in [`Kind`]
/// order. Boxes become twelve triangles.
pub(crate) fn build_geometry(scene: &Scene, materials: &[WhittedMaterial], one_sided: bool) -> Geometry {
    build_geometry_with(scene, materials, one_sided, PARALLEL_SPHERES)
}

/// [`build_geometry`], converting a final run of at least `parallel` kept
/// spheres on all cores.
fn build_geometry_with(
    scene: &Scene,
    materials: &[WhittedMaterial],
    one_sided: bool,
    parallel: usize,
) -> Geometry {
    let mut g = Geometry::default();
    let prims = &scene.primitives;
    // Sized up front, so that a large scene's arrays are not copied as they
    // grow; and the last primitive that is not a kept sphere found, after
    // which the list is a run of them (an SPD sphere scene: a floor, then
    // spheres). Counted on all cores: a pass over every primitive.
    let (spheres, triangles, last_other) = prims
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            let (s, t) = match &p.shape {
                Shape::Sphere { .. } => (1, 0),
                Shape::Polygon { vertices } => (0, vertices.len().saturating_sub(2)),
                Shape::Patch(p) => (0, p.vertices.len().saturating_sub(2)),
                Shape::Box { .. } => (0, 12),
                _ => (0, 0),
            };
            (s, t, (!kept_sphere(p)).then_some(i))
        })
        .reduce(|| (0, 0, None), |(s0, t0, o0), (s1, t1, o1)| (s0 + s1, t0 + t1, o0.max(o1)));
    g.spheres.reserve_exact(spheres);
    g.triangles.reserve(triangles);
    // Per-primitive data per kind, joined in id order at the end.
    let mut info: [Vec<PrimInfo>; Kind::COUNT] = Default::default();
    info[Kind::Sphere as usize].reserve_exact(spheres);
    info[Kind::Triangle as usize].reserve(triangles);
    let records = Records { materials, one_sided };
    let run = last_other.map_or(0, |i| i + 1);
    let run = if prims.len() - run >= parallel { run } else { prims.len() };
    // Shapes too large for single precision are left out (the reader warns).
    for prim in prims[..run].iter().filter(|p| p.shape.magnitude() <= MAX_COORDINATE) {
        let record = |inside_only, patch| records.of(prim, inside_only, patch);
        match &prim.shape {
            Shape::Sphere { center, radius } => {
                if *radius == 0.0 {
                    continue;
                }
                let (sphere, info_of) = records.sphere(prim, *center, *radius);
                g.spheres.push(sphere);
                info[Kind::Sphere as usize].push(info_of);
            }
            Shape::Cone(cone) => {
                let nffkit_formats::Cone { base, base_radius, apex, apex_radius } = &**cone;
                let (b, a) = (v3(*base), v3(*apex));
                let height = (a - b).length();
                if height == 0.0 || (*base_radius == 0.0 && *apex_radius == 0.0) {
                    continue;
                }
                let (r0, r1) = (base_radius.abs() as f32, apex_radius.abs() as f32);
                g.cones.push(Cone { base: b, axis: (a - b) / height, height, r0, slope: (r1 - r0) / height });
                info[Kind::Cone as usize].push(record(*base_radius < 0.0 || *apex_radius < 0.0, None));
            }
            Shape::Polygon { vertices } => {
                for t in triangles_of(vertices) {
                    g.triangles.push(Triangle { v: t.map(|i| v3(vertices[i as usize])) });
                    info[Kind::Triangle as usize].push(record(false, None));
                }
            }
            Shape::Patch(patch) => {
                let nffkit_formats::Patch { vertices, normals } = &**patch;
                for t in triangles_of(vertices) {
                    g.triangles.push(Triangle { v: t.map(|i| v3(vertices[i as usize])) });
                    let n = t.map(|i| v3(normals[i as usize]).normalize_or_zero());
                    info[Kind::Triangle as usize].push(record(false, Some(g.patch_normals.len() as u32)));
                    g.patch_normals.push(n);
                }
            }
            Shape::Plane { points } => {
                let [a, b, c] = &**points;
                let (a, b, c) = (*a, *b, *c);
                // The normal in double precision: the points may be far apart.
                let n = (b - a).cross(c - a).normalize();
                if !n.is_finite() {
                    continue;
                }
                g.planes.push(Plane { point: v3(a), n: v3(n) });
                info[Kind::Plane as usize].push(record(false, None));
            }
            Shape::Box(aabb) => {
                let nffkit_formats::AxisBox { min, max } = &**aabb;
                for [a, b, c, d] in box_faces(*min, *max) {
                    for t in [[a, b, c], [a, c, d]] {
                        g.triangles.push(Triangle { v: t.map(v3) });
                        info[Kind::Triangle as usize].push(record(false, None));
                    }
                }
            }
        }
    }
    // The run of kept spheres that ends the list, converted on all cores
    // straight into both lists (their lengths known, each core writes its
    // own places).
    if run < prims.len() {
        let mut lists = (std::mem::take(&mut g.spheres), std::mem::take(&mut info[Kind::Sphere as usize]));
        lists.par_extend(prims[run..].par_iter().map(|prim| match prim.shape {
            Shape::Sphere { center, radius } => records.sphere(prim, center, radius),
            _ => unreachable!("the run holds only spheres"),
        }));
        (g.spheres, info[Kind::Sphere as usize]) = lists;
    }
    // The first kind's list grows to hold the others' instead of all being
    // copied into a fresh one: a sphere scene's is the only one, not copied.
    let [first, rest @ ..] = info;
    g.info = first;
    g.info.reserve_exact(rest.iter().map(Vec::len).sum());
    for kind in rest {
        g.info.extend(kind);
    }
    g.any_cull = g.info.iter().any(|i| i.cull != Cull::None);
    g.assign_ids();
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::uniform;
    use nffkit_formats::scene::SourceLine;

    /// Converting the spheres that end the list on all cores gives the
    /// geometry that converting them one by one gives: materials, culling
    /// (inside-only spheres, one-sided opaque ones, two-sided transmissive
    /// ones) and lines; spheres left out (radius 0, too large) end the
    /// run's start where they are.
    #[test]
    fn the_final_run_of_spheres_converts_on_all_cores_as_one_by_one() {
        let mut rnd = uniform(0x5eed_1234_abcd_ef01);
        let m = |t: f32| WhittedMaterial { t, ..crate::testing::white() };
        let materials = [m(0.0), m(0.0), m(0.5), m(0.0)];
        for skipped in [None, Some(0.0), Some(1e30)] {
            let mut scene = Scene::default();
            let floor = Shape::Polygon { vertices: vec![DVec3::ZERO, DVec3::X, DVec3::Y] };
            scene.primitives.push(Primitive { shape: floor, material: None, line: SourceLine(1) });
            for i in 0..3000u32 {
                let center = DVec3::new(rnd() as f64, rnd() as f64, rnd() as f64) * 10.0;
                let radius = if i % 7 == 3 { -0.25 } else { 0.5 } * (1.0 + rnd() as f64);
                let radius = match skipped {
                    Some(r) if i == 1000 => r,
                    _ => radius,
                };
                let material = Some(i % 3);
                scene.primitives.push(Primitive {
                    shape: Shape::Sphere { center, radius },
                    material,
                    line: SourceLine(i + 2),
                });
            }
            for one_sided in [false, true] {
                let one = build_geometry_with(&scene, &materials, one_sided, usize::MAX);
                let all = build_geometry_with(&scene, &materials, one_sided, 1);
                assert_eq!(format!("{all:?}"), format!("{one:?}"), "{skipped:?}, one-sided {one_sided}");
                assert_eq!(one.spheres.len(), if skipped.is_some() { 2999 } else { 3000 });
            }
        }
    }
}
