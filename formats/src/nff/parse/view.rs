//! The `v` block: its lines read in any order, every error in it
//! reported, and its values checked (a view direction, an `up` off it,
//! numbers the renderer's single precision holds), with the cause named
//! where a length overflows or underflows. A P3F view ends with two more
//! lines, `aperture` and `focal` (the lens).

use super::{is_recovery_point, Entity, Parser, Res, What, MAX_RESOLUTION, NFF_VIEW_LINES, VIEW_KEYWORDS};
use crate::nff::diag::{Diagnostic, Severity};
use crate::nff::lexer::Token;
use crate::scene::{Dialect, Lens, View, MAX_COORDINATE};
use glam::DVec3;

/// The values of a view block as they are read.
#[derive(Default)]
struct ViewValues {
    /// from, at, up.
    vecs: [DVec3; 3],
    angle: f64,
    hither: f64,
    res: [u32; 2],
    /// P3F's aperture and focal ratio.
    lens: [f64; 2],
}

/// Index of `aperture` in [`VIEW_KEYWORDS`].
const APERTURE: usize = 6;

impl<'a> Parser<'a> {
    /// The `v` block. Every error in it is reported: a broken line is
    /// skipped up to the next view keyword, a missing line is reported where
    /// it was expected, and the values are checked as far as they were read.
    pub(super) fn view(&mut self, t: Token<'a>, e: Entity) -> Res<()> {
        self.view_seen = true;
        if self.scene.view.is_some() {
            self.warn(&t, "second view (`v`); it replaces the first".into());
        }
        self.warn_if_after_objects(&t, "view");
        let mut seen: [Option<Token<'a>>; 8] = [None; 8];
        let mut ok = [false; 8];
        let mut v = ViewValues { lens: [0.0, 1.0], ..ViewValues::default() };
        let mut errors = Vec::new();
        let p3f = self.opts.dialect == Dialect::P3f;
        let lines = if p3f { &VIEW_KEYWORDS[..] } else { &VIEW_KEYWORDS[..NFF_VIEW_LINES] };
        while let Some(k) = self.peek() {
            let Some(i) = lines.iter().position(|w| *w == k.text) else { break };
            self.bump();
            if seen[i].is_some() {
                self.warn(&k, format!("`{}` given twice in one view; the last one counts", k.display()));
            }
            seen[i] = Some(k);
            match self.view_line(i, e, &mut v) {
                Ok(()) => ok[i] = true,
                Err(d) => {
                    errors.push(d);
                    while let Some(n) = self.peek() {
                        if lines.contains(&n.text) || is_recovery_point(&n) {
                            break;
                        }
                        self.bump();
                    }
                }
            }
        }
        for i in (0..NFF_VIEW_LINES).filter(|&i| seen[i].is_none() && i != 4) {
            errors.push(self.missing_view_line(i, &seen));
        }
        if seen[4].is_none() {
            self.warn(&t, "the view has no `hither` line; using 0".into());
        }
        let lens = p3f.then(|| self.lens_lines(&t, &seen, &ok, &mut errors, v.lens)).flatten();
        errors.extend(self.check_view(&seen, &ok, &mut v));
        let Some(last) = errors.pop() else {
            let ViewValues { vecs: [from, at, up], angle, hither, res, .. } = v;
            self.scene.view = Some(View { from, at, up, angle, hither, resolution: res, lens });
            return Ok(());
        };
        for d in errors {
            self.push_error(d);
        }
        Err(last)
    }

    /// The values after view keyword `i`.
    fn view_line(&mut self, i: usize, e: Entity, v: &mut ViewValues) -> Res<()> {
        match i {
            0..=2 => {
                let what = ["a `from` coordinate", "an `at` coordinate", "an `up` coordinate"][i];
                v.vecs[i] = self.vec3(What::Text(what), e)?;
            }
            3 => v.angle = self.number(What::Text("the field of view angle in degrees"), e)?,
            4 => v.hither = self.number(What::Text("the hither distance"), e)?,
            6 => {
                v.lens[0] = self.number(What::Text("the lens aperture (a multiple of the pixel size)"), e)?
            }
            7 => {
                v.lens[1] =
                    self.number(What::Text("the focal distance (a multiple of the view-plane distance)"), e)?
            }
            _ => {
                for r in &mut v.res {
                    *r = self.count("a resolution in pixels", 1, MAX_RESOLUTION, e)?.0 as u32;
                }
            }
        }
        Ok(())
    }

    /// "expected `at`, found `up`": at the next view line present, or at
    /// whatever follows the block.
    fn missing_view_line(&mut self, i: usize, seen: &[Option<Token<'a>>; 8]) -> Diagnostic {
        let kw = String::from_utf8_lossy(VIEW_KEYWORDS[i]);
        let note = Some(
            "a view is: v, from x y z, at x y z, up x y z, angle deg, hither d, resolution w h".to_string(),
        );
        let found = seen[i + 1..NFF_VIEW_LINES].iter().flatten().next().copied().or_else(|| self.peek());
        match found {
            Some(f) => {
                let mut d =
                    self.error_at(&f, format!("expected the view's `{kw}` line, found `{}`", f.display()));
                d.note = note;
                d
            }
            None => Diagnostic {
                severity: Severity::Error,
                line: self.eof().0,
                column: self.eof().1,
                width: 1,
                message: format!("unexpected end of file: expected the view's `{kw}` line"),
                note,
            },
        }
    }

    /// P3F's lens from its `aperture` and `focal` lines (`[aperture,
    /// focal]` as read, or their defaults 0 and 1): checked, and `None`
    /// (a pinhole) when the view has neither, with a warning, as the
    /// course's reader expects both.
    fn lens_lines(
        &mut self,
        t: &Token<'a>,
        seen: &[Option<Token<'a>>; 8],
        ok: &[bool; 8],
        errors: &mut Vec<Diagnostic>,
        [aperture, focal]: [f64; 2],
    ) -> Option<Lens> {
        let (a, f) = (seen[APERTURE], seen[APERTURE + 1]);
        if a.is_none() || f.is_none() {
            let missing = match (a, f) {
                (None, None) => "`aperture` and `focal` lines",
                (None, _) => "`aperture` line (using 0, a pinhole)",
                _ => "`focal` line (using 1, focus on `at`)",
            };
            self.warn(t, format!("the view has no {missing}; the course's view ends with both"));
            if a.is_none() && f.is_none() {
                return None;
            }
        }
        if let (Some(at), true) = (a, ok[APERTURE]) {
            if aperture < 0.0 {
                errors.push(self.error_at(&at, format!("`aperture` must not be negative, found {aperture}")));
            }
        }
        if let (Some(at), true) = (f, ok[APERTURE + 1]) {
            if focal <= 0.0 {
                errors.push(self.error_at(&at, format!("`focal` must be greater than 0, found {focal}")));
            }
        }
        Some(Lens { aperture, focal })
    }

    /// The checks on the view's values, each run when the lines it needs
    /// were read.
    fn check_view(
        &mut self,
        seen: &[Option<Token<'a>>; 8],
        ok: &[bool; 8],
        v: &mut ViewValues,
    ) -> Vec<Diagnostic> {
        let mut errors = Vec::new();
        let mut usable = *ok;
        for (i, vec) in v.vecs.iter().enumerate().filter(|&(i, _)| ok[i]) {
            if let Some(x) = vec.to_array().into_iter().find(|x| x.abs() > MAX_COORDINATE) {
                let tok = seen[i].expect("a line read is a line seen");
                errors.push(self.error_at(
                    &tok,
                    format!(
                        "`{}` coordinate {x:e} is beyond what single-precision rendering holds \
                         (at most {MAX_COORDINATE:e})",
                        tok.display(),
                    ),
                ));
                usable[i] = false;
            }
        }
        errors.extend(self.check_view_direction(seen, &usable, v.vecs));
        if ok[3] && !(v.angle > 0.0 && v.angle < 180.0) {
            let angle_tok = seen[3].expect("a line read is a line seen");
            errors.push(self.error_at(
                &angle_tok,
                format!("`angle` must be between 0 and 180 degrees, found {}", v.angle),
            ));
        }
        if ok[4] && v.hither < 0.0 {
            let hither_tok = seen[4].expect("a line read is a line seen");
            self.warn(&hither_tok, format!("negative hither {}; using 0", v.hither));
            v.hither = 0.0;
        }
        errors
    }

    /// The view direction and `up`: a direction at all, and `up` not along
    /// it, with the cause named where a length overflows or underflows.
    fn check_view_direction(
        &self,
        seen: &[Option<Token<'a>>; 8],
        usable: &[bool; 8],
        [from, at, up]: [DVec3; 3],
    ) -> Option<Diagnostic> {
        if !(usable[0] && usable[1]) {
            return None;
        }
        let line = |i: usize| seen[i].expect("a line read is a line seen");
        let dir = at - from;
        if dir == DVec3::ZERO {
            return Some(
                self.error_at(&line(1), "`at` is the same point as `from`: no view direction".into()),
            );
        }
        if !normalizable(dir) {
            return Some(self.error_at(
                &line(1),
                format!(
                    "`at` is only {:e} from `from`: the square of that distance underflows, so it \
                     gives no view direction",
                    length(dir)
                ),
            ));
        }
        if !usable[2] {
            return None;
        }
        let message = if up == DVec3::ZERO {
            "`up` is zero".to_string()
        } else if !normalizable(up) {
            format!(
                "`up` is too short to give a direction: its length, {:e}, is so small that its square underflows \
                 (write it longer, e.g. `up 0 1 0`)",
                length(up)
            )
        } else if up.normalize().cross(dir.normalize()).length() < 1e-9 {
            "`up` is parallel to the view direction (from `from` to `at`)".to_string()
        } else {
            return None;
        };
        Some(self.error_at(&line(2), message))
    }
}

/// Whether `v` has a length whose square is a normal number (so that
/// `normalize` divides by something exact enough).
fn normalizable(v: DVec3) -> bool {
    v.length_squared() >= f64::MIN_POSITIVE
}

/// The length of `v`, without the underflow or overflow of its square.
fn length(v: DVec3) -> f64 {
    let m = v.abs().max_element();
    if m == 0.0 {
        0.0
    } else {
        m * (v / m).length()
    }
}
