//! `raylab check`'s reproducers: the first wrong answers and t failures, each a line with
//! where its ray is, the ray, the exact answer and the answer given.

use super::evidence::Evidence;
use super::hint_geometry::{determinant_below_rounding, small_determinant, sphere_rounding};
use super::hint_geometry::{meets_back, near, past_tmin, t_rounding};
use super::hint_geometry::{plane_t, quadratic, surface_ts, within_rounding_of_edge};
use super::t_failures::{fine_t, other_root, round_trip_digits, short_print, t_of, times_length};
use raylab::check::grade::{self, Answer, Exact, Judged, Verdict};
use raylab::math::Real;

/// A wrong answer: a leak, a false hit or a wrong primitive (shown first).
fn wrong<T: Real>(j: &Judged<T>) -> bool {
    !matches!(j.graded.verdict, Verdict::Right | Verdict::Tie)
}

/// A right or tied hit whose t is beyond the tolerance (shown after the wrong answers).
fn t_failed<T: Real>(j: &Judged<T>) -> bool {
    j.graded.t_error == Some(grade::TError::Beyond)
}

/// The ray [`reproducers`] shows first, if any: the first wrong answer, else the first t
/// failure.
pub(super) fn first_shown<T: Real>(judged: &[Judged<T>]) -> Option<usize> {
    (judged.iter().position(wrong)).or_else(|| judged.iter().position(t_failed))
}

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
    let meets = |i: usize, p: u32, t: f64| meets_at(exact, i, p, t);
    let evidence = Evidence::of(judged, exact, answers, written.text, meets);
    for (heading, one, wanted) in [
        (
            "wrong answers",
            "wrong answer",
            &wrong as &dyn Fn(&Judged<T>) -> bool,
        ),
        (
            "hits whose t is beyond the tolerance",
            "hit whose t is beyond the tolerance",
            &t_failed,
        ),
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
        // ("the first of the 1 wrong answers" read oddly.)
        let which = match count {
            1 => format!("the one {one}"),
            _ => format!("the first of the {count} {heading}"),
        };
        lines.push(format!(
            "{which}{kinds} (ray, exact answer, the answer given):"
        ));
        let shown = (judged.iter().enumerate()).filter(|(_, j)| wanted(j));
        for (i, j) in shown.take(most) {
            lines.push(reproducer(i, j, exact, answers, place, written, &evidence));
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

/// What may explain a right primitive given with its t far off, where nothing else does: the
/// sphere's quadratic losing its digits (an f32 t 6e-6 off, of a direction whose d·d
/// underflows, was a bare failure), a t no root of the sphere (its roots told), a triangle's
/// determinant that rounding loses (t a quotient by it).
fn t_failure_cause<T: Real>(exact: &Exact<T>, i: usize, prim: u32, t: T) -> Option<String> {
    use raylab::geometry::Shape;
    let off = match (meets_at(exact, i, prim, t.f64()), exact.shape(prim)) {
        (true, _) => None,
        (false, Shape::Sphere(_)) => Some(passes(exact, i, prim, t)),
        (false, Shape::Triangle(_)) => small_determinant(exact, i, prim, 0.0)
            .map(|fact| format!("{fact}, and t (a quotient by it) far off")),
    };
    let facts: Vec<String> = off
        .into_iter()
        .chain(sphere_rounding(exact, i, prim))
        .collect();
    (!facts.is_empty()).then(|| facts.join("; "))
}

/// One graded ray as a line: where the ray is, the ray, the exact answer and the one given.
fn reproducer<T: Real>(
    i: usize,
    j: &Judged<T>,
    exact: &Exact<T>,
    answers: &[(usize, Answer<T>)],
    place: &dyn Fn(usize) -> String,
    written: Written,
    evidence: &Evidence,
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
                short_print(exact, i, &j.exact, &answers[i].1, evidence).map(|printed| {
                    format!(
                        "t is the exact one {printed}: print {0} (%.{0}g)",
                        round_trip_digits::<T>()
                    )
                }),
                other_root(exact, i, &j.exact, &answers[i].1),
                times_length(exact, i, &j.exact, &answers[i].1),
            ) {
                // (Both: `%.4f`'s 0.0000 for 1.4e-5 was told of tmin alone.)
                (Some(hint), Some(printed), ..) => format!("; {hint}; {printed}"),
                (Some(hint), ..) => format!("; {hint}"),
                (None, Some(printed), _, _) => format!("; {printed}"),
                (None, None, Some(_), _) => format!(
                    "; t is the ray's other meeting with the sphere: the nearest root above \
                     tmin wins{}",
                    match (gap_past_tmin(exact, i, &j.exact), j.exact) {
                        (Some((gap, true)), Answer::Hit { prim, .. }) => format!(
                            " (the exact one is only {gap:.1e} past tmin{})",
                            lost_past_tmin(exact, i, prim, gap, evidence, "skips")
                                .map_or(String::new(), |why| format!(": {why}"))
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
                (None, None, None, None) => match answers[i].1 {
                    Answer::Hit { t, prim } => (t_failure_cause(exact, i, prim, t))
                        .map_or(String::new(), |cause| format!("; {cause}")),
                    Answer::Miss => String::new(),
                },
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
            _ => match outside.or_else(|| missed(exact, i, &j.exact, &answers[i].1, evidence)) {
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
        let (t, tmin) = (shown(t), shown(tmin));
        Some(format!(
            "t {t} is not above tmin {tmin}{behind}: only tmin < t < tmax counts"
        ))
    } else if t >= tmax {
        let (t, tmax) = (shown(t), shown(tmax));
        Some(format!(
            "t {t} is not below tmax {tmax}: only tmin < t < tmax counts, both ends open"
        ))
    } else {
        None
    }
}

/// Why the answer given is wrong, where the geometry says so (exactly, or in f64 with
/// margins: a hint, never a verdict), and only what sets the exact hit apart from the answer
/// given: the given primitive not met where its t says (where the ray passes it instead, or
/// the exact hit's t on another index), or met farther on; then why the exact hit may have
/// been missed: behind the origin with tmin < 0 (the given one is not), a triangle's small
/// determinant, a sphere's tangent or far root, a triangle's edge or vertex, its back (the
/// given one is not met from its back), a hit an epsilon past tmin would lose, a sphere's two
/// roots.
fn missed<T: Real>(
    exact: &Exact<T>,
    i: usize,
    standing: &Answer<T>,
    given: &Answer<T>,
    evidence: &Evidence,
) -> Option<String> {
    let given_hit = match *given {
        Answer::Hit { t, prim } if !t.is_nan() => Some((t, prim)),
        _ => None,
    };
    let exact_hit = match *standing {
        Answer::Hit { t, prim } => Some((t, prim)),
        Answer::Miss => None,
    };
    let joined = |facts: Vec<String>| (!facts.is_empty()).then(|| facts.join("; "));
    let mut facts = Vec::new();
    // (A NaN t was taken as a miss and told of the exact hit's edge, or of nothing.)
    if let Answer::Hit { t, prim } = *given {
        if t.is_nan() && (prim as usize) < exact.primitives {
            facts.push(not_a_number(exact, i, prim));
        }
    }
    if let Some((t, p)) = given_hit {
        let other = exact_hit.is_none_or(|(_, q)| q != p);
        let rounded_in = other
            .then(|| rounded_into_interval(exact, i, p, t))
            .flatten();
        if let Some(fact) = rounded_in {
            facts.push(fact);
        } else if other && !meets_at(exact, i, p, t.f64()) {
            facts.push(not_met(exact, i, p, t, exact_hit, evidence.shift));
        }
    }
    // (Numbers shown in the precision graded, as written: f64 of an f32 ran to 16 digits.)
    let Some((te_shown, prim)) = exact_hit else {
        return joined(facts);
    };
    let te = te_shown.f64();
    // (Behind the origin with tmin < 0, where the given t is not: that explains the hit
    // passed over, and a program ignoring tmin was told the nearest hit wins.)
    let tmin = exact.rays[i].1.tmin;
    let behind_explains =
        te < 0.0 && tmin.f64() < 0.0 && given_hit.is_none_or(|(t, _)| t.f64() >= 0.0);
    match given_hit {
        Some((_, p)) if p == prim => return joined(facts),
        Some((t, p)) if facts.is_empty() && near(t.f64(), te) => facts.push(format!(
            "primitive {p} is met too, at nearly the exact hit's t, but after it: two hits this \
             close can swap in rounded arithmetic, and the nearer one wins"
        )),
        // (A nearer hit the ray does not have: only where the ray passes the given primitive.)
        Some((t, _)) if t.f64() <= te => return joined(facts),
        // (The rule only where the program passed over a nearer hit it could not have missed
        // by rounding; a correct program that rounded a nearer edge away was told it.)
        Some((t, _)) if facts.is_empty() => facts.push(format!(
            "the given t {} is past the exact hit's t {}: {}",
            shown(t),
            shown(te_shown),
            match evidence.passes_nearer && !behind_explains {
                true => "the nearest hit wins",
                false => "the nearer hit is missed",
            }
        )),
        _ => {}
    }
    if behind_explains {
        facts.push(format!(
            "the exact hit is behind the origin (t {}), which counts where tmin < 0 (here {})",
            shown(te_shown),
            shown(tmin)
        ));
        return joined(facts);
    }
    facts.extend(small_determinant(exact, i, prim, evidence.epsilon_below()));
    facts.extend(sphere_rounding(exact, i, prim));
    // (An epsilon's loss, where the run bears one out, rather than the face's side: both
    // true, the first the likelier cause of a hit this near tmin; beside a tangent, which
    // explains the miss, it was noise.)
    let near = gap_past_tmin(exact, i, standing).filter(|&(gap, near)| near && gap > 0.0);
    let (fact, tangent) = where_on(
        exact,
        i,
        te,
        prim,
        given_hit.map(|(_, p)| p),
        match () {
            // (A program that met a back right does not cull: the side explains nothing.)
            _ if evidence.meets_backs => Back::Unsaid,
            _ if evidence.culls_backs()
                && near.is_none_or(|(gap, _)| gap >= evidence.tmin_epsilon_below()) =>
            {
                Back::WithRule
            }
            _ => Back::Said,
        },
    );
    let placed = fact.is_some();
    facts.extend(fact);
    // (A sphere missed with nothing else to say of it: its two roots, for the student's
    // quadratic to be checked against; first where the far one is past tmax, which a program
    // taking the far root loses: told first of the hit's nearness to tmin, it was misled.)
    let roots = match (exact.shape(prim), given_hit, placed) {
        (raylab::geometry::Shape::Sphere(s), None, false) => {
            let ([near_root, far_root], _, _) = quadratic(exact, i, &s);
            let tmax = exact.rays[i].1.tmax;
            let past = far_root >= tmax.f64();
            let roots = format!(
                "the ray meets the sphere twice (its discriminant is above 0), at t {}{}",
                two_roots([near_root, far_root]),
                match past {
                    true => format!(": the far one is past tmax {}", shown(tmax)),
                    false => String::new(),
                }
            );
            Some((roots, past))
        }
        _ => None,
    };
    let (before, after) = match roots {
        Some((roots, true)) => (Some(roots), None),
        other => (None, other.map(|(roots, _)| roots)),
    };
    facts.extend(before);
    if let (Some((gap, _)), false) = (near, tangent) {
        facts.push(format!(
            "the exact hit is only {gap:.1e} past tmin: a hit counts however near tmin{}",
            lost_past_tmin(exact, i, prim, gap, evidence, "loses")
                .map_or(String::new(), |why| format!(" ({why})"))
        ));
    }
    facts.extend(after);
    joined(facts)
}

/// Where ray `i` passes primitive `p`, which it does not meet at the given `t`: the exact
/// hit's t on another index (`exact_hit`: with `shift`, the index every such answer is off
/// by), outside a triangle (beyond which edges, in Möller–Trumbore's u and v), parallel to
/// its plane, missing a sphere, or meeting it at another t.
fn not_met<T: Real>(
    exact: &Exact<T>,
    i: usize,
    p: u32,
    t: T,
    exact_hit: Option<(T, u32)>,
    shift: Option<i64>,
) -> String {
    if let Some((te, q)) = exact_hit.filter(|&(te, _)| near(te.f64(), t.f64())) {
        let within = if te == t { "" } else { " (within 10⁻⁶)" };
        let index = format!(
            "the given t {} is the exact hit's{within}, on primitive {q}, not {p}",
            shown(t)
        );
        return match shift {
            Some(k) => format!(
                "{index}: every primitive given at the exact t is 1 {} one the ray meets \
                 there (indices count from 0, in the scene's order)",
                if k > 0 { "past" } else { "before" }
            ),
            None => format!("{index}; {}", passes(exact, i, p, t)),
        };
    }
    passes(exact, i, p, t)
}

/// A given t that is NaN, on primitive `p`: where the ray is parallel to a triangle's plane
/// (its determinant exactly 0), the division that made it.
fn not_a_number<T: Real>(exact: &Exact<T>, i: usize, p: u32) -> String {
    use raylab::geometry::{triangle, Location};
    let nan = "the given t is not a number (NaN)";
    match exact.shape(p).locate(&exact.rays[i].1.ray) {
        Location::Triangle(triangle::Location::EdgeOn) => format!(
            "{nan}: the ray is parallel to triangle {p}'s plane (its determinant is 0), where \
             a division by it gives NaN or ∞: no hit"
        ),
        _ => nan.to_string(),
    }
}

/// Where the given primitive `p`, a triangle, is met at the given `t` (within the grader's
/// t tolerance, 10⁻⁶ of |o| + |t·d| + extent: [`grade::t_error`]) but its exact t is not
/// inside the ray's open interval (the origin on it, t exactly 0 = tmin): that, the given t
/// being that t rounded into the interval. (A program's t of 3.7e-17 on the triangle whose
/// vertex is the origin showed as a bare wrong primitive.)
fn rounded_into_interval<T: Real>(exact: &Exact<T>, i: usize, p: u32, t: T) -> Option<String> {
    let shape = exact.shape(p);
    let raylab::geometry::Shape::Triangle(_) = shape else {
        return None;
    };
    let ray = &exact.rays[i].1;
    let (inf, tmin, tmax) = (T::of(f64::INFINITY), ray.tmin, ray.tmax);
    let line = raylab::tracefile::TraceRay {
        tmin: -inf,
        tmax: inf,
        ..*ray
    };
    let [Answer::Hit { t: on, .. }] = grade::exact_answers(&[shape], &[line])[..] else {
        return None;
    };
    let (_, apart) = grade::t_error(ray, on, t, shape.extent(), 1e-6);
    if apart > 1e-6 {
        return None;
    }
    let (end, side) = match () {
        _ if on <= tmin => (tmin, "above tmin"),
        _ if on >= tmax => (tmax, "below tmax"),
        _ => return None,
    };
    let (on, end, t) = (shown(on), shown(end), shown(t));
    Some(format!(
        "the ray meets triangle {p} exactly at t {on}, not {side} {end}: the given t {t} is that \
         t rounded into the interval (only tmin < t < tmax counts)"
    ))
}

/// Where ray `i` passes primitive `p`, which it does not meet at the given `t`: outside a
/// triangle (beyond which edges, in Möller–Trumbore's u and v), parallel to its plane,
/// missing a sphere, or meeting it at another t.
fn passes<T: Real>(exact: &Exact<T>, i: usize, p: u32, t: T) -> String {
    use raylab::geometry::{sphere, triangle, Location, Shape};
    let shape = exact.shape(p);
    let t = shown(t);
    match (&shape, shape.locate(&exact.rays[i].1.ray)) {
        (_, Location::Triangle(triangle::Location::Outside(edges))) => {
            // (Edge k's outside is where the weight of the vertex opposite it is below 0.)
            let beyond = |k: usize| ["v < 0", "u + v > 1", "u < 0"][k];
            let names: Vec<&str> = edges.iter().map(|&k| triangle::EDGES[k]).collect();
            let conditions: Vec<&str> = edges.iter().map(|&k| beyond(k)).collect();
            format!(
                "the ray passes triangle {p} outside, beyond its edge{} {} ({}, u and v the \
                 weights of v1 and v2): no hit",
                if edges.len() > 1 { "s" } else { "" },
                names.join(" and "),
                conditions.join(" and ")
            )
        }
        (Shape::Triangle(tri), Location::Triangle(triangle::Location::EdgeOn)) => {
            match triangle::zero_area(&tri.0) {
                true => format!(
                    "triangle {p} has zero area (its vertices on one line): it is never hit"
                ),
                false => format!("the ray is parallel to triangle {p}'s plane: no hit"),
            }
        }
        (_, Location::Sphere(sphere::Location::Misses)) => {
            let rounding = match sphere_rounding(exact, i, p) {
                Some(fact) => format!("; {fact}"),
                None => String::new(),
            };
            format!("the ray misses sphere {p} (its discriminant is below 0): no hit{rounding}")
        }
        (Shape::Sphere(s), location) => {
            let (roots, _, _) = quadratic(exact, i, s);
            match location {
                Location::Sphere(sphere::Location::Tangent) => format!(
                    "the ray touches sphere {p} (a tangent, discriminant 0) at t {}, not at the \
                     given t {t}",
                    approx(roots[0])
                ),
                _ => format!(
                    "the ray meets sphere {p} at t {}, not at the given t {t}",
                    two_roots(roots)
                ),
            }
        }
        (Shape::Triangle(tri), _) => format!(
            "the ray meets triangle {p} at t {}, not at the given t {t}",
            approx(plane_t(exact, i, tri))
        ),
    }
}

/// A sphere's two roots (of a ray through it: not a tangent) as a hint shows them (`0.5 and
/// 2`): [`approx`], or the fewest significant digits up to 15 that tell them apart (17 claimed
/// digits f64's estimate does not hold), or one where even 15 do not (a ray within an ulp or
/// so of a tangent).
fn two_roots([near, far]: [f64; 2]) -> String {
    if approx(near) != approx(far) {
        return format!("{} and {}", approx(near), approx(far));
    }
    let digits = |k: usize, x: f64| format!("{:.*e}", k - 1, x);
    match (8..=15).find(|&k| digits(k, near) != digits(k, far)) {
        Some(k) => format!("{} and {}", digits(k, near), digits(k, far)),
        None => format!(
            "{} (twice: the roots are closer than f64 tells)",
            approx(near)
        ),
    }
}

/// A t (or tmin, tmax) as a hint shows it: in the precision graded, its shortest digits, in
/// exponent form outside 10⁻³…10⁶ (a t of 1.4e28 ran to 29 digits, one of 10⁻¹⁷ to 17 zeros).
fn shown<T: Real>(t: T) -> String {
    match t != T::zero() && t.is_finite() && !(1e-3..1e6).contains(&t.f64().abs()) {
        true => format!("{t:e}"),
        false => t.to_string(),
    }
}

/// An f64 estimate as shown in a hint: to 7 decimals, or 7 significant digits outside
/// 10⁻³…10⁶.
fn approx(x: f64) -> String {
    // (0 without its sign: a root "at t -6.4064873 and -0" read as a bug.)
    let x = if x == 0.0 { 0.0 } else { x };
    match x != 0.0 && !(1e-3..1e6).contains(&x.abs()) {
        true => format!("{x:.6e}"),
        false => format!("{:.7}", x)
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string(),
    }
}

/// Whether ray `i` meets primitive `p` at about `t` (10⁻⁶ of it, in f64): the given answer's
/// primitive where it says.
fn meets_at<T: Real>(exact: &Exact<T>, i: usize, p: u32, t: f64) -> bool {
    use raylab::geometry::triangle::Location as On;
    use raylab::geometry::{sphere, Location};
    let met = match exact.shape(p).locate(&exact.rays[i].1.ray) {
        Location::Sphere(at) => at != sphere::Location::Misses,
        Location::Triangle(at) => matches!(at, On::Inside { .. } | On::Edge(_) | On::Vertex(_)),
    };
    met && surface_ts(exact, i, p).iter().any(|&r| near(r, t))
}

/// How a hint tells of a triangle met from its back.
#[derive(Clone, Copy, PartialEq)]
enum Back {
    /// Not at all: the program met a back right, so the side explains nothing.
    Unsaid,
    /// As a fact.
    Said,
    /// With the rule that both sides count: the run bears culling out.
    WithRule,
}

/// Where on primitive `prim` ray `i` meets it at `te`, where that explains a miss, decided
/// exactly where it is a place ([`raylab::geometry::Shape::locate`]): a sphere's tangent
/// or far root (the origin inside, or the near root not above tmin); a triangle's edge or
/// vertex, and its back (as `back` says it) where `given` (the primitive given instead, if
/// any) is not a triangle met from its back too. With whether it is a tangent.
fn where_on<T: Real>(
    exact: &Exact<T>,
    i: usize,
    te: f64,
    prim: u32,
    given: Option<u32>,
    back: Back,
) -> (Option<String>, bool) {
    use raylab::geometry::{sphere, triangle, Location, Shape};
    let ray = &exact.rays[i].1.ray;
    let shape = exact.shape(prim);
    let fact = match (&shape, shape.locate(ray)) {
        (_, Location::Sphere(sphere::Location::Tangent)) => {
            let tangent = "the ray touches the sphere (a double root, discriminant 0): a \
                           tangent is a hit";
            return (Some(tangent.into()), true);
        }
        (Shape::Sphere(s), _) => {
            let r = s.radius.f64();
            let ([near, far], c, _) = quadratic(exact, i, s);
            ((te - far).abs() < (te - near).abs()).then(|| {
                let why = match c < -1e-6 * r * r {
                    true => "the origin is inside the sphere",
                    false => "the near root is not above tmin",
                };
                format!("the exact hit is the sphere's far root, where the ray leaves it: {why}")
            })
        }
        // (Both where both hold: a hit on an edge of a triangle met from its back was told of
        // the edge alone, where a culling program's leak was the back's.)
        (Shape::Triangle(tri), location) => {
            let mut facts = Vec::new();
            // (Rounding too: a correct program that rounds a weight below 0 was told only of
            // the rule, as an open-edge bug is.) (Which weight: a student's open `u` test lost
            // 226 hits, all on the edge where u = 0, told of "u, v or u + v".)
            let on = match &location {
                Location::Triangle(at @ triangle::Location::Edge(k)) => {
                    Some((at, EDGE_WEIGHTS[*k], EDGE_ROUNDED[*k]))
                }
                Location::Triangle(at @ triangle::Location::Vertex(k)) => {
                    Some((at, VERTEX_WEIGHTS[*k], "u, v or u + v rounded past 0 or 1"))
                }
                _ => None,
            };
            if let Some((at, weights, rounded)) = on {
                facts.push(format!(
                    "the exact hit is {at} of the triangle, where {weights} ({UV}): the edges \
                     count, closed (an open test, or {rounded}, loses it)"
                ));
            }
            // (Not beside a determinant below rounding, said apart: its weights are noise.)
            let edge = within_rounding_of_edge(exact, i, tri, &location)
                .filter(|&(_, w)| w < 1e-3 && !determinant_below_rounding(exact, i, tri));
            if let Some((edge, weight)) = edge {
                facts.push(format!(
                    "the exact hit is inside the triangle, {weight:.1e} (barycentric) from its \
                     edge {}, where {} ({UV}): within rounding of it ({} loses it)",
                    raylab::geometry::triangle::EDGES[edge],
                    EDGE_WEIGHTS[edge],
                    EDGE_ROUNDED[edge]
                ));
            }
            // (The side always, as a fact; the rule only where the run bears culling out: a
            // culling program's leaks on edges were told of the edges alone, or of nothing.)
            let given_faces_back = given.is_some_and(|g| meets_back(exact, i, g));
            let rule = match back {
                Back::WithRule => ": both sides count",
                Back::Said | Back::Unsaid => "",
            };
            if back != Back::Unsaid && meets_back(exact, i, prim) && !given_faces_back {
                let n = "n = (v1 − v0) × (v2 − v0)";
                facts.push(format!(
                    "the exact hit is on the triangle's back (d·n > 0 for {n}){rule}"
                ));
            }
            (!facts.is_empty()).then(|| facts.join("; "))
        }
    };
    (fact, false)
}

/// What u and v are, as the hints name them.
const UV: &str = "u and v the weights of v1 and v2";

/// The weight that is 0 (or 1) on each edge of [`raylab::geometry::triangle::EDGES`], and what
/// rounding past it does.
const EDGE_WEIGHTS: [&str; 3] = ["v = 0", "u + v = 1", "u = 0"];
const EDGE_ROUNDED: [&str; 3] = [
    "v rounded below 0",
    "u + v rounded above 1",
    "u rounded below 0",
];

/// The weights at each vertex.
const VERTEX_WEIGHTS: [&str; 3] = ["u = v = 0", "u = 1, v = 0", "u = 0, v = 1"];

/// [`past_tmin`] of the exact hit `standing` (none for a miss), at its [`fine_t`].
fn gap_past_tmin<T: Real>(exact: &Exact<T>, i: usize, standing: &Answer<T>) -> Option<(f64, bool)> {
    match *standing {
        Answer::Hit { t, prim } => past_tmin(exact, i, fine_t(exact, i, prim, t)),
        Answer::Miss => None,
    }
}

/// What `loses` (or skips) the hit of ray `i` on `prim` `gap` past tmin: t rounded to tmin
/// or below, where the gap is within t's rounding ([`t_rounding`]: t = 1 + 2⁻¹⁴ was said to
/// be lost so, 512 ulps of f32 away), and an epsilon in tmin's place where the run bears one
/// out ([`Evidence::tmin_epsilon_below`]: a correct f32 program that got a hit 1.4e-8 past
/// tmin was told of an epsilon beside one 4.3e-8 past it). `None` where neither is so.
fn lost_past_tmin<T: Real>(
    exact: &Exact<T>,
    i: usize,
    prim: u32,
    gap: f64,
    evidence: &Evidence,
    loses: &str,
) -> Option<String> {
    let tmin = exact.rays[i].1.tmin.f64();
    let rounding = t_rounding(exact, i, prim, tmin + gap);
    let epsilon = gap < evidence.tmin_epsilon_below();
    Some(match (epsilon, gap <= rounding) {
        (true, true) => {
            format!("an epsilon in its place {loses} it, and so does t rounded to tmin or below")
        }
        (false, true) => format!("t rounded to tmin or below {loses} it"),
        (true, false) => format!("an epsilon in its place {loses} it"),
        (false, false) => return None,
    })
}
