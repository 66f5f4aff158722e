//! Seeded test geometry for the hard-case families: a tiny generator (so every run sees the
//! same cases), closed meshes whose vertices and edge midpoints are exact in f32, and rays
//! aimed at those points or exactly through them.

use crate::geometry::{Ray, Shape};

/// SplitMix64: a tiny seeded generator so every test run sees the same cases.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// An axis-aligned cube [offset, offset + size]³, each face an n×n grid of quads split into
/// two triangles along alternating diagonals. With n and size powers of two and an offset on
/// the same grid, every vertex and every edge midpoint is exact in f32.
pub fn cube(n: usize, size: f32, offset: [f32; 3]) -> Vec<Shape<f32>> {
    let mut tris = Vec::new();
    let step = size / n as f32;
    for axis in 0..3 {
        for side in [0.0f32, 1.0] {
            let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
            let p = |u: usize, v: usize| {
                let mut q = [0.0f32; 3];
                q[axis] = offset[axis] + side * size;
                q[a1] = offset[a1] + u as f32 * step;
                q[a2] = offset[a2] + v as f32 * step;
                q
            };
            for u in 0..n {
                for v in 0..n {
                    let (p00, p10, p01, p11) = (p(u, v), p(u + 1, v), p(u, v + 1), p(u + 1, v + 1));
                    if (u + v) % 2 == 0 {
                        tris.push(Shape::from([p00, p10, p11]));
                        tris.push(Shape::from([p00, p11, p01]));
                    } else {
                        tris.push(Shape::from([p00, p10, p01]));
                        tris.push(Shape::from([p10, p11, p01]));
                    }
                }
            }
        }
    }
    tris
}

/// An icosphere: the icosahedron subdivided `levels` times, vertices pushed to the sphere in
/// f32. Shared vertices are the same f32 values in every triangle that uses them.
pub fn icosphere(levels: u32, radius: f32, centre: [f32; 3]) -> Vec<Shape<f32>> {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut verts: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let mut faces: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::new();
        let mut midpoint = |a: usize, b: usize, verts: &mut Vec<[f64; 3]>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (verts[a], verts[b]);
                verts.push([
                    (p[0] + q[0]) / 2.0,
                    (p[1] + q[1]) / 2.0,
                    (p[2] + q[2]) / 2.0,
                ]);
                verts.len() - 1
            })
        };
        for f in &faces {
            let ab = midpoint(f[0], f[1], &mut verts);
            let bc = midpoint(f[1], f[2], &mut verts);
            let ca = midpoint(f[2], f[0], &mut verts);
            next.extend([[f[0], ab, ca], [f[1], bc, ab], [f[2], ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    let pts: Vec<[f32; 3]> = verts
        .iter()
        .map(|v| {
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            [0, 1, 2].map(|k| (centre[k] as f64 + v[k] / len * radius as f64) as f32)
        })
        .collect();
    faces
        .iter()
        .map(|f| Shape::from([pts[f[0]], pts[f[1]], pts[f[2]]]))
        .collect()
}

/// Every vertex and every edge midpoint (computed in f32) of a triangle mesh.
pub fn vertices_and_edge_midpoints(mesh: &[Shape<f32>]) -> Vec<[f32; 3]> {
    let mut out = Vec::new();
    for s in mesh {
        if let Some(v) = s.triangle() {
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                out.push(a);
                out.push([0, 1, 2].map(|c| (a[c] + b[c]) * 0.5));
            }
        }
    }
    out.sort_by(|a, b| a.partial_cmp(b).unwrap());
    out.dedup();
    out
}

/// Rays from `origins` at every vertex and edge midpoint of `mesh`.
pub fn aimed_rays(mesh: &[Shape<f32>], origins: &[[f32; 3]]) -> Vec<Ray<f32>> {
    let targets = vertices_and_edge_midpoints(mesh);
    origins
        .iter()
        .flat_map(|o| {
            targets
                .iter()
                .map(move |p| Ray::new(*o, [0, 1, 2].map(|k| p[k] - o[k])))
        })
        .collect()
}

pub fn random_points(rng: &mut Rng, n: usize, lo: f64, hi: f64) -> Vec<[f32; 3]> {
    (0..n)
        .map(|_| [0, 1, 2].map(|_| rng.range(lo, hi) as f32))
        .collect()
}

/// Rays from `o` to each point of `targets`, and rays ending exactly on each (origin the
/// target minus a short direction of few bits, kept where that subtraction is exact), so
/// that the exact ray passes exactly through the target.
pub fn rays_through(targets: &[[f32; 3]], origins: &[[f32; 3]]) -> Vec<Ray<f32>> {
    let mut rays = Vec::new();
    for o in origins {
        for p in targets {
            rays.push(Ray::new(*o, [0, 1, 2].map(|k| p[k] - o[k])));
        }
    }
    let steps = [[0.25f32, 0.5, 1.0], [-0.5, 0.125, -1.0], [0.0, -0.75, 0.5]];
    for p in targets {
        for d in steps {
            let o = [0, 1, 2].map(|k| p[k] - d[k]);
            let exact = (0..3).all(|k| o[k] as f64 + d[k] as f64 == p[k] as f64);
            if exact {
                rays.push(Ray::new(o, d));
            }
        }
    }
    rays
}
