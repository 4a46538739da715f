//! The scene `render` draws when given no file: a level-3 sphereflake over a
//! checkerboard, made by the project's own generators.

use crate::sphereflake::{Floor, Sphereflake};
use nffkit_formats::Scene;

/// The built-in default scene.
pub fn default_scene() -> Scene {
    Sphereflake::at(3, Floor::Checker(12, 12)).scene()
}
