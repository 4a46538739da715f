//! Property tests: the reader never panics on any bytes, and the writer
//! round-trips any scene exactly, NFF or P3F.

use glam::DVec3;
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_formats::{
    Dialect, Directives, Lens, Light, LightArea, Material, Primitive, Scene, Shape, SourceLine, View,
};
use proptest::prelude::*;

fn num() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e6..1e6f64,
        (-10i32..10).prop_map(|i| i as f64),
        prop::num::f64::NORMAL,
        Just(-0.0),
        Just(1.11022e-16),
    ]
}

fn vec3() -> impl Strategy<Value = DVec3> {
    (num(), num(), num()).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        (vec3(), num()).prop_map(|(center, radius)| Shape::Sphere { center, radius }),
        (vec3(), 0.0..5.0f64, vec3(), 0.0..5.0f64).prop_map(|(base, br, apex, ar)| {
            Shape::cone(base, br, apex + DVec3::new(0.0, 0.0, 7.0e7), ar)
        }),
        prop::collection::vec(vec3(), 3..8).prop_map(|vertices| Shape::Polygon { vertices }),
        prop::collection::vec((vec3(), vec3()), 3..6).prop_map(|vn| {
            Shape::patch(vn.iter().map(|p| p.0).collect(), vn.iter().map(|p| p.1).collect())
        }),
    ]
}

fn material() -> impl Strategy<Value = Material> {
    (vec3(), num(), num(), num(), num(), num()).prop_map(|(color, kd, ks, shine, t, ior)| Material {
        specular: glam::DVec3::ONE,
        color,
        kd,
        ks,
        shine,
        t,
        ior,
    })
}

prop_compose! {
    fn scene()(
        background in prop::option::of(vec3()),
        lights in prop::collection::vec((vec3(), prop::option::of(vec3())), 0..4),
        materials in prop::collection::vec(material(), 0..4),
        shapes in prop::collection::vec((shape(), 0u32..8), 0..12),
        angle in 1.0..179.0f64,
        hither in 0.0..10.0f64,
        res in (1u32..4000, 1u32..4000),
    ) -> Scene {
        let view = View { lens: None,
            from: DVec3::new(1.5, -2.0, 3.25), at: DVec3::ZERO, up: DVec3::Z,
            angle, hither, resolution: [res.0, res.1],
        };
        // Material indices never decrease, as in any file (see Scene's invariant).
        let mut sorted: Vec<u32> = shapes.iter().map(|s| s.1).collect();
        sorted.sort();
        let primitives = shapes.into_iter().zip(sorted).map(|((shape, _), m)| Primitive {
            shape,
            material: if materials.is_empty() || m == 0 { None } else { Some((m - 1) % materials.len() as u32) },
            line: SourceLine(0),
        }).collect::<Vec<_>>();
        // Keep indices monotone after the modulo.
        let mut last = None;
        let primitives = primitives.into_iter().map(|mut p| {
            if p.material < last { p.material = last; }
            last = p.material;
            p
        }).collect();
        Scene {
            view: Some(view), background,
            lights: lights.into_iter().map(|(position, color)| Light { area: None, position, color }).collect(),
            materials, primitives, ..Scene::default()
        }
    }
}

fn area() -> impl Strategy<Value = Option<LightArea>> {
    prop::option::of(
        (vec3(), 0.0..10.0f64, 0.0..10.0f64).prop_map(|(facing, w, h)| LightArea {
            facing: facing + DVec3::new(0.0, 0.0, 3.0e7),
            size: [w, h],
        }),
    )
}

prop_compose! {
    /// A P3F scene: what an NFF one holds (each light with a colour, as the
    /// course's reader wants), plus specular colours, area lights, a lens,
    /// boxes, a cube map and the directives.
    fn p3f_scene()(
        base in scene(),
        colours in prop::collection::vec((vec3(), area()), 4),
        speculars in prop::collection::vec(vec3(), 4),
        lens in (0.0..50.0f64, 0.01..10.0f64),
        boxes in prop::collection::vec((vec3(), (0.0..9.0f64, 0.0..9.0f64, 0.0..9.0f64)), 0..3),
        environment in prop::option::of("[a-z_./]{1,12}"),
        spp in prop::option::of(1u32..=65536),
        accel in prop::option::of(0u32..3),
    ) -> Scene {
        let mut s = base;
        s.dialect = Dialect::P3f;
        if let Some(v) = &mut s.view {
            v.lens = Some(Lens { aperture: lens.0, focal: lens.1 });
        }
        for (l, (c, a)) in s.lights.iter_mut().zip(colours) {
            l.color = Some(c);
            // Facing a point other than its centre, whatever the magnitudes.
            let z = l.position.z;
            let facing = |f: DVec3| DVec3::new(f.x, f.y, if z.abs() > 1.0 { -z } else { z + 3.0 });
            l.area = a.map(|a| LightArea { facing: facing(a.facing), ..a });
        }
        for (m, c) in s.materials.iter_mut().zip(speculars.into_iter().cycle()) {
            m.specular = c;
        }
        let material = s.primitives.last().and_then(|p| p.material);
        s.primitives.extend(boxes.into_iter().map(|(min, (x, y, z))| Primitive {
            shape: Shape::aabb(min, min + DVec3::new(x, y, z)),
            material,
            line: SourceLine(0),
        }));
        s.environment = environment;
        s.directives = Directives { spp, accel };
        s
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn write_then_parse_is_identity(s in scene()) {
        let text = nff::write(&s, Vec::new()).unwrap();
        let back = nff::parse(&text, &ParseOptions::default());
        let back = back.map_err(|e| TestCaseError::fail(format!("{e}\n{}", String::from_utf8_lossy(&text))))?;
        prop_assert_eq!(back.scene, s);
    }

    #[test]
    fn p3f_write_then_parse_is_identity(s in p3f_scene()) {
        let text = nff::write(&s, Vec::new()).unwrap();
        let opts = ParseOptions { dialect: Dialect::P3f, ..ParseOptions::default() };
        let back = nff::parse(&text, &opts);
        let back = back.map_err(|e| TestCaseError::fail(format!("{e}\n{}", String::from_utf8_lossy(&text))))?;
        prop_assert_eq!(back.scene, s);
    }

    #[test]
    fn numbers_read_exactly_like_the_standard_library(
        s in prop_oneof![
            "[-+]?[0-9]{0,20}(\\.[0-9]{0,20})?([eE][-+]?[0-9]{1,3})?",
            any::<f64>().prop_map(|x| format!("{x}")),
            any::<f64>().prop_map(|x| format!("{x:e}")),
        ]
    ) {
        let src = format!("v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0\nresolution 1 1\ns {s} 0 0 1\n");
        let ours = nff::parse(src.as_bytes(), &ParseOptions::default()).ok().map(|p| match p.scene.primitives[0].shape {
            nffkit_formats::Shape::Sphere { center, .. } => center.x.to_bits(),
            _ => unreachable!(),
        });
        let std = s.parse::<f64>().ok().filter(|v| v.is_finite()).map(f64::to_bits);
        prop_assert_eq!(ours, std, "{}", s);
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        let _ = nff::parse(&bytes, &ParseOptions::default());
        let _ = nff::parse(&bytes, &ParseOptions { lenient: true, fragment: true, ..Default::default() });
        let _ = nff::parse(&bytes, &ParseOptions { dialect: Dialect::P3f, ..Default::default() });
    }

    #[test]
    fn nff_like_token_soup_never_panics(
        toks in prop::collection::vec(prop_oneof![
            Just("v"), Just("b"), Just("l"), Just("f"), Just("c"), Just("s"), Just("p"), Just("pp"),
            Just("from"), Just("at"), Just("up"), Just("angle"), Just("hither"), Just("resolution"),
            Just("0"), Just("1"), Just("-1"), Just("3"), Just("1e300"), Just("nan"), Just("#"), Just("\n"),
            Just("4000000000"), Just(".5"), Just("x"),
            Just("bclr"), Just("al"), Just("box"), Just("mesh"), Just("env"), Just("spp"), Just("accel"),
            Just("aperture"), Just("focal"), Just("-4"), Just("0"),
        ], 0..200)
    ) {
        let src = toks.join(" ");
        let _ = nff::parse(src.as_bytes(), &ParseOptions::default());
        let _ = nff::parse(src.as_bytes(), &ParseOptions { dialect: Dialect::P3f, ..Default::default() });
        let _ = nff::parse(src.as_bytes(), &ParseOptions { dialect: Dialect::P3f, strict: true, ..Default::default() });
        let _ = nff::parse(src.as_bytes(), &ParseOptions { lenient: true, fragment: true, ..Default::default() });
    }
}
