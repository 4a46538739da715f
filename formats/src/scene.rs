//! The scene as the NFF file states it: plain data, close to the text.
//!
//! Geometry is kept in `f64` so that a file read and written again gives the
//! same numbers ([`crate::nff::write`] prints the shortest text that parses back
//! to the same value).

use glam::DVec3;
use strum::{EnumCount, IntoStaticStr, VariantArray};

/// An RGB triple, nominally in [0, 1].
pub type Color = DVec3;

/// Where an entity came from in its source file (1-based line; 0 when the
/// entity was made by a program).
///
/// Provenance, not content: two entities that differ only in where they were
/// read from compare equal, so `parse(write(s)) == s` holds.
#[derive(Debug, Clone, Copy, Default)]
pub struct SourceLine(pub u32);

impl PartialEq for SourceLine {
    fn eq(&self, _other: &Self) -> bool {
        true
    }
}

/// The `v` block: a pinhole camera.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// Eye position.
    pub from: DVec3,
    /// Point at the centre of the image.
    pub at: DVec3,
    /// Up direction; need not be perpendicular to the view direction.
    pub up: DVec3,
    /// Field of view in degrees, between the centres of the outer pixel rows
    /// (and columns).
    pub angle: f64,
    /// Distance of the hither (near clipping) plane from the eye.
    pub hither: f64,
    /// Image size in pixels, x then y.
    pub resolution: [u32; 2],
    /// P3F's `aperture` and `focal` lines: a thin lens. `None` in NFF, and
    /// in a P3F view without them (a pinhole).
    pub lens: Option<Lens>,
}

impl View {
    /// The side of one pixel of a `width` x `height` image on an image
    /// plane at unit distance, as `dialect` reads this view's `angle`
    /// ([`Dialect::pixel_size`]).
    pub fn pixel_size(&self, dialect: Dialect, width: u32, height: u32) -> f64 {
        dialect.pixel_size(self.angle, width, height)
    }
}

/// P3F's thin lens, in the file's own units (docs/p3f.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lens {
    /// Lens radius as a multiple of the pixel size on the view plane (the
    /// plane through `at`); 0 is a pinhole.
    pub aperture: f64,
    /// Distance in focus as a multiple of the view-plane distance
    /// (`|at - from|`).
    pub focal: f64,
}

/// The language a scene was written in. It decides what the view's
/// `angle` spans, whether transmitters weigh reflection by Fresnel's
/// equations, and how the scene is written back.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, strum::Display, strum::EnumString)]
#[strum(serialize_all = "lowercase")]
pub enum Dialect {
    /// Eric Haines' Neutral File Format (with the 2017 course's `pl` and
    /// `aabb`).
    #[default]
    Nff,
    /// The P3D course's P3F: NFF plus specular colours, area lights, a
    /// lens, a cube map and render directives (docs/p3f.md).
    P3f,
}

impl Dialect {
    /// The side of one pixel of a `width` x `height` image on an image
    /// plane at unit distance for a view `angle` degrees wide: in NFF (the
    /// spec) the angle spans the centres of the outer pixels of the smaller
    /// side, so there are `n - 1` pixels across it; in P3F (the course's
    /// camera) it spans the image height edge to edge. Pixels are square.
    pub fn pixel_size(self, angle: f64, width: u32, height: u32) -> f64 {
        let span = 2.0 * (angle.to_radians() * 0.5).tan();
        match self {
            Dialect::Nff => {
                let n = width.min(height);
                if n > 1 {
                    span / (n - 1) as f64
                } else {
                    span
                }
            }
            Dialect::P3f => span / height.max(1) as f64,
        }
    }
}

/// The four corners of each face of the box `min`..`max`, counter-clockwise
/// seen from outside.
pub fn box_faces(min: DVec3, max: DVec3) -> [[DVec3; 4]; 6] {
    // Corner bits: x = 1, y = 2, z = 4 at the max side.
    const FACES: [[usize; 4]; 6] =
        [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]];
    let corner = |i: usize| {
        let pick = |bit: usize, lo: f64, hi: f64| if i & bit != 0 { hi } else { lo };
        DVec3::new(pick(1, min.x, max.x), pick(2, min.y, max.y), pick(4, min.z, max.z))
    };
    FACES.map(|f| f.map(corner))
}

/// P3F's directives: what the file asks of the renderer, defaults the
/// command line overrides.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Directives {
    /// `spp N`: samples per pixel; 0 is the course's one fixed sample at
    /// each pixel's centre.
    pub spp: Option<u32>,
    /// `accel N`: 0 none, 1 uniform grid, 2 BVH (the course's numbering).
    pub accel: Option<u32>,
}

/// A positional light (`l x y z [r g b]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Light {
    /// Position in world space.
    pub position: DVec3,
    /// Colour, when the file gives one. Without it the renderer chooses an
    /// intensity (SPD's exporters use 1/sqrt(number of lights)).
    pub color: Option<Color>,
    /// P3F's `al`: the light is a rectangle centred on `position`.
    pub area: Option<LightArea>,
}

/// The rectangle of a P3F area light (`al`), centred on the light's
/// position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightArea {
    /// The point the rectangle faces (its normal points there).
    pub facing: DVec3,
    /// Width and height.
    pub size: [f64; 2],
}

/// The `f` line: colour and classic Whitted shading terms.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Surface (diffuse) colour.
    pub color: Color,
    /// Colour of the highlight and the reflection: white in NFF; P3F's
    /// `f` gives it.
    pub specular: Color,
    /// Diffuse weight.
    pub kd: f64,
    /// Specular weight (highlights and mirror reflection).
    pub ks: f64,
    /// Phong exponent of the highlight.
    pub shine: f64,
    /// Transmittance (weight of the refracted ray); T > 0 makes the surface
    /// two-sided.
    pub t: f64,
    /// Index of refraction.
    pub ior: f64,
}

impl Default for Material {
    /// White, fully diffuse: what primitives before any `f` line get.
    fn default() -> Self {
        Material { color: DVec3::ONE, specular: DVec3::ONE, kd: 1.0, ks: 0.0, shine: 1.0, t: 0.0, ior: 1.0 }
    }
}

/// The largest coordinate or radius a shape may have to be rendered: the
/// renderer works in single precision, and squared distances (up to 1e36
/// and a few times that) must stay below `f32::MAX` (3.4e38). Larger
/// shapes are read, warned about, and left out of renders.
pub const MAX_COORDINATE: f64 = 1e18;

/// A geometric primitive as written in the file.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// `s`: negative radius means only the inside is visible.
    Sphere {
        /// Centre.
        center: DVec3,
        /// Radius (negative: inside visible only).
        radius: f64,
    },
    /// `c`: an open cone or cylinder (no end caps). Both radii negative means
    /// only the inside is visible.
    Cone(Box<Cone>),
    /// `p`: a planar polygon, counter-clockwise seen from its visible side.
    /// May be concave.
    Polygon {
        /// Vertices in order.
        vertices: Vec<DVec3>,
    },
    /// `pp`: a polygonal patch, a polygon with a normal per vertex.
    Patch(Box<Patch>),
    /// `pl`, an extension from the 2017 course files: the infinite plane
    /// through three points, its front given by the right-hand rule
    /// (`(b - a) × (c - a)`). Unbounded: it has no box.
    Plane {
        /// The three points, in order.
        points: Box<[DVec3; 3]>,
    },
    /// `aabb`, an extension seen in the same course's scenes: an
    /// axis-aligned box, its faces facing out.
    Box(Box<AxisBox>),
}

// The shapes larger than a sphere are boxed: a scene is mostly spheres or
// polygons, and a primitive's size sets the memory every file's parse, copy
// and flattening pass through (the level-6 sphereflake holds 598k).
#[cfg(target_pointer_width = "64")]
const _: () = assert!(std::mem::size_of::<Shape>() == 40 && std::mem::size_of::<Primitive>() == 56);

/// A [`Shape::Cone`].
#[derive(Debug, Clone, PartialEq)]
pub struct Cone {
    /// Centre of the base disc.
    pub base: DVec3,
    /// Radius at the base.
    pub base_radius: f64,
    /// Centre of the apex disc.
    pub apex: DVec3,
    /// Radius at the apex.
    pub apex_radius: f64,
}

/// A [`Shape::Patch`].
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// Vertices in order.
    pub vertices: Vec<DVec3>,
    /// One normal per vertex.
    pub normals: Vec<DVec3>,
}

/// A [`Shape::Box`].
#[derive(Debug, Clone, PartialEq)]
pub struct AxisBox {
    /// Lowest corner.
    pub min: DVec3,
    /// Highest corner.
    pub max: DVec3,
}

/// The kinds of [`Shape`], in declaration order, for counts and reports;
/// [`Shape::kind`] names each shape's, so a new shape does not compile
/// until it has a kind here.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, EnumCount, VariantArray, IntoStaticStr)]
#[strum(serialize_all = "lowercase")]
pub enum ShapeKind {
    /// `s`.
    Sphere,
    /// `c`.
    Cone,
    /// `p`.
    Polygon,
    /// `pp`.
    Patch,
    /// `pl`.
    Plane,
    /// `aabb`.
    Box,
}

impl ShapeKind {
    /// The name, in the singular (`"patch"`).
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// The name in the plural (`"patches"`).
    pub fn plural(self) -> &'static str {
        match self {
            ShapeKind::Sphere => "spheres",
            ShapeKind::Cone => "cones",
            ShapeKind::Polygon => "polygons",
            ShapeKind::Patch => "patches",
            ShapeKind::Plane => "planes",
            ShapeKind::Box => "boxes",
        }
    }
}

impl Shape {
    /// Axis-aligned bounds `(min, max)` of the shape; `None` for an
    /// unbounded plane.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        Some(match self {
            Shape::Sphere { center, radius } => {
                let r = DVec3::splat(radius.abs());
                (*center - r, *center + r)
            }
            Shape::Cone(c) => {
                let rb = DVec3::splat(c.base_radius.abs());
                let ra = DVec3::splat(c.apex_radius.abs());
                ((c.base - rb).min(c.apex - ra), (c.base + rb).max(c.apex + ra))
            }
            Shape::Polygon { vertices } => vertex_bounds(vertices),
            Shape::Patch(p) => vertex_bounds(&p.vertices),
            Shape::Box(b) => (b.min.min(b.max), b.min.max(b.max)),
            Shape::Plane { .. } => return None,
        })
    }

    /// The largest magnitude among the shape's coordinates and radii
    /// (normals aside), to compare with [`MAX_COORDINATE`].
    pub fn magnitude(&self) -> f64 {
        let of = |v: &DVec3| v.abs().max_element();
        let of_all = |vs: &[DVec3]| vs.iter().map(of).fold(0.0, f64::max);
        match self {
            Shape::Sphere { center, radius } => of(center).max(radius.abs()),
            Shape::Cone(c) => of(&c.base).max(of(&c.apex)).max(c.base_radius.abs()).max(c.apex_radius.abs()),
            Shape::Polygon { vertices } => of_all(vertices),
            Shape::Patch(p) => of_all(&p.vertices),
            Shape::Plane { points } => of_all(&points[..]),
            Shape::Box(b) => of(&b.min).max(of(&b.max)),
        }
    }

    /// A [`Shape::Cone`].
    pub fn cone(base: DVec3, base_radius: f64, apex: DVec3, apex_radius: f64) -> Shape {
        Shape::Cone(Box::new(Cone { base, base_radius, apex, apex_radius }))
    }

    /// A [`Shape::Patch`].
    pub fn patch(vertices: Vec<DVec3>, normals: Vec<DVec3>) -> Shape {
        Shape::Patch(Box::new(Patch { vertices, normals }))
    }

    /// A [`Shape::Plane`].
    pub fn plane(points: [DVec3; 3]) -> Shape {
        Shape::Plane { points: Box::new(points) }
    }

    /// A [`Shape::Box`].
    pub fn aabb(min: DVec3, max: DVec3) -> Shape {
        Shape::Box(Box::new(AxisBox { min, max }))
    }

    /// A polygon's or a patch's vertices.
    pub fn vertices(&self) -> Option<&[DVec3]> {
        match self {
            Shape::Polygon { vertices } => Some(vertices),
            Shape::Patch(p) => Some(&p.vertices),
            _ => None,
        }
    }

    /// The shape's kind.
    pub fn kind(&self) -> ShapeKind {
        match self {
            Shape::Sphere { .. } => ShapeKind::Sphere,
            Shape::Cone { .. } => ShapeKind::Cone,
            Shape::Polygon { .. } => ShapeKind::Polygon,
            Shape::Patch { .. } => ShapeKind::Patch,
            Shape::Plane { .. } => ShapeKind::Plane,
            Shape::Box { .. } => ShapeKind::Box,
        }
    }
}

/// The box of a polygon's vertices.
fn vertex_bounds(vertices: &[DVec3]) -> (DVec3, DVec3) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for v in vertices {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    (lo, hi)
}

/// A shape with the material it was given.
#[derive(Debug, Clone, PartialEq)]
pub struct Primitive {
    /// The geometry.
    pub shape: Shape,
    /// Index into [`Scene::materials`]; `None` before the file's first `f`.
    pub material: Option<u32>,
    /// Where it was read from.
    pub line: SourceLine,
}

/// The sky blue every SPD database uses as its background (`b 0.078 0.361
/// 0.753`); the generators and mesh2nff use it too.
pub const SPD_SKY: DVec3 = DVec3::new(0.078, 0.361, 0.753);

/// A whole NFF scene (or a fragment of one, when `view` is `None`).
///
/// Invariant kept by the reader: primitives' material indices never decrease
/// (each `f` line starts a new material that applies until the next one).
/// [`crate::nff::write`] relies on it to write each `f` line once.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Scene {
    /// The language it was written in.
    pub dialect: Dialect,
    /// The camera, absent in a fragment.
    pub view: Option<View>,
    /// Background colour; `None` means the file gave none (black).
    pub background: Option<Color>,
    /// Lights in file order.
    pub lights: Vec<Light>,
    /// Materials in file order, one per `f` line.
    pub materials: Vec<Material>,
    /// Primitives in file order.
    pub primitives: Vec<Primitive>,
    /// P3F's `env DIR`: a folder of six cube-map images, as written
    /// (relative to the scene file).
    pub environment: Option<String>,
    /// P3F's render directives.
    pub directives: Directives,
}

impl Scene {
    /// The material of a primitive, the default one before any `f` line.
    pub fn material_of(&self, prim: &Primitive) -> Material {
        prim.material.map(|m| self.materials[m as usize].clone()).unwrap_or_default()
    }

    /// Bounds of all bounded primitives (infinite planes have none), `None`
    /// for a scene without any.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        self.primitives.iter().filter_map(|p| p.shape.bounds()).reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
    }

    /// Count of primitives by kind, indexed by [`ShapeKind`] (`n[kind as
    /// usize]`): spheres, cones, polygons, patches, planes, boxes.
    pub fn counts(&self) -> [usize; ShapeKind::COUNT] {
        let mut n = [0; ShapeKind::COUNT];
        for p in &self.primitives {
            n[p.shape.kind() as usize] += 1;
        }
        n
    }
}
