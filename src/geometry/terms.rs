//! What the ray inspector shows of a shape's own math for one ray: the lecture's linear system
//! for a triangle, the quadratic for a sphere. Each shape's terms are written here, so the
//! inspector's text (`raylab inspect`) and the window's panel print them without naming a
//! shape.

use super::{Ray, Shape};

/// A primitive's terms for one ray, in f64 from the f32 inputs.
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeTerms {
    /// The lecture's linear system A·x = b for o + t·d = v₀ + u·e₁ + v·e₂: A = [−d e₁ e₂]
    /// (rows here), b = o − v₀, x = (t, u, v) = A⁻¹·b.
    Triangle {
        a: [[f64; 3]; 3],
        b: [f64; 3],
        x: [f64; 3],
    },
    /// |o + t·d − c|² = r² as a·t² + b·t + c = 0 with a = d·d, b = 2·d·(o − c),
    /// c = |o − c|² − r², and its discriminant b² − 4ac.
    Sphere {
        a: f64,
        b: f64,
        c: f64,
        discriminant: f64,
    },
}

impl Shape<f32> {
    /// This shape's terms for `ray` ([`ShapeTerms`]).
    pub fn terms(&self, ray: &Ray<f32>) -> ShapeTerms {
        let o = ray.o.map(f64::from);
        let d = ray.d.map(f64::from);
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        match self {
            Shape::Triangle(v) => {
                let v = v.map(|p| p.map(f64::from));
                let (e1, e2) = (sub(v[1], v[0]), sub(v[2], v[0]));
                let b = sub(o, v[0]);
                let a = [0, 1, 2].map(|r| [-d[r], e1[r], e2[r]]);
                ShapeTerms::Triangle {
                    a,
                    b,
                    x: solve3(&a, b),
                }
            }
            Shape::Sphere { centre, radius } => {
                let oc = sub(o, centre.map(f64::from));
                let r = *radius as f64;
                let (a, b, c) = (dot(d, d), 2.0 * dot(d, oc), dot(oc, oc) - r * r);
                ShapeTerms::Sphere {
                    a,
                    b,
                    c,
                    discriminant: b * b - 4.0 * a * c,
                }
            }
        }
    }
}

fn v3(v: [f64; 3]) -> String {
    format!("{} {} {}", v[0], v[1], v[2])
}

impl ShapeTerms {
    /// The `name: value` lines of `raylab inspect` (every digit).
    pub fn lines(&self) -> Vec<String> {
        match self {
            ShapeTerms::Triangle { a, b, x } => {
                let mut lines = vec!["shape: triangle".to_string()];
                lines.extend(
                    (a.iter().enumerate()).map(|(r, row)| format!("A_row{r}: {}", v3(*row))),
                );
                lines.push(format!("b: {}", v3(*b)));
                lines.push(format!("x_tuv: {}", v3(*x)));
                lines
            }
            ShapeTerms::Sphere {
                a,
                b,
                c,
                discriminant,
            } => vec![
                "shape: sphere".to_string(),
                format!("quadratic_abc: {a} {b} {c}"),
                format!("discriminant: {discriminant}"),
            ],
        }
    }

    /// The window panel's (label, value) rows, the values formatted by `v3` (triangles) or
    /// to a few digits (spheres).
    pub fn rows(&self, v3: impl Fn([f64; 3]) -> String) -> Vec<(&'static str, String)> {
        match self {
            ShapeTerms::Triangle { a, b, x } => vec![
                ("A = [-d e1 e2]", v3(a[0])),
                ("", v3(a[1])),
                ("", v3(a[2])),
                ("b = o - v0", v3(*b)),
                ("x = A^-1 b = (t,u,v)", v3(*x)),
            ],
            ShapeTerms::Sphere {
                a,
                b,
                c,
                discriminant,
            } => vec![
                ("a t^2 + b t + c", format!("a {a:.4}, b {b:.4}, c {c:.4}")),
                ("b^2 - 4ac", format!("{discriminant:.6}")),
            ],
        }
    }
}

/// x = A⁻¹·b by Cramer's rule in f64 (NaN where A is singular).
fn solve3(a: &[[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let det = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    [0, 1, 2].map(|col| {
        let mut m = *a;
        for (r, row) in m.iter_mut().enumerate() {
            row[col] = b[r];
        }
        det(&m) / d
    })
}
