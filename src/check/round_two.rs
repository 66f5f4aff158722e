//! The suite's second round of families: the kinds of input that make rounding go wrong
//! (shared apexes, T-junctions, rays in a triangle's plane, near copies, subnormals, origins at
//! a vertex, signed zeros, slivers).

use super::meshes::{aimed_rays, cube, icosphere, rays_through, vertices_and_edge_midpoints, Rng};
use super::suite::Family;
use crate::geometry::{Ray, Shape};

/// The second round's families (the rounding's hard kinds): a fan around a shared apex, T-junctions,
/// rays in a triangle's plane along its edge, permuted and 1-ulp-perturbed coincident copies,
/// subnormal geometry, origins at a vertex, −0.0 directions, slivers.
pub fn round_two() -> Vec<Family> {
    let mut out = Vec::new();
    let mut rng = Rng(106);

    // A fan of 12 triangles around an apex, the rim wavy (not planar).
    let apex = [0.3f32, -0.2, 0.5];
    let rim: Vec<[f32; 3]> = (0..12)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 12.0;
            [
                a.cos() as f32,
                a.sin() as f32,
                (0.3 * (3.0 * a).sin()) as f32,
            ]
        })
        .collect();
    let fan: Vec<Shape<f32>> = (0..12)
        .map(|i| Shape::from([apex, rim[i], rim[(i + 1) % 12]]))
        .collect();
    let mut targets = vertices_and_edge_midpoints(&fan);
    targets.push(apex);
    let origins = [[0.1f32, 0.2, 3.0], [-0.4, 0.3, -2.5], [2.0, -1.5, 1.0]];
    out.push(Family::new(
        "fan of 12 around an apex",
        fan,
        rays_through(&targets, &origins),
    )
        .probing("12 triangles around a shared apex, rays exactly through the apex, the vertices and the edge midpoints."));

    // T-junctions: a vertex of two small triangles in the middle of a big one's edge, in
    // z = 0 (exact) and the same turned in 3D (rounded: the T vertex then lies within
    // rounding of the edge).
    let flat = [
        [[0.0f32, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.5, -1.0, 0.0], [1.0, 0.0, 0.0]],
        [[1.0, 0.0, 0.0], [1.5, -1.0, 0.0], [2.0, 0.0, 0.0]],
        [[1.0, 0.0, 0.0], [0.5, -1.0, 0.0], [1.5, -1.0, 0.0]],
    ];
    let turn = |p: [f32; 3]| {
        let p = p.map(f64::from);
        let (a, b) = (0.7f64, 0.4f64);
        let x = p[0] * a.cos() - p[1] * a.sin();
        let y = p[0] * a.sin() + p[1] * a.cos();
        let (y, z) = (y * b.cos() - p[2] * b.sin(), y * b.sin() + p[2] * b.cos());
        [x as f32 + 5.0, y as f32, z as f32]
    };
    let mut shapes: Vec<Shape<f32>> = flat.iter().map(|v| Shape::from(*v)).collect();
    shapes.extend(flat.iter().map(|v| Shape::from(v.map(turn))));
    let mut targets = vertices_and_edge_midpoints(&shapes);
    for x in [0.25f32, 0.75, 1.0, 1.25, 1.75] {
        targets.push([x, 0.0, 0.0]);
        targets.push(turn([x, 0.0, 0.0]));
    }
    let origins = [[0.7f32, 0.3, -2.0], [1.1, -0.4, 3.0], [5.2, 0.5, -2.0]];
    out.push(Family::new(
        "T-junctions",
        shapes,
        rays_through(&targets, &origins),
    )
        .probing("T-junctions: a vertex in the middle of another triangle's edge, flat and turned in 3D."));

    // Rays in a triangle's plane (x + y + z = 1): along its edges' lines, across it, and
    // tilted out of the plane by an ulp; a wall behind catches what passes.
    let tri = [[1.0f32, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let shapes = vec![
        Shape::from(tri),
        Shape::from([[-8.0, -8.0, 6.0], [8.0, -8.0, 6.0], [0.0, 8.0, 6.0]]),
        Shape::from([[-8.0, -8.0, -6.0], [0.0, 8.0, -6.0], [8.0, -8.0, -6.0]]),
    ];
    let mut rays = Vec::new();
    for (i, j) in [(0, 1), (1, 2), (2, 0)] {
        let e = [0, 1, 2].map(|k| tri[j][k] - tri[i][k]);
        for s in [-3.0f32, -1.0, -0.5, 1.5, 2.0, 4.0] {
            let o = [0, 1, 2].map(|k| tri[i][k] + s * e[k]);
            for scale in [1.0f32, 0.25, 8.0] {
                for sign in [1.0f32, -1.0] {
                    let d = e.map(|c| c * scale * sign);
                    rays.push(Ray::new(o, d));
                    // One ulp out of the plane, either way.
                    rays.push(Ray::new(o, [d[0], d[1], (d[2] + 0.5).next_up() - 0.5]));
                    rays.push(Ray::new(o, [d[0].next_down(), d[1], d[2]]));
                }
            }
        }
    }
    for _ in 0..120 {
        // Across the triangle inside its plane: from a point of the plane to another.
        let a = [rng.range(-1.0, 2.0), rng.range(-1.0, 2.0)];
        let b = [rng.range(0.0, 1.0), rng.range(0.0, 1.0)];
        let on = |x: f64, y: f64| [x as f32, y as f32, (1.0 - x - y) as f32];
        let (p, q) = (on(a[0], a[1]), on(b[0], b[1]));
        rays.push(Ray::new(p, [0, 1, 2].map(|k| q[k] - p[k])));
    }
    out.push(Family::new("rays in a triangle's plane", shapes, rays)
        .probing("Rays in a triangle's plane along its edges' lines, across it, and one ulp out of the plane: edge-on is a miss."));

    // Coincident copies: each triangle also with its vertices rotated and reversed, and with
    // one coordinate moved by an ulp, the copies shuffled among the originals.
    let mut shapes = Vec::new();
    for _ in 0..12 {
        let c = [
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
            rng.range(2.0, 6.0),
        ];
        let v: [[f32; 3]; 3] =
            [0, 1, 2].map(|_| [0, 1, 2].map(|k| (c[k] + rng.range(-1.0, 1.0)) as f32));
        let mut moved = v;
        let (vi, k) = (rng.below(3), rng.below(3));
        moved[vi][k] = if rng.below(2) == 0 {
            moved[vi][k].next_up()
        } else {
            moved[vi][k].next_down()
        };
        let mut copies = vec![v, [v[1], v[2], v[0]], [v[2], v[1], v[0]], moved];
        for i in (1..copies.len()).rev() {
            copies.swap(i, rng.below(i + 1));
        }
        shapes.extend(copies.into_iter().map(Shape::from));
    }
    let mut targets = vertices_and_edge_midpoints(&shapes);
    targets.truncate(200);
    let origins = [[0.0f32, 0.0, -2.0], [1.5, -0.5, 0.0]];
    out.push(Family::new(
        "coincident copies, permuted and 1-ulp moved",
        shapes,
        rays_through(&targets, &origins),
    )
        .probing("Coincident copies of triangles, vertices permuted and one coordinate moved by an ulp: ties and near ties."));

    // Subnormal geometry: a cube of side 2^-130 (every coordinate below f32's least normal
    // 2^-126), seen from inside and outside.
    let size = 2f32.powi(-130);
    let mesh = cube(2, size, [0.0; 3]);
    let origins: Vec<[f32; 3]> = (0..3)
        .map(|i| {
            let f = if i == 2 { 2.5 } else { rng.range(0.2, 0.8) };
            [0, 1, 2].map(|_| size * f as f32)
        })
        .collect();
    out.push(
        Family::new(
            "subnormal cube 2^-130",
            mesh.clone(),
            aimed_rays(&mesh, &origins),
        )
        .probing("A cube of side 2^-130: every coordinate subnormal in f32."),
    );

    // Origins exactly at a vertex of a closed mesh: the faces there are met at t = 0, which
    // tmin = 0 excludes.
    let ico = icosphere(1, 1.0, [0.0; 3]);
    let corners = vertices_and_edge_midpoints(&ico);
    let mut rays = Vec::new();
    for _ in 0..300 {
        let o = corners[rng.below(corners.len())];
        let p = corners[rng.below(corners.len())];
        let d = match rng.below(3) {
            0 => [0, 1, 2].map(|_| rng.range(-1.0, 1.0) as f32),
            _ => [0, 1, 2].map(|k| p[k] - o[k]),
        };
        if d != [0.0; 3] {
            rays.push(Ray::new(o, d));
        }
    }
    out.push(Family::new("origins at a vertex", ico, rays)
        .probing("Origins exactly at a vertex of a closed mesh: the faces there meet the ray at t = 0, which does not count."));

    // −0.0 in directions: rays along the cube's edges and seams, and across them, with every
    // sign of zero.
    let mesh = cube(2, 2.0, [-1.0; 3]);
    let mut rays = Vec::new();
    for sx in [0.0f32, -0.0] {
        for sy in [0.0f32, -0.0] {
            for o in [
                [-1.0f32, -1.0, -5.0],
                [1.0, -1.0, -5.0],
                [0.0, -1.0, -5.0],
                [0.0, 0.0, -5.0],
                [-1.0, 0.0, -5.0],
                [0.5, 1.0, -5.0],
                [0.0, 0.0, 0.0],
            ] {
                for dz in [1.0f32, -1.0] {
                    rays.push(Ray::new(o, [sx, sy, dz]));
                }
                rays.push(Ray::new(o, [sx, 1.0, sy]));
                rays.push(Ray::new(o, [-1.0, sy, sx]));
            }
        }
    }
    out.push(Family::new("-0.0 directions", mesh, rays)
        .probing("Directions with -0.0 components along and across a cube's edges: signed zeros in divisions."));

    // Slivers: needles 1e-3..1e-7 wide and a cap with its apex an ulp off the long edge, a
    // wall behind.
    let mut shapes = Vec::new();
    for (k, w) in [1e-3f32, 1e-5, 1e-7].into_iter().enumerate() {
        let x = 3.0 * k as f32;
        shapes.push(Shape::from([
            [x, 0.0, 2.0],
            [x + 2.0, 0.0, 2.0],
            [x + 1.0, w, 2.0],
        ]));
    }
    shapes.push(Shape::from([
        [9.0, 0.0, 2.0],
        [11.0, 0.0, 2.0],
        [10.0, 0.0f32.next_up(), 2.0],
    ]));
    shapes.push(Shape::from([
        [9.0, 0.0, 2.0],
        [10.0, -0.0f32.next_up(), 2.0],
        [11.0, 0.0, 2.0],
    ]));
    shapes.push(Shape::from([
        [-10.0, -10.0, 9.0],
        [30.0, -10.0, 9.0],
        [10.0, 20.0, 9.0],
    ]));
    let mut targets = vertices_and_edge_midpoints(&shapes[..5]);
    for _ in 0..100 {
        let k = rng.below(4);
        let x = 3.0 * k as f64 + rng.range(0.0, 2.0);
        let y = [1e-3, 1e-5, 1e-7, 1e-45][k] * rng.range(-0.5, 1.5);
        targets.push([x as f32, y as f32, 2.0]);
    }
    let origins = [[1.0f32, 0.0, 0.0], [5.0, 0.5, -1.0]];
    out.push(Family::new(
        "slivers 1e-3..1e-45 wide",
        shapes,
        rays_through(&targets, &origins),
    )
        .probing("Needle triangles 1e-3 to 1e-45 wide and one of zero width, a wall behind: slivers must not leak."));
    out
}
