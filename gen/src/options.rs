//! Option values as the generators' flags take them (`X,Y`, `R,G,B`,
//! `W,H`), and options parsed from a list of words, so each generator's
//! `Default` is what its flags declare. The binaries share these parsers.

use anyhow::Result;
use glam::{DVec2, DVec3};

fn numbers(s: &str, n: usize) -> Result<Vec<f64>, String> {
    let v: Result<Vec<f64>, _> = s.split(',').map(|p| p.trim().parse::<f64>()).collect();
    match v {
        Ok(v) if v.len() == n && v.iter().all(|x| x.is_finite()) => Ok(v),
        _ => Err(format!("expected {n} comma-separated numbers, found `{s}`")),
    }
}

/// Options `T` (a struct deriving `clap::Args`) from `args`, as its
/// binary's command line would give them (without the program name): how
/// the golden catalogue states a generator's options, and how a generator's
/// `Default` takes the defaults its flags declare.
pub fn parse_args<T, I, S>(args: I) -> Result<T>
where
    T: clap::Args + clap::FromArgMatches,
    I: IntoIterator<Item = S>,
    S: Into<std::ffi::OsString> + Clone,
{
    let command = T::augment_args(clap::Command::new("options").no_binary_name(true));
    let matches = command.try_get_matches_from(args)?;
    Ok(T::from_arg_matches(&matches)?)
}

/// `R,G,B` or `X,Y,Z`.
pub fn parse_triple(s: &str) -> Result<DVec3, String> {
    numbers(s, 3).map(|v| DVec3::new(v[0], v[1], v[2]))
}

/// `X,Y`.
pub fn parse_pair(s: &str) -> Result<DVec2, String> {
    numbers(s, 2).map(|v| DVec2::new(v[0], v[1]))
}

/// `W,H` as two positive whole numbers.
pub fn parse_resolution(s: &str) -> Result<[u32; 2], String> {
    two_counts(s, "W,H")
}

/// `NX,NY` (squares across and down) as two positive whole numbers.
pub fn parse_squares(s: &str) -> Result<[u32; 2], String> {
    two_counts(s, "NX,NY")
}

fn two_counts(s: &str, form: &str) -> Result<[u32; 2], String> {
    let parts: Vec<&str> = s.split(',').collect();
    let parsed: Vec<u32> = parts.iter().filter_map(|p| p.trim().parse::<u32>().ok()).collect();
    match parsed[..] {
        [w, h] if parts.len() == 2 && w > 0 && h > 0 && w <= 65536 && h <= 65536 => Ok([w, h]),
        _ => Err(format!("expected two whole numbers from 1 to 65536 as {form}, found `{s}`")),
    }
}
