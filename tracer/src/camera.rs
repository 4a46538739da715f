//! The camera: NFF's pinhole view, and a thin lens for depth of field (the
//! pinhole is the aperture-0 case of the same type).
//!
//! Field of view convention (the spec's): `angle` is measured between the
//! centres of the outer pixel rows or columns, not between the image edges.
//! With N pixels along the smaller image side, pixel centres are spaced
//! 2·tan(angle/2)/(N−1) apart on an image plane at unit distance; pixels are
//! square. So a 512-pixel image spans tan(angle/2)·512/511 to each side of the
//! centre, and `--width/--height` overrides keep that field of view. A
//! P3F view's `angle` is the course's: the image height, edge to edge
//! ([`View::pixel_size`] holds both conventions).

use crate::math::Ray;
use glam::{DVec3, Vec2, Vec3A};
use nffkit_formats::{Dialect, View};

/// Rays from image positions.
#[derive(Debug, Clone)]
pub struct Camera {
    /// Eye position (lens centre).
    pub eye: Vec3A,
    forward: Vec3A,
    right: Vec3A,
    up: Vec3A,
    /// Image plane size of one pixel at unit distance.
    pixel: f32,
    width: u32,
    height: u32,
    /// Lens radius (0: pinhole).
    pub aperture: f32,
    /// Distance from the eye to the plane in focus.
    pub focus: f32,
    /// Hither distance: eye rays start at this depth.
    pub hither: f32,
}

impl Camera {
    /// The camera of an NFF `v` block at `width` × `height` pixels.
    pub fn new(view: &View, width: u32, height: u32) -> Camera {
        Camera::in_dialect(view, Dialect::Nff, width, height)
    }

    /// The camera of a `v` block read as `dialect` reads it, at `width` ×
    /// `height` pixels (a pinhole: [`Camera::with_lens`] adds the lens).
    pub fn in_dialect(view: &View, dialect: Dialect, width: u32, height: u32) -> Camera {
        let f = |v: DVec3| Vec3A::new(v.x as f32, v.y as f32, v.z as f32);
        let dir = view.at - view.from;
        let forward = dir.normalize();
        // `up` made unit first: a short one (1e-150) would underflow in the
        // cross product.
        let right = forward.cross(view.up.normalize()).normalize();
        let up = right.cross(forward);
        let pixel = view.pixel_size(dialect, width, height);
        Camera {
            eye: f(view.from),
            forward: f(forward),
            right: f(right),
            up: f(up),
            pixel: pixel as f32,
            width,
            height,
            aperture: 0.0,
            focus: dir.length() as f32,
            hither: view.hither as f32,
        }
    }

    /// Turn into a thin-lens camera with lens radius `aperture`, focused at
    /// `focus` (the from-at distance when `None`).
    pub fn with_lens(mut self, aperture: f32, focus: Option<f32>) -> Camera {
        self.aperture = aperture;
        if let Some(f) = focus {
            self.focus = f;
        }
        self
    }

    /// Image size.
    pub fn resolution(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The view's basis (forward, right, up) and the pixel's side on the
    /// image plane at distance 1.
    pub(crate) fn frame(&self) -> (Vec3A, Vec3A, Vec3A, f32) {
        (self.forward, self.right, self.up, self.pixel)
    }

    /// The ray through raster position `(x, y)` (pixel `(i, j)` spans
    /// `[i, i+1) × [j, j+1)`, `y` downwards), with `lens` a point on the unit
    /// disc (ignored by a pinhole). Returns the ray and its minimum distance
    /// (the hither plane, measured along the view direction).
    #[inline]
    pub fn ray(&self, x: f32, y: f32, lens: Vec2) -> (Ray, f32) {
        let sx = (x - self.width as f32 * 0.5) * self.pixel;
        let sy = (self.height as f32 * 0.5 - y) * self.pixel;
        let dir = (self.forward + self.right * sx + self.up * sy).normalize();
        let cos = dir.dot(self.forward);
        let t_min = self.hither / cos;
        if self.aperture <= 0.0 {
            return (Ray { o: self.eye, d: dir }, t_min);
        }
        let focus_point = self.eye + dir * (self.focus / cos);
        let lens_point = self.eye + (self.right * lens.x + self.up * lens.y) * self.aperture;
        let d = (focus_point - lens_point).normalize();
        (Ray { o: lens_point, d }, self.hither / d.dot(self.forward))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view(angle: f64) -> View {
        View {
            lens: None,
            from: DVec3::new(0.0, 0.0, 0.0),
            at: DVec3::new(0.0, 0.0, -10.0),
            up: DVec3::new(0.0, 1.0, 0.3), // not perpendicular on purpose
            angle,
            hither: 1.0,
            resolution: [512, 512],
        }
    }

    #[test]
    fn outer_pixel_centres_span_the_angle() {
        let c = Camera::new(&view(90.0), 5, 5);
        let (left, _) = c.ray(0.5, 2.5, Vec2::ZERO);
        let (right, _) = c.ray(4.5, 2.5, Vec2::ZERO);
        let angle = left.d.angle_between(right.d).to_degrees();
        assert!((angle - 90.0).abs() < 1e-4, "{angle}");
        assert!(right.d.x > 0.0, "image x goes right");
        let (top, _) = c.ray(2.5, 0.5, Vec2::ZERO);
        assert!(top.d.y > 0.0, "image y goes down");
    }

    #[test]
    fn centre_ray_looks_at_at_and_hither_is_along_the_view() {
        let c = Camera::new(&view(45.0), 4, 4);
        let (r, t_min) = c.ray(2.0, 2.0, Vec2::ZERO);
        assert!((r.d - Vec3A::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert!((t_min - 1.0).abs() < 1e-6);
        let (r, t_min) = c.ray(0.0, 0.0, Vec2::ZERO);
        assert!((r.at(t_min).z + 1.0).abs() < 1e-5, "hither is a plane, not a sphere");
    }

    #[test]
    fn non_square_keeps_square_pixels() {
        let c = Camera::new(&view(60.0), 8, 4);
        let (a, _) = c.ray(0.5, 1.5, Vec2::ZERO);
        let (b, _) = c.ray(1.5, 1.5, Vec2::ZERO);
        let (d, _) = c.ray(0.5, 2.5, Vec2::ZERO);
        let dx = (a.d / a.d.z - b.d / b.d.z).length();
        let dy = (a.d / a.d.z - d.d / d.d.z).length();
        assert!((dx - dy).abs() < 1e-5);
        // The vertical field (smaller side) is the angle.
        let (top, _) = c.ray(4.0, 0.5, Vec2::ZERO);
        let (bottom, _) = c.ray(4.0, 3.5, Vec2::ZERO);
        assert!((top.d.angle_between(bottom.d).to_degrees() - 60.0).abs() < 1e-3);
    }

    #[test]
    fn p3f_angle_spans_the_image_height_edge_to_edge() {
        let v = view(60.0);
        let c = Camera::in_dialect(&v, Dialect::P3f, 8, 4);
        let (top, _) = c.ray(4.0, 0.0, Vec2::ZERO);
        let (bottom, _) = c.ray(4.0, 4.0, Vec2::ZERO);
        assert!((top.d.angle_between(bottom.d).to_degrees() - 60.0).abs() < 1e-3);
        let nff = Camera::in_dialect(&v, Dialect::Nff, 8, 4);
        assert!(c.pixel < nff.pixel, "edges span more pixels than outer centres");
    }

    #[test]
    fn thin_lens_rays_meet_on_the_focal_plane() {
        let c = Camera::new(&view(45.0), 16, 16).with_lens(0.5, Some(4.0));
        let (a, _) = c.ray(3.0, 5.0, Vec2::new(0.9, 0.0));
        let (b, _) = c.ray(3.0, 5.0, Vec2::new(-0.3, 0.7));
        let ta = -4.0 / a.d.z;
        let tb = -4.0 / b.d.z;
        assert!((a.at(ta) - b.at(tb)).length() < 1e-4);
        assert!((a.o - c.eye).length() > 0.1);
    }
}
