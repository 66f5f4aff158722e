//! The Cornell box rendered by raylab against a reference written independently inside this
//! test: its own OBJ reading, its own camera, f64 Möller–Trumbore, its own shading and sRGB.
//!
//! Tolerance: every pixel the reference calls unambiguous must match within 1 of 255 in each
//! channel (f32 against f64 shading and one rounding). A pixel is ambiguous, and skipped, when
//! its camera ray or its shadow ray passes within a relative 1e-4 (in barycentrics) of a
//! triangle's edge, where f32 and f64 may rightly pick different triangles. At least 95% of
//! the pixels must be unambiguous.

use raylab::render::{render_image, LabStep, RenderSettings, Stage};
use raylab::{Camera, Scene};

const OBJ: &str = include_str!("../../assets/cornell_lab.obj");
const MTL: &str = include_str!("../../assets/cornell_lab.mtl");
const MARGIN: f64 = 1e-4;

type V = [f64; 3];
fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

struct RefScene {
    tris: Vec<([V; 3], V)>,
    /// (centre, radius, colour), indexed after the triangles.
    spheres: Vec<(V, f64, V)>,
}

fn parse_reference_scene() -> RefScene {
    let mut kd = std::collections::HashMap::new();
    let mut name = String::new();
    for line in MTL.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first() {
            Some(&"newmtl") => name = w[1].to_string(),
            Some(&"Kd") => {
                kd.insert(
                    name.clone(),
                    [1, 2, 3].map(|k| w[k].parse::<f32>().unwrap() as f64),
                );
            }
            _ => {}
        }
    }
    let mut verts = Vec::new();
    let mut color = [0.0; 3];
    let mut tris = Vec::new();
    for line in OBJ.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first() {
            Some(&"v") => verts.push([1, 2, 3].map(|k| w[k].parse::<f32>().unwrap() as f64)),
            Some(&"usemtl") => color = kd[w[1]],
            Some(&"f") => {
                let idx: Vec<usize> = w[1..]
                    .iter()
                    .map(|s| s.parse::<usize>().unwrap() - 1)
                    .collect();
                tris.push(([verts[idx[0]], verts[idx[1]], verts[idx[2]]], color));
            }
            _ => {}
        }
    }
    RefScene {
        tris,
        spheres: Vec::new(),
    }
}

/// The nearest root of |o + t·d − c|² = r² in (tmin, tmax), and whether the ray grazes the
/// sphere or meets it within rounding of tmin or tmax (ambiguous).
fn ref_sphere(o: V, d: V, c: V, r: f64, tmin: f64, tmax: f64) -> (Option<f64>, bool) {
    let oc = sub(o, c);
    let (a, b, cc) = (dot(d, d), dot(oc, d), dot(oc, oc) - r * r);
    let disc = b * b - a * cc;
    let grazing = disc.abs() <= MARGIN * (b * b).max(a * cc.abs()).max(a * r * r);
    if disc < 0.0 {
        return (None, grazing);
    }
    let sq = disc.sqrt();
    // The root without cancellation, then the other from the product of the roots.
    let q = -(b + b.signum() * sq);
    let (t0, t1) = if q == 0.0 {
        (0.0, 0.0)
    } else {
        (q / a, cc / q)
    };
    let (lo, hi) = (t0.min(t1), t0.max(t1));
    let near = |t: f64| (t - tmin).abs() < 1e-6 || (t - tmax).abs() < 1e-6 * tmax.abs();
    let t = [lo, hi].into_iter().find(|t| *t > tmin && *t < tmax);
    (t, grazing || near(lo) || near(hi))
}

/// Nearest hit with tmin < t < tmax: (t, triangle, ambiguous?).
fn ref_hit(
    s: &RefScene,
    o: V,
    d: V,
    tmin: f64,
    tmax: f64,
    skip: Option<usize>,
) -> (Option<(f64, usize)>, bool) {
    let mut best: Option<(f64, usize)> = None;
    let mut ambiguous = false;
    let mut hits = Vec::new();
    for (k, (c, r, _)) in s.spheres.iter().enumerate() {
        let i = s.tris.len() + k;
        if skip == Some(i) {
            continue;
        }
        let (t, amb) = ref_sphere(o, d, *c, *r, tmin, tmax);
        ambiguous |= amb;
        if let Some(t) = t {
            hits.push((t, i));
            if best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, i));
            }
        }
    }
    for (i, (v, _)) in s.tris.iter().enumerate() {
        if skip == Some(i) {
            continue;
        }
        let e1 = sub(v[1], v[0]);
        let e2 = sub(v[2], v[0]);
        let p = cross(d, e2);
        let det = dot(e1, p);
        if det == 0.0 {
            continue;
        }
        let tv = sub(o, v[0]);
        let b1 = dot(tv, p) / det;
        let q = cross(tv, e1);
        let b2 = dot(d, q) / det;
        let t = dot(e2, q) / det;
        let b0 = 1.0 - b1 - b2;
        let margin = b0.min(b1).min(b2);
        let in_range = t > tmin && t < tmax;
        if margin.abs() < MARGIN && t > tmin - 1e-6 && t < tmax + 1e-6 {
            ambiguous = true;
        }
        if margin >= 0.0 && in_range {
            hits.push((t, i));
            if best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, i));
            }
        }
    }
    // Two surfaces at (nearly) the same depth.
    if let Some((bt, bi)) = best {
        if hits
            .iter()
            .any(|&(t, i)| i != bi && (t - bt).abs() < MARGIN * bt)
        {
            ambiguous = true;
        }
    }
    (best, ambiguous)
}

fn srgb8(x: f64) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let s = if x <= 0.0031308 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// The reference image: RGB per pixel, or None where ambiguous.
fn reference(step: LabStep, w: u32, h: u32) -> Vec<Option<[u8; 3]>> {
    reference_of(&parse_reference_scene(), step, w, h)
}

/// [`reference`] of any reference scene seen from the lab camera.
fn reference_of(s: &RefScene, step: LabStep, w: u32, h: u32) -> Vec<Option<[u8; 3]>> {
    let light = [0.0, -0.5, -0.7];
    let power = 14.0;
    let o = [0.0, 0.0, -3.001f32 as f64];
    let f = w as f64;
    let mut out = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let u = i as f64 - w as f64 / 2.0 + 0.5;
            let v = j as f64 - h as f64 / 2.0 + 0.5;
            let len = (u * u + v * v + f * f).sqrt();
            let d = [u / len, v / len, f / len];
            let (hit, amb) = ref_hit(s, o, d, 0.0, f64::INFINITY, None);
            if amb {
                out.push(None);
                continue;
            }
            let Some((t, idx)) = hit else {
                out.push(Some([0, 0, 0]));
                continue;
            };
            let p = [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
            let (mut n, rho) = match s.tris.get(idx) {
                Some((tri, rho)) => (cross(sub(tri[1], tri[0]), sub(tri[2], tri[0])), *rho),
                None => {
                    let (c, _, rho) = s.spheres[idx - s.tris.len()];
                    (sub(p, c), rho)
                }
            };
            let nl = dot(n, n).sqrt();
            n = n.map(|c| c / nl);
            if dot(n, d) > 0.0 {
                n = n.map(|c| -c);
            }
            let r = sub(light, p);
            let r2 = dot(r, r);
            let mut dlight =
                power * (dot(n, r) / r2.sqrt()).max(0.0) / (4.0 * std::f64::consts::PI * r2);
            let mut ambiguous = false;
            if matches!(step, LabStep::Shadows | LabStep::Indirect) && dlight > 0.0 {
                // Shadow ray from the exact hit point; 1e-9 keeps it off its own surface.
                let (blocker, amb) = ref_hit(s, p, r, 1e-9, 1.0, Some(idx));
                ambiguous = amb;
                if blocker.is_some() {
                    dlight = 0.0;
                }
            }
            let total = match step {
                LabStep::Flat => 1.0,
                LabStep::Direct | LabStep::Shadows => dlight,
                LabStep::Indirect => dlight + 0.5,
            };
            out.push((!ambiguous).then(|| rho.map(|c| srgb8(c * total))));
        }
    }
    out
}

/// Holds every pixel the reference decided to within 1 of 255 per channel (alpha 255);
/// returns (pixels compared, worst channel difference).
fn compare_with_reference(
    step: LabStep,
    img: &[u8],
    reference: &[Option<[u8; 3]>],
    w: u32,
) -> (usize, i32) {
    let (mut compared, mut worst) = (0, 0i32);
    for (k, r) in reference.iter().enumerate() {
        let Some(r) = r else { continue };
        compared += 1;
        for c in 0..3 {
            let diff = (img[4 * k + c] as i32 - r[c] as i32).abs();
            worst = worst.max(diff);
            assert!(
                diff <= 1,
                "{step}: pixel ({}, {}) channel {c}: raylab {} vs reference {}",
                k % w as usize,
                k / w as usize,
                img[4 * k + c],
                r[c]
            );
        }
        assert_eq!(img[4 * k + 3], 255);
    }
    (compared, worst)
}

fn render(step: LabStep, w: u32, h: u32) -> Vec<u8> {
    let settings = RenderSettings {
        width: w,
        height: h,
        step,
        ..Default::default()
    };
    render_image(&Scene::cornell().into(), &Camera::cornell(w), &settings)
        .unwrap()
        .0
}

#[test]
fn every_step_matches_the_independent_reference() {
    let (w, h) = (96u32, 72u32);
    for step in LabStep::ALL {
        let img = render(step, w, h);
        let reference = reference(step, w, h);
        let (compared, worst) = compare_with_reference(step, &img, &reference, w);
        println!(
            "{step}: {compared} of {} pixels compared, worst channel difference {worst}",
            w * h
        );
        assert!(
            compared * 100 >= reference.len() * 95,
            "{step}: only {compared} unambiguous pixels"
        );
    }
}

#[test]
fn the_cornell_box_with_spheres_matches_the_independent_reference() {
    // assets/scenes/cornell_spheres.scene, loaded and rendered by raylab, against the
    // reference above with its two spheres written out here (centre, radius, colour), as the
    // file's comments describe them.
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/cornell_spheres.scene"
    );
    let stage = Stage::from(Scene::load(std::path::Path::new(path), Default::default()).unwrap());
    let mut reference_scene = parse_reference_scene();
    reference_scene.spheres = vec![
        (
            [0.33f32, 0.2054, -0.39].map(f64::from),
            0.2f32 as f64,
            [0.95f32; 3].map(f64::from),
        ),
        (
            [-0.5f32, 0.7, -0.5].map(f64::from),
            0.3f32 as f64,
            [0.95f32, 0.75, 0.35].map(f64::from),
        ),
    ];
    let (w, h) = (96u32, 72u32);
    for step in LabStep::ALL {
        let settings = RenderSettings {
            width: w,
            height: h,
            step,
            ..Default::default()
        };
        let img = render_image(&stage, &Camera::cornell(w), &settings)
            .unwrap()
            .0;
        let reference = reference_of(&reference_scene, step, w, h);
        let (compared, _) = compare_with_reference(step, &img, &reference, w);
        let mut on_spheres = 0;
        for (k, r) in reference.iter().enumerate() {
            if r.is_none() {
                continue;
            }
            let o = [0.0, 0.0, -3.001f32 as f64];
            let (i, j) = ((k % w as usize) as f64, (k / w as usize) as f64);
            let (u, v, f) = (i - w as f64 / 2.0 + 0.5, j - h as f64 / 2.0 + 0.5, w as f64);
            let hit = ref_hit(&reference_scene, o, [u, v, f], 0.0, f64::INFINITY, None).0;
            on_spheres += hit.is_some_and(|(_, i)| i >= 30) as usize;
        }
        println!("{step}: {compared} pixels compared, {on_spheres} of them on the spheres");
        assert!(
            compared * 100 >= reference.len() * 93,
            "{step}: {compared} compared"
        );
        assert!(
            on_spheres > 300,
            "{step}: {on_spheres} sphere pixels compared"
        );
    }
}

fn count_colour(img: &[u8], rgb: [u8; 3]) -> usize {
    img.chunks_exact(4).filter(|p| p[..3] == rgb).count()
}

#[test]
fn flat_render_shows_walls_and_both_blocks() {
    let (w, h) = (160u32, 120u32);
    let img = render(LabStep::Flat, w, h);
    let scene = Scene::cornell();
    let enc = |c: [f32; 3]| c.map(raylab::render::linear_to_srgb8);
    // Every Cornell material is visible over a real area.
    let mut colours: Vec<[u8; 3]> = scene.colors().iter().map(|c| enc(*c)).collect();
    colours.dedup();
    assert_eq!(colours.len(), 7, "seven materials in lab order");
    for c in colours {
        let n = count_colour(&img, c);
        assert!(n > 100, "colour {c:?} covers only {n} pixels");
    }
    // Left of the image is the purple wall (x negated: the lab's x = L is on screen left).
    let px = |i: u32, j: u32| -> [u8; 3] {
        let k = 4 * (j * w + i) as usize;
        [img[k], img[k + 1], img[k + 2]]
    };
    assert_eq!(px(5, h / 2), enc([0.75, 0.15, 0.75]), "left wall purple");
    assert_eq!(
        px(w - 6, h / 2),
        enc([0.75, 0.75, 0.15]),
        "right wall yellow"
    );
    assert_eq!(px(w / 2, 3), enc([0.15, 0.75, 0.75]), "ceiling cyan");
    assert_eq!(px(w / 4, h - 3), enc([0.15, 0.75, 0.15]), "floor green");
    assert_eq!(
        px(w * 2 / 5, h / 2),
        enc([0.15, 0.15, 0.75]),
        "tall block blue, left of centre"
    );
    assert_eq!(
        px(w * 3 / 5, h * 17 / 20),
        enc([0.75, 0.15, 0.15]),
        "short block red, front right"
    );
    assert_eq!(px(w / 2, h / 6), enc([0.75, 0.75, 0.75]), "back wall white");
}

#[test]
fn shadows_darken_and_indirect_lifts_them() {
    let (w, h) = (128u32, 96u32);
    let black = |img: &[u8]| count_colour(img, [0, 0, 0]);
    let direct = render(LabStep::Direct, w, h);
    let shadows = render(LabStep::Shadows, w, h);
    let indirect = render(LabStep::Indirect, w, h);
    assert!(
        black(&shadows) > black(&direct) + 200,
        "blocks cast shadows"
    );
    assert_eq!(
        black(&indirect),
        0,
        "the indirect term lights every surface"
    );
    // Shadows only remove light: no pixel is brighter with shadows than without.
    assert!(direct.iter().zip(&shadows).all(|(d, s)| s <= d));
}

#[test]
fn supersampling_is_the_mean_of_stratified_samples() {
    // 2x2 supersampling at W×H averages what the 2W×2H image has in each 2×2 block (the same
    // sample positions; the focal length doubles with the width).
    let (w, h) = (40u32, 30u32);
    let scene = Stage::from(Scene::cornell());
    let ss = RenderSettings {
        width: w,
        height: h,
        spp: 2,
        ..Default::default()
    };
    let (img, stats) = render_image(&scene, &Camera::cornell(w), &ss).unwrap();
    assert_eq!(stats.primary_rays, 4 * (w * h) as u64);
    let big = RenderSettings {
        width: 2 * w,
        height: 2 * h,
        ..Default::default()
    };
    let cam =
        Camera::from_yaw_pitch(Camera::cornell(w).position(), 0.0, 0.0, 2.0 * w as f64).unwrap();
    let (big_img, _) = render_image(&scene, &cam, &big).unwrap();
    let to_lin = |v: u8| {
        let s = v as f64 / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    let mut edge_pixels = 0;
    for j in 0..h {
        for i in 0..w {
            for c in 0..3 {
                let mean: f64 = [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .iter()
                    .map(|(a, b)| {
                        to_lin(big_img[4 * ((2 * j + b) * 2 * w + 2 * i + a) as usize + c])
                    })
                    .sum::<f64>()
                    / 4.0;
                let got = img[4 * (j * w + i) as usize + c] as i32;
                let diff = (got - srgb8(mean) as i32).abs();
                assert!(
                    diff <= 2,
                    "pixel ({i},{j}) channel {c}: {got} vs {}",
                    srgb8(mean)
                );
            }
            let k = 4 * (j * w + i) as usize;
            if img[k..k + 3] != big_img[4 * (2 * j * 2 * w + 2 * i) as usize..][..3] {
                edge_pixels += 1;
            }
        }
    }
    assert!(edge_pixels > 20, "supersampling blends colours along edges");
}

#[test]
fn bad_settings_are_errors_not_panics() {
    let scene = Stage::from(Scene::cornell());
    let cam = Camera::cornell(64);
    for (w, h, spp) in [
        (0, 10, 1),
        (10, 0, 1),
        (100_000, 10, 1),
        (10, 10, 0),
        (10, 10, 1000),
    ] {
        let s = RenderSettings {
            width: w,
            height: h,
            spp,
            ..Default::default()
        };
        assert!(render_image(&scene, &cam, &s).is_err(), "{w}x{h} spp {spp}");
    }
    let s = RenderSettings {
        width: 4,
        height: 4,
        ..Default::default()
    };
    let mut small = vec![0u8; 10];
    assert!(raylab::render_into(&scene, &cam, &s, &mut small).is_err());
}

#[test]
fn srgb_table_matches_the_exact_curve() {
    use raylab::render::{linear_to_srgb8, linear_to_srgb8_reference};
    // Every f32 in [0, 1] at a stride, plus the neighbourhood of every decision level.
    let mut mismatches = 0;
    let mut checked = 0;
    let mut x = 0.0f32;
    while x <= 1.0 {
        checked += 1;
        if linear_to_srgb8(x) != linear_to_srgb8_reference(x) {
            mismatches += 1;
        }
        x = f32::from_bits(x.to_bits() + 997);
    }
    assert!(checked > 1_000_000);
    // f32 rounding of a level may move a value lying within an ulp of it by one code.
    assert!(mismatches <= 4, "{mismatches} of {checked}");
    assert_eq!(linear_to_srgb8(f32::NAN), 0);
    assert_eq!(linear_to_srgb8(-1.0), 0);
    assert_eq!(linear_to_srgb8(2.0), 255);
    assert_eq!(linear_to_srgb8(1.0), 255);
    assert_eq!(linear_to_srgb8(0.5), 188);
}

#[test]
fn the_ray_inspector_agrees_with_the_independent_reference_and_the_image() {
    // Every pixel of a 48×36 Cornell box, inspected: the lecture's terms against their
    // definitions, the hit against the independent f64 reference, the colour against the
    // rendered image (the same ray, the same shading) and the reference's colour, and the
    // blocker against the reference's shadow ray.
    use raylab::render::inspect::{inspect, ShapeTerms};
    let (w, h) = (48u32, 36u32);
    let stage = Stage::from(Scene::cornell());
    let scene = stage.scene();
    let cam = Camera::cornell(w);
    let reference_scene = parse_reference_scene();
    let settings = RenderSettings {
        width: w,
        height: h,
        step: LabStep::Indirect,
        ..Default::default()
    };
    let img = render_image(&stage, &cam, &settings).unwrap().0;
    let reference_img = reference(LabStep::Indirect, w, h);
    let (mut hits, mut blocked, mut checked_blockers) = (0, 0, 0);
    for j in 0..h {
        for i in 0..w {
            let ins = inspect(&stage, &cam, &settings, i, j).unwrap();
            let (u, v, f) = (i as f64 + 0.5 - 24.0, j as f64 + 0.5 - 18.0, w as f64);
            assert_eq!(ins.uvf, [u, v, f]);
            let len = (u * u + v * v + f * f).sqrt();
            for k in 0..3 {
                assert!((ins.d_camera[k] - ins.uvf[k] / len).abs() < 1e-15);
                // The lab camera looks along +z unturned: world d = camera d (to f32).
                assert!((ins.ray.d[k] as f64 - ins.d_camera[k]).abs() < 1e-6);
            }
            let pixel = &img[4 * (j * w + i) as usize..][..3];
            let o = ins.ray.o.map(f64::from);
            let d = ins.ray.d.map(f64::from);
            let (expected, ambiguous) = ref_hit(&reference_scene, o, d, 0.0, f64::INFINITY, None);
            let Some(hit) = &ins.hit else {
                assert!(ambiguous || expected.is_none(), "({i}, {j})");
                assert_eq!(pixel, [0, 0, 0]);
                continue;
            };
            hits += 1;
            if !ambiguous {
                let (t, prim) = expected.expect("the reference hits too");
                assert_eq!(hit.prim as usize, prim, "({i}, {j})");
                assert!(
                    (hit.t as f64 - t).abs() <= 1e-6 * t,
                    "({i}, {j}) {} vs {t}",
                    hit.t
                );
                // The exact t, correctly rounded: within half an ulp of the reference's.
                let half_ulp = (hit.t_exact.next_up() - hit.t_exact) as f64 / 2.0;
                assert!(
                    (hit.t_exact as f64 - t).abs() <= half_ulp + 1e-12 * t,
                    "({i}, {j}) exact {} vs {t}",
                    hit.t_exact
                );
            }
            // x = A⁻¹b solves the system, and its t is the hit's.
            let ShapeTerms::Triangle(raylab::geometry::triangle::Terms { a, b, x }) = hit.terms
            else {
                panic!("the box is triangles")
            };
            for r in 0..3 {
                let ax: f64 = (0..3).map(|c| a[r][c] * x[c]).sum();
                assert!((ax - b[r]).abs() <= 1e-9 * (1.0 + b[r].abs()), "({i}, {j})");
            }
            assert!((x[0] - hit.t as f64).abs() <= 1e-5 * x[0], "({i}, {j})");
            assert!(x[1] >= -1e-9 && x[2] >= -1e-9 && x[1] + x[2] <= 1.0 + 1e-9);
            assert!(["f32 filter", "f64 intervals", "exact"].contains(&hit.decided_by));
            // The colour the inspector gives is the image's pixel, and the reference's.
            let srgb = hit.colour.map(raylab::render::linear_to_srgb8);
            assert_eq!(pixel, srgb, "({i}, {j})");
            if let Some(r) = reference_img[(j * w + i) as usize] {
                for c in 0..3 {
                    assert!((srgb[c] as i32 - r[c] as i32).abs() <= 1, "({i}, {j})");
                }
            }
            assert_eq!(hit.rho, scene.colors()[hit.prim as usize]);
            assert_eq!(hit.indirect, scene.ambient);
            // The blocker: the reference's nearest blocker seen from the light.
            let Some(shadow) = hit.shadow else { continue };
            let from_light = ref_hit(
                &reference_scene,
                shadow.o.map(f64::from),
                shadow.d.map(f64::from),
                1e-9,
                1.0 - 1e-9,
                Some(hit.prim as usize),
            );
            blocked += hit.blocked_by.is_some() as usize;
            if let (found, false) = from_light {
                checked_blockers += 1;
                assert_eq!(hit.blocked_by, found.map(|(_, p)| p as u32), "({i}, {j})");
            }
        }
    }
    println!("{hits} hits, {blocked} shadow rays blocked, {checked_blockers} blockers checked");
    assert!(hits > 1500 && blocked > 50 && checked_blockers > 1000);
}

/// The terms the inspector names as a step's colour (`colour_terms`, D and N "not in step")
/// are the ones the step's formula takes: ρ = 1, D = 2 and N = 4 give 1, 2 or 6.
#[test]
fn a_steps_named_colour_terms_are_its_formulas() {
    for step in LabStep::ALL {
        let named = match (step.uses_direct(), step.uses_indirect()) {
            (false, false) => 1.0,
            (true, false) => 2.0,
            (true, true) => 6.0,
            (false, true) => panic!("{step:?}: N without D"),
        };
        let formula = raylab::render::shade::step_channel(step, 1.0f32, 2.0, 4.0);
        assert_eq!(formula, named, "{step:?}: {}", step.colour_terms());
    }
}
