//! `raylab check`'s hints beside a wrong answer: each a fact of the exact geometry, checked
//! on rays built for it (the classic bugs' programs hold the hints to their bugs:
//! classic_bugs.rs).

use common::binary::text;

use crate::common;

crate::raylab_runner!();
crate::check_runner!();

/// The output of `raylab check` of `answers` for `scene` and `rays` (their texts).
pub(super) struct Hints {
    pub(super) out: String,
}

impl Hints {
    /// The reproducer line of answer `n` (from 1), by the answer file's line it names.
    pub(super) fn line(&self, n: usize) -> String {
        let at = format!("answers.txt:{n}): ");
        (self.out.lines().find(|l| l.contains(&at)))
            .unwrap_or_else(|| panic!("no line {n}: {}", self.out))
            .to_string()
    }
}

pub(super) fn hints(scene: &str, rays: &str, answers: &str) -> Hints {
    hints_with(scene, rays, answers, &[])
}

/// [`hints`] with more arguments for `raylab check`.
pub(super) fn hints_with(scene: &str, rays: &str, answers: &str, args: &[&str]) -> Hints {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let files = [
        ("scene.txt", scene),
        ("rays.txt", rays),
        ("answers.txt", answers),
    ];
    for (name, text) in files {
        std::fs::write(d.join(name), text).unwrap();
    }
    let path = |name: &str| d.join(name).to_str().unwrap().to_string();
    let o = check_answers(
        &path("scene.txt"),
        &path("rays.txt"),
        &d.join("answers.txt"),
        args,
    );
    Hints {
        out: text(&o.stdout),
    }
}

/// The hints are facts of the exact geometry: a ray 10⁻¹⁷ beside a vertex meets the inside,
/// within rounding of its edge (an f64 test within 10⁻⁹ had said "at vertex v0"), and from
/// the back, where the run bears out culled backs (a back face passed over inside: ray 3; a
/// front met right before another: ray 5, so the pass is no last hit's), a hit on an edge
/// from the back is told both, a primitive given at a t where the ray does not meet it is
/// said so, with the t where it does, not told that the nearest hit wins (nor that the exact
/// one is a back face: so is the one given), and one met just past the exact hit is told so.
#[test]
fn the_hints_name_the_exact_place_and_a_given_t_that_meets_nothing() {
    let scene = "tri 0 0 0 1 0 0 0 1 0\ntri 0 0 5 1 0 5 0 1 5\ntri 0 0 1e-7 1 0 1e-7 0 1 1e-7\n\
                 tri 5 5 9 5 6 9 6 5 9\ntri 4 4 20 4 8 20 8 4 20\n";
    // Beside vertex v0 by 6e-17 and 1e-17 (inside); through the edge v0–v1 exactly; through
    // the inside, to be answered with the far triangle at t 2 (it lies at t 6), and with the
    // triangle 10⁻⁷ behind the first, where it lies; through the front at z = 9, before the
    // one at z = 20.
    let rays = "6e-17 1e-17 -1 0 0 1 0 inf\n0.5 0 -1 0 0 1 0 inf\n0.25 0.25 -1 0 0 1 0 inf\n\
                0.25 0.25 -1 0 0 1 0 inf\n5.25 5.25 -1 0 0 1 0 inf\n";
    let h = hints(
        scene,
        rays,
        "miss\nmiss\nhit 2 1\nhit 1.0000001 2\nhit 10 3\n",
    );
    assert!(
        h.line(1).ends_with(
            "[leak: the exact hit is inside the triangle, 1.0e-17 (barycentric) from its edge \
             v0–v1, where v = 0 (u and v the weights of v1 and v2): within rounding of it (v \
             rounded below 0 loses it); the \
             exact hit is on the triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − v0)): both \
             sides count]"
        ),
        "{}",
        h.out
    );
    assert!(
        h.line(2).ends_with(
            "[leak: the exact hit is on the edge v0–v1 of the triangle, where v = 0 (u and v the \
             weights of v1 and v2): the edges count, closed (an open test, or v rounded below 0, \
             loses it); the exact hit is on the \
             triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − v0)): both sides count]"
        ),
        "{}",
        h.out
    );
    assert!(
        h.line(3)
            .ends_with("[wrong primitive: the ray meets triangle 1 at t 6, not at the given t 2]"),
        "{}",
        h.out
    );
    assert!(
        h.line(4).ends_with(
            "[wrong primitive: primitive 2 is met too, at nearly the exact hit's t, but after it: \
             two hits this close can swap in rounded arithmetic, and the nearer one wins]"
        ),
        "{}",
        h.out
    );
}

/// The hints' numbers hold where f64's textbook formulas do not: a tiny sphere 2²⁰ away met
/// at two roots 0.003 apart (b² − a·c had cancelled to one root, "closer than f64 tells"),
/// a far tiny sphere's discriminant below the rounding of the textbook formula's (r² lost
/// beside |o − c|²), a tangent at tmin (said twice met), no index shift claimed where another
/// answer at the exact t names the exact primitive, a hit 8.9e-8 past tmin (said 1.2e-7, from
/// its t rounded to f32), and roots alike to 9 digits shown to 10 (17 claimed what f64's
/// estimate does not hold).
#[test]
fn the_hints_hold_for_far_tiny_spheres_tangents_and_mixed_indices() {
    let scene = "sphere 1048576 0 0 0.00390625\nsphere 0 0 20 5\n\
                 tri 0 0 1 1 0 1 0 1 1\ntri 0 0 2 1 0 2 0 1 2\n\
                 tri -1 0 1 1 0 1.0000003576278687 -1 2 1\n";
    // (The last ray: 2²¹ from the first sphere, its roots alike to 9 digits.)
    let rays = "0 0.00250742048956453800201416015625 0.000801336951553821563720703125 \
                2 0 0 0 inf\n5 0 0 0 0 1 20 inf\n0.25 0.25 0 0 0 1 0 inf\n\
                0.5 0.25 0 0 0 1 0 inf\n-0.5 0.5 0 0 0 1 1 inf\n\
                2097152 -0.0024874298833310604095458984375 0.0030068219639360904693603515625 \
                -0.25 0 0 0 inf\n";
    let h = hints(
        scene,
        rays,
        "miss\nhit 74.641014 1\nhit 1 2\nhit 1 3\nmiss\nmiss\n",
    );
    assert!(
        h.line(1).ends_with(
            "[leak: sphere 0's |b² − a·c| is only 7.6e-18 of a·|o − c|² (b = d·(o − c): a \
             quarter of b² − 4ac with b = 2 d·(o − c)), below the rounding of the textbook \
             formula in f32 (c = |o − c|² − r², with r² 1.4e-17 of |o − c|²): computed so, it can \
             come out with the other sign; the ray meets the sphere twice (its discriminant is \
             above 0), at t 524287.998557 and 524288.001443]"
        ),
        "{}",
        h.out
    );
    assert!(
        h.line(2).ends_with(
            "[false hit: the ray touches sphere 1 (a tangent, discriminant 0) at t 20, not at \
             the given t 74.641014]"
        ),
        "{}",
        h.out
    );
    assert!(
        h.line(4).ends_with(
            "[wrong primitive: the given t 1 is the exact hit's, on primitive 2, not 3; the ray \
             meets triangle 3 at t 2, not at the given t 1]"
        ),
        "{}",
        h.out
    );
    assert!(
        h.line(5).ends_with(
            "[leak: the exact hit is only 8.9e-8 past tmin: a hit counts however near tmin (t \
             rounded to tmin or below loses it)]"
        ),
        "{}",
        h.out
    );
    assert!(
        h.line(6).ends_with(
            "[leak: sphere 0's |b² − a·c| is only 2.8e-20 of a·|o − c|² (b = d·(o − c): a \
             quarter of b² − 4ac with b = 2 d·(o − c)), below the rounding of the textbook \
             formula in f32 (c = |o − c|² − r², with r² 1.4e-17 of |o − c|²): computed so, it can \
             come out with the other sign; the ray meets the sphere twice (its discriminant is \
             above 0), at t 4.194303999e6 and 4.194304001e6]"
        ),
        "{}",
        h.out
    );
}

/// "The nearest hit wins" only where the program passed over a nearer hit well inside its
/// triangle: one that gave the far triangle only where the near one's edge was hit is told
/// the nearer hit is missed, and of the edge (a correct program that rounded an edge away was
/// told the rule).
#[test]
fn the_nearest_hit_rule_needs_a_nearer_hit_passed_over_inside() {
    let scene = "tri 0 0 1 1 0 1 0 1 1\ntri -5 -5 2 5 -5 2 0 5 2\n";
    // On the near triangle's edge v0–v1, and inside it; the far one behind both.
    let rays = "0.5 0 0 0 0 1 0 inf\n0.25 0.25 0 0 0 1 0 inf\n";
    let h = hints(scene, rays, "hit 2 1\nhit 1 0\n");
    assert!(
        h.line(1).contains(
            "[wrong primitive: the given t 2 is past the exact hit's t 1: the nearer hit is \
             missed; the exact hit is on the edge v0–v1 of the triangle"
        ),
        "{}",
        h.out
    );
    let h = hints(scene, rays, "hit 2 1\nhit 2 1\n");
    for n in [1, 2] {
        assert!(h.line(n).contains("1: the nearest hit wins"), "{}", h.out);
    }
    // A hit behind the origin passed over (tmin −∞) is told so, not the rule: the program
    // ignores tmin (it was told "the nearest hit wins").
    let scene = "tri 0 0 -1.5 1 0 -1.5 0 1 -1.5\ntri -5 -5 2 5 -5 2 0 5 2\n";
    let rays = "0.25 0.25 0 0 0 1 -inf inf\n0.25 0.25 0 0 0 1 -inf inf\n";
    let h = hints(scene, rays, "hit 2 1\nhit 2 1\n");
    assert!(
        h.line(1).ends_with(
            "[wrong primitive: the given t 2 is past the exact hit's t -1.5: the nearer hit is \
             missed; the exact hit is behind the origin (t -1.5), which counts where tmin < 0 \
             (here -inf)]"
        ),
        "{}",
        h.out
    );
}

/// A t printed short is named so only where the program prints short, by the digits two or
/// more of its t's were written with (or the decimals all were): a t of 1 for 0.9999839 from
/// a program that prints 9 digits elsewhere (or 12, with trailing zeros), or from a run of
/// that one answer, is a t failure and no more (it was told to print 9 digits); from one that
/// prints 2, the digits to print. And as what was rounded: 1.500065008… is 1.50007 to 6
/// digits, where its f32 1.500064969 gives 1.50006 (a program printing its f32 t), said as
/// that f32 so rounded (it was a bare t failure).
#[test]
fn a_short_t_is_blamed_on_the_printing_only_where_the_program_prints_short() {
    let scene = "tri -1 -1 0.9999839 1 -1 0.9999839 0 1 0.9999839\n";
    let rays = "0 0 0 0 0 1 0 inf\n".repeat(3);
    for other in ["1.23456789", "1.50000000000"] {
        let h = hints(
            scene,
            &rays,
            &format!("hit 1 0\nhit {other} 0\nhit {other} 0\n"),
        );
        let line = h.line(1);
        assert!(line.ends_with("of |o| + |t·d| + extent]"), "{}", h.out);
    }
    let h = hints(scene, &rays[..18], "hit 1 0\n");
    assert!(h.line(1).ends_with("of |o| + |t·d| + extent]"), "{}", h.out);
    let h = hints(scene, &rays, "hit 1 0\nhit 1.5 0\nhit 2.5 0\n");
    assert!(
        h.line(1)
            .ends_with("t is the exact one to 2 significant digits: print 9 (%.9g)]"),
        "{}",
        h.out
    );
    // A fixed count of decimals, `%.4f` (it had a bare t failure), beside a t with an
    // exponent, as JavaScript's `toFixed(4)` writes 1e21 and more (no decimals were named).
    for third in ["", "hit 9.999839e-1 0\n"] {
        let rays = &rays[..if third.is_empty() { 36 } else { 54 }];
        let h = hints(
            scene,
            rays,
            &format!("hit 1.0000 0\nhit 12.5000 0\n{third}"),
        );
        assert!(
            h.line(1)
                .ends_with("t is the exact one to 4 decimals (%.4f): print 9 (%.9g)]"),
            "{}",
            h.out
        );
    }
    // A t of 1.4e-5 at `%.4f` is 0.0000: not above tmin, and printed so (told of tmin alone).
    let near = "tri -1 -1 1.4e-5 1 -1 1.4e-5 0 1 1.4e-5\n";
    let h = hints(near, &rays[..36], "hit 0.0000 0\nhit 0.0000 0\n");
    assert!(
        h.line(1).ends_with(
            "t 0 is not above tmin 0: only tmin < t < tmax counts; t is the exact one to 4 \
             decimals (%.4f): print 9 (%.9g)]"
        ),
        "{}",
        h.out
    );
    let z = "4.500195026397705";
    let scene = format!("tri -10 -10 {z} 10 -10 {z} 0 10 {z}\n");
    let rays = "0 0 0 0 0 3 0 inf\n0 0 0 0 0 3 0 inf\n";
    let h = hints(&scene, rays, "hit 1.50006 0\nhit 1.50007 0\n");
    assert!(
        h.line(1).ends_with(
            "t is the exact one in f32 (1.50006496906280517578125) to 6 significant digits: \
             print 9 (%.9g)]"
        ),
        "{}",
        h.out
    );
    assert!(
        h.line(2)
            .ends_with("t is the exact one to 6 significant digits: print 9 (%.9g)]"),
        "{}",
        h.out
    );
}

/// A primitive given at a t its exact t rounds to, across tmin (the origin on a triangle:
/// exactly 0, not above tmin 0), is told so (it was a bare wrong primitive), a t far from 1
/// in exponent form; a determinant
/// below f32's smallest normal number is told to underflow in f32, and not in f64.
#[test]
fn a_t_rounded_past_tmin_and_an_underflowing_determinant_are_named() {
    let scene = "tri 0 0 0 1 0 0 0 1 0\ntri -10 -10 5 10 -10 5 0 10 5\n";
    let h = hints(scene, "0 0 0 0.1 0.1 1 0 inf\n", "hit 1e-17 0\n");
    assert!(
        h.line(1).ends_with(
            "[wrong primitive: the ray meets triangle 0 exactly at t 0, not above tmin 0: the \
             given t 1e-17 is that t rounded into the interval (only tmin < t < tmax counts)]"
        ),
        "{}",
        h.out
    );
    // (A t far from 1 in its exponent form: 1e28 ran to 29 digits.)
    let h = hints(scene, "0 0 -1 0 0 1 0 inf\n", "hit 1e28 1\n");
    assert!(
        h.line(1)
            .contains("the ray meets triangle 1 at t 6, not at the given t 1e28;"),
        "{}",
        h.out
    );
    // (Met from its front: a back's miss would be culling's.)
    let tiny = "tri 0 0 1e-20 0 1e-20 1e-20 1e-20 0 1e-20\n";
    let ray = "2e-21 2e-21 0 0 0 1 0 inf\n";
    // (In f32 no epsilon: underflow explains the miss, and a correct f32 program that lost
    // the suite's subnormal cube so was told it culled.)
    let h = hints(tiny, ray, "miss\n");
    assert!(
        h.line(1).contains(
            "is 1.0e-40, below f32's smallest normal number 1.2e-38: in f32 it comes out 0 or \
             without its digits (f64 holds it); the exact"
        ) && !h.line(1).contains("epsilon"),
        "{}",
        h.out
    );
    let h = hints_with(tiny, ray, "miss\n", &["--precision", "f64"]);
    assert!(
        h.line(1).contains("is 1.0e-40, near 0: an epsilon"),
        "{}",
        h.out
    );
}

/// Indices counted from 1 are named where ties are: on a shared edge the program's own choice
/// (the tie's other primitive) shifted is not the exact one's, and the rule was held back (a
/// student's program got "the ray passes triangle 1 outside" on every ray of the cube).
#[test]
fn an_index_from_1_is_named_beside_ties_the_program_chose_otherwise() {
    // Two triangles sharing the edge (1, 0)–(0, 1) at z = 1, a third far off; through the
    // shared edge (tied: the program chose triangle 1, and said 2), inside the second, inside
    // the first.
    let scene = "tri 0 0 1 1 0 1 0 1 1\ntri 1 0 1 1 1 1 0 1 1\ntri 5 5 1 6 5 1 5 6 1\n";
    let rays = "0.5 0.5 0 0 0 1 0 inf\n0.75 0.75 0 0 0 1 0 inf\n0.25 0.25 0 0 0 1 0 inf\n";
    let h = hints(scene, rays, "hit 1 2\nhit 1 2\nhit 1 1\n");
    let rule = "every primitive given at the exact t is 1 past one the ray meets there (indices \
                count from 0, in the scene's order)]";
    for n in [1, 3] {
        assert!(h.line(n).ends_with(rule), "{}", h.out);
    }
}

/// A sphere missed where its far root is past tmax says so first (a program taking the far
/// root loses the near one: told first that the hit was near tmin, a student was misled).
#[test]
fn a_sphere_missed_with_its_far_root_past_tmax_says_so() {
    let scene = "sphere 0 0 20 5\n";
    // (And a direction whose d·d underflows in f32: it was told only of the two roots.)
    let h = hints(scene, "0 0 0 0 0 1e-20 0 inf\n", "miss\n");
    assert!(
        h.line(1).contains(
            "[leak: d·d is 1.0e-40, below f32's smallest normal number 1.2e-38: in f32 the \
             quadratic's a = d·d comes out 0 or without its digits (f64 holds it); the ray \
             meets the sphere twice"
        ),
        "{}",
        h.out
    );
    let h = hints(
        scene,
        "0 0 0 0 0 1 14.9 16\n0 0 0 0 0 1 0 inf\n",
        "miss\nhit 15 0\n",
    );
    assert!(
        h.line(1).ends_with(
            "[leak: the ray meets the sphere twice (its discriminant is above 0), at t 15 and \
             25: the far one is past tmax 16]"
        ),
        "{}",
        h.out
    );
}

/// A t failure on a triangle whose determinant is below the rounding of its terms (a ray
/// one ulp out of the plane, from the suite's family 27) says so: t, a quotient by it, is
/// as lost (it was a bare t failure).
#[test]
fn a_t_divided_by_a_lost_determinant_says_so() {
    let ray = "0.106316842138767242431640625 -0.04984928667545318603515625 \
               0.943532466888427734375 0.1345444619655609130859375 \
               0.15075765550136566162109375 -0.28530216217041015625 0 inf\n";
    let h = hints("tri 1 0 0 0 1 0 0 0 1\n", ray, "hit 1.3333334 0\n");
    assert!(
        h.line(1).ends_with(
            "[t failure: o + t·d off by 1.37e-1 of |o| + |t·d| + extent; the triangle's \
             determinant e1·(d × e2) (e1 = v1 − v0, e2 = v2 − v0) is 4.5e-8, below the \
             rounding of its terms in f32: rounded, it can come out 0 or with the other sign, \
             and t (a quotient by it) far off]"
        ),
        "{}",
        h.out
    );
}

/// A NaN t, as a program dividing by a determinant of 0 gives for a ray in a triangle's
/// plane, is said to be one, and why (it was a bare false hit, or told of another hit's
/// edge).
#[test]
fn a_nan_t_on_a_triangle_the_ray_is_parallel_to_says_so() {
    let h = hints(
        "tri 0 0 0 1 0 0 0 1 0\n",
        "-1 0.25 0 1 0 0 0 inf\n",
        "hit nan 0\n",
    );
    assert!(
        h.line(1).ends_with(
            "[false hit: the given t is not a number (NaN): the ray is parallel to triangle 0's \
             plane (its determinant is 0), where a division by it gives NaN or ∞: no hit]"
        ),
        "{}",
        h.out
    );
}

/// Graded in f64, an epsilon on a determinant below f32's smallest normal number is named
/// beside the f32 that loses it too (a JavaScript student's `Math.fround` program, graded
/// in f64, was told of an epsilon alone).
#[test]
fn an_epsilon_below_f32s_range_names_f32_too() {
    let h = hints_with(
        "tri 0 0 1e-20 1e-20 0 1e-20 0 1e-20 1e-20\ntri 5 0 2 6 0 2 5 1 2\n",
        "2e-21 2e-21 0 0 0 1 0 inf\n5.2 0.2 0 0 0 1 0 inf\n",
        "miss\nhit 2 1\n",
        &["--precision", "f64"],
    );
    assert!(
        h.line(1).contains(
            "is -1.0e-40, near 0: an epsilon on it (|det| < ε: no hit) loses the hit, where \
             only det = 0 is parallel (or the program computes in f32, where it is below the \
             smallest normal number: `--precision f32` grades it so)"
        ),
        "{}",
        h.out
    );
}

/// A determinant is said to be below the rounding of its terms only where its six products
/// e1ᵢ·dⱼ·e2ₖ allow it: a sliver's 2.0e-7, its one product, rounds to within an ulp in any
/// f32 formula (|e1| |d| |e2| = 2 had it said to come out 0 or with the other sign).
#[test]
fn a_determinant_of_one_product_is_not_said_to_round_away() {
    let h = hints(
        "tri 0 0 0 2 0 0 1 1e-7 0\n",
        "1 2.5e-8 1 0 0 -1 0 inf\n",
        "miss\n",
    );
    assert!(h.line(1).ends_with("[leak]"), "{}", h.out);
    // Grazing a triangle whose plane is not the axes' instead: its products cancel, said so
    // (as where epsilons are named, above).
    let h = hints(
        "tri 0 0 0 0 1 -1 1 0 0\n",
        "-0.75 -0.75 0.7499997615814208984375 1 1 -0.9999997615814208984375 0 inf\n",
        "miss\n",
    );
    assert!(
        h.line(1).contains("below the rounding of its terms in f32"),
        "{}",
        h.out
    );
}

/// A right sphere given with its t far off, where the quadratic loses its digits, is told why:
/// in f32 a direction of length 10⁻²⁰ has d·d below the smallest normal number (a correct
/// f32 program's t 6e-6 off was a bare failure).
#[test]
fn a_t_failure_where_the_quadratic_loses_its_digits_is_told_so() {
    let scene = "sphere 0 0 10 1\n";
    let rays = "0 0 0 0 0 1e-20 0 inf\n";
    let h = hints(scene, rays, "hit 9.0001e20 0\n");
    // Beside the roots the given t is not (those were lost where the fact was first added).
    assert!(
        h.out.contains(
            "[t failure: o + t·d off by 4.96e-6 of |o| + |t·d| + extent; the ray meets sphere 0 \
             at t 9.000000e20 and 1.100000e21, not at the given t 9.0001e20; d·d is 1.0e-40, \
             below f32's smallest normal number 1.2e-38: in f32 the quadratic's a = d·d comes \
             out 0 or without its digits (f64 holds it)]"
        ),
        "{}",
        h.out
    );
}

/// Answers right but a line late (a line printed before the first) are said to be so, not
/// only told of geometry; answers fewer than the rays name the ray where they stop lining up
/// with the exact ones. (Both were told of wrong primitives alone, and a ray checked alone
/// passed.)
#[test]
fn answers_a_line_off_or_one_short_are_named_so() {
    // Ray k meets triangle k alone, at t = k + 1.
    let scene: String = (0..5)
        .map(|k| {
            format!(
                "tri {} -0.5 {z} {} -0.5 {z} {k} 0.5 {z}\n",
                k as f64 - 0.5,
                k as f64 + 0.5,
                z = k + 1
            )
        })
        .collect();
    let rays: String = (0..5).map(|k| format!("{k} 0 0 0 0 1 0 inf\n")).collect();
    let late = "miss\nhit 1 0\nhit 2 1\nhit 3 2\nhit 4 3\n";
    let h = hints(&scene, &rays, late);
    let said =
        "its answers are the exact ones a line off: answer K is the exact answer of ray K − 1";
    assert!(h.out.contains(said), "{}", h.out);
    assert!(
        !hints(&scene, &rays, "hit 1 0\nhit 2 1\nhit 3 2\nhit 4 3\nmiss\n")
            .out
            .contains(said)
    );
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name);
    std::fs::write(path("scene.txt"), &scene).unwrap();
    std::fs::write(path("rays.txt"), &rays).unwrap();
    std::fs::write(path("answers.txt"), "hit 1 0\nhit 2 1\nhit 4 3\nhit 5 4\n").unwrap();
    let s = |name: &str| path(name).to_str().unwrap().to_string();
    let o = check_answers(&s("scene.txt"), &s("rays.txt"), &path("answers.txt"), &[]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    let rays = s("rays.txt");
    let said = format!(
        "4 answers for the 5 rays of {rays}: they line up with the exact answers, but for the \
         answer of {rays}:3 (ray 3) left out? (each answer after it the exact answer of the ray \
         1 later)"
    );
    assert!(err.contains(&said), "{said} in {err}");
}

/// A leak on an edge or at a vertex names the weight that is 0 (or 1) there, and what rounding
/// past it loses: an open `u` test lost its hits on the edge where u = 0, told of "u, v or
/// u + v" alike.
#[test]
fn a_leak_on_an_edge_names_its_weight() {
    let scene = "tri 0 0 0 1 0 0 0 1 0\n";
    let rays = "0 0.5 -1 0 0 1 0 inf\n0.5 0.5 -1 0 0 1 0 inf\n1 0 -1 0 0 1 0 inf\n";
    let h = hints(scene, rays, "miss\nmiss\nmiss\n");
    for (n, said) in [
        (1, "on the edge v2–v0 of the triangle, where u = 0 ("),
        (1, "an open test, or u rounded below 0, loses it"),
        (2, "on the edge v1–v2 of the triangle, where u + v = 1 ("),
        (2, "an open test, or u + v rounded above 1, loses it"),
        (3, "at vertex v1 of the triangle, where u = 1, v = 0 ("),
    ] {
        assert!(h.line(n).contains(said), "{said}: {}", h.out);
    }
}
