//! Sample patterns drawn as the literature draws them: the points of one
//! pixel in the unit square, over the strata the pattern guarantees. A
//! jittered pattern has one point per cell of its √n x √n grid; n-rooks has
//! one per row and per column of an n x n board (the P3D report's chess
//! rooks); multi-jittered has both, so it is drawn with the √n x √n grid
//! and, finer, its n x n sub-grid (the report's §4.1). Hammersley and Sobol
//! at powers of two are (0, m, 2)-nets, which include the n-rooks property.
//!
//! The SVG's user space is the unit square itself (y down, as in the image),
//! so each `<circle class="sample">` holds a sample's coordinates exactly.

use nffkit_tracer::sampling::{Sampler, SamplerKind};
use std::fmt::Write as _;

/// The `n` sample positions of pixel (0, 0), dimension 0, in [0, 1)².
pub fn points(kind: SamplerKind, n: u32, seed: u32) -> Vec<[f32; 2]> {
    let sampler = Sampler::new(kind, n, seed).0;
    (0..sampler.spp).map(|i| sampler.sample(0, 0, i, 0).to_array()).collect()
}

/// The pattern as a standalone SVG of `px` pixels square: strata lines at
/// a fixed on-screen width, dots sized to fit inside their cells, and one
/// sample (the first) highlighted with the row and column of the finest
/// strata it occupies (or its cell, for a grid of cells only), which no
/// other sample shares.
pub fn svg(kind: SamplerKind, n: u32, seed: u32, px: u32) -> String {
    let pts = points(kind, n, seed);
    let count = pts.len() as u32;
    let (coarse, fine) = kind.strata(count);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{px}\" height=\"{px}\" viewBox=\"-0.03 -0.03 1.06 1.06\">\n\
         <title>{kind}, {count} samples</title>\n\
         <rect x=\"0\" y=\"0\" width=\"1\" height=\"1\" fill=\"white\"/>\n"
    );
    // The highlighted sample's row and column (fine strata) or cell.
    if let Some(&[x, y]) = pts.first() {
        let band = |cells: u32, v: f32| (v * cells as f32).floor() / cells as f32;
        if fine > 0 {
            let c = 1.0 / fine as f32;
            let _ = writeln!(
                s,
                "<rect class=\"row\" x=\"0\" y=\"{}\" width=\"1\" height=\"{c}\" fill=\"#ffe08a\"/>\n\
                 <rect class=\"column\" x=\"{}\" y=\"0\" width=\"{c}\" height=\"1\" fill=\"#ffe08a\"/>",
                band(fine, y),
                band(fine, x)
            );
        }
        if coarse > 0 {
            let c = 1.0 / coarse as f32;
            let _ = writeln!(
                s,
                "<rect class=\"cell\" x=\"{}\" y=\"{}\" width=\"{c}\" height=\"{c}\" fill=\"#ffc04d\" fill-opacity=\"0.6\"/>",
                band(coarse, x),
                band(coarse, y)
            );
        }
    }
    for (cells, class, width, colour) in [(fine, "fine", 1.0, "#9fb4d8"), (coarse, "coarse", 2.0, "#2f4f8a")]
    {
        for k in 1..cells {
            let v = k as f64 / cells as f64;
            let _ = writeln!(
                s,
                "<path class=\"{class}\" d=\"M{v} 0V1M0 {v}H1\" stroke=\"{colour}\" stroke-width=\"{width}\" vector-effect=\"non-scaling-stroke\"/>"
            );
        }
    }
    s += "<rect x=\"0\" y=\"0\" width=\"1\" height=\"1\" fill=\"none\" stroke=\"black\" stroke-width=\"2\" vector-effect=\"non-scaling-stroke\"/>\n";
    // Radius: a third of the finest cell's side, so dots stay inside it.
    let cell = 1.0 / (if fine > 0 { fine } else { coarse.max(1) * 2 }).max(4) as f64;
    let r = (cell / 3.0).clamp(0.004, 0.02);
    for (i, [x, y]) in pts.iter().enumerate() {
        let (class, fill) = if i == 0 { ("sample first", "#d62728") } else { ("sample", "#1f3b73") };
        let rr = if i == 0 { r * 1.4 } else { r };
        let _ =
            writeln!(s, "<circle class=\"{class}\" cx=\"{x}\" cy=\"{y}\" r=\"{rr:.4}\" fill=\"{fill}\"/>");
    }
    s += "</svg>\n";
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multi_jittered_has_one_point_per_row_column_and_cell() {
        for n in [16u32, 64] {
            let pts = points(SamplerKind::MultiJittered, n, 1);
            let root = (n as f64).sqrt() as u32;
            let mut rows = vec![0; n as usize];
            let mut cells = vec![0; n as usize];
            for [x, y] in pts {
                rows[(y * n as f32) as usize] += 1;
                cells[((y * root as f32) as u32 * root + (x * root as f32) as u32) as usize] += 1;
            }
            assert!(rows.iter().chain(&cells).all(|&c| c == 1));
        }
    }
}
