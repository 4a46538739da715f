//! The anti-aliasing playground's engine: nffkit's tracer behind a small
//! C-style interface that a browser calls through WebAssembly
//! (`wasm32-unknown-unknown`, the tracer's portable lanes). `aademo
//! --playground` writes the page that drives it.
//!
//! The page's settings arrive as JSON ([`Settings`]) and become the very
//! scene and [`RenderSettings`] that `render` builds from the equivalent
//! command line ([`Settings::command`] prints it), so the image after the
//! last pass is `render`'s. Each web worker holds its own instance with a
//! band of rows ([`Session`]); every call to [`pg_pass`] adds one sample to
//! each pixel of the band ([`nffkit_tracer::progressive`]).
//!
//! The interface passes numbers and byte buffers only (no generated glue,
//! so no `wasm-bindgen` version to keep in step): the page asks for memory
//! with [`pg_alloc`], writes the JSON there and calls [`pg_load`]; results
//! are read from linear memory at the address a call returns.

mod session;
mod settings;

pub use session::Session;
pub use settings::{SceneChoice, Settings};

use std::cell::RefCell;

thread_local! {
    /// The instance's session (one per worker) and the last error.
    static STATE: RefCell<(Option<Session>, String)> = const { RefCell::new((None, String::new())) };
}

/// `len` bytes for the page to fill; free with [`pg_free`].
#[no_mangle]
pub extern "C" fn pg_alloc(len: usize) -> *mut u8 {
    let mut v = Vec::<u8>::with_capacity(len.max(1));
    let p = v.as_mut_ptr();
    std::mem::forget(v);
    p
}

/// Give back memory from [`pg_alloc`].
///
/// # Safety
///
/// `ptr` and `len` must be a pair [`pg_alloc`] returned and not yet freed.
#[no_mangle]
pub unsafe extern "C" fn pg_free(ptr: *mut u8, len: usize) {
    drop(Vec::from_raw_parts(ptr, 0, len.max(1)));
}

/// Read the settings (UTF-8 JSON, `len` bytes at `ptr`), build the scene
/// and start a session on rows `y0..y1`. Returns 0, or 1 with the reason
/// in [`pg_error`].
///
/// # Safety
///
/// `ptr` must point at `len` readable bytes.
#[no_mangle]
pub unsafe extern "C" fn pg_load(ptr: *const u8, len: usize, y0: u32, y1: u32) -> u32 {
    let bytes = std::slice::from_raw_parts(ptr, len);
    let result = std::str::from_utf8(bytes)
        .map_err(|e| format!("the settings are not UTF-8: {e}"))
        .and_then(Settings::from_json)
        .and_then(|s| Session::new(&s, y0, y1));
    STATE.with_borrow_mut(|(session, error)| match result {
        Ok(s) => {
            *session = Some(s);
            0
        }
        Err(e) => {
            *session = None;
            *error = e;
            1
        }
    })
}

/// The last error's length; its bytes are at [`pg_error`].
#[no_mangle]
pub extern "C" fn pg_error_len() -> usize {
    STATE.with_borrow(|(_, e)| e.len())
}

/// The last error's UTF-8 bytes.
#[no_mangle]
pub extern "C" fn pg_error() -> *const u8 {
    STATE.with_borrow(|(_, e)| e.as_ptr())
}

fn with_session<T>(default: T, f: impl FnOnce(&mut Session) -> T) -> T {
    STATE.with_borrow_mut(|(s, _)| s.as_mut().map_or(default, f))
}

/// Take one more sample in every pixel of the band; returns the samples
/// per pixel taken so far (0 with no session).
#[no_mangle]
pub extern "C" fn pg_pass() -> u32 {
    with_session(0, |s| s.pass())
}

/// Samples per pixel the settings take in all.
#[no_mangle]
pub extern "C" fn pg_total() -> u32 {
    with_session(0, |s| s.total())
}

/// The band's image so far as linear RGB `f32`s, row by row (3 per pixel);
/// valid until the next call.
#[no_mangle]
pub extern "C" fn pg_pixels() -> *const f32 {
    with_session(std::ptr::null(), |s| s.pixels().as_ptr())
}

/// The band's image so far as 8-bit RGBA for a canvas, quantised as
/// `render` writes its PNGs; valid until the next call.
#[no_mangle]
pub extern "C" fn pg_rgba() -> *const u8 {
    with_session(std::ptr::null(), |s| s.rgba().as_ptr())
}

/// The unit-square positions of pixel (`px`, `py`)'s samples (x, y pairs
/// in sample order, [`pg_total`] of them); valid until the next call.
#[no_mangle]
pub extern "C" fn pg_pattern(px: u32, py: u32) -> *const f32 {
    with_session(std::ptr::null(), |s| s.pattern(px, py).as_ptr())
}

/// The strata of the pattern, for drawing it: `coarse << 16 | fine`
/// cells per side (0: none).
#[no_mangle]
pub extern "C" fn pg_strata() -> u32 {
    with_session(0, |s| s.strata())
}

/// The image's width in pixels.
#[no_mangle]
pub extern "C" fn pg_width() -> u32 {
    with_session(0, |s| s.width())
}

/// The image's height in pixels.
#[no_mangle]
pub extern "C" fn pg_height() -> u32 {
    with_session(0, |s| s.height())
}

/// The length of the command line that renders the same image.
#[no_mangle]
pub extern "C" fn pg_command_len() -> usize {
    with_session(0, |s| s.command().len())
}

/// The command line's UTF-8 bytes.
#[no_mangle]
pub extern "C" fn pg_command() -> *const u8 {
    with_session(std::ptr::null(), |s| s.command().as_ptr())
}
