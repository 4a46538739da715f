// The CPU's double-precision steps in single precision, on adapters
// without f64 arithmetic: triangles' exact edge hits go by the f32 edge
// functions, and shadow rays leaving a cone may see it again (speckles of
// self-shadowing, which the CPU's f64 avoids).

fn div(x: f32, y: f32) -> f32 {
    return x / y;
}

fn exact_difference(a: f32, b: f32, c: f32, d: f32) -> f32 {
    return a * b - c * d;
}

// `intersect_cone`'s precision.
alias Real = f32;

// x with b's sign, as the CPU's `copysign`.
fn with_sign_of(x: f32, b: f32) -> f32 {
    return copysign(x, b);
}
