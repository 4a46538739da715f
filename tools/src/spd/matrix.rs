//! The SPD library's 4×4 matrices (libvec.c), row-vector convention
//! (`v · M`), with every product written in the C's order: the outputs
//! depend on each rounding, down to the sign of a zero (`x + 0·0` turns a
//! `-0` into `0`).

use glam::DVec3;

/// A 4×4 matrix, `m[row][column]`.
pub type Matrix = [[f64; 4]; 4];

/// `lib_create_identity_matrix`.
pub fn identity() -> Matrix {
    let mut m = [[0.0; 4]; 4];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    m
}

/// The axes of `lib_create_rotate_matrix`.
#[derive(Debug, Clone, Copy)]
pub enum Axis {
    /// About X.
    X,
    /// About Y.
    Y,
    /// About Z.
    Z,
}

/// `lib_create_rotate_matrix`: rotation by `angle` about a coordinate axis.
pub fn rotate(axis: Axis, angle: f64) -> Matrix {
    let (c, s) = (angle.cos(), angle.sin());
    let mut m = [[0.0; 4]; 4];
    match axis {
        Axis::X => {
            m[0][0] = 1.0;
            m[1][1] = c;
            m[2][2] = c;
            m[1][2] = s;
            m[2][1] = -s;
        }
        Axis::Y => {
            m[1][1] = 1.0;
            m[0][0] = c;
            m[2][2] = c;
            m[2][0] = s;
            m[0][2] = -s;
        }
        Axis::Z => {
            m[2][2] = 1.0;
            m[0][0] = c;
            m[1][1] = c;
            m[0][1] = s;
            m[1][0] = -s;
        }
    }
    m[3][3] = 1.0;
    m
}

/// `lib_create_axis_rotate_matrix`: rotation by `angle` about the unit
/// vector `a`.
pub fn axis_rotate(a: DVec3, angle: f64) -> Matrix {
    let (c, s) = (angle.cos(), angle.sin());
    let t = 1.0 - c;
    [
        [a.x * a.x + (1.0 - a.x * a.x) * c, a.x * a.y * t + a.z * s, a.x * a.z * t - a.y * s, 0.0],
        [a.x * a.y * t - a.z * s, a.y * a.y + (1.0 - a.y * a.y) * c, a.y * a.z * t + a.x * s, 0.0],
        [a.x * a.z * t + a.y * s, a.y * a.z * t - a.x * s, a.z * a.z + (1.0 - a.z * a.z) * c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// `lib_transform_vector`: `v · M` without translation.
pub fn transform_vector(v: DVec3, m: &Matrix) -> DVec3 {
    DVec3::new(
        v.x * m[0][0] + v.y * m[1][0] + v.z * m[2][0],
        v.x * m[0][1] + v.y * m[1][1] + v.z * m[2][1],
        v.x * m[0][2] + v.y * m[1][2] + v.z * m[2][2],
    )
}

/// `lib_transform_coord`: the four-component `v · M`.
pub fn transform_coord(v: [f64; 4], m: &Matrix) -> [f64; 4] {
    std::array::from_fn(|k| v[0] * m[0][k] + v[1] * m[1][k] + v[2] * m[2][k] + v[3] * m[3][k])
}

/// `lib_normalize_vector`: `v` over its length, unless that is 0.
pub fn normalize(v: DVec3) -> DVec3 {
    let d = v.dot(v).sqrt();
    if d > 0.0 {
        DVec3::new(v.x / d, v.y / d, v.z / d)
    } else {
        v
    }
}

/// `lib_transform_point`: `v · M` with the translation row.
pub fn transform_point(v: DVec3, m: &Matrix) -> DVec3 {
    DVec3::new(
        v.x * m[0][0] + v.y * m[1][0] + v.z * m[2][0] + m[3][0],
        v.x * m[0][1] + v.y * m[1][1] + v.z * m[2][1] + m[3][1],
        v.x * m[0][2] + v.y * m[1][2] + v.z * m[2][2] + m[3][2],
    )
}

/// `lib_matrix_multiply`: `a · b`.
pub fn multiply(a: &Matrix, b: &Matrix) -> Matrix {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] + a[i][3] * b[3][j])
    })
}

/// libvec.c `det3x3`.
#[allow(clippy::too_many_arguments)]
fn det3(a1: f64, a2: f64, a3: f64, b1: f64, b2: f64, b3: f64, c1: f64, c2: f64, c3: f64) -> f64 {
    a1 * (b2 * c3 - b3 * c2) - b1 * (a2 * c3 - a3 * c2) + c1 * (a2 * b3 - a3 * b2)
}

/// libvec.c `lib_matrix_det4x4`.
pub fn det4(m: &Matrix) -> f64 {
    let [[a1, b1, c1, d1], [a2, b2, c2, d2], [a3, b3, c3, d3], [a4, b4, c4, d4]] = *m;
    a1 * det3(b2, b3, b4, c2, c3, c4, d2, d3, d4) - b1 * det3(a2, a3, a4, c2, c3, c4, d2, d3, d4)
        + c1 * det3(a2, a3, a4, b2, b3, b4, d2, d3, d4)
        - d1 * det3(a2, a3, a4, b2, b3, b4, c2, c3, c4)
}

/// libvec.c `lib_invert_matrix`: the adjoint over the determinant (the
/// identity for a singular matrix, as the library gives).
pub fn invert(m: &Matrix) -> Matrix {
    let [[a1, b1, c1, d1], [a2, b2, c2, d2], [a3, b3, c3, d3], [a4, b4, c4, d4]] = *m;
    let adj = [
        [
            det3(b2, b3, b4, c2, c3, c4, d2, d3, d4),
            -det3(b1, b3, b4, c1, c3, c4, d1, d3, d4),
            det3(b1, b2, b4, c1, c2, c4, d1, d2, d4),
            -det3(b1, b2, b3, c1, c2, c3, d1, d2, d3),
        ],
        [
            -det3(a2, a3, a4, c2, c3, c4, d2, d3, d4),
            det3(a1, a3, a4, c1, c3, c4, d1, d3, d4),
            -det3(a1, a2, a4, c1, c2, c4, d1, d2, d4),
            det3(a1, a2, a3, c1, c2, c3, d1, d2, d3),
        ],
        [
            det3(a2, a3, a4, b2, b3, b4, d2, d3, d4),
            -det3(a1, a3, a4, b1, b3, b4, d1, d3, d4),
            det3(a1, a2, a4, b1, b2, b4, d1, d2, d4),
            -det3(a1, a2, a3, b1, b2, b3, d1, d2, d3),
        ],
        [
            -det3(a2, a3, a4, b2, b3, b4, c2, c3, c4),
            det3(a1, a3, a4, b1, b3, b4, c1, c3, c4),
            -det3(a1, a2, a4, b1, b2, b4, c1, c2, c4),
            det3(a1, a2, a3, b1, b2, b3, c1, c2, c3),
        ],
    ];
    let det = det4(m);
    if det.abs() < 1.0e-8 {
        return identity();
    }
    adj.map(|row| row.map(|x| x / det))
}

/// libvec.c `lib_transform_normal`: `v` times the transpose of `m`.
pub fn transform_normal(v: DVec3, m: &Matrix) -> DVec3 {
    DVec3::new(
        v.x * m[0][0] + v.y * m[0][1] + v.z * m[0][2],
        v.x * m[1][0] + v.y * m[1][1] + v.z * m[1][2],
        v.x * m[2][0] + v.y * m[2][1] + v.z * m[2][2],
    )
}
