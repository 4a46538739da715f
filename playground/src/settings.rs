//! What the page asks for, as JSON, and the scene and render settings it
//! means: the same the command line tools build from
//! [`Settings::command`].

use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::{dialect, Scene};
use nffkit_gen::planegen::Board;
use nffkit_gen::sphereflake::{Floor, Sphereflake};
use nffkit_tracer::filter::FilterKind;
use nffkit_tracer::prepare::PrepareOptions;
use nffkit_tracer::render::RenderSettings;
use nffkit_tracer::sampling::{Sampler, SamplerKind};
use serde::Deserialize;

/// The scene to trace.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SceneChoice {
    /// `planegen --nx N --ny N --rotate R`.
    Board {
        /// Squares per side.
        squares: u32,
        /// Turn in degrees.
        rotate: f64,
    },
    /// `sphereflake --level L --checker 8,8`.
    Sphereflake {
        /// Recursion level.
        level: u32,
    },
    /// A file the user dropped on the page: its name (for the dialect and
    /// messages) and text.
    File {
        /// The file's name.
        name: String,
        /// Its contents.
        text: String,
    },
}

/// The page's settings.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// The scene.
    pub scene: SceneChoice,
    /// Sample pattern (by its command-line name in the JSON).
    #[serde(deserialize_with = "sampler_named")]
    pub sampler: SamplerKind,
    /// Samples per pixel asked for.
    pub spp: u32,
    /// Reconstruction filter (by its command-line name in the JSON).
    #[serde(deserialize_with = "filter_named")]
    pub filter: FilterKind,
    /// Seed of the random patterns.
    pub seed: u32,
    /// Side of each light's square (0: point lights).
    pub light_size: f32,
    /// Lens radius (0: pinhole; `None`: the scene's own, a P3F file's lens).
    pub aperture: Option<f32>,
    /// Focus distance (`None`: the distance to the view's `at`).
    pub focus: Option<f32>,
    /// Image size in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

/// The largest image the page may ask for, per side.
pub const MAX_SIDE: u32 = 2048;
/// The most samples per pixel.
pub const MAX_SPP: u32 = 4096;
/// The deepest sphereflake (820,000 spheres: a browser's memory).
pub const MAX_LEVEL: u32 = 6;
/// The most squares per side of the board.
pub const MAX_SQUARES: u32 = 512;
/// The largest dropped file.
pub const MAX_FILE: usize = 64 << 20;

/// The member of `all` that `name` names, or what the names are.
fn named<T: Copy + Into<&'static str>>(all: &[T], name: &str, what: &str) -> Result<T, String> {
    all.iter().copied().find(|k| (*k).into() == name).ok_or_else(|| {
        let names: Vec<&str> = all.iter().map(|&k| k.into()).collect();
        format!("no {what} `{name}`; expected one of {}", names.join(", "))
    })
}

fn sampler_named<'de, D: serde::Deserializer<'de>>(d: D) -> Result<SamplerKind, D::Error> {
    named(SamplerKind::ALL, &String::deserialize(d)?, "sampler").map_err(serde::de::Error::custom)
}

fn filter_named<'de, D: serde::Deserializer<'de>>(d: D) -> Result<FilterKind, D::Error> {
    named(FilterKind::ALL, &String::deserialize(d)?, "filter").map_err(serde::de::Error::custom)
}

impl Settings {
    /// Parse and check the page's JSON.
    pub fn from_json(text: &str) -> Result<Settings, String> {
        let s: Settings = serde_json::from_str(text).map_err(|e| format!("bad settings: {e}"))?;
        s.check()?;
        Ok(s)
    }

    fn check(&self) -> Result<(), String> {
        if !(1..=MAX_SPP).contains(&self.spp) {
            return Err(format!("samples per pixel from 1 to {MAX_SPP} (got {})", self.spp));
        }
        if !(1..=MAX_SIDE).contains(&self.width) || !(1..=MAX_SIDE).contains(&self.height) {
            return Err(format!(
                "image sides from 1 to {MAX_SIDE} pixels (got {}x{})",
                self.width, self.height
            ));
        }
        if !(self.light_size >= 0.0 && self.light_size.is_finite()) {
            return Err(format!("the light size must be 0 or more (got {})", self.light_size));
        }
        if self.aperture.is_some_and(|a| !(a >= 0.0 && a.is_finite())) {
            return Err("the aperture must be 0 or more".into());
        }
        if self.focus.is_some_and(|f| !(f > 0.0 && f.is_finite())) {
            return Err("the focus distance must be positive".into());
        }
        match &self.scene {
            SceneChoice::Board { squares, rotate }
                if !(1..=MAX_SQUARES).contains(squares) || !rotate.is_finite() =>
            {
                return Err(format!("a board of 1 to {MAX_SQUARES} squares a side, turned a finite angle"));
            }
            SceneChoice::Sphereflake { level } if *level > MAX_LEVEL => {
                return Err(format!("sphereflake levels from 0 to {MAX_LEVEL} here (got {level})"));
            }
            SceneChoice::File { text, .. } if text.len() > MAX_FILE => {
                return Err(format!("files up to {} MB here", MAX_FILE >> 20));
            }
            _ => {}
        }
        Ok(())
    }

    /// The scene, as the generators or the reader make it (a file's
    /// warnings are not shown; its errors are, with line and column).
    pub fn scene(&self) -> Result<Scene, String> {
        Ok(match &self.scene {
            SceneChoice::Board { squares, rotate } => {
                Board { nx: *squares, ny: *squares, rotate: *rotate, ..Default::default() }.scene()
            }
            SceneChoice::Sphereflake { level } => Sphereflake::at(*level, Floor::Checker(8, 8)).scene(),
            SceneChoice::File { name, text } => {
                let dialect = dialect::detect(std::path::Path::new(name), text.as_bytes(), None);
                let opts = ParseOptions { dialect, ..Default::default() };
                nff::parse(text.as_bytes(), &opts).map_err(|e| format!("{name}: {e}"))?.scene
            }
        })
    }

    /// How to prepare the scene: `render`'s defaults with the page's size
    /// and lens.
    pub fn prepare_options(&self) -> PrepareOptions {
        PrepareOptions {
            width: Some(self.width),
            height: Some(self.height),
            aperture: self.aperture,
            focus: self.focus,
            ..Default::default()
        }
    }

    /// How to render: `render`'s defaults with a named sampler (so one
    /// sample is jittered like the rest, not the pixel centre).
    pub fn render_settings(&self) -> RenderSettings {
        let mut s = RenderSettings {
            sampler: Sampler::new(self.sampler, self.spp, self.seed).0,
            centre_single_sample: false,
            filter: self.filter,
            ..Default::default()
        };
        s.shade.light_size = self.light_size;
        s
    }

    /// The shell command that renders the same image (a dropped file is
    /// named as `SCENE`).
    pub fn command(&self) -> String {
        let source = match &self.scene {
            SceneChoice::Board { squares, rotate } => {
                format!("planegen --nx {squares} --ny {squares} --rotate {rotate} | render -")
            }
            SceneChoice::Sphereflake { level } => {
                format!("sphereflake --level {level} --checker 8,8 | render -")
            }
            SceneChoice::File { name, .. } => format!("render {}", shell_word(name)),
        };
        let mut c = format!(
            "{source} --width {} --height {} --sampler {} --spp {} --filter {} --seed {}",
            self.width, self.height, self.sampler, self.spp, self.filter, self.seed
        );
        if self.light_size > 0.0 {
            c += &format!(" --light-size {}", self.light_size);
        }
        if let Some(a) = self.aperture {
            c += &format!(" --aperture {a}");
        }
        if let Some(f) = self.focus {
            c += &format!(" --focus {f}");
        }
        c + " -o playground.png"
    }
}

/// `s` quoted for a POSIX shell where it needs it.
fn shell_word(s: &str) -> String {
    if !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || "._-/+".contains(c)) {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Session;
    use nffkit_tracer::prepare::prepare;
    use nffkit_tracer::render::render;

    fn json(scene: &str, extra: &str) -> String {
        format!(
            "{{\"scene\":{scene},\"sampler\":\"cmj\",\"spp\":4,\"filter\":\"tent\",\"seed\":2,\"light_size\":0.5,\
             \"aperture\":null,\"focus\":null,\"width\":40,\"height\":30{extra}}}"
        )
    }

    #[test]
    fn a_session_ends_on_renders_image_and_names_its_command() {
        let s = Settings::from_json(&json("{\"kind\":\"board\",\"squares\":8,\"rotate\":20}", "")).unwrap();
        assert_eq!(
            s.command(),
            "planegen --nx 8 --ny 8 --rotate 20 | render - --width 40 --height 30 --sampler cmj --spp 4 \
             --filter tent --seed 2 --light-size 0.5 -o playground.png"
        );
        let want = render(
            &prepare(&s.scene().unwrap(), &s.prepare_options()).unwrap(),
            &s.render_settings(),
            &|_, _| {},
        );
        let mut session = Session::new(&s, 10, 20).unwrap();
        while session.pass() < session.total() {}
        let got = session.pixels().to_vec();
        let rows: Vec<f32> = want.film.pixels[10 * 40..20 * 40].iter().flat_map(|p| p.to_array()).collect();
        assert_eq!(got, rows);
        assert_eq!(session.pattern(3, 4).len(), 8);
    }

    #[test]
    fn bad_settings_and_files_say_what_is_wrong() {
        let e = |scene: &str, extra: &str| Settings::from_json(&json(scene, extra)).unwrap_err();
        assert!(e("{\"kind\":\"board\",\"squares\":0,\"rotate\":0}", "").contains("1 to 512"));
        assert!(e("{\"kind\":\"sphereflake\",\"level\":9}", "").contains("levels from 0 to 6"));
        assert!(e("{\"kind\":\"board\",\"squares\":4,\"rotate\":0}", ",\"colour\":1").contains("colour"));
        let bad = Settings::from_json(&json(
            "{\"kind\":\"file\",\"name\":\"a b.nff\",\"text\":\"v\\nfrom 0 0\\n\"}",
            "",
        ))
        .unwrap();
        let err = Session::new(&bad, 0, 30).err().unwrap();
        assert!(err.starts_with("a b.nff: line 2, column 9: unexpected end of file"), "{err}");
        assert!(bad.command().starts_with("render 'a b.nff' "));
        let sampler = json("{\"kind\":\"board\",\"squares\":4,\"rotate\":0}", "").replace("cmj", "halton");
        assert!(Settings::from_json(&sampler)
            .unwrap_err()
            .contains("no sampler `halton`; expected one of random"));
    }
}
