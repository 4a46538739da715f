//! Wall time for reports (build and render seconds), where the platform
//! has a clock: `wasm32-unknown-unknown` has none without a JavaScript
//! host's help (`std::time::Instant::now` panics there), so the browser
//! playground's reports read zero and the page times passes itself.

/// Time since [`Stopwatch::start`].
#[derive(Debug, Clone, Copy)]
pub struct Stopwatch {
    #[cfg(not(all(target_arch = "wasm32", target_os = "unknown")))]
    start: std::time::Instant,
}

impl Stopwatch {
    /// Start timing.
    #[inline]
    pub fn start() -> Stopwatch {
        Stopwatch {
            #[cfg(not(all(target_arch = "wasm32", target_os = "unknown")))]
            start: std::time::Instant::now(),
        }
    }

    /// Seconds since the start (0 without a clock).
    #[inline]
    pub fn seconds(&self) -> f64 {
        #[cfg(not(all(target_arch = "wasm32", target_os = "unknown")))]
        return self.start.elapsed().as_secs_f64();
        #[cfg(all(target_arch = "wasm32", target_os = "unknown"))]
        0.0
    }
}
