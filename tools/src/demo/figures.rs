//! The P3D report's figures 4 to 8, rebuilt from this project's own
//! generators and renderer: the plane generator's checkerboard without and
//! with 8x8 anti-aliasing, hard and soft shadows, and depth of field. Each
//! figure is rendered from the very `render` arguments printed under it
//! (parsed by [`crate::render::args`]), so the command on the page is the one
//! that made the picture.

use crate::gen::planegen::Board;
use crate::gen::sphereflake::{Floor, Sphereflake};
use crate::render::args::render_config_from;
use anyhow::{Context, Result};
use nffkit_formats::image_io::RgbImage;
use nffkit_formats::Scene;
use nffkit_tracer::prepare::prepare;
use nffkit_tracer::render::render;
use rayon::prelude::*;

/// One figure of the report.
pub struct Figure {
    /// The report's figure number.
    pub number: u32,
    /// The report's caption.
    pub caption: &'static str,
    /// The generator command that makes the scene.
    pub generator: &'static str,
    /// The `render` arguments (after `-`, the scene on standard input).
    pub render: &'static [&'static str],
}

impl Figure {
    /// The shell command that makes the figure.
    pub fn command(&self) -> String {
        format!("{} | render - {} -o fig{}.png", self.generator, self.render.join(" "), self.number)
    }

    fn scene(&self) -> Scene {
        if self.generator.starts_with("planegen") {
            Board { nx: 16, ny: 16, ..Default::default() }.scene()
        } else {
            Sphereflake::at(3, Floor::Checker(8, 8)).scene()
        }
    }
}

/// Figures 4 to 8 of the P3D report.
pub const FIGURES: [Figure; 5] = [
    Figure {
        number: 4,
        caption: "Plane generator scene with no anti-aliasing",
        generator: "planegen --nx 16 --ny 16",
        render: &["--width", "256", "--height", "256"],
    },
    Figure {
        number: 5,
        caption: "Plane generator scene with an 8x8 anti-aliasing",
        generator: "planegen --nx 16 --ny 16",
        render: &["--width", "256", "--height", "256", "--spp", "64", "--sampler", "multi-jittered"],
    },
    Figure {
        number: 6,
        caption: "Hard shadows",
        generator: "sphereflake --level 3 --checker 8,8",
        render: &["--width", "256", "--height", "256", "--spp", "4"],
    },
    Figure {
        number: 7,
        caption: "Soft shadows",
        generator: "sphereflake --level 3 --checker 8,8",
        render: &[
            "--width",
            "256",
            "--height",
            "256",
            "--spp",
            "16",
            "--light-size",
            "1",
            "--light-shape",
            "disk",
        ],
    },
    Figure {
        number: 8,
        caption: "Depth of field example",
        generator: "sphereflake --level 3 --checker 8,8",
        render: &["--width", "256", "--height", "256", "--spp", "64", "--aperture", "0.08", "--focus", "2.6"],
    },
];

/// Render every figure, in parallel; `tick` after each.
pub fn render_all(tick: &(dyn Fn() + Sync)) -> Result<Vec<RgbImage>> {
    FIGURES
        .par_iter()
        .map(|f| {
            let config = render_config_from(f.render.iter().copied())
                .with_context(|| format!("figure {}: bad render arguments", f.number))?;
            let prepared = prepare(&f.scene(), &config.prepare)?;
            let image = render(&prepared, &config.settings, &|_, _| {}).film.to_image();
            tick();
            Ok(image)
        })
        .collect()
}
