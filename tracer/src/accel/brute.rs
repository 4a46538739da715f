//! No acceleration: every ray tests every primitive. The reference the other
//! structures are checked against, and the baseline of the P3D report's Table 1.

use super::{test_prim, test_shadow, Intersector};
use crate::geometry::{Geometry, Hit};
use crate::math::RayQuery;
use crate::stats::Counters;

/// Brute force.
#[derive(Debug, Clone, Copy, Default)]
pub struct BruteForce;

impl Intersector for BruteForce {
    type Scratch = ();

    fn scratch(&self, _: &Geometry) {}

    fn intersect_bounded(
        &self,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        _: &mut (),
        c: &mut Counters,
    ) -> Option<Hit> {
        let mut best = None;
        for id in 0..geom.bounded_len() as u32 {
            test_prim(geom, id, q, &mut best, t_max, c);
        }
        best
    }

    fn occluder_bounded(
        &self,
        geom: &Geometry,
        q: &RayQuery,
        t_max: f32,
        _: &mut (),
        c: &mut Counters,
    ) -> Option<u32> {
        (0..geom.bounded_len() as u32).find(|&id| test_shadow(geom, id, q, t_max, c))
    }
}
