//! Quality checks: golden-image regression over the scene catalogue
//! ([`golden`]) and the image metrics it and the demo use ([`metrics`]).

pub mod golden;
pub mod metrics;
