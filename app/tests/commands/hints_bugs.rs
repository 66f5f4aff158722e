//! `raylab check`'s hints that name a bug only where the run bears it out, told apart from
//! the bugs that give the same answers: culled backs, the last hit, an epsilon in tmin's place
//! or on the determinant (hints.rs: the facts themselves).

use super::hints::{hints, hints_with};

/// A hint that names a bug holds only where the program's other answers bear it out: a leak
/// on the edge of a tiny triangle met from its back is told of the edge (and of rounding), not
/// of an epsilon on the determinant nor of culled back faces where the program met the same
/// triangle from its back inside, with the same determinant; where it met nothing, of the
/// back (culling explains both misses: no epsilon is borne out), and met from its front, of
/// the epsilon. (A correct f32 program that rounded a tiny cube's edge away was told of an
/// epsilon it did not have; a culling program, of an epsilon on its backs.)
#[test]
fn a_bugs_hint_needs_the_programs_other_answers_to_bear_it_out() {
    // Met from its back (d·n = 10⁻⁶ > 0), inside and on its edge v0–v1, both at t 1.
    let scene = "tri 0 0 1 0.001 0 1 0 0.001 1\n";
    let rays = "0.0002 0.0002 0 0 0 1 0 inf\n0.0005 0 0 0 0 1 0 inf\n";
    let edge = "the exact hit is on the edge v0–v1 of the triangle, where v = 0 (u and v the \
                weights of v1 and v2): the edges count, closed (an open test, or v rounded below \
                0, loses it)";
    let determinant = "is -1.0e-6, near 0: an epsilon on it (|det| < ε: no hit) loses the hit";
    let back = "the exact hit is on the triangle's back";
    let h = hints(scene, rays, "hit 1 0\nmiss\n");
    let line = h.line(2);
    assert!(line.ends_with(&format!("[leak: {edge}]")), "{}", h.out);
    let one = "the one wrong answer: 1 leak (ray, exact answer, the answer given):";
    assert!(h.out.contains(one), "{}", h.out);
    let h = hints(scene, rays, "miss\nmiss\n");
    for line in [h.line(1), h.line(2)] {
        assert!(
            !line.contains("epsilon") && line.contains(back),
            "{}",
            h.out
        );
    }
    assert!(h.line(2).contains(edge), "{}", h.out);
    // The edge's ray alone: its back as a fact, not the rule (nothing bears culling out), and
    // beside the edge (a culling program's leaks on edges were told of the edges alone).
    let h = hints(
        scene,
        &format!("{}\n", rays.lines().nth(1).unwrap()),
        "miss\n",
    );
    let side = "the exact hit is on the triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − v0))";
    assert!(
        h.line(1).ends_with(&format!("[leak: {edge}; {side}]")),
        "{}",
        h.out
    );
    // The same triangle met from its front (v1 and v2 swapped: the edge is v2–v0 now).
    let front = "tri 0 0 1 0 0.001 1 0.001 0 1\n";
    let h = hints(front, rays, "miss\nmiss\n");
    let determinant = determinant.replace("-1.0e-6", "1.0e-6");
    for line in [h.line(1), h.line(2)] {
        assert!(
            line.contains(&determinant) && !line.contains(back),
            "{}",
            h.out
        );
    }
}

/// An epsilon in tmin's place, and one on the determinant, are named only where no hit as
/// near tmin (as small a determinant) was answered right, and a miss no rounding explains
/// bears one out; else what rounding does: a hit 3e-8 past tmin is lost to t rounded to tmin
/// (in f32 within its rounding: no epsilon is borne out; in f64 it is), a determinant of
/// 2.4e-7 beside products of 1 that cancel can round to 0 in f32. (A correct f32 program was
/// told of an epsilon beside a hit nearer tmin it had answered right.)
#[test]
fn epsilons_are_named_only_where_no_nearer_case_was_answered_right() {
    // (Met from their fronts: misses of backs would be culling's.)
    let scene = "tri 0 0 1e-8 0 1 1e-8 1 0 1e-8\ntri 2 0 3e-8 2 1 3e-8 3 0 3e-8\n";
    let rays = "0.2 0.2 0 0 0 1 0 inf\n2.2 0.2 0 0 0 1 0 inf\n";
    let rounded = "the exact hit is only 3.0e-8 past tmin: a hit counts however near tmin (";
    let h = hints(scene, rays, "hit 1e-08 0\nmiss\n");
    let only_rounding = format!("[leak: {rounded}t rounded to tmin or below loses it)]");
    assert!(h.line(2).ends_with(&only_rounding), "{}", h.out);
    let h = hints(scene, rays, "miss\nmiss\n");
    assert!(h.line(2).ends_with(&only_rounding), "{}", h.out);
    let h = hints_with(scene, rays, "miss\nmiss\n", &["--precision", "f64"]);
    // (In f64 t's rounding is 1.6e-14 here: it loses nothing 3e-8 past tmin.)
    let epsilon = format!("[leak: {rounded}an epsilon in its place loses it)]");
    assert!(h.line(2).ends_with(&epsilon), "{}", h.out);
    // Rays grazing the tilted plane y + z = 0 (met from the front), meeting it at t 1 at
    // weights 0.25 and 0.25: determinants 2⁻²³ and 2⁻²², where its products d_y·e1_z·e2_x and
    // d_z·e1_y·e2_x are near 1 and cancel.
    let scene = "tri 0 0 0 0 1 -1 1 0 0\n";
    let rays = "-0.75 -0.75 0.74999988079071044921875 1 1 -0.99999988079071044921875 0 inf\n\
                -0.75 -0.75 0.7499997615814208984375 1 1 -0.9999997615814208984375 0 inf\n";
    let rounds = "below the rounding of its terms in f32: rounded, it can come out 0 or with the \
                  other sign";
    for answers in ["hit 1 0\nmiss\n", "miss\nmiss\n"] {
        let h = hints(scene, rays, answers);
        assert!(
            h.line(2).ends_with(&format!("is 2.4e-7, {rounds}]")),
            "{}",
            h.out
        );
    }
    // In f64 neither rounds: missed both, the program bears out an epsilon; with the first
    // met right, not below it.
    let f64 = ["--precision", "f64"];
    let h = hints_with(scene, rays, "miss\nmiss\n", &f64);
    let epsilon = "is 2.4e-7, near 0: an epsilon on it (|det| < ε: no hit) loses the hit";
    assert!(h.line(2).contains(epsilon), "{}", h.out);
    let h = hints_with(scene, rays, "hit 1 0\nmiss\n", &f64);
    assert!(h.line(2).ends_with("[leak]"), "{}", h.out);
}

/// A bug is named only where the run bears it out, however the rays are cut: one ray, alone
/// in its run, missed 1.2e-17 inside an edge of a face met from its back, is told of the edge
/// and its rounding, and of the back as a fact, not of culled back faces (the rule that both
/// sides count) or an epsilon (a student's correct f64 program checking the one ray pulled
/// out of its suite was told "both sides count"). And an epsilon
/// of 1e-3 is named from a miss of determinant 6.4e-4 beside a hit met right at 2e-3 (it was
/// named only below 10⁻⁴).
#[test]
fn one_ray_alone_is_told_no_bug_its_run_cannot_bear_out() {
    let scene = "tri 0 0 1 1 0 1 0 1 1\n";
    let h = hints_with(
        scene,
        "0.3 1.2e-17 0 0 0 1 0 inf\n",
        "miss\n",
        &["--precision", "f64"],
    );
    assert!(
        h.line(1).ends_with(
            "[leak: the exact hit is inside the triangle, 1.2e-17 (barycentric) from its edge \
             v0–v1, where v = 0 (u and v the weights of v1 and v2): within rounding of it (v \
             rounded below 0 loses it); the \
             exact hit is on the triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − v0))]"
        ),
        "{}",
        h.out
    );
    // In f32, 10⁻⁶ inside is within rounding too.
    let h = hints(scene, "0.3 1e-6 0 0 0 1 0 inf\n", "miss\n");
    assert!(
        h.line(1).ends_with(
            "[leak: the exact hit is inside the triangle, 1.0e-6 (barycentric) from its edge \
             v0–v1, where v = 0 (u and v the weights of v1 and v2): within rounding of it (v \
             rounded below 0 loses it); the \
             exact hit is on the triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − v0))]"
        ),
        "{}",
        h.out
    );
    // Grazing the plane z = 0 at t 1, determinants -6.4e-4 and -2e-3.
    let scene = "tri 0 0 0 1 0 0 0 1 0\n";
    let rays = "-0.75 0.25 -6.4e-4 1 0 6.4e-4 0 inf\n-0.75 0.25 -2e-3 1 0 2e-3 0 inf\n";
    let h = hints_with(scene, rays, "miss\nhit 1 0\n", &["--precision", "f64"]);
    assert!(
        h.line(1).contains(
            "is -6.4e-4, near 0: an epsilon on it (|det| < ε: no hit) loses the hit, where only \
             det = 0 is parallel"
        ),
        "{}",
        h.out
    );
}

/// Passing over a back face for a front one farther on is what culling does: such a program
/// is told the nearer hit is missed and that both sides count, not that the nearest hit wins;
/// one that also passes over a front is told the rule, and of the back as a fact alone (a
/// last-hit program was told it culled, a culling one that the nearest hit wins).
#[test]
fn culling_and_the_last_hit_are_told_apart() {
    // A back at z = 1 (x 0..1), a front at z = 1 (x 5..6), and a large front at z = 2.
    let scene = "tri 0 0 1 1 0 1 0 1 1\ntri -10 -10 2 -10 20 2 20 -10 2\ntri 5 0 1 5 1 1 6 0 1\n";
    let rays = "0.25 0.25 0 0 0 1 0 inf\n5.25 0.25 0 0 0 1 0 inf\n";
    let back = "the exact hit is on the triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − v0))";
    let culled = hints(scene, rays, "hit 2 1\nhit 1 2\n");
    assert!(
        culled.line(1).ends_with(&format!(
            "[wrong primitive: the given t 2 is past the exact hit's t 1: the nearer hit is \
             missed; {back}: both sides count]"
        )),
        "{}",
        culled.out
    );
    let last = hints(scene, rays, "hit 2 1\nhit 2 1\n");
    assert!(
        last.line(1).ends_with(&format!(
            "[wrong primitive: the given t 2 is past the exact hit's t 1: the nearest hit wins; \
             {back}]"
        )),
        "{}",
        last.out
    );
    // The first ray alone: its pass is culling's answer and a last hit's alike, so neither
    // rule is said (a last-hit program's ray alone was told that both sides count).
    let alone = hints(scene, rays.lines().next().unwrap(), "hit 2 1\n");
    assert!(
        alone.line(1).ends_with(&format!(
            "[wrong primitive: the given t 2 is past the exact hit's t 1: the nearer hit is \
             missed; {back}]"
        )),
        "{}",
        alone.out
    );
}

/// A hit near tmin passed over for a farther one bears out an epsilon in tmin's place only
/// where the program passes over no other nearer hit and keeps the nearest one elsewhere: a
/// last-hit program is told the nearest hit wins and not of an epsilon (it was told both), an
/// epsilon program the reverse, and a pass alone neither.
#[test]
fn an_epsilon_in_tmins_place_is_not_a_last_hits_pass() {
    // Fronts: 1e-8 and 3e-8 past the origins, a large one at z = 2, one at z = 1.
    let scene = "tri 0 0 1e-8 0 1 1e-8 1 0 1e-8\ntri 2 0 3e-8 2 1 3e-8 3 0 3e-8\n\
                 tri -10 -10 2 -10 20 2 20 -10 2\ntri 5 0 1 5 1 1 6 0 1\n";
    let rays = "2.2 0.2 0 0 0 1 0 inf\n5.25 0.25 0 0 0 1 0 inf\n-5 -5 0 0 0 1 0 inf\n";
    let f64 = ["--precision", "f64"];
    let passed = "[wrong primitive: the given t 2 is past the exact hit's t 3e-8: the";
    let near = "the exact hit is only 3.0e-8 past tmin: a hit counts however near tmin";
    let last = hints_with(scene, rays, "hit 2 2\nhit 2 2\nhit 2 2\n", &f64);
    // (Nor of rounding: in f64 t's is 1.6e-14 here.)
    assert!(
        last.line(1)
            .ends_with(&format!("{passed} nearest hit wins; {near}]")),
        "{}",
        last.out
    );
    // The first ray alone: its pass bears out no epsilon (nor the last hit).
    let alone = hints_with(scene, rays.lines().next().unwrap(), "hit 2 2\n", &f64);
    assert!(
        alone
            .line(1)
            .ends_with(&format!("{passed} nearer hit is missed; {near}]")),
        "{}",
        alone.out
    );
    let epsilon = hints_with(scene, rays, "hit 2 2\nhit 1 3\nhit 2 2\n", &f64);
    assert!(
        epsilon.line(1).ends_with(&format!(
            "{passed} nearer hit is missed; {near} (an epsilon in its place loses it)]"
        )),
        "{}",
        epsilon.out
    );
}

/// Möller–Trumbore's culling test, `det < ε`, misses backs and fronts of tiny determinant:
/// the epsilon is named and the back said as a fact, not the rule that both sides count (a
/// front missed clearly inside bears culling out no more than an epsilon on |det| does,
/// whose program misses backs of tiny determinant too, and would be told it culls).
#[test]
fn culling_with_an_epsilon_names_the_epsilon_and_the_back() {
    // A back at z = 1, a front grazed at determinant 2.4e-7 (x 10..11), a front at z = 1.
    let scene = "tri 0 0 1 1 0 1 0 1 1\ntri 10 0 0 10 1 -1 11 0 0\ntri 5 0 1 5 1 1 6 0 1\n";
    let rays = "0.25 0.25 0 0 0 1 0 inf\n\
                9.25 -0.75 0.7499997615814208984375 1 1 -0.9999997615814208984375 0 inf\n\
                5.25 0.25 0 0 0 1 0 inf\n";
    let h = hints_with(
        scene,
        rays,
        "miss\nmiss\nhit 1 2\n",
        &["--precision", "f64"],
    );
    let back = "the exact hit is on the triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − v0))";
    assert!(h.line(1).ends_with(&format!("[leak: {back}]")), "{}", h.out);
    assert!(
        h.line(2)
            .contains("is 2.4e-7, near 0: an epsilon on it (|det| < ε: no hit)"),
        "{}",
        h.out
    );
}

/// A back face missed just past tmin (up to 10⁻², as students' epsilons reach) is what an
/// epsilon in tmin's place loses as much as culling: alone, or beside a front met right, it
/// bears out neither (a program with only `t > tmin + 1e-4` was told that both sides count,
/// and that a hit 512 ulps of f32 past tmin was lost to t's rounding; one with `1e-3`, a hit
/// 2⁻¹⁰ past tmin); a back missed far from tmin beside that front bears out culling. And a
/// farther hit given for one 2⁻¹⁰ past tmin is no last hit's pass.
#[test]
fn a_back_missed_just_past_tmin_is_no_culling() {
    // Triangle 0 met from its back, triangle 1 (far off) from its front.
    let scene = "tri 0 0 0 1 0 0 0 1 0\ntri 5 5 0 5 6 0 6 5 0\n";
    let near = "0.25 0.25 -1.00006103515625 0 0 1 1 inf\n";
    let front = "5.25 5.25 -1 0 0 1 0 inf\n";
    let far = "0.25 0.25 -1 0 0 1 0 inf\n";
    let back = "the exact hit is on the triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − v0))";
    let past = "the exact hit is only 6.1e-5 past tmin: a hit counts however near tmin";
    for (rays, answers) in [
        (near.to_string(), "miss\n"),
        (format!("{near}{front}"), "miss\nhit 1 1\n"),
    ] {
        let h = hints(scene, &rays, answers);
        assert!(
            h.line(1).ends_with(&format!("[leak: {back}; {past}]")),
            "{}",
            h.out
        );
    }
    let h = hints(
        scene,
        &format!("{near}{front}{far}"),
        "miss\nhit 1 1\nmiss\n",
    );
    assert!(
        h.line(1).contains(&format!("{back}: both sides count")),
        "{}",
        h.out
    );
    // 2⁻¹⁰ past tmin, with the far front at z = 5 behind it: missed, and passed over.
    let scene = "tri 0 0 0 1 0 0 0 1 0\ntri 0 0 5 0 1 5 1 0 5\n";
    let rays = "0.25 0.25 -0.0009765625 0 0 1 0 inf\n";
    let past = "the exact hit is only 9.8e-4 past tmin: a hit counts however near tmin]";
    let h = hints(scene, rays, "miss\n");
    assert!(h.line(1).ends_with(&format!("{back}; {past}")), "{}", h.out);
    let h = hints(scene, rays, "hit 5.0009765625 1\n");
    assert!(
        h.line(1).contains("the nearer hit is missed") && h.line(1).ends_with(past),
        "{}",
        h.out
    );
}
