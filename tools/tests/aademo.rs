//! The anti-aliasing demo at small size: stratified and low-discrepancy
//! samplers beat random at 16 spp on the checkerboard, and the sheet, table
//! and plot hold every case.

use nffkit_tools::aademo::{contact_sheet, convergence_svg, run, table, DemoConfig};
use nffkit_tracer::sampling::SamplerKind;

#[test]
fn stratified_samplers_beat_random_at_16_spp() {
    let cfg = DemoConfig { size: 48, spps: vec![4, 16], reference_spp: 256, ..Default::default() };
    let result = run(&cfg, &|_| {}).unwrap();
    let err = |k: SamplerKind| result.tiles.iter().find(|t| t.kind == k && t.spp == 16).unwrap().rmse;
    let random = err(SamplerKind::Random);
    for k in [
        SamplerKind::MultiJittered,
        SamplerKind::CorrelatedMultiJittered,
        SamplerKind::Hammersley,
        SamplerKind::Sobol,
        SamplerKind::Jittered,
    ] {
        assert!(err(k) < random, "{k}: {} vs random {random}", err(k));
    }
    let sheet = contact_sheet(&result, &cfg);
    assert_eq!(sheet.width, 3 * (48 + 4) + 4);
    let t = table(&result, &cfg);
    assert_eq!(t.lines().count(), 2 + SamplerKind::ALL.len());
    let svg = convergence_svg(&result, &cfg);
    assert_eq!(svg.matches("<polyline").count(), SamplerKind::ALL.len());
}
