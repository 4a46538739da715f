// The CPU's double-precision steps, on adapters with f64 arithmetic.

// x / y rounded as the CPU's division rounds it. GPUs may divide by an
// approximate reciprocal (Vulkan allows 2.5 ulp), and an ulp in a
// direction or a distance changes which of two coincident surfaces a ray
// sees; the quotient rounded from f64 is the correctly rounded one but in
// the rarest halfway cases.
fn div(x: f32, y: f32) -> f32 {
    return f32(f64(x) / f64(y));
}

// a·b − c·d of f32 values: the products are exact in f64, so this is the
// CPU's value bit for bit.
fn exact_difference(a: f32, b: f32, c: f32, d: f32) -> f32 {
    return f32(f64(a) * f64(b) - f64(c) * f64(d));
}

// `intersect_cone`'s precision.
alias Real = f64;

// x with b's sign, b's zeros counted positive.
fn with_sign_of(x: f64, b: f64) -> f64 {
    return select(-x, x, b >= 0.0lf);
}
