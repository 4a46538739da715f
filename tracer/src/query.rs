//! Which hit a ray asks for: the nearest (eye, mirror and refracted rays)
//! or any (shadow rays). Traversals are written once for both, generic over
//! the [`Query`]; see [`crate::accel`].

/// Which hit a traversal looks for.
pub(crate) trait Query {
    /// Any hit ends the search (a shadow ray's blocker); otherwise the
    /// nearest is kept, ties to the lowest id.
    const ANY_HIT: bool;
}

/// The nearest hit: eye, mirror and refracted rays.
pub(crate) enum Nearest {}

/// Any hit: shadow rays.
pub(crate) enum AnyHit {}

impl Query for Nearest {
    const ANY_HIT: bool = false;
}

impl Query for AnyHit {
    const ANY_HIT: bool = true;
}
