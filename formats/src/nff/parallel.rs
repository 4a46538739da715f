//! Reading a large file on every core: the file is cut into chunks at lines
//! that start an entity (`s`, `p`, `pp`, `c`, `f`, `l`, `b`, `v`, the
//! reader's own keyword list: a line starting with one of these words can only begin an entity, since numbers
//! never start with a letter and comments start with `#`), each chunk is
//! read on its own thread as a fragment, and the parts are joined.
//!
//! What a chunk cannot know is what came before it: the current material,
//! whether objects were already seen, and the line it starts on. Materials
//! are renumbered at the join (a primitive before its chunk's first `f`
//! takes the previous chunk's last material), and lines moved on by the
//! line breaks of the chunks before (each chunk's lexer counts its own as
//! it reads). Everything that would make the reader *say* something
//! that depends on earlier chunks (a light or view after the first object,
//! a second view, a second `env`, `spp` or `accel`, no view at all), and
//! any diagnostic at all, sends the file back to the sequential reader, so
//! the result and the diagnostics are always exactly those of reading it
//! in one piece. P3F's `mesh` is never cut: its lines hold only numbers.

use super::parse::{parse_chunk, primitives_hint, ParseOptions, Parsed, ENTITY_KEYWORDS};
use crate::scene::Scene;
use rayon::prelude::*;

/// Files at least this large are read in parallel.
pub const PARALLEL_MIN_BYTES: usize = 1 << 20;
/// Smallest chunk worth a thread.
const MIN_CHUNK: usize = 512 << 10;

/// Chunks for a file of `len` bytes: one per core, at least 512 KB each.
pub fn default_chunks(len: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    cores.min(len / MIN_CHUNK).max(1)
}

/// Read `src` in `chunks` pieces on as many threads; `None` when the pieces
/// cannot be joined into exactly what the sequential reader gives (then the
/// caller reads the file in one piece).
pub(super) fn parse_in_chunks(src: &[u8], opts: &ParseOptions, chunks: usize) -> Option<Parsed> {
    let starts = split_points(src, chunks);
    if starts.len() < 2 {
        return None;
    }
    let ends = starts.iter().skip(1).copied().chain(std::iter::once(src.len()));
    let pieces: Vec<&[u8]> = starts.iter().zip(ends).map(|(&a, b)| &src[a..b]).collect();
    let parts: Vec<Part> = std::thread::scope(|scope| {
        let handles: Vec<_> = pieces
            .iter()
            .enumerate()
            .map(|(i, &piece)| {
                // The first chunk's list becomes the whole file's (see
                // `join`), so it is given room for all of it.
                let room = primitives_hint(piece, if i == 0 { src.len() } else { piece.len() });
                scope.spawn(move || {
                    // Read as if it began the file; `join` moves its lines
                    // on by the lines of the chunks before it.
                    let (scene, diags, lines) = parse_chunk(piece, opts, room);
                    Part { scene, quiet: diags.is_empty(), lines }
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap_or_else(|_| Part::failed())).collect()
    });
    join(parts, opts)
}

/// A chunk read on its own, as if it began the file.
struct Part {
    scene: Scene,
    /// Whether the reader said nothing about it.
    quiet: bool,
    /// The line breaks in it (the chunk after it starts that many lines
    /// on), counted when it is quiet.
    lines: u32,
}

impl Part {
    /// A chunk whose reading failed: the join gives up on it.
    fn failed() -> Part {
        Part { scene: Scene::default(), quiet: false, lines: 0 }
    }
}

/// Byte offsets where chunks start: 0, then one near each `len/chunks`
/// mark, at the start of a line whose first word is an entity keyword.
fn split_points(src: &[u8], chunks: usize) -> Vec<usize> {
    let mut starts = vec![0];
    for k in 1..chunks {
        let target = src.len() * k / chunks;
        if let Some(at) = next_entity_line(src, target.max(*starts.last().unwrap_or(&0) + 1)) {
            if at > *starts.last().unwrap_or(&0) {
                starts.push(at);
            }
        }
    }
    starts
}

/// The first line at or after `from` that starts with an NFF entity keyword
/// (the course extensions are left out: their notes would send the file
/// back to the sequential reader anyway) followed by a space or tab.
fn next_entity_line(src: &[u8], from: usize) -> Option<usize> {
    let mut i = from;
    while i < src.len() {
        let nl = i + src[i..].iter().position(|&b| b == b'\n')?;
        let line = &src[nl + 1..];
        let word_end = line.iter().position(|&b| b == b' ' || b == b'\t').unwrap_or(0);
        if word_end > 0 && ENTITY_KEYWORDS.iter().any(|k| k.as_bytes() == &line[..word_end]) {
            return Some(nl + 1);
        }
        i = nl + 1;
    }
    None
}

/// Join chunk scenes in order, or `None` if the sequential reader would
/// have said something the chunks could not (module doc), or the joined
/// list cannot be had (the sequential reader then grows its own).
fn join(parts: Vec<Part>, opts: &ParseOptions) -> Option<Parsed> {
    let total = parts.iter().map(|p| p.scene.primitives.len()).sum::<usize>();
    let mut parts = parts.into_iter();
    // The first chunk is the scene so far (its materials need no
    // renumbering, its lines are the file's); its list grows in place to
    // hold every primitive, so the join copies only the later chunks, each
    // once.
    let Part { mut scene, quiet, lines } = parts.next()?;
    if !quiet {
        return None;
    }
    // Lines before the chunk being joined.
    let mut before = lines;
    if scene.primitives.try_reserve_exact(total - scene.primitives.len()).is_err() {
        return None;
    }
    for Part { scene: part, quiet, lines } in parts {
        let objects_before = !scene.primitives.is_empty();
        if !quiet
            || (part.view.is_some() && (scene.view.is_some() || objects_before))
            || (!part.lights.is_empty() && objects_before)
            || (part.environment.is_some() && scene.environment.is_some())
            || (part.directives.spp.is_some() && scene.directives.spp.is_some())
            || (part.directives.accel.is_some() && scene.directives.accel.is_some())
        {
            return None;
        }
        let offset = scene.materials.len() as u32;
        let inherited = offset.checked_sub(1);
        // (Lines past 2^32 are left to the sequential reader.)
        let after = before.checked_add(lines)?;
        before.checked_add(part.primitives.last().map_or(0, |p| p.line.0))?;
        // Copied on every core: the copy's cost is mostly the kernel
        // handing out fresh pages, which both cores can do at once.
        scene.primitives.par_extend(part.primitives.into_par_iter().map(|mut p| {
            p.material = p.material.map(|m| m + offset).or(inherited);
            p.line.0 += before;
            p
        }));
        before = after;
        // (The part's own list is freed here, before the next is copied.)
        scene.materials.extend(part.materials);
        scene.lights.extend(part.lights);
        scene.background = part.background.or(scene.background);
        scene.view = part.view.or(scene.view);
        scene.environment = part.environment.or(scene.environment);
        scene.directives.spp = part.directives.spp.or(scene.directives.spp);
        scene.directives.accel = part.directives.accel.or(scene.directives.accel);
    }
    if scene.view.is_none() && !opts.fragment {
        return None;
    }
    Some(Parsed { scene, diagnostics: Vec::new() })
}
