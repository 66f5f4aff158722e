//! The hard-case suite: families of shapes and rays (fixed seeds, several hundred rays each)
//! and an exact reference for them, written independently of the library's own exact level:
//! every f32 input is an exact rational (`num-rational`), hit or miss is decided for the closed
//! triangle or sphere, the nearest primitive (exact ties to the lower index), and t.
//!
//! Shared by tests/hard_cases.rs (which asserts on it) and examples/speed_vs_error.rs (which
//! reports speed against error on it).

use super::{cube, icosphere, vertices_and_edge_midpoints, Rng};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use raylab::geometry::{Ray, Shape};
use raylab::math::Real;
use std::cmp::Ordering;

/// One family: a scene and the rays shot at it (all with tmin = 0, tmax = ∞), in f32 (the
/// suite) or f64.
pub struct Family<T: Real = f32> {
    pub name: String,
    pub shapes: Vec<Shape<T>>,
    pub rays: Vec<Ray<T>>,
}

impl<T: Real> Family<T> {
    pub fn new(name: impl Into<String>, shapes: Vec<Shape<T>>, rays: Vec<Ray<T>>) -> Self {
        Self {
            name: name.into(),
            shapes,
            rays,
        }
    }
}

/// Every family.
pub fn all() -> Vec<Family> {
    [
        closed_meshes(),
        tiny_huge_and_offset(),
        grazing_and_far(),
        near_coincident(),
        spheres(),
        cornell(),
        cornell_translated(),
        round_two(),
    ]
    .into_iter()
    .flatten()
    .collect()
}

pub type Q = BigRational;

pub fn q(x: f32) -> Q {
    Q::from_float(x).expect("finite")
}

/// Any finite f32 or f64 as the exact rational it is.
pub fn qr<T: Real>(x: T) -> Q {
    Q::from_float(x.f64()).expect("finite")
}

/// An exact t: a rational, or an irrational sphere root known within 2⁻²⁵⁶ relative.
#[derive(Clone, Debug)]
pub enum RefT {
    Exact(Q),
    Between(Q, Q),
}

impl RefT {
    fn bounds(&self) -> (&Q, &Q) {
        match self {
            RefT::Exact(x) => (x, x),
            RefT::Between(lo, hi) => (lo, hi),
        }
    }

    /// Exact comparison; an irrational root never equals another number here (the families
    /// hold one sphere each), so its bounds always separate.
    pub fn cmp(&self, other: &RefT) -> Ordering {
        if let (RefT::Exact(a), RefT::Exact(b)) = (self, other) {
            return a.cmp(b);
        }
        let ((alo, ahi), (blo, bhi)) = (self.bounds(), other.bounds());
        if ahi < blo {
            Ordering::Less
        } else if alo > bhi {
            Ordering::Greater
        } else {
            panic!("reference cannot order {self:?} and {other:?}")
        }
    }

    pub fn f64(&self) -> f64 {
        self.bounds().0.to_f64().unwrap()
    }

    /// The value correctly rounded to T (nearest, ties to even, IEEE overflow and
    /// underflow), or `None` where an irrational root's bounds round apart.
    pub fn rounded<T: Real + Bits>(&self) -> Option<T> {
        let (lo, hi) = self.bounds();
        let (a, b) = (round_q::<T>(lo), round_q::<T>(hi));
        (a.to_bits_u64() == b.to_bits_u64()).then_some(a)
    }
}

/// Bit patterns, to compare floats bit for bit in tests (−0 ≠ +0).
pub trait Bits {
    fn to_bits_u64(self) -> u64;
}
impl Bits for f32 {
    fn to_bits_u64(self) -> u64 {
        self.to_bits() as u64
    }
}
impl Bits for f64 {
    fn to_bits_u64(self) -> u64 {
        self.to_bits()
    }
}

/// x rounded to the nearest value of T with ties to even, written from the definition with
/// integers (independent of the library's search over midpoints): the binade of x, its
/// quantum 2^(max(e, emin) − p + 1), the quotient and remainder, ∞ from 2^(emax+1) up.
pub fn round_q<T: Real>(x: &Q) -> T {
    let (precision, emin, emax): (i64, i64, i64) = match std::mem::size_of::<T>() {
        4 => (24, -126, 127),
        _ => (53, -1022, 1023),
    };
    if x.is_zero() {
        return T::zero();
    }
    let negative = x.is_negative();
    let (n, d) = (x.numer().abs(), x.denom().clone());
    let shifted = |v: &BigInt, by: i64| -> BigInt {
        if by >= 0 {
            v << by as usize
        } else {
            v >> (-by) as usize
        }
    };
    // 2^e ≤ |x| < 2^(e+1).
    let mut e = n.bits() as i64 - d.bits() as i64;
    let below = if e >= 0 {
        n < shifted(&d, e)
    } else {
        shifted(&n, -e) < d
    };
    if below {
        e -= 1;
    }
    let quantum = e.max(emin) - (precision - 1);
    let (num, den) = if quantum >= 0 {
        (n, shifted(&d, quantum))
    } else {
        (shifted(&n, -quantum), d)
    };
    let (mut m, r) = (&num / &den, &num % &den);
    let twice_r: BigInt = r * 2;
    if twice_r > den || (twice_r == den && (&m % 2u32) == BigInt::one()) {
        m += 1;
    }
    let magnitude = if m.bits() as i64 + quantum > emax + 1 {
        f64::INFINITY
    } else {
        let m = m.to_f64().expect("at most 2^53");
        m * 2f64.powi((quantum / 2) as i32) * 2f64.powi((quantum - quantum / 2) as i32)
    };
    let v = T::of(magnitude);
    if negative {
        -v
    } else {
        v
    }
}

/// √x within bounds 2⁻²⁵⁶ apart (relative), exact when x is a square.
fn sqrt_q(x: &Q) -> RefT {
    let (n, m) = (x.numer(), x.denom());
    let k = 256u32;
    let big = n * m * (BigInt::one() << (2 * k));
    let s = big.sqrt();
    let den = m * (BigInt::one() << k);
    if &s * &s == big {
        RefT::Exact(Q::new(s, den))
    } else {
        RefT::Between(Q::new(s.clone(), den.clone()), Q::new(s + 1, den))
    }
}

pub fn sub(a: &[Q; 3], b: &[Q; 3]) -> [Q; 3] {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}
pub fn cross(a: &[Q; 3], b: &[Q; 3]) -> [Q; 3] {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}
pub fn dot(a: &[Q; 3], b: &[Q; 3]) -> Q {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

/// Exact t of the ray on one primitive with tmin < t (nearest root for a sphere).
pub fn exact_t<T: Real>(shape: &Shape<T>, o: &[Q; 3], d: &[Q; 3], tmin: &Q) -> Option<RefT> {
    match shape {
        Shape::Triangle(v) => {
            let v = v.map(|p| p.map(qr));
            let e1 = sub(&v[1], &v[0]);
            let e2 = sub(&v[2], &v[0]);
            let p = cross(d, &e2);
            let det = dot(&e1, &p);
            if det.is_zero() {
                return None; // in the plane or degenerate: a miss by convention
            }
            let s0 = sub(o, &v[0]);
            let qv = cross(&s0, &e1);
            let b1 = dot(&s0, &p) / &det;
            let b2 = dot(d, &qv) / &det;
            let t = dot(&e2, &qv) / &det;
            let inside = !b1.is_negative() && !b2.is_negative() && &b1 + &b2 <= Q::one();
            (inside && &t > tmin).then_some(RefT::Exact(t))
        }
        Shape::Sphere { centre, radius } => {
            let f = sub(o, &centre.map(qr));
            let r = qr(*radius);
            let a = dot(d, d);
            let b = dot(&f, d);
            let c = dot(&f, &f) - &r * &r;
            let disc = &b * &b - &a * &c;
            if disc.is_negative() {
                return None;
            }
            let root = sqrt_q(&disc);
            let (lo, hi) = root.bounds();
            let nb = -&b;
            let near = match &root {
                RefT::Exact(s) => RefT::Exact((&nb - s) / &a),
                _ => RefT::Between((&nb - hi) / &a, (&nb - lo) / &a),
            };
            let far = match &root {
                RefT::Exact(s) => RefT::Exact((&nb + s) / &a),
                _ => RefT::Between((&nb + lo) / &a, (&nb + hi) / &a),
            };
            let tmin = RefT::Exact(tmin.clone());
            [near, far]
                .into_iter()
                .find(|t| t.cmp(&tmin) == Ordering::Greater)
        }
    }
}

/// Exact nearest hit with t > 0: (t, primitive), ties to the lower index.
pub fn exact_nearest<T: Real>(shapes: &[Shape<T>], ray: &Ray<T>) -> Option<(RefT, u32)> {
    exact_nearest_between(shapes, ray, &Q::zero(), None)
}

/// Exact nearest hit with tmin < t < tmax (tmax `None`: ∞), ties to the lower index.
pub fn exact_nearest_between<T: Real>(
    shapes: &[Shape<T>],
    ray: &Ray<T>,
    tmin: &Q,
    tmax: Option<&Q>,
) -> Option<(RefT, u32)> {
    let (o, d) = (ray.o.map(qr), ray.d.map(qr));
    let mut best: Option<(RefT, u32)> = None;
    for (i, s) in shapes.iter().enumerate() {
        let Some(t) = exact_t(s, &o, &d, tmin) else {
            continue;
        };
        let below = tmax.is_none_or(|m| t.cmp(&RefT::Exact(m.clone())) == Ordering::Less);
        if below
            && best
                .as_ref()
                .is_none_or(|(bt, _)| t.cmp(bt) == Ordering::Less)
        {
            best = Some((t, i as u32));
        }
    }
    best
}

#[derive(Default)]
pub struct Counts {
    pub rays: usize,
    pub leaks: usize,
    pub false_hits: usize,
    pub wrong_nearest: usize,
    pub pass_through: usize,
    pub rel_errors: Vec<f64>,
}

impl Counts {
    /// Rays answered wrongly in any way (a leak is also a pass-through: counted once).
    pub fn wrong(&self) -> usize {
        self.false_hits + self.wrong_nearest + self.pass_through
    }

    /// Scores one answer `got` = (t, primitive) against the exact reference.
    pub fn add(
        &mut self,
        shapes: &[Shape<f32>],
        ray: &Ray<f32>,
        exact: &Option<(RefT, u32)>,
        got: Option<(f64, u32)>,
    ) {
        self.rays += 1;
        match (exact, got) {
            (Some(_), None) => {
                self.leaks += 1;
                self.pass_through += 1;
            }
            (None, Some(_)) => self.false_hits += 1,
            (Some((t, prim)), Some((gt, gprim))) => {
                if *prim != gprim {
                    // A primitive exactly behind the nearest surface: slipped through it.
                    // (One the exact ray does not meet at all is a wrong primitive.)
                    let (o, d) = (ray.o.map(q), ray.d.map(q));
                    let beyond = exact_t(&shapes[gprim as usize], &o, &d, &Q::zero())
                        .is_some_and(|gt_exact| gt_exact.cmp(t) == Ordering::Greater);
                    if beyond {
                        self.pass_through += 1;
                    } else {
                        self.wrong_nearest += 1;
                    }
                } else {
                    let t = t.f64();
                    self.rel_errors.push(((gt - t) / t).abs());
                }
            }
            (None, None) => {}
        }
    }

    /// The relative t error at `quantile` (0.5: median, 1: largest).
    pub fn rel(&self, quantile: f64) -> f64 {
        let mut e = self.rel_errors.clone();
        e.sort_by(f64::total_cmp);
        let i = ((e.len() as f64 - 1.0) * quantile).round() as usize;
        e.get(i).copied().unwrap_or(0.0)
    }
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

/// The closed meshes families.
pub fn closed_meshes() -> Vec<Family> {
    let mut out = Vec::new();
    let mut rng = Rng(101);
    let cube_mesh = cube(2, 2.0, [-1.0; 3]);
    let rays = aimed_rays(&cube_mesh, &random_points(&mut rng, 3, -0.9, 0.9));
    out.push(Family::new("cube, from inside", cube_mesh.clone(), rays));
    // From outside, rays aimed at silhouette edges touch the mesh only at the edge.
    let rays = aimed_rays(&cube_mesh, &random_points(&mut rng, 2, 2.0, 4.0));
    out.push(Family::new("cube, from outside", cube_mesh.clone(), rays));

    let ico = icosphere(1, 1.0, [0.0; 3]);
    let rays = aimed_rays(&ico, &random_points(&mut rng, 3, -0.5, 0.5));
    out.push(Family::new("icosphere, from inside", ico.clone(), rays));
    let rays = aimed_rays(&ico, &random_points(&mut rng, 2, 1.5, 3.0));
    out.push(Family::new("icosphere, from outside", ico.clone(), rays));
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
        ));
    }
    out
}

/// The grazing and far families.
pub fn grazing_and_far() -> Vec<Family> {
    let mut out = Vec::new();
    let mut rng = Rng(103);
    // Grazing: a big triangle in z = 0, rays at 1e-1..1e-6 rad aimed near its edge x = 0.
    let tri = vec![Shape::Triangle([
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
    out.push(Family::new("grazing 1e-1..1e-6 rad", tri, rays));

    // Far: small triangles and spheres at 1e3..1e6 seen from the origin.
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for e in 3..=6 {
        let dist = 10f32.powi(e);
        let c = [dist * 0.6, dist * 0.8, rng.range(-1.0, 1.0) as f32];
        let s = dist * 1e-3;
        shapes.push(Shape::Triangle([
            [c[0] - s, c[1], c[2] - s],
            [c[0] + s, c[1], c[2] - s],
            [c[0], c[1], c[2] + s],
        ]));
        let sc = [-c[0], c[1], c[2]];
        shapes.push(Shape::Sphere {
            centre: sc,
            radius: s,
        });
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
    ));
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
        shapes.push(Shape::Triangle([
            [x - 1.0, -1.0, z + gap],
            [x + 1.0, -1.0, z + gap],
            [x, 1.0, z + gap],
        ]));
        shapes.push(Shape::Triangle([
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
    out.push(Family::new("parallel 1e-3..1e-7 apart", shapes, rays));

    // Crossing triangles: two planes meeting along a line at 1e-1..1e-4 rad; rays aimed near
    // the line, where the nearer one changes.
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for (k, angle) in [1e-1f64, 1e-2, 1e-3, 1e-4].into_iter().enumerate() {
        let x = 10.0 * k as f32;
        let dz = (2.0 * angle.tan()) as f32;
        shapes.push(Shape::Triangle([
            [x - 1.0, -1.0, 1.0 - dz],
            [x + 1.0, -1.0, 1.0 - dz],
            [x, 1.0, 1.0 + dz],
        ]));
        shapes.push(Shape::Triangle([
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
    out.push(Family::new("crossing at 1e-1..1e-4 rad", shapes, rays));

    // A triangle just in front of a sphere (and one touching it: exact ties on the axis).
    let mut shapes = Vec::new();
    let mut rays = Vec::new();
    for (k, gap) in [1e-3f32, 1e-5, 1e-7, 0.0].into_iter().enumerate() {
        let x = 10.0 * k as f32;
        let z = 4.0 - gap;
        shapes.push(Shape::Sphere {
            centre: [x, 0.0, 5.0],
            radius: 1.0,
        });
        shapes.push(Shape::Triangle([
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
    ));

    // 60 different triangles overlapping in one tilted plane z = (x + 2y)/4 (vertices exact in
    // f32), growing with the index, and one just in front of the plane: every ray meets many
    // at exactly the same t, the lowest index among them wins, unless the one in front is hit.
    let mut shapes = Vec::new();
    let on_plane = |x: f32, y: f32| [x, y, (x + 2.0 * y) / 4.0];
    for k in 0..60 {
        let r = 1.0 + k as f32 * 0.25;
        let (cx, cy) = ((k % 7) as f32 * 0.25 - 0.75, (k % 5) as f32 * 0.25 - 0.5);
        shapes.push(Shape::Triangle([
            on_plane(cx - r, cy - r),
            on_plane(cx + r, cy - r),
            on_plane(cx, cy + r),
        ]));
    }
    let front = |x: f32, y: f32| {
        let p = on_plane(x, y);
        [p[0], p[1], p[2] - 1.0 / 1024.0]
    };
    shapes.push(Shape::Triangle([
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
    out.push(Family::new("60 overlapping coplanar faces", shapes, rays));
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
        shapes.push(Shape::Sphere {
            centre: c,
            radius: r,
        });
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
    out.push(Family::new("small far spheres 1e-3..1e-5", shapes, rays));

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
            vec![Shape::Sphere { centre, radius }],
            rays,
        ));
    }

    // Inside and just outside (one ulp beyond the surface point).
    let sphere = vec![Shape::Sphere {
        centre: [0.0, 0.0, 0.0],
        radius: 5.0,
    }];
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
    out.push(Family::new("inside and one ulp outside", sphere, rays));

    // Near-tangent: the ray passes the centre at r·(1 ± 10^-k), k = 3..7, and exactly at r.
    let sphere = vec![Shape::Sphere {
        centre: [0.0, 0.0, 8.0],
        radius: 2.0,
    }];
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
    ));
    out
}

/// The cornell families.
pub fn cornell() -> Vec<Family> {
    let mut out = Vec::new();
    let scene = raylab::Scene::cornell();
    let cam = raylab::Camera::cornell(64);
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
    ));
    out
}

/// The cornell translated families.
pub fn cornell_translated() -> Vec<Family> {
    let mut out = Vec::new();
    let scene = raylab::Scene::cornell();
    let cam = raylab::Camera::cornell(32);
    for offset in [1e4f32, 1e5, 1e6] {
        let shift = |p: [f32; 3]| [p[0] + offset, p[1] - offset, p[2] + offset];
        let shapes: Vec<Shape<f32>> = scene
            .shapes
            .iter()
            .map(|s| match s {
                Shape::Triangle(v) => Shape::Triangle(v.map(shift)),
                other => *other,
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
        ));
    }
    out
}

/// Rays from `o` to each point of `targets`, and rays ending exactly on each (origin the
/// target minus a short direction of few bits, kept where that subtraction is exact), so
/// that the exact ray passes exactly through the target.
fn rays_through(targets: &[[f32; 3]], origins: &[[f32; 3]]) -> Vec<Ray<f32>> {
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
        .map(|i| Shape::Triangle([apex, rim[i], rim[(i + 1) % 12]]))
        .collect();
    let mut targets = vertices_and_edge_midpoints(&fan);
    targets.push(apex);
    let origins = [[0.1f32, 0.2, 3.0], [-0.4, 0.3, -2.5], [2.0, -1.5, 1.0]];
    out.push(Family::new(
        "fan of 12 around an apex",
        fan,
        rays_through(&targets, &origins),
    ));

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
    let mut shapes: Vec<Shape<f32>> = flat.iter().map(|v| Shape::Triangle(*v)).collect();
    shapes.extend(flat.iter().map(|v| Shape::Triangle(v.map(turn))));
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
    ));

    // Rays in a triangle's plane (x + y + z = 1): along its edges' lines, across it, and
    // tilted out of the plane by an ulp; a wall behind catches what passes.
    let tri = [[1.0f32, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let shapes = vec![
        Shape::Triangle(tri),
        Shape::Triangle([[-8.0, -8.0, 6.0], [8.0, -8.0, 6.0], [0.0, 8.0, 6.0]]),
        Shape::Triangle([[-8.0, -8.0, -6.0], [0.0, 8.0, -6.0], [8.0, -8.0, -6.0]]),
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
    out.push(Family::new("rays in a triangle's plane", shapes, rays));

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
        shapes.extend(copies.into_iter().map(Shape::Triangle));
    }
    let mut targets = vertices_and_edge_midpoints(&shapes);
    targets.truncate(200);
    let origins = [[0.0f32, 0.0, -2.0], [1.5, -0.5, 0.0]];
    out.push(Family::new(
        "coincident copies, permuted and 1-ulp moved",
        shapes,
        rays_through(&targets, &origins),
    ));

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
    out.push(Family::new(
        "subnormal cube 2^-130",
        mesh.clone(),
        aimed_rays(&mesh, &origins),
    ));

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
    out.push(Family::new("origins at a vertex", ico, rays));

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
    out.push(Family::new("-0.0 directions", mesh, rays));

    // Slivers: needles 1e-3..1e-7 wide and a cap with its apex an ulp off the long edge, a
    // wall behind.
    let mut shapes = Vec::new();
    for (k, w) in [1e-3f32, 1e-5, 1e-7].into_iter().enumerate() {
        let x = 3.0 * k as f32;
        shapes.push(Shape::Triangle([
            [x, 0.0, 2.0],
            [x + 2.0, 0.0, 2.0],
            [x + 1.0, w, 2.0],
        ]));
    }
    shapes.push(Shape::Triangle([
        [9.0, 0.0, 2.0],
        [11.0, 0.0, 2.0],
        [10.0, 0.0f32.next_up(), 2.0],
    ]));
    shapes.push(Shape::Triangle([
        [9.0, 0.0, 2.0],
        [10.0, -0.0f32.next_up(), 2.0],
        [11.0, 0.0, 2.0],
    ]));
    shapes.push(Shape::Triangle([
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
    ));
    out
}
