// The scene as the shaders see it: one uniform block of settings and
// eight storage buffers, laid out by `gpu/layout.rs` (each struct here
// mirrors one there, field for field).

struct Params {
    // Camera (`camera.rs`): eye, then the basis, then pixel size, aperture,
    // focus distance and hither in `lens`.
    eye: vec4<f32>,
    forward: vec4<f32>,
    right: vec4<f32>,
    up: vec4<f32>,
    lens: vec4<f32>,
    // Background colour in xyz, the ambient factor in w.
    background: vec4<f32>,
    // Camera resolution (x, y) and the first pixel of the window (z, w).
    image: vec4<u32>,
    // Window width and height, then the rows of this dispatch: first row
    // (relative to the window) and count.
    window: vec4<u32>,
    // Sampler kind (`SamplerKind` as `layout::sampler_code` numbers it),
    // samples per pixel, the pattern's side n, seed.
    sampler: vec4<u32>,
    // One eye ray through each pixel centre (0/1), filter kind, maximum
    // depth, what to compute (`MODE_*`).
    render: vec4<u32>,
    // Light side or diameter, light shape (0 square, 1 disk), the weight
    // below which rays are not traced, and 1 (`one()` in geometry.wgsl).
    shade: vec4<f32>,
    // Light count, whether any primitive culls, the band index of this
    // dispatch (its slot in the counters), unused.
    counts: vec4<u32>,
    // Where each kind's ids start: triangles, cones, planes, and the count
    // of all (spheres start at 0).
    ids: vec4<u32>,
    // Offsets in `shapes` (in vec4s): triangles, cones, planes, patch
    // normals (spheres start at 0).
    shape_at: vec4<u32>,
    // Offsets in `tables` (in vec4s): materials, lights, the filter's CDF;
    // and whether there is a cube map.
    table_at: vec4<u32>,
    // The cube map's faces: width, height and first texel in `env`.
    faces: array<vec4<u32>, 6>,
}

// A 4-wide BVH node (`Node4`): the four child boxes in structure-of-arrays
// form, then the children. A slot whose count is `UNUSED` is empty.
struct Node {
    lo: array<vec4<f32>, 3>,
    hi: array<vec4<f32>, 3>,
    child: vec4<u32>,
    count: vec4<u32>,
}

const UNUSED: u32 = 0xffffffffu;

// What to compute: the Whitted image, or (for the benchmark) only the
// nearest hit of one eye ray through each pixel centre.
const MODE_RENDER: u32 = 0u;
const MODE_EYE_HITS: u32 = 1u;

// Counter slots per band: eye rays, eye rays that hit, shadow rays,
// reflected rays, refracted rays.
const COUNTERS: u32 = 8u;

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<storage, read> nodes: array<Node>;
// Primitive ids in leaf order.
@group(0) @binding(2) var<storage, read> leaf_ids: array<u32>;
// Spheres (centre, radius), then triangles (three vertices), cones (base
// and height, axis and r0, slope), planes (point, normal) and patch normals
// (three), at `P.shape_at`.
@group(0) @binding(3) var<storage, read> shapes: array<vec4<f32>>;
// Per primitive: material, patch (UNUSED for none), cull rule, unused.
@group(0) @binding(4) var<storage, read> info: array<vec4<u32>>;
// Materials (three vec4s each), lights (four each) and the filter's CDF
// (257 floats, four to a vec4), at `P.table_at`.
@group(0) @binding(5) var<storage, read> tables: array<vec4<f32>>;
// Cube-map texels, 8-bit RGB packed in the low three bytes.
@group(0) @binding(6) var<storage, read> env: array<u32>;
// One colour per pixel of the window (MODE_EYE_HITS: distance and id).
@group(0) @binding(7) var<storage, read_write> film: array<vec4<f32>>;
// COUNTERS slots per band.
@group(0) @binding(8) var<storage, read_write> counters: array<atomic<u32>>;
