//! Analytic checks in the spirit of pbrt's integrator tests: scenes whose
//! pixel values can be worked out by hand.

use glam::Vec3A;
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_tracer::prepare::{prepare, PrepareOptions};
use nffkit_tracer::render::{render, RenderSettings};

fn render_nff(src: &str, opts: &PrepareOptions) -> nffkit_tracer::film::Film {
    let scene = nff::parse(src.as_bytes(), &ParseOptions::default()).unwrap().scene;
    let prepared = prepare(&scene, opts).unwrap();
    render(&prepared, &RenderSettings::default(), &|_, _| {}).film
}

const VIEW: &str = "b 0.2 0.3 0.4\nv\nfrom 0 0 10\nat 0 0 0\nup 0 1 0\nangle 30\nhither 1\nresolution 5 5\n";

fn close(a: Vec3A, b: Vec3A) -> bool {
    (a - b).abs().max_element() < 1e-5
}

#[test]
fn lit_head_on_diffuse_sphere_has_the_known_value() {
    let src = format!("{VIEW}l 0 0 10 0.5 0.5 0.5\nf 0.5 1 0.25 0.8 0 1 0 1\ns 0 0 0 1\n");
    let film = render_nff(&src, &PrepareOptions::default());
    // N.L = 1 at the centre: I * Kd * colour.
    assert!(close(film.get(2, 2), Vec3A::new(0.2, 0.4, 0.1)), "{}", film.get(2, 2));
    // The corner ray misses: background.
    assert!(close(film.get(0, 0), Vec3A::new(0.2, 0.3, 0.4)));
}

#[test]
fn lights_without_colour_get_one_over_sqrt_n() {
    let src = format!("{VIEW}l 0 0 10\nl 0 0 10\nf 0.5 0.5 0.5 0.5 0 1 0 1\ns 0 0 0 1\n");
    let film = render_nff(&src, &PrepareOptions::default());
    let expect = 2.0 * (1.0 / 2f32.sqrt()) * 0.5 * 0.5;
    assert!(close(film.get(2, 2), Vec3A::splat(expect)), "{}", film.get(2, 2));
}

#[test]
fn mirror_reflects_the_background_and_adds_the_highlight() {
    let src = format!("{VIEW}l 0 0 10 0.5 0.5 0.5\nf 1 1 1 0 0.5 20 0 1\ns 0 0 0 1\n");
    let film = render_nff(&src, &PrepareOptions::default());
    // Highlight: Ks * I * (R.V)^20 with R.V = 1; reflection: Ks * background.
    let expect = Vec3A::splat(0.25) + 0.5 * Vec3A::new(0.2, 0.3, 0.4);
    assert!(close(film.get(2, 2), expect), "{}", film.get(2, 2));
}

#[test]
fn glass_at_normal_incidence_shows_what_is_behind() {
    let src = format!("{VIEW}l 0 0 10 1 1 1\nf 1 1 1 0 0 1 1 1.5\ns 0 0 0 1\n");
    let film = render_nff(&src, &PrepareOptions::default());
    // T = 1 twice (in and out), nothing else: the background comes through.
    assert!(close(film.get(2, 2), Vec3A::new(0.2, 0.3, 0.4)), "{}", film.get(2, 2));
}

#[test]
fn shadow_ray_blocks_the_light() {
    // A floor lit from straight above; a sphere between the light and the
    // floor's centre. The camera sees the centre of the floor past the
    // sphere (the sight line clears it by 3.5 radii).
    let view = "v\nfrom 0 -8 8\nat 0 0 0\nup 0 0 1\nangle 60\nhither 1\nresolution 5 5\n";
    let floor = "l 0 0 10 1 1 1\nf 1 1 1 1 0 1 0 1\np 4\n-20 -20 0\n20 -20 0\n20 20 0\n-20 20 0\n";
    let lit = render_nff(&format!("{view}{floor}"), &PrepareOptions::default());
    let shadowed = render_nff(&format!("{view}{floor}s 0 0 5 1\n"), &PrepareOptions::default());
    assert!(lit.get(2, 2).x > 0.5, "unshadowed floor is lit: {}", lit.get(2, 2));
    assert_eq!(shadowed.get(2, 2), Vec3A::ZERO, "the sphere's shadow, with no ambient term, is black");
    // Away from the shadow the floor is as bright as before.
    assert!(close(shadowed.get(0, 4), lit.get(0, 4)));
}

#[test]
fn one_sided_rule_hides_back_faces() {
    // A polygon facing away from the camera (clockwise seen from the eye).
    let poly = "f 1 1 1 1 0 1 0 1\np 4\n-5 -5 0\n-5 5 0\n5 5 0\n5 -5 0\n";
    let src = format!("{VIEW}l 0 0 10 1 1 1\n{poly}");
    let two = render_nff(&src, &PrepareOptions::default());
    let one = render_nff(&src, &PrepareOptions { one_sided: true, ..Default::default() });
    assert!(two.get(2, 2).x > 0.9, "two-sided shading lights the back face");
    assert!(close(one.get(2, 2), Vec3A::new(0.2, 0.3, 0.4)), "one-sided: invisible");
}

#[test]
fn inside_only_sphere_shows_its_far_wall() {
    // Negative radius: the camera outside sees through the front to the
    // inside of the back wall (lit from the eye, N.L < 0 there: black).
    let src = format!("{VIEW}l 0 0 10 1 1 1\nf 1 1 1 1 0 1 0 1\ns 0 0 0 -1\n");
    let film = render_nff(&src, &PrepareOptions::default());
    let c = film.get(2, 2);
    assert!(c != Vec3A::new(0.2, 0.3, 0.4), "the sphere is hit");
}

#[test]
fn patch_normals_are_interpolated() {
    // A flat quad whose patch normals tilt: shading varies across it, while
    // the same quad as `p` is uniformly lit by a light at infinity-ish.
    let pp = "f 1 1 1 1 0 1 0 1\npp 4\n-3 -3 0 -0.5 0 0.866\n3 -3 0 0.5 0 0.866\n3 3 0 0.5 0 0.866\n-3 3 0 -0.5 0 0.866\n";
    let src = format!("{VIEW}l 0 0 1000 1 1 1\n{pp}");
    let film = render_nff(&src, &PrepareOptions::default());
    let (left, centre) = (film.get(1, 2).x, film.get(2, 2).x);
    assert!(centre > left + 0.01, "centre {centre} vs left {left}");
}
