//! `raylab check`'s reproducers: the first wrong answers and t failures, each a line with
//! where its ray is, the ray, the exact answer and the answer given.

use raylab::check::grade::{self, Answer, Exact, Judged, Verdict};
use raylab::math::real::{cross, dot, sub};
use raylab::math::Real;

/// The first `most` wrong answers and the first `most` t failures, each under a heading, as
/// one-line reproducers.
pub(super) fn reproducers<T: Real>(
    judged: &[Judged<T>],
    exact: &Exact<T>,
    answers: &[(usize, Answer<T>)],
    place: &dyn Fn(usize) -> String,
    written: Written,
    most: usize,
) -> Vec<String> {
    let mut lines = Vec::new();
    let wrong = |j: &Judged<T>| !matches!(j.graded.verdict, Verdict::Right | Verdict::Tie);
    let t_failed = |j: &Judged<T>| j.graded.t_error == Some(grade::TError::Beyond);
    for (heading, wanted) in [
        ("wrong answers", &wrong as &dyn Fn(&Judged<T>) -> bool),
        ("hits whose t is beyond the tolerance", &t_failed),
    ] {
        let count = judged.iter().filter(|j| wanted(j)).count();
        if count == 0 || most == 0 {
            continue;
        }
        // (Which kinds: "wrong answers" read as the table's `wrong` column, which counts
        // wrong primitives alone.)
        let kinds = match heading == "wrong answers" {
            true => format!(": {}", kinds_of(judged)),
            false => String::new(),
        };
        lines.push(format!(
            "the first of the {count} {heading}{kinds} (ray, exact answer, the answer given):"
        ));
        let shown = (judged.iter().enumerate()).filter(|(_, j)| wanted(j));
        for (i, j) in shown.take(most) {
            lines.push(reproducer(i, j, exact, answers, place, written));
        }
    }
    lines
}

/// The wrong answers' count by verdict: `2 leaks, 1 false hit` (those with none left out).
fn kinds_of<T: Real>(judged: &[Judged<T>]) -> String {
    [
        (Verdict::Leak, "leak", "leaks"),
        (Verdict::FalseHit, "false hit", "false hits"),
        (Verdict::Wrong, "wrong primitive", "wrong primitives"),
    ]
    .iter()
    .map(|&(v, one, many)| {
        let n = judged.iter().filter(|j| j.graded.verdict == v).count();
        (n, raylab::words::count(n, one, many))
    })
    .filter(|(n, _)| *n > 0)
    .map(|(_, text)| text)
    .collect::<Vec<_>>()
    .join(", ")
}

/// One graded ray as a line: where the ray is, the ray, the exact answer and the one given.
fn reproducer<T: Real>(
    i: usize,
    j: &Judged<T>,
    exact: &Exact<T>,
    answers: &[(usize, Answer<T>)],
    place: &dyn Fn(usize) -> String,
    written: Written,
) -> String {
    let ray = exact.rays[i].1;
    let given_t = t_of(&answers[i].1);
    let outside = outside_interval(exact, i, &answers[i].1);
    let what = match j.graded.verdict {
        // (Not "off by inf": no point is off by a t that is no number or infinite.)
        Verdict::Right | Verdict::Tie if given_t.is_some_and(f64::is_nan) => {
            "t failure: t is not a number".to_string()
        }
        Verdict::Right | Verdict::Tie if given_t.is_some_and(f64::is_infinite) => {
            "t failure: t is infinite, where the exact t is not".to_string()
        }
        // What the tolerance judges: the point's distance, not t's own relative error (t 4x
        // too small can put the point 0.27 of the scale off).
        Verdict::Right | Verdict::Tie => format!(
            "t failure: o + t·d off by {:.2e} of |o| + |t·d| + extent{}",
            j.graded.relative,
            match (
                outside.as_deref(),
                short_print(&j.exact, &answers[i].1),
                other_root(exact, i, &j.exact, &answers[i].1),
                times_length(exact, i, &j.exact, &answers[i].1),
            ) {
                (Some(hint), ..) => format!("; {hint}"),
                (None, Some(digits), _, _) => format!(
                    "; t is the exact one to {digits} significant digits: print {0} (%.{0}g)",
                    round_trip_digits::<T>()
                ),
                (None, None, Some(_), _) => format!(
                    "; t is the ray's other meeting with the sphere: the nearest root above \
                     tmin wins{}",
                    match t_of(&j.exact).and_then(|te| past_tmin(exact, i, te)) {
                        Some((gap, true)) => format!(
                            " (the exact one is only {gap:.1e} past tmin: an epsilon in its \
                             place skips it)"
                        ),
                        _ => String::new(),
                    }
                ),
                (None, None, None, Some(length)) => format!(
                    "; t is the exact one times |d| = {}: t is in units of d, not normalised",
                    match (1e-3..1e6).contains(&length) {
                        true => format!("{length:.6}"),
                        false => format!("{length:.3e}"),
                    }
                ),
                (None, None, None, None) => String::new(),
            }
        ),
        v => match answers[i].1 {
            Answer::Hit { prim, .. } if prim as usize >= exact.primitives => {
                let last = exact.primitives.saturating_sub(1);
                let from_1 = match prim as usize == exact.primitives {
                    true => " (indices count from 0)",
                    false => "",
                };
                format!(
                    "{}: index {prim} is past the last primitive, {last}{from_1}",
                    v.name()
                )
            }
            _ => match outside.or_else(|| missed(exact, i, &j.exact, &answers[i].1)) {
                Some(hint) => format!("{}: {hint}", v.name()),
                None => v.name().to_string(),
            },
        },
    };
    let line = answers[i].0;
    format!(
        "  {}: {}  exact: {}  given ({}:{line}): {}  [{what}]",
        place(i),
        ray.line(),
        j.exact.text(),
        written.name,
        written.line(line).unwrap_or_else(|| answers[i].1.text())
    )
}

/// Where the answers were read: the name of their file (`its output` for a program's) and
/// its text, so that an answer is shown as written (`hit 1e39 0` was shown as `hit inf 0`,
/// `hit 1.50 3` as `hit 1.5 3`).
#[derive(Clone, Copy)]
pub(super) struct Written<'a> {
    pub name: &'a str,
    pub text: &'a str,
}

impl Written<'_> {
    /// Line `n` (from 1) as written, its spaces trimmed, control characters escaped and a
    /// long one cut.
    fn line(&self, n: usize) -> Option<String> {
        let text = self.text.strip_prefix('\u{feff}').unwrap_or(self.text);
        let line = text.lines().nth(n.checked_sub(1)?)?.trim();
        Some(raylab_app::one_line(&raylab::words::shown(line)))
    }
}

/// Where a given hit's t is not inside the ray's open interval (tmin, tmax): which end it
/// passes. A hint beside the verdict (a hit behind the origin showed as a wrong primitive and
/// no more; on a sphere, as its other root).
fn outside_interval<T: Real>(exact: &Exact<T>, i: usize, given: &Answer<T>) -> Option<String> {
    let Answer::Hit { t, .. } = *given else {
        return None;
    };
    let ray = &exact.rays[i].1;
    let (tmin, tmax) = (ray.tmin, ray.tmax);
    if t.is_nan() {
        None
    } else if t <= tmin {
        let behind = match tmin == T::zero() && t < tmin {
            true => " (it is behind the origin)",
            false => "",
        };
        Some(format!(
            "t {t} is not above tmin {tmin}{behind}: only tmin < t < tmax counts"
        ))
    } else if t >= tmax {
        Some(format!(
            "t {t} is not below tmax {tmax}: only tmin < t < tmax counts, both ends open"
        ))
    } else {
        None
    }
}

/// Where the given hit is on a sphere and its t is, to 10⁻⁶ relative, the root of the ray's
/// quadratic that is not the exact answer's (the far root, or the one behind tmin): that root,
/// in f64. A hint beside the verdict, which the exact grading gave (a program that tried only
/// the far root was told its t was off by 0.47, and no more).
fn other_root<T: Real>(
    exact: &Exact<T>,
    i: usize,
    standing: &Answer<T>,
    given: &Answer<T>,
) -> Option<f64> {
    let Answer::Hit { t, prim } = *given else {
        return None;
    };
    let raylab::geometry::Shape::Sphere(s) = exact.shape(prim) else {
        return None;
    };
    let (roots, _, disc) = quadratic(exact, i, s.centre.map(|c| c.f64()), s.radius.f64());
    let exact_t = t_of(standing)?;
    if disc < 0.0 || roots.iter().any(|r| !r.is_finite()) {
        return None;
    }
    let near = |x: f64, y: f64| (x - y).abs() <= 1e-6 * x.abs().max(y.abs()).max(1e-30);
    let other = match near(roots[0], exact_t) {
        true => roots[1],
        false => roots[0],
    };
    (near(t.f64(), other) && !near(t.f64(), exact_t)).then_some(other)
}

/// Why the exact hit may have been missed (a leak, or a farther primitive given), where the
/// geometry says so (exactly, or in f64 with margins: a hint, never a verdict), and only
/// what sets the exact hit apart from the answer given: the given primitive met farther on
/// (or not where its t says), a hit behind the origin with tmin < 0 (the given one is not), a
/// sphere's tangent or far root, a triangle's edge or vertex, its back (the given one is not
/// met from its back), a hit an epsilon past tmin would lose.
fn missed<T: Real>(
    exact: &Exact<T>,
    i: usize,
    standing: &Answer<T>,
    given: &Answer<T>,
) -> Option<String> {
    let Answer::Hit { t, prim } = *standing else {
        return None;
    };
    // (Numbers shown in the precision graded, as written: f64 of an f32 ran to 16 digits.)
    let (te, te_shown) = (t.f64(), t);
    let given_hit = match *given {
        Answer::Hit { t, prim: p } if p == prim || t.is_nan() || t.f64() <= te => return None,
        Answer::Hit { t, prim } => Some((t, prim)),
        Answer::Miss => None,
    };
    let tmin = exact.rays[i].1.tmin;
    let mut facts = Vec::new();
    if let Some((t, p)) = given_hit {
        facts.push(match meets_at(exact, i, p, t.f64()) {
            true => format!(
                "the given t {t} is past the exact hit's t {te_shown}: the nearest hit wins"
            ),
            false => format!("the ray does not meet primitive {p} at the given t {t}"),
        });
    }
    let behind = te < 0.0 && tmin.f64() < 0.0;
    if behind && given_hit.is_none_or(|(t, _)| t.f64() >= 0.0) {
        facts.push(format!(
            "the exact hit is behind the origin (t {te_shown}), which counts where tmin < 0 \
             (here {tmin})"
        ));
        return Some(facts.join("; "));
    }
    // (An epsilon's loss, where it could be one, rather than the face's side: both true, the
    // first the likelier cause of a hit this near tmin; beside a tangent, which explains the
    // miss, it was noise.)
    let near = past_tmin(exact, i, te).filter(|&(gap, near)| near && gap > 0.0);
    let (fact, tangent) = where_on(
        exact,
        i,
        te,
        prim,
        given_hit.map(|(_, p)| p),
        near.is_none(),
    );
    facts.extend(fact);
    if let (Some((gap, _)), false) = (near, tangent) {
        facts.push(format!(
            "the exact hit is only {gap:.1e} past tmin: a hit counts however near tmin, where \
             an epsilon in its place loses it"
        ));
    }
    (!facts.is_empty()).then(|| facts.join("; "))
}

/// Whether ray `i` meets primitive `p` at about `t` (10⁻⁶ of it, in f64): the given answer's
/// primitive where it says.
fn meets_at<T: Real>(exact: &Exact<T>, i: usize, p: u32, t: f64) -> bool {
    use raylab::geometry::{Location, Shape};
    let ray = &exact.rays[i].1.ray;
    let (o, d) = (ray.o.map(|c| c.f64()), ray.d.map(|c| c.f64()));
    let near = |x: f64| (x - t).abs() <= 1e-6 * x.abs().max(t.abs()).max(1e-30);
    match exact.shape(p) {
        Shape::Sphere(s) => {
            let (roots, _, disc) = quadratic(exact, i, s.centre.map(|c| c.f64()), s.radius.f64());
            disc >= 0.0 && roots.iter().any(|&r| near(r))
        }
        Shape::Triangle(tri) => {
            use raylab::geometry::triangle::Location as On;
            let on = matches!(
                Shape::Triangle(tri).locate(ray),
                Location::Triangle(On::Inside { .. } | On::Edge(_) | On::Vertex(_))
            );
            let (v0, n) = plane_of(&tri);
            on && near(dot(sub(v0, o), n) / dot(d, n))
        }
    }
}

/// Where on primitive `prim` ray `i` meets it at `te`, where that explains a miss, decided
/// exactly where it is a place ([`raylab::geometry::Shape::locate`]): a sphere's tangent
/// or far root (the origin inside, or the near root not above tmin); a triangle's edge or
/// vertex, else (where `back` asks) its back where `given` (the primitive given instead, if
/// any) is not a triangle met from its back too. With whether it is a tangent.
fn where_on<T: Real>(
    exact: &Exact<T>,
    i: usize,
    te: f64,
    prim: u32,
    given: Option<u32>,
    back: bool,
) -> (Option<String>, bool) {
    use raylab::geometry::{sphere, triangle, Location, Shape};
    let ray = &exact.rays[i].1.ray;
    let d = ray.d.map(|c| c.f64());
    let faces_back = |shape: &Shape<T>| match shape {
        Shape::Triangle(tri) => {
            let (_, n) = plane_of(tri);
            dot(d, n) > 1e-6 * length(d) * length(n)
        }
        Shape::Sphere(_) => false,
    };
    let shape = exact.shape(prim);
    let fact = match (&shape, shape.locate(ray)) {
        (_, Location::Sphere(sphere::Location::Tangent)) => {
            let tangent = "the ray touches the sphere (a double root, discriminant 0): a \
                           tangent is a hit";
            return (Some(tangent.into()), true);
        }
        (Shape::Sphere(s), _) => {
            let (centre, r) = (s.centre.map(|c| c.f64()), s.radius.f64());
            let ([near, far], c, _) = quadratic(exact, i, centre, r);
            ((te - far).abs() < (te - near).abs()).then(|| {
                let why = match c < -1e-6 * r * r {
                    true => "the origin is inside the sphere",
                    false => "the near root is not above tmin",
                };
                format!("the exact hit is the sphere's far root, where the ray leaves it: {why}")
            })
        }
        (
            _,
            Location::Triangle(at @ (triangle::Location::Edge(_) | triangle::Location::Vertex(_))),
        ) => Some(format!(
            "the exact hit is {at} of the triangle: the edges count, closed"
        )),
        (Shape::Triangle(_), _) => {
            let given_faces_back = given.is_some_and(|g| faces_back(&exact.shape(g)));
            (back && faces_back(&shape) && !given_faces_back).then(|| {
                "the exact hit is on the triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − \
                 v0)): both sides count"
                    .into()
            })
        }
    };
    (fact, false)
}

/// A triangle's v0 and its normal n = (v1 − v0) × (v2 − v0), in f64 (d·n > 0: met from its
/// back).
fn plane_of<T: Real>(tri: &raylab::geometry::Triangle<T>) -> ([f64; 3], [f64; 3]) {
    let v = tri.0.map(|p| p.map(|c| c.f64()));
    (v[0], cross(sub(v[1], v[0]), sub(v[2], v[0])))
}

/// How far past the ray's tmin the exact hit at `te` lies (t − tmin), and whether that is
/// near enough for a fixed epsilon in place of tmin to lose it: at most 10⁻⁴, or its point
/// within 10⁻⁶ of |o| + |t·d| of the point at tmin. `None` for tmin −∞.
fn past_tmin<T: Real>(exact: &Exact<T>, i: usize, te: f64) -> Option<(f64, bool)> {
    let traced = &exact.rays[i].1;
    let (o, d) = (traced.ray.o.map(|c| c.f64()), traced.ray.d.map(|c| c.f64()));
    let tmin = traced.tmin.f64();
    let gap = te - tmin;
    let near = gap <= 1e-4 || gap * length(d) <= 1e-6 * (length(o) + te.abs() * length(d));
    tmin.is_finite().then_some((gap, near))
}

/// Ray `i`'s meetings with the sphere at `centre` of radius `r`, in f64: the near and far
/// roots of a·t² + 2b·t + c = 0 (the discriminant taken as 0 where it rounds below), c (below
/// 0: the origin inside) and the discriminant b² − a·c.
fn quadratic<T: Real>(
    exact: &Exact<T>,
    i: usize,
    centre: [f64; 3],
    r: f64,
) -> ([f64; 2], f64, f64) {
    let ray = &exact.rays[i].1.ray;
    let (o, d) = (ray.o.map(|c| c.f64()), ray.d.map(|c| c.f64()));
    let oc = sub(o, centre);
    let (a, b, c) = (dot(d, d), dot(d, oc), dot(oc, oc) - r * r);
    let disc = b * b - a * c;
    let root = disc.max(0.0).sqrt();
    ([(-b - root) / a, (-b + root) / a], c, disc)
}

/// The t of a hit, in f64.
fn t_of<T: Real>(answer: &Answer<T>) -> Option<f64> {
    match *answer {
        Answer::Hit { t, .. } => Some(t.f64()),
        Answer::Miss => None,
    }
}

fn length(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Where the given t is, to 10⁻⁶ relative, the exact t times |d| (the ray's direction
/// normalised, its t in units of length) and |d| is not 1: |d|. A hint beside the t failure.
fn times_length<T: Real>(
    exact: &Exact<T>,
    i: usize,
    standing: &Answer<T>,
    given: &Answer<T>,
) -> Option<f64> {
    let (Answer::Hit { t: te, .. }, Answer::Hit { t, .. }) = (standing, given) else {
        return None;
    };
    let length = length(exact.rays[i].1.ray.d.map(|c| c.f64()));
    let (want, got) = (te.f64() * length, t.f64());
    let near = (want - got).abs() <= 1e-6 * want.abs().max(got.abs());
    ((length - 1.0).abs() > 1e-6 && near && got.is_finite()).then_some(length)
}

/// The significant digits that print every value of `T` so that it reads back the same: 9
/// for f32, 17 for f64.
fn round_trip_digits<T: Real>() -> usize {
    if T::PRECISION <= 24 {
        9
    } else {
        17
    }
}

/// Where the given t is the exact t rounded to fewer significant digits than `T` needs (a
/// C `%g` prints 6), how many: the t failure is the printing's, not the arithmetic's.
fn short_print<T: Real>(exact: &Answer<T>, given: &Answer<T>) -> Option<usize> {
    let (Answer::Hit { t: exact, .. }, Answer::Hit { t: given, .. }) = (exact, given) else {
        return None;
    };
    if !given.is_finite() || *given == T::zero() {
        return None;
    }
    // The shortest decimal that reads back as the given t, its significant digits only.
    let shortest = given.to_string();
    let digits = shortest.trim_start_matches('-').replace('.', "");
    let digits = digits
        .trim_start_matches('0')
        .trim_end_matches('0')
        .len()
        .max(1);
    let rounded = format!("{:.*e}", digits - 1, exact.f64())
        .parse::<T>()
        .ok()?;
    (digits < round_trip_digits::<T>() && rounded == *given).then_some(digits)
}
