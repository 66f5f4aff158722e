//! Where a ray meets a primitive, decided exactly: inside a triangle, on one of its edges, at
//! one of its vertices or outside it (from the exact signs of the ray's Plücker products with
//! the three edges, [`raylab::geometry::exact::orient`]); on a sphere, tangent to it or
//! outside it (from the exact sign of the discriminant, as a sum of f64s). What the ray inspector
//! says of a crack: a leak on a shared edge is a ray that runs exactly through the edge, or
//! within rounding of it.

use raylab::geometry::exact::{orient, orient_rational, two_sum};
use raylab::geometry::{Ray, Shape, Sphere, Triangle};
use std::cmp::Ordering;
use std::fmt;

/// A triangle's edges, in the order of [`Location`]'s edge numbers: edge k runs from vertex k
/// to vertex k + 1.
pub const EDGES: [&str; 3] = ["v0–v1", "v1–v2", "v2–v0"];

/// Where a ray's line meets a primitive.
#[derive(Clone, Debug, PartialEq)]
pub enum Location {
    /// Strictly inside the triangle; `nearest` is the edge it passes closest to, `weight` the
    /// barycentric weight of the vertex opposite it (an f64 estimate, for showing only: the
    /// decision is exact).
    Inside { nearest: usize, weight: f64 },
    /// Exactly on edge k (not at its ends).
    Edge(usize),
    /// Exactly at vertex k.
    Vertex(usize),
    /// Outside the triangle: beyond these edges.
    Outside(Vec<usize>),
    /// The ray is parallel to the triangle's plane (edge-on: missed).
    EdgeOn,
    /// Through the sphere (two points).
    Sphere,
    /// Tangent to the sphere (the exact discriminant is zero: one point).
    Tangent,
    /// Outside the sphere.
    MissesSphere,
}

/// The exact sign of det[d, a − o, b − o].
fn side(d: [f64; 3], o: [f64; 3], a: [f64; 3], b: [f64; 3]) -> Ordering {
    orient(d, o, a, b).unwrap_or_else(|| orient_rational(d, o, a, b))
}

/// The same determinant in plain f64 (for showing sizes, never for a decision).
fn side_f64(d: [f64; 3], o: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let (p, q) = (
        [0, 1, 2].map(|k| a[k] - o[k]),
        [0, 1, 2].map(|k| b[k] - o[k]),
    );
    d[0] * (p[1] * q[2] - p[2] * q[1])
        + d[1] * (p[2] * q[0] - p[0] * q[2])
        + d[2] * (p[0] * q[1] - p[1] * q[0])
}

/// Where the line of `ray` meets `shape`, decided exactly.
pub fn locate(shape: &Shape, ray: &Ray) -> Location {
    let (o, d) = (ray.o.map(f64::from), ray.d.map(f64::from));
    match shape {
        Shape::Triangle(Triangle(v)) => triangle(&v.map(|p| p.map(f64::from)), o, d),
        Shape::Sphere(Sphere { centre, radius }) => {
            sphere(centre.map(f64::from), *radius as f64, o, d)
        }
    }
}

fn triangle(v: &[[f64; 3]; 3], o: [f64; 3], d: [f64; 3]) -> Location {
    // The sign every edge has for a line through the inside: that of d·((v1 − v0) × (v2 − v0))
    // (the three edges' products sum to it).
    let inside = side(d, v[0], v[1], v[2]);
    if inside == Ordering::Equal {
        return Location::EdgeOn;
    }
    let signs = [0, 1, 2].map(|k| side(d, o, v[k], v[(k + 1) % 3]));
    let beyond: Vec<usize> = (0..3).filter(|&k| signs[k] == inside.reverse()).collect();
    if !beyond.is_empty() {
        return Location::Outside(beyond);
    }
    let zeros: Vec<usize> = (0..3).filter(|&k| signs[k] == Ordering::Equal).collect();
    match zeros[..] {
        [] => {
            let values = [0, 1, 2].map(|k| side_f64(d, o, v[k], v[(k + 1) % 3]));
            let total: f64 = values.iter().sum();
            let weights = values.map(|x| x / total);
            let nearest = (0..3)
                .min_by(|&a, &b| weights[a].total_cmp(&weights[b]))
                .expect("three edges");
            Location::Inside {
                nearest,
                weight: weights[nearest],
            }
        }
        [k] => Location::Edge(k),
        // Edges i and j meet at their shared vertex.
        [i, j] => Location::Vertex(if j == (i + 1) % 3 { j } else { i }),
        _ => Location::EdgeOn,
    }
}

fn sphere(centre: [f64; 3], radius: f64, o: [f64; 3], d: [f64; 3]) -> Location {
    let safe = |x: f64| x == 0.0 || (2f64.powi(-120)..=2f64.powi(120)).contains(&x.abs());
    let inputs = [centre, o, d].concat();
    if !(inputs.iter().chain([&radius]).all(|&x| safe(x))) {
        // (Past the range where the expansions below stay clear of underflow: whether the
        // line meets the sphere, exactly, without telling a touch from a crossing.)
        let all = f64::INFINITY;
        return match raylab::geometry::sphere::exact(o, d, centre, radius, -all, all) {
            Some(_) => Location::Sphere,
            None => Location::MissesSphere,
        };
    }
    // The discriminant b² − a·c with a = d·d, b = f·d, c = f·f − r², f = o − centre, as an
    // exact sum of f64s.
    let f: Vec<Expansion> = (0..3).map(|k| sum(&[o[k]], &[-centre[k]])).collect();
    let d: Vec<Expansion> = d.iter().map(|&x| vec![x]).collect();
    let dot = |x: &[Expansion], y: &[Expansion]| {
        (0..3).fold(Vec::new(), |acc, k| sum(&acc, &product(&x[k], &y[k])))
    };
    let (a, b) = (dot(&d, &d), dot(&f, &d));
    let c = sum(&dot(&f, &f), &product(&[-radius], &[radius]));
    let disc = sum(&product(&b, &b), &product(&product(&[-1.0], &a), &c));
    match disc
        .iter()
        .rev()
        .find(|x| **x != 0.0)
        .map_or(Ordering::Equal, |x| x.total_cmp(&0.0))
    {
        Ordering::Less => Location::MissesSphere,
        Ordering::Equal => Location::Tangent,
        Ordering::Greater => Location::Sphere,
    }
}

/// A sum of f64s that do not overlap, smallest first (Shewchuk): its sign is its last term's.
type Expansion = Vec<f64>;

/// e + b, exactly.
fn grow(e: &[f64], b: f64) -> Expansion {
    let mut out = Vec::with_capacity(e.len() + 1);
    let mut q = b;
    for &x in e {
        let (s, h) = two_sum(q, x);
        if h != 0.0 {
            out.push(h);
        }
        q = s;
    }
    if q != 0.0 {
        out.push(q);
    }
    out
}

/// e + f, exactly.
fn sum(e: &[f64], f: &[f64]) -> Expansion {
    f.iter().fold(e.to_vec(), |acc, &x| grow(&acc, x))
}

/// e · f, exactly (each product of two terms split by a fused multiply-add).
fn product(e: &[f64], f: &[f64]) -> Expansion {
    let mut out = Vec::new();
    for &x in e {
        for &y in f {
            let p = x * y;
            out = grow(&grow(&out, x.mul_add(y, -p)), p);
        }
    }
    out
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            Location::Inside { nearest, weight } => write!(
                f,
                "inside (nearest the edge {}: barycentric {weight:.1e})",
                EDGES[*nearest]
            ),
            Location::Edge(k) => write!(f, "on the edge {}", EDGES[*k]),
            Location::Vertex(k) => write!(f, "at vertex v{k}"),
            Location::Outside(edges) => {
                let names: Vec<&str> = edges.iter().map(|&k| EDGES[k]).collect();
                match names[..] {
                    [one] => write!(f, "outside, beyond the edge {one}"),
                    _ => write!(f, "outside, beyond the edges {}", names.join(" and ")),
                }
            }
            Location::EdgeOn => f.write_str("edge-on (the ray is parallel to its plane)"),
            Location::Sphere => f.write_str("on the sphere"),
            Location::Tangent => f.write_str("tangent to the sphere (discriminant exactly 0)"),
            Location::MissesSphere => f.write_str("outside the sphere"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [f32; 3], d: [f32; 3]) -> Ray {
        Ray::new(o, d)
    }

    #[test]
    fn inside_on_an_edge_at_a_vertex_and_outside_are_told_apart_exactly() {
        let tri = Shape::from([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]);
        let at = |x: f32, y: f32| locate(&tri, &ray([x, y, 0.0], [0.0, 0.0, 1.0]));
        assert!(matches!(at(0.25, 0.25), Location::Inside { .. }));
        assert_eq!(at(0.5, 0.0), Location::Edge(0));
        assert_eq!(at(0.5, 0.5), Location::Edge(1));
        assert_eq!(at(0.0, 0.5), Location::Edge(2));
        assert_eq!(at(0.0, 0.0), Location::Vertex(0));
        assert_eq!(at(1.0, 0.0), Location::Vertex(1));
        assert_eq!(at(0.0, 1.0), Location::Vertex(2));
        assert_eq!(at(0.6, 0.6), Location::Outside(vec![1]));
        assert_eq!(at(-0.5, -0.5), Location::Outside(vec![0, 2]));
        // Just off the edge v1–v2, by one f32 step: outside, not on it.
        let next = f32::from_bits(0.5f32.to_bits() + 1);
        assert_eq!(at(next, 0.5), Location::Outside(vec![1]));
        // Seen from behind: the same answers (two-sided).
        let back = locate(&tri, &ray([0.5, 0.0, 2.0], [0.0, 0.0, -1.0]));
        assert_eq!(back, Location::Edge(0));
        // In the triangle's plane.
        let flat = locate(&tri, &ray([-1.0, 0.25, 1.0], [1.0, 0.0, 0.0]));
        assert_eq!(flat, Location::EdgeOn);
        assert_eq!(at(0.0, 1.0).to_string(), "at vertex v2");
        assert_eq!(at(0.5, 0.0).to_string(), "on the edge v0–v1");
    }

    #[test]
    fn a_sphere_is_met_touched_or_missed() {
        let ball = Shape::sphere([0.0, 0.0, 5.0], 1.0);
        let at = |x: f32| locate(&ball, &ray([x, 0.0, 0.0], [0.0, 0.0, 1.0]));
        assert_eq!(at(0.5), Location::Sphere);
        assert_eq!(at(1.0), Location::Tangent);
        assert_eq!(at(-1.0), Location::Tangent);
        assert_eq!(
            at(f32::from_bits(1.0f32.to_bits() + 1)),
            Location::MissesSphere
        );
    }
}
