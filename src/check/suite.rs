//! The hard-case suite: families of shapes and rays (fixed seeds, several hundred rays each)
//! on which intersection code goes wrong: closed meshes seen at their edges and vertices, tiny,
//! huge and far scenes, grazing rays, near coincident surfaces and exact ties, spheres at their
//! silhouette and tangent, and the lab's Cornell box. Every number is an f32 value, so the
//! families mean the same in f32 and f64.
//!
//! `raylab suite export` writes them in the `trace` formats; the tests hold every intersection
//! path of raylab to exact answers on them.

pub use super::classic::classic_bugs;
use super::meshes::{aimed_rays, cube, icosphere, random_points, vertices_and_edge_midpoints, Rng};
pub use super::round_two::round_two;
use crate::geometry::{Ray, Shape};
use crate::math::Real;
use crate::tracefile::TraceRay;

/// One family: a scene and the rays shot at it, in f32 (the suite) or f64.
pub struct Family<T: Real = f32> {
    /// What it is, in a few words (unique in the suite).
    pub name: String,
    /// What it probes, in a sentence (the exported suite's README lists it).
    pub probes: String,
    /// The classic bug it catches, in a few words (the exported suite's README lists it).
    pub catches: String,
    /// The primitives; an index is a position here.
    pub shapes: Vec<Shape<T>>,
    /// The rays.
    pub rays: Vec<Ray<T>>,
    /// Each ray's (tmin, tmax), both open; empty where every ray is whole (0, ∞).
    pub spans: Vec<(T, T)>,
}

impl<T: Real> Family<T> {
    /// A family of these shapes and rays, each ray whole (0 < t < ∞).
    pub fn new(name: impl Into<String>, shapes: Vec<Shape<T>>, rays: Vec<Ray<T>>) -> Self {
        Self {
            name: name.into(),
            probes: String::new(),
            catches: String::new(),
            shapes,
            rays,
            spans: Vec::new(),
        }
    }

    /// A family of rays with their own intervals.
    pub fn with_spans(
        name: impl Into<String>,
        shapes: Vec<Shape<T>>,
        rays: Vec<TraceRay<T>>,
    ) -> Self {
        let mut family = Self::new(name, shapes, rays.iter().map(|r| r.ray).collect());
        family.spans = rays.iter().map(|r| (r.tmin, r.tmax)).collect();
        family
    }

    /// The rays as the trace formats hold them, each with its interval.
    pub fn trace_rays(&self) -> Vec<TraceRay<T>> {
        (self.rays.iter().enumerate())
            .map(|(i, &ray)| match self.spans.get(i) {
                Some(&(tmin, tmax)) => TraceRay { ray, tmin, tmax },
                None => TraceRay::whole(ray),
            })
            .collect()
    }

    /// With a sentence on what it probes.
    pub fn probing(mut self, probes: impl Into<String>) -> Self {
        self.probes = probes.into();
        self
    }

    /// With the classic bug it catches.
    pub fn catching(mut self, catches: impl Into<String>) -> Self {
        self.catches = catches.into();
        self
    }
}

/// The classic bugs each family before the classic-bug ones catches, as measured with the
/// programs of examples/check/bugs/ (each exact.py with one bug; app/tests/commands/classic_bugs.rs
/// holds the named families to it). t in units of a normalised direction fails nearly all.
const CAUGHT: [&str; 32] = [
    "hits behind the origin; open edges; the last hit; Möller–Trumbore in f32",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32",
    "hits behind the origin; open edges; the last hit; Möller–Trumbore in f32",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32",
    "hits behind the origin; open edges; the last hit; Möller–Trumbore in f32",
    "hits behind the origin; open edges; the last hit; Möller–Trumbore in f32",
    "hits behind the origin; open edges; the last hit; Möller–Trumbore in f32",
    "hits behind the origin; open edges; the last hit; Möller–Trumbore in f32",
    "none of these: it holds a correct program's t on grazing rays",
    "the last hit instead of the nearest",
    "Möller–Trumbore in f32 (surfaces closer than its rounding)",
    "the last hit instead of the nearest; Möller–Trumbore in f32",
    "the last hit instead of the nearest",
    "the last hit instead of the nearest; Möller–Trumbore in f32",
    "the last hit instead of the nearest",
    "hits behind the origin; t >= tmin for >; the sphere's near root only",
    "hits behind the origin; t >= tmin for >; the sphere's near root only",
    "hits behind the origin; t >= tmin for >; the sphere's near root only",
    "the sphere's near root only",
    "none of these: it holds a correct program at a sphere's tangent",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32",
    "t >= tmin for >; the last hit instead of the nearest; Möller–Trumbore in f32",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32 (every ray)",
    "t >= tmin for >; open edges; the last hit; Möller–Trumbore in f32",
    "open edges; the last hit instead of the nearest",
    "open edges; the last hit instead of the nearest; Möller–Trumbore in f32",
];

/// Every family.
pub fn all() -> Vec<Family> {
    let mut families: Vec<Family> = [
        closed_meshes(),
        tiny_huge_and_offset(),
        grazing_and_far(),
        near_coincident(),
        spheres(),
        cornell(),
        cornell_translated(),
        round_two(),
        classic_bugs(),
    ]
    .into_iter()
    .flatten()
    .collect();
    for (family, caught) in families.iter_mut().zip(CAUGHT) {
        family.catches = caught.to_string();
    }
    families
}

/// A family's name in lowercase words joined by `-` (`cube-from-inside`), as its directory
/// spells it after the number.
pub fn slug(name: &str) -> String {
    // A minus sign that starts a number is a word (`2^-17` is not `2^17`).
    let mut spelled = String::new();
    let mut prev = ' ';
    for (i, c) in name.char_indices() {
        let next_is_digit = name[i + c.len_utf8()..].starts_with(|d: char| d.is_ascii_digit());
        match c == '-' && !prev.is_ascii_alphanumeric() && next_is_digit {
            true => spelled.push_str(" minus "),
            false => spelled.push(c),
        }
        prev = c;
    }
    let words: Vec<String> = spelled
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_ascii_lowercase)
        .collect();
    words.join("-")
}

/// Every family's name as its directory spells it after the number ([`slug`]),
/// in order. (Made once: each is a whole suite's build.)
pub fn slugs() -> &'static [String] {
    static SLUGS: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    SLUGS.get_or_init(|| all().iter().map(|f| slug(&f.name)).collect())
}

/// The closed meshes families.
pub fn closed_meshes() -> Vec<Family> {
    let mut out = Vec::new();
    let mut rng = Rng(101);
    let cube_mesh = cube(2, 2.0, [-1.0; 3]);
    let rays = aimed_rays(&cube_mesh, &random_points(&mut rng, 3, -0.9, 0.9));
    out.push(Family::new("cube, from inside", cube_mesh.clone(), rays)
        .probing("Rays from inside a closed cube at every vertex and edge midpoint: a watertight method never lets one out."));
    // From outside, rays aimed at silhouette edges touch the mesh only at the edge.
    let rays = aimed_rays(&cube_mesh, &random_points(&mut rng, 2, 2.0, 4.0));
    out.push(Family::new("cube, from outside", cube_mesh.clone(), rays)
        .probing("Rays from outside at a closed cube's vertices and edge midpoints, silhouette edges included (touching only the edge is a hit)."));

    let ico = icosphere(1, 1.0, [0.0; 3]);
    let rays = aimed_rays(&ico, &random_points(&mut rng, 3, -0.5, 0.5));
    out.push(Family::new("icosphere, from inside", ico.clone(), rays)
        .probing("Rays from inside a closed icosphere (shared vertices rounded to f32) at its vertices and edge midpoints."));
    let rays = aimed_rays(&ico, &random_points(&mut rng, 2, 1.5, 3.0));
    out.push(Family::new("icosphere, from outside", ico.clone(), rays)
        .probing("Rays from outside at an icosphere's vertices and edge midpoints, silhouettes included."));
    out
}

/// The tiny huge and offset families.
pub fn tiny_huge_and_offset() -> Vec<Family> {
    let mut out = Vec::new();
    let mut rng = Rng(102);
    for (family, size, offset) in [
        ("tiny cube 2^-17", 2f32.powi(-17), [0.0f32; 3]),
        ("huge cube 2^17", 2f32.powi(17), [0.0; 3]),
        ("cube at 1e4", 64.0, [1e4, -1e4, 2e4]),
        ("cube at 1e6", 4096.0, [1e6, 1e6, -1e6]),
    ] {
        let mesh = cube(2, size, offset);
        let origins: Vec<[f32; 3]> = (0..4)
            .map(|_| [0, 1, 2].map(|k| offset[k] + size * rng.range(0.1, 0.9) as f32))
            .collect();
        out.push(Family::new(
            family,
            mesh.clone(),
            aimed_rays(&mesh, &origins),
        )
        .probing("A closed cube tiny, huge or far from the origin, rays from inside at its vertices and edge midpoints: tolerances that do not scale leak or hit wrongly."));
    }
    out
}

/// The grazing and far families.
pub fn grazing_and_far() -> Vec<Family> {
    let mut out = Vec::new();
    let mut rng = Rng(103);
    // Grazing: a big triangle in z = 0, rays at 1e-1..1e-6 rad aimed near its edge x = 0.
    let tri = vec![Shape::from([
        [0.0, -4.0, 0.0],
        [0.0, 4.0, 0.0],
        [8.0, 0.0, 0.0],
    ])];
    let mut rays = Vec::new();
    for e in 1..=6 {
        let a = 10f64.powi(-e);
        for _ in 0..60 {
            let az = rng.range(0.0, std::f64::consts::TAU);
            let x = rng.range(-1e-3, 1e-3);
            let dir = [a.cos() * az.cos(), a.cos() * az.sin(), a.sin()];
            let target = [x, rng.range(-1.0, 1.0), 0.0];
            let o = [0, 1, 2].map(|k| (target[k] - 2.0 * dir[k]) as f32);
            rays.push(Ray::new(o, dir.map(|c| c as f32)));
        }
    }
    out.push(Family::new("grazing 1e-1..1e-6 rad", tri, rays).probing(
        "A big triangle met at 1e-1 to 1e-6 rad near its edge: rays nearly in its plane.",
    ));

    // Far: small triangles and spheres at 1e3..1e6 seen from the origin.
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for e in 3..=6 {
        let dist = 10f32.powi(e);
        let c = [dist * 0.6, dist * 0.8, rng.range(-1.0, 1.0) as f32];
        let s = dist * 1e-3;
        shapes.push(Shape::from([
            [c[0] - s, c[1], c[2] - s],
            [c[0] + s, c[1], c[2] - s],
            [c[0], c[1], c[2] + s],
        ]));
        let sc = [-c[0], c[1], c[2]];
        shapes.push(Shape::sphere(sc, s));
        for _ in 0..60 {
            let p = [
                c[0] + s * rng.range(-1.2, 1.2) as f32,
                c[1],
                c[2] + s * rng.range(-1.2, 1.2) as f32,
            ];
            rays.push(Ray::new([0.0; 3], p));
            let p = [0, 1, 2].map(|k| sc[k] + s * rng.range(-1.2, 1.2) as f32);
            rays.push(Ray::new([0.0; 3], p));
        }
    }
    out.push(Family::new(
        "far triangles and spheres 1e3..1e6",
        shapes,
        rays,
    )
        .probing("Small triangles and spheres 1e3 to 1e6 away from the origin: t large, the shape small."));
    out
}

/// The near coincident families.
pub fn near_coincident() -> Vec<Family> {
    let mut out = Vec::new();
    let mut rng = Rng(104);
    // Parallel triangles 1e-3..1e-7 apart: which is nearer?
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for (k, gap) in [1e-3f32, 1e-5, 1e-6, 1e-7].into_iter().enumerate() {
        let x = 10.0 * k as f32;
        let z = 1.0f32;
        shapes.push(Shape::from([
            [x - 1.0, -1.0, z + gap],
            [x + 1.0, -1.0, z + gap],
            [x, 1.0, z + gap],
        ]));
        shapes.push(Shape::from([
            [x - 1.0, -1.0, z],
            [x + 1.0, -1.0, z],
            [x, 1.0, z],
        ]));
        for _ in 0..100 {
            let p = [
                x + rng.range(-0.4, 0.4) as f32,
                rng.range(-0.8, 0.2) as f32,
                z,
            ];
            let o = [x, 0.0, -1.0];
            rays.push(Ray::new(o, [0, 1, 2].map(|c| p[c] - o[c])));
        }
    }
    out.push(
        Family::new("parallel 1e-3..1e-7 apart", shapes, rays)
            .probing("Two parallel triangles 1e-3 to 1e-7 apart: which one is nearer."),
    );

    // Crossing triangles: two planes meeting along a line at 1e-1..1e-4 rad; rays aimed near
    // the line, where the nearer one changes.
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for (k, angle) in [1e-1f64, 1e-2, 1e-3, 1e-4].into_iter().enumerate() {
        let x = 10.0 * k as f32;
        let dz = (2.0 * angle.tan()) as f32;
        shapes.push(Shape::from([
            [x - 1.0, -1.0, 1.0 - dz],
            [x + 1.0, -1.0, 1.0 - dz],
            [x, 1.0, 1.0 + dz],
        ]));
        shapes.push(Shape::from([
            [x - 1.0, -1.0, 1.0],
            [x + 1.0, -1.0, 1.0],
            [x, 1.0, 1.0],
        ]));
        for _ in 0..100 {
            let p = [
                x + rng.range(-0.3, 0.3) as f32,
                rng.range(-1e-3, 1e-3) as f32,
                1.0,
            ];
            let o = [x, rng.range(-0.5, 0.5) as f32, -1.0];
            rays.push(Ray::new(o, [0, 1, 2].map(|c| p[c] - o[c])));
        }
    }
    out.push(Family::new("crossing at 1e-1..1e-4 rad", shapes, rays)
        .probing("Two triangles crossing at 1e-1 to 1e-4 rad: the nearer one changes along the crossing line."));

    // A triangle just in front of a sphere (and one touching it: exact ties on the axis).
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for (k, gap) in [1e-3f32, 1e-5, 1e-7, 0.0].into_iter().enumerate() {
        let x = 10.0 * k as f32;
        let z = 4.0 - gap;
        shapes.push(Shape::sphere([x, 0.0, 5.0], 1.0));
        shapes.push(Shape::from([
            [x - 0.5, -0.5, z],
            [x + 0.5, -0.5, z],
            [x, 0.5, z],
        ]));
        rays.push(Ray::new([x, 0.0, 0.0], [0.0, 0.0, 1.0]));
        for _ in 0..99 {
            let p = [
                x + rng.range(-0.01, 0.01) as f32,
                rng.range(-0.01, 0.01) as f32,
                4.0,
            ];
            let o = [x, 0.0, 0.0];
            rays.push(Ray::new(o, [0, 1, 2].map(|c| p[c] - o[c])));
        }
    }
    out.push(Family::new(
        "triangle 1e-3..0 before a sphere",
        shapes,
        rays,
    )
        .probing("A triangle 1e-3 to 0 in front of a sphere (touching on the axis: an exact tie, where either passes; raylab answers the lower index)."));

    // 60 different triangles overlapping in one tilted plane z = (x + 2y)/4 (vertices exact in
    // f32), growing with the index, and one just in front of the plane: every ray meets many
    // at exactly the same t, the lowest index among them wins, unless the one in front is hit.
    let mut shapes = Vec::new();
    let on_plane = |x: f32, y: f32| [x, y, (x + 2.0 * y) / 4.0];
    for k in 0..60 {
        let r = 1.0 + k as f32 * 0.25;
        let (cx, cy) = ((k % 7) as f32 * 0.25 - 0.75, (k % 5) as f32 * 0.25 - 0.5);
        shapes.push(Shape::from([
            on_plane(cx - r, cy - r),
            on_plane(cx + r, cy - r),
            on_plane(cx, cy + r),
        ]));
    }
    let front = |x: f32, y: f32| {
        let p = on_plane(x, y);
        [p[0], p[1], p[2] - 1.0 / 1024.0]
    };
    shapes.push(Shape::from([
        front(2.0, 2.0),
        front(4.0, 2.0),
        front(3.0, 4.0),
    ]));
    let mut rays = Vec::new();
    for _ in 0..400 {
        let p = on_plane(rng.range(-6.0, 6.0) as f32, rng.range(-6.0, 6.0) as f32);
        let o = [
            rng.range(-1.0, 1.0) as f32,
            rng.range(-1.0, 1.0) as f32,
            -30.0,
        ];
        rays.push(Ray::new(o, [0, 1, 2].map(|c| p[c] - o[c])));
    }
    out.push(Family::new("60 overlapping coplanar faces", shapes, rays)
        .probing("60 triangles overlapping in one plane: exact ties at every ray (either of those tied passes; raylab answers the lowest index), unless the one just in front is hit."));
    out
}

/// The spheres families.
pub fn spheres() -> Vec<Family> {
    let mut out = Vec::new();
    let mut rng = Rng(105);
    // Small and far: radius/distance 1e-3..1e-5, rays at the silhouette and across it.
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for (k, ratio) in [1e-3f64, 1e-4, 1e-5].into_iter().enumerate() {
        let dist = 10f64.powi(k as i32 + 1);
        let c = [dist * 0.48, -dist * 0.6, dist * 0.64].map(|x| x as f32);
        let r = (dist * ratio) as f32;
        shapes.push(Shape::sphere(c, r));
        for _ in 0..120 {
            let off = rng.range(0.9, 1.1) * r as f64;
            let a = rng.range(0.0, std::f64::consts::TAU);
            // A point off the centre by about r, perpendicular-ish to the view line.
            let p = [
                c[0] as f64 + off * a.cos() * 0.8,
                c[1] as f64 + off * a.sin(),
                c[2] as f64 - off * a.cos() * 0.6,
            ];
            rays.push(Ray::new([0.0; 3], p.map(|x| x as f32)));
        }
    }
    out.push(Family::new("small far spheres 1e-3..1e-5", shapes, rays)
        .probing("Spheres whose radius is 1e-3 to 1e-5 of their distance, rays at the silhouette: the quadratic's cancellation."));

    // Origins exactly on the sphere (Pythagorean points), going in, out and in random
    // directions.
    for (centre, radius, p) in [
        ([0.0f32, 0.0, 0.0], 5.0f32, [3.0f32, 4.0, 0.0]),
        ([1.0, 2.0, 3.0], 13.0, [6.0, 14.0, 3.0]),
        ([0.5, 0.25, 0.0], 0.625, [0.875, 0.75, 0.0]),
    ] {
        let n = [0, 1, 2].map(|k| p[k] - centre[k]);
        let rays: Vec<Ray<f32>> = (0..200)
            .map(|j| match j % 4 {
                0 => Ray::new(p, n.map(|x| -x)),
                1 => Ray::new(p, n),
                _ => Ray::new(p, [0, 1, 2].map(|_| rng.range(-1.0, 1.0) as f32)),
            })
            .collect();
        let family = format!("origin on the sphere, r = {radius}");
        out.push(Family::new(
            &family,
            vec![Shape::sphere(centre, radius)],
            rays,
        )
        .probing("Ray origins exactly on a sphere, going in, out and across: t = 0 is not a hit (tmin = 0 is open)."));
    }

    // Inside and just outside (one ulp beyond the surface point).
    let sphere = vec![Shape::sphere([0.0, 0.0, 0.0], 5.0)];
    let mut rays = Vec::new();
    for j in 0..300 {
        let o = match j % 3 {
            0 => [0, 1, 2].map(|_| rng.range(-2.8, 2.8) as f32),
            1 => [3.0f32.next_up(), 4.0f32.next_up(), 0.0],
            _ => [0.0, -3.0f32.next_down(), 4.0f32.next_up()],
        };
        let d = [0, 1, 2].map(|_| rng.range(-1.0, 1.0) as f32);
        rays.push(Ray::new(o, d));
    }
    out.push(
        Family::new("inside and one ulp outside", sphere, rays)
            .probing("Origins inside a sphere and one ulp outside it."),
    );

    // Near-tangent: the ray passes the centre at r·(1 ± 10^-k), k = 3..7, and exactly at r.
    let sphere = vec![Shape::sphere([0.0, 0.0, 8.0], 2.0)];
    let mut rays = Vec::new();
    for k in 3..=7 {
        for _ in 0..60 {
            let s = if rng.below(2) == 0 { 1.0 } else { -1.0 };
            let miss = 2.0 * (1.0 + s * 10f64.powi(-k) * rng.range(0.5, 1.5));
            let a = rng.range(0.0, std::f64::consts::TAU);
            rays.push(Ray::new(
                [(miss * a.cos()) as f32, (miss * a.sin()) as f32, 0.0],
                [0.0, 0.0, 1.0],
            ));
        }
    }
    for p in [[2.0f32, 0.0, 0.0], [0.0, -2.0, 0.0], [-2.0, 0.0, 0.0]] {
        rays.push(Ray::new(p, [0.0, 0.0, 1.0])); // exactly tangent: touches at t = 8
    }
    out.push(Family::new(
        "near-tangent 1e-3..1e-7 and tangent",
        sphere,
        rays,
    )
        .probing("Rays passing a sphere at r(1 ± 1e-3..1e-7), and exactly tangent (a tangent touch is a hit)."));
    out
}

/// The cornell families.
pub fn cornell() -> Vec<Family> {
    let mut out = Vec::new();
    let scene = crate::Scene::cornell();
    let cam = crate::Camera::cornell(64);
    let mut rays: Vec<Ray<f32>> = (0..48)
        .flat_map(|j| (0..64).map(move |i| (i, j)))
        .map(|(i, j)| cam.ray_for_pixel(i, j, 64, 48))
        .collect();
    let o = cam.ray_for_pixel(0, 0, 64, 48).o;
    rays.extend(
        vertices_and_edge_midpoints(&scene.shapes)
            .into_iter()
            .map(|p| Ray::new(o, [0, 1, 2].map(|k| p[k] - o[k]))),
    );
    out.push(Family::new(
        "Cornell primary + edges/vertices",
        scene.shapes.clone(),
        rays,
    )
        .probing("The lab's Cornell box: the camera rays of a 64×48 image (row by row, from the top left), then rays at every vertex and edge midpoint."));
    out
}

/// The cornell translated families.
pub fn cornell_translated() -> Vec<Family> {
    let mut out = Vec::new();
    let scene = crate::Scene::cornell();
    let cam = crate::Camera::cornell(32);
    for offset in [1e4f32, 1e5, 1e6] {
        let shift = |p: [f32; 3]| [p[0] + offset, p[1] - offset, p[2] + offset];
        let shapes: Vec<Shape<f32>> = scene
            .shapes
            .iter()
            .map(|s| match s.triangle() {
                Some(v) => Shape::from(v.map(shift)),
                None => *s,
            })
            .collect();
        let rays: Vec<Ray<f32>> = (0..24)
            .flat_map(|j| (0..32).map(move |i| (i, j)))
            .map(|(i, j)| {
                let r = cam.ray_for_pixel(i, j, 32, 24);
                Ray::new(shift(r.o), r.d)
            })
            .collect();
        out.push(Family::new(
            format!("Cornell and camera at +{offset:e}"),
            shapes,
            rays,
        )
        .probing("The Cornell box and its camera moved 1e4 to 1e6 away: the same image, far from the origin."));
    }
    out
}
