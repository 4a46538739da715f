//! No acceleration: every ray tests every primitive. The reference the other
//! structures are checked against, and the baseline of the P3D report's Table 1.

use super::{test_prim, Intersector, Query, Tracer};
use crate::geometry::{Geometry, Hit};
use crate::math::RayQuery;

/// Brute force.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct BruteForce;

impl Intersector for BruteForce {
    type Scratch = ();

    fn scratch(&self, _: &Geometry) {}

    fn trace_bounded<Q: Query>(
        tr: &mut Tracer<'_, Self>,
        q: &RayQuery,
        t_max: f32,
        mut best: Option<Hit>,
    ) -> Option<Hit> {
        let geom = tr.geom;
        for id in 0..geom.bounded_len() as u32 {
            if test_prim::<Q>(geom, id, q, &mut best, t_max, &mut tr.counters) {
                break;
            }
        }
        best
    }
}
