//! The f64 geometry of a graded ray that `check`'s hints and the run's evidence share: its
//! origin and direction, a triangle's plane, Möller–Trumbore's determinant (and what a small
//! one loses), a sphere's roots (and what the textbook quadratic loses), which side the ray
//! meets, how near two t's are, and what a correct program's rounding can lose (a hit near an
//! edge, near tmin or tmax) or not (a hit clearly inside).

use raylab::check::grade::Exact;
use raylab::geometry::Triangle;
use raylab::math::real::{cross, dot, sub};
use raylab::math::Real;

/// Möller–Trumbore's determinant e1·(d × e2) of ray `i` and triangle `tri` (−d·n), in f64.
pub(super) fn determinant<T: Real>(exact: &Exact<T>, i: usize, tri: &Triangle<T>) -> f64 {
    let (_, n) = plane_of(tri);
    -dot(o_and_d(exact, i).1, n)
}

/// Whether ray `i` meets triangle `tri`'s plane from its back (d·n > 0, beyond 10⁻⁶ of |d| |n|).
pub(super) fn faces_back<T: Real>(exact: &Exact<T>, i: usize, tri: &Triangle<T>) -> bool {
    let d = o_and_d(exact, i).1;
    let (_, n) = plane_of(tri);
    dot(d, n) > 1e-6 * length(d) * length(n)
}

/// Whether ray `i` meets primitive `prim` from its back: a triangle ([`faces_back`]); never
/// a sphere, nor an index past the last.
pub(super) fn meets_back<T: Real>(exact: &Exact<T>, i: usize, prim: u32) -> bool {
    match (prim as usize) < exact.primitives {
        true => match exact.shape(prim) {
            raylab::geometry::Shape::Triangle(tri) => faces_back(exact, i, &tri),
            raylab::geometry::Shape::Sphere(_) => false,
        },
        false => false,
    }
}

/// Whether `x` and `y` agree to 10⁻⁶ of the larger (in f64).
pub(super) fn near(x: f64, y: f64) -> bool {
    (x - y).abs() <= 1e-6 * x.abs().max(y.abs()).max(1e-30)
}

/// A triangle's v0 and its normal n = (v1 − v0) × (v2 − v0), in f64 (d·n > 0: met from its
/// back).
pub(super) fn plane_of<T: Real>(tri: &Triangle<T>) -> ([f64; 3], [f64; 3]) {
    let v = tri.0.map(|p| p.map(|c| c.f64()));
    (v[0], cross(sub(v[1], v[0]), sub(v[2], v[0])))
}

/// Ray `i`'s origin and direction in f64.
pub(super) fn o_and_d<T: Real>(exact: &Exact<T>, i: usize) -> ([f64; 3], [f64; 3]) {
    let ray = &exact.rays[i].1.ray;
    (ray.o.map(|c| c.f64()), ray.d.map(|c| c.f64()))
}

/// Where ray `i` meets triangle `tri`, located `at` ([`raylab::geometry::Shape::locate`]),
/// inside but within rounding of an edge: the edge it passes nearest and the barycentric
/// weight of the vertex opposite. Within rounding: a
/// weight below 2⁶ unit roundoffs of the precision graded, times the system's condition
/// (|e1| |d| |e2| / |det|) and the reach of its coordinates (1 + (|o| + |v0|) / the
/// triangle's extent): a correct program can round it past the edge. (A correct f64 program
/// that rounded away a hit 1.2e-17 inside an edge of a face met from its back was told it
/// culled back faces.)
pub(super) fn within_rounding_of_edge<T: Real>(
    exact: &Exact<T>,
    i: usize,
    tri: &Triangle<T>,
    at: &raylab::geometry::Location,
) -> Option<(usize, f64)> {
    use raylab::geometry::{triangle, Location};
    let &Location::Triangle(triangle::Location::Inside { nearest, weight }) = at else {
        return None;
    };
    let o = o_and_d(exact, i).0;
    let v = tri.0.map(|p| p.map(|c| c.f64()));
    let condition = terms(exact, i, tri) / determinant(exact, i, tri).abs();
    let extent = length(sub(v[1], v[0])).max(length(sub(v[2], v[0])));
    let reach = 1.0 + (length(o) + length(v[0])) / extent;
    let bound = 64.0 * T::UNIT_ROUNDOFF.f64() * condition * reach;
    (weight < bound).then_some((nearest, weight))
}

/// Whether ray `i` meets primitive `prim` clearly inside: a triangle inside, its products of
/// three in the precision's normal range, neither within rounding of an edge nor with a
/// determinant below the rounding of its terms; a sphere through, its discriminant clear of
/// the textbook formula's rounding. A correct program answers such a hit right: one it misses
/// there is a bug's, not rounding's.
pub(super) fn clearly_inside<T: Real>(exact: &Exact<T>, i: usize, prim: u32) -> bool {
    use raylab::geometry::{sphere, triangle, Location, Shape};
    let shape = exact.shape(prim);
    match (&shape, shape.locate(&exact.rays[i].1.ray)) {
        (Shape::Triangle(tri), at @ Location::Triangle(triangle::Location::Inside { .. })) => {
            // (Its products of three in the precision's normal range, with its digits to
            // spare: a correct f32 program loses the suite's subnormal cube's hits to
            // underflow, and was told it culled.)
            let range =
                (T::MIN_NORMAL_EXP + T::PRECISION) as i32..(T::MAX_EXP - T::PRECISION) as i32;
            let scale = terms(exact, i, tri).log2();
            range.contains(&(scale as i32))
                && !determinant_rounds(exact, i, tri)
                && within_rounding_of_edge(exact, i, tri, &at).is_none()
        }
        // (Its discriminant clear of the textbook b² − a·c's rounding: a correct program's
        // far tiny sphere can lose a ray through it near the rim.)
        (Shape::Sphere(s), Location::Sphere(sphere::Location::Through)) => {
            let (a, _, oc2, disc) = sphere_terms(exact, i, s);
            disc > discriminant_rounding::<T>(a, oc2)
        }
        _ => false,
    }
}

/// Where ray `i` meets (or passes) sphere `prim` such that the textbook quadratic loses it,
/// as facts: in f32, a = d·d below its smallest normal number underflows (the suite's tiny
/// directions were told only that the ray meets the sphere twice); and a discriminant within
/// the rounding of the textbook b² − a·c (c = |o − c|² − r²: r² lost beside the distance
/// of a far small sphere) can come out with the other sign.
pub(super) fn sphere_rounding<T: Real>(exact: &Exact<T>, i: usize, prim: u32) -> Option<String> {
    let raylab::geometry::Shape::Sphere(s) = exact.shape(prim) else {
        return None;
    };
    let (a, b, oc2, disc) = sphere_terms(exact, i, &s);
    let f32 = T::PRECISION <= 24;
    let mut facts = Vec::new();
    if f32 && a < f32::MIN_POSITIVE as f64 && a > 0.0 {
        facts.push(format!(
            "d·d is {a:.1e}, below f32's smallest normal number {:.1e}: in f32 the \
             quadratic's a = d·d comes out 0 or without its digits (f64 holds it)",
            f32::MIN_POSITIVE
        ));
    }
    let r2 = s.radius.f64().powi(2);
    // (The loose bound of [`discriminant_rounding`] said so of discriminants 6 to 17 times
    // the rounding an f32 program's could have: a few unit roundoffs of the terms, which a
    // program's own rounding reaches.)
    let rounding = 4.0 * T::UNIT_ROUNDOFF.f64() * (b * b + a * (oc2 + r2));
    if disc.abs() <= rounding && disc != 0.0 {
        facts.push(format!(
            "sphere {prim}'s |b² − a·c| is only {:.1e} of a·|o − c|² (b = d·(o − c): a \
             quarter of b² − 4ac with b = 2 d·(o − c)), below the rounding of the textbook \
             formula in {} (c = |o − c|² − r², with r² {:.1e} of |o − c|²): computed so, it \
             can come out with the other sign",
            disc.abs() / (a * oc2),
            if f32 { "f32" } else { "f64" },
            r2 / oc2
        ));
    }
    (!facts.is_empty()).then(|| facts.join("; "))
}

/// Ray `i`'s meetings with the sphere at `centre` of radius `r`, in f64: the near and far
/// roots of a·t² + 2b·t + c = 0 (the discriminant taken as 0 where it rounds below), c (below
/// 0: the origin inside) and the discriminant b² − a·c (computed as a·r² − |d × (o − c)|²).
pub(super) fn quadratic<T: Real>(
    exact: &Exact<T>,
    i: usize,
    sphere: &raylab::geometry::Sphere<T>,
) -> ([f64; 2], f64, f64) {
    let (a, b, oc2, disc) = sphere_terms(exact, i, sphere);
    let c = oc2 - sphere.radius.f64().powi(2);
    // (Stable: q = −b ∓ √disc away from 0, the roots q/a and c/q: −b ± √disc cancelled where
    // the origin is near the surface.)
    let q = -b - b.signum() * disc.max(0.0).sqrt();
    let (x, y) = match q == 0.0 {
        true => (0.0, 0.0),
        false => (q / a, c / q),
    };
    ([x.min(y), x.max(y)], c, disc)
}

/// Where ray `i`'s line crosses the triangle's plane, in f64: its t.
pub(super) fn plane_t<T: Real>(
    exact: &Exact<T>,
    i: usize,
    tri: &raylab::geometry::Triangle<T>,
) -> f64 {
    let (o, d) = o_and_d(exact, i);
    let (v0, n) = plane_of(tri);
    dot(sub(v0, o), n) / dot(d, n)
}

/// Where ray `i`'s line meets primitive `p`'s surface, in f64: a triangle's plane t (twice),
/// a sphere's near and far roots ([`quadratic`]). Whether the ray meets the primitive itself
/// there is the caller's to ask.
pub(super) fn surface_ts<T: Real>(exact: &Exact<T>, i: usize, p: u32) -> [f64; 2] {
    match exact.shape(p) {
        raylab::geometry::Shape::Triangle(tri) => [plane_t(exact, i, &tri); 2],
        raylab::geometry::Shape::Sphere(s) => quadratic(exact, i, &s).0,
    }
}

/// A loose bound of the rounding of the textbook discriminant b² − a·c in the precision
/// graded, of a ray and sphere with a = d·d and |o − c|² = `oc2` ([`sphere_terms`]): 2¹⁰ unit
/// roundoffs of a·|o − c|². A miss with a discriminant within it is not clearly inside, so it
/// bears out no bug. What a hint may say of its sign takes the formula's own rounding, far
/// smaller ([`sphere_rounding`]); between the two a miss is told neither.
fn discriminant_rounding<T: Real>(a: f64, oc2: f64) -> f64 {
    1024.0 * T::UNIT_ROUNDOFF.f64() * a * oc2
}

/// Ray `i` against sphere `s`, in f64: a = d·d, b = d·(o − c), |o − c|² and the
/// discriminant b² − a·c (as a·r² − |d × (o − c)|², the line's distance from the centre: b²
/// and a·c cancel for a small sphere far away, and gave it two equal roots, or none).
fn sphere_terms<T: Real>(
    exact: &Exact<T>,
    i: usize,
    s: &raylab::geometry::Sphere<T>,
) -> (f64, f64, f64, f64) {
    let (o, d) = o_and_d(exact, i);
    let (centre, r) = (s.centre.map(|c| c.f64()), s.radius.f64());
    let oc = sub(o, centre);
    let across = cross(d, oc);
    let a = dot(d, d);
    (a, dot(d, oc), dot(oc, oc), a * r * r - dot(across, across))
}

/// How far past the ray's tmin the exact hit at `te` lies (t − tmin), and whether that is
/// near enough for a fixed epsilon in place of tmin to lose it: at most 10⁻² (students'
/// epsilons reach 10⁻³ and 10⁻²: a back face lost to `t > tmin + 1e-3` was taken for one
/// culled), or its point within 10⁻⁶ of |o| + |t·d| of the point at tmin. `None` for tmin −∞.
pub(super) fn past_tmin<T: Real>(exact: &Exact<T>, i: usize, te: f64) -> Option<(f64, bool)> {
    let (o, d) = o_and_d(exact, i);
    let tmin = exact.rays[i].1.tmin.f64();
    let gap = te - tmin;
    let near = gap <= 1e-2 || gap * length(d) <= 1e-6 * (length(o) + te.abs() * length(d));
    tmin.is_finite().then_some((gap, near))
}

/// Whether the exact hit at `te` on primitive `prim` lies within rounding of the ray's tmin
/// or tmax, where a correct program's rounded t can fall past it ([`t_rounding`]).
pub(super) fn near_an_end<T: Real>(exact: &Exact<T>, i: usize, prim: u32, te: f64) -> bool {
    let ray = &exact.rays[i].1;
    let rounding = t_rounding(exact, i, prim, te);
    [ray.tmin.f64(), ray.tmax.f64()]
        .into_iter()
        .any(|end| end.is_finite() && (te - end).abs() <= rounding)
}

/// How far a correct program's t for the exact hit at `te` on primitive `prim` may stray in
/// the precision graded: 2⁶ unit roundoffs of |o| / |d| + |t|, times the condition of t (a
/// triangle's |e1| |d| |e2| / |det|; a sphere's |b| / √(b² − a·c), which grows toward its
/// rim).
pub(super) fn t_rounding<T: Real>(exact: &Exact<T>, i: usize, prim: u32, te: f64) -> f64 {
    use raylab::geometry::Shape;
    let (o, d) = o_and_d(exact, i);
    let condition = match exact.shape(prim) {
        Shape::Triangle(tri) => terms(exact, i, &tri) / determinant(exact, i, &tri).abs(),
        Shape::Sphere(s) => {
            let (_, b, _, disc) = sphere_terms(exact, i, &s);
            1.0 + b.abs() / disc.max(0.0).sqrt()
        }
    };
    64.0 * T::UNIT_ROUNDOFF.f64() * (length(o) / length(d) + te.abs()) * condition
}

/// The size of Möller–Trumbore's determinant's terms for ray `i` and triangle `tri`:
/// |e1| |d| |e2|.
fn terms<T: Real>(exact: &Exact<T>, i: usize, tri: &Triangle<T>) -> f64 {
    let v = tri.0.map(|p| p.map(|c| c.f64()));
    length(sub(v[1], v[0])) * length(o_and_d(exact, i).1) * length(sub(v[2], v[0]))
}

/// Whether the determinant may be below the rounding of its terms in the precision graded
/// (by the bound of their sizes, [`terms`]): where it may, a miss is not clearly inside.
pub(super) fn determinant_rounds<T: Real>(exact: &Exact<T>, i: usize, tri: &Triangle<T>) -> bool {
    determinant(exact, i, tri).abs() < 3.0 * T::UNIT_ROUNDOFF.f64() * terms(exact, i, tri)
}

/// Whether the determinant is below the rounding of its six products e1ᵢ·dⱼ·e2ₖ in the
/// precision graded, so that a correct program's can come out 0 or with the other sign: what
/// a hint says. (By [`terms`]' |e1| |d| |e2| a sliver's −4.0e-7, its one product, was said
/// to round so.)
pub(super) fn determinant_below_rounding<T: Real>(
    exact: &Exact<T>,
    i: usize,
    tri: &Triangle<T>,
) -> bool {
    let v = tri.0.map(|p| p.map(|c| c.f64()));
    let (e1, e2, d) = (sub(v[1], v[0]), sub(v[2], v[0]), o_and_d(exact, i).1);
    let products: f64 = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ]
    .iter()
    .map(|&[a, b, c]| (e1[a] * d[b] * e2[c]).abs())
    .sum();
    determinant(exact, i, tri).abs() < 3.0 * T::UNIT_ROUNDOFF.f64() * products
}

/// |a|.
pub(super) fn length(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Where the exact hit is on a triangle whose Möller–Trumbore determinant e1·(d × e2) (e1 =
/// v1 − v0, e2 = v2 − v0) is not 0 but small, what that loses, as facts: in f32, one below
/// its smallest normal number underflows; one below the rounding of its terms can come out 0
/// or with the other sign; and one below 10⁻² and below `epsilon_below` (where the run bears
/// an epsilon out: [`super::evidence::Evidence::epsilon_below`]) is lost to the textbook's
/// |det| < ε test. (Correct f32 programs were told of the epsilon alone.)
pub(super) fn small_determinant<T: Real>(
    exact: &Exact<T>,
    i: usize,
    prim: u32,
    epsilon_below: f64,
) -> Option<String> {
    let raylab::geometry::Shape::Triangle(tri) = exact.shape(prim) else {
        return None;
    };
    let det = determinant(exact, i, &tri);
    let f32 = T::PRECISION <= 24;
    let below_f32 = det.abs() < f32::MIN_POSITIVE as f64;
    let underflows = f32 && below_f32;
    let rounds = determinant_below_rounding(exact, i, &tri);
    let epsilon = det.abs() < 1e-2 && det.abs() < epsilon_below;
    let lost = "an epsilon on it (|det| < ε: no hit) loses the hit, where only det = 0 is \
                parallel";
    let underflow = format!(
        "below f32's smallest normal number {:.1e}: in f32 it comes out 0 or without its \
         digits (f64 holds it)",
        f32::MIN_POSITIVE
    );
    let rounding = format!(
        "below the rounding of its terms in {}: rounded, it can come out 0 or with the other \
         sign",
        if f32 { "f32" } else { "f64" }
    );
    // (Graded in f64, a determinant below f32's range: a program computing in float loses
    // it so, where the run bore out an epsilon; a JavaScript student's `Math.fround` program
    // was told of an epsilon alone.)
    let in_f32 = match !f32 && below_f32 {
        true => {
            " (or the program computes in f32, where it is below the smallest normal \
                 number: `--precision f32` grades it so)"
        }
        false => "",
    };
    let why = match (underflows, rounds, epsilon) {
        (true, _, false) => underflow,
        (true, _, true) => format!("{underflow}; and {lost}"),
        (false, true, false) => rounding,
        (false, true, true) => format!("near 0: {lost}{in_f32} (and it is {rounding})"),
        (false, false, true) => format!("near 0: {lost}{in_f32}"),
        (false, false, false) => return None,
    };
    (det != 0.0).then(|| {
        format!(
            "the triangle's determinant e1·(d × e2) (e1 = v1 − v0, e2 = v2 − v0) is {det:.1e}, \
             {why}"
        )
    })
}
