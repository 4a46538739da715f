//! Wavefront OBJ with its MTL: the scene's triangles ([`super::triangles`])
//! with a normal at every corner, one `usemtl` per NFF material.
//!
//! MTL from the NFF material: `Kd` = colour x Kd (what `mesh2nff` reads back
//! as the same product: its largest channel becomes Kd), `Ks` = Ks (grey),
//! `Ns` = Shine, `d` = 1 - T and `Tf` = T (transmission), `Ni` = ior,
//! `illum` 2 (matte or highlights), 3 (mirror reflection) or 6 (refraction).
//! The view and the lights have no place in OBJ.

use super::triangles::groups;
use super::{num, ExportOptions};
use nffkit_formats::{Material, Scene};
use std::fmt::Write as _;

/// The OBJ text (naming `mtl_name` as its library), the MTL text, and what
/// the pair cannot hold.
pub fn write(scene: &Scene, opts: &ExportOptions, mtl_name: &str) -> (String, String, Vec<String>) {
    let (groups, mut lost) = groups(scene, opts.tessellate);
    let mut obj = String::new();
    let _ = writeln!(obj, "# Written by nffkit's nffconvert.\nmtllib {mtl_name}");
    let mut mtl = String::from("# Written by nffkit's nffconvert.\n");
    let mut base = 1usize;
    for g in &groups {
        let name = format!("m{}", g.material);
        material(&name, &super::material(scene, g.material), &mut mtl);
        let _ = writeln!(obj, "o {name}\nusemtl {name}");
        for p in &g.positions {
            let _ = writeln!(obj, "v {} {} {}", num(p.x), num(p.y), num(p.z));
        }
        for n in &g.normals {
            let _ = writeln!(obj, "vn {} {} {}", num(n.x), num(n.y), num(n.z));
        }
        for t in &g.triangles {
            let [a, b, c] = t.map(|i| i as usize + base);
            let _ = writeln!(obj, "f {a}//{a} {b}//{b} {c}//{c}");
        }
        base += g.positions.len();
    }
    if scene.view.is_some() {
        lost.push("the view: OBJ has no camera".into());
    }
    if !scene.lights.is_empty() {
        lost.push(format!(
            "{} light{}: OBJ has none",
            scene.lights.len(),
            nffkit_formats::plural(scene.lights.len())
        ));
    }
    if scene.background.is_some() {
        lost.push("the background colour".into());
    }
    (obj, mtl, lost)
}

fn material(name: &str, m: &Material, out: &mut String) {
    let kd = m.color * m.kd;
    let illum = if m.t > 0.0 {
        6
    } else if m.ks > 0.0 {
        3
    } else {
        2
    };
    let _ = writeln!(out, "newmtl {name}");
    let _ = writeln!(out, "Kd {} {} {}", num(kd.x), num(kd.y), num(kd.z));
    let _ = writeln!(out, "Ks {0} {0} {0}", num(m.ks));
    let _ = writeln!(out, "Ns {}", num(m.shine));
    let _ = writeln!(out, "d {}", num(1.0 - m.t));
    let _ = writeln!(out, "Tf {0} {0} {0}", num(m.t));
    let _ = writeln!(out, "Ni {}", num(m.ior));
    let _ = writeln!(out, "illum {illum}\n");
}
