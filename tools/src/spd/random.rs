//! The SPD library's random numbers (libvec.c), reproduced exactly: the
//! databases' shapes depend on every bit.

const M1: i64 = 134456;
const IA1: i64 = 8121;
const IC1: i64 = 28411;

/// `lib_gauss_rand`: a normally distributed number from the seed, by the
/// polar method on a linear congruential generator. (The C writes
/// `ix * 2.0 * RM1` with `RM1` a macro `1.0/M1`, so the product is
/// divided by M1, not multiplied by its reciprocal.)
pub fn gauss_rand(seed: i64) -> f64 {
    let mut ix2 = seed;
    loop {
        let ix1 = (IC1 + ix2 * IA1) % M1;
        ix2 = (IC1 + ix1 * IA1) % M1;
        let v1 = ix1 as f64 * 2.0 * 1.0 / M1 as f64 - 1.0;
        let v2 = ix2 as f64 * 2.0 * 1.0 / M1 as f64 - 1.0;
        let r = v1 * v1 + v2 * v2;
        if r < 1.0 {
            return v1 * (-2.0 * r.ln() / r).sqrt();
        }
    }
}
