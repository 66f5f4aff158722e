//! `raylab check`'s hints beside a wrong answer: each a fact of the exact geometry, checked
//! on rays built for it (the classic bugs' programs hold the hints to their bugs:
//! classic_bugs.rs).

use common::binary::text;

use crate::common;

crate::raylab_runner!();
crate::check_runner!();

/// The output of `raylab check` of `answers` for `scene` and `rays` (their texts).
struct Hints {
    out: String,
}

impl Hints {
    /// The reproducer line of answer `n` (from 1), by the answer file's line it names.
    fn line(&self, n: usize) -> String {
        let at = format!("answers.txt:{n}): ");
        (self.out.lines().find(|l| l.contains(&at)))
            .unwrap_or_else(|| panic!("no line {n}: {}", self.out))
            .to_string()
    }
}

fn hints(scene: &str, rays: &str, answers: &str) -> Hints {
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
        &[],
    );
    Hints {
        out: text(&o.stdout),
    }
}

/// The hints are facts of the exact geometry: a ray 10⁻¹⁷ beside a vertex meets the inside
/// (an f64 test within 10⁻⁹ had said "at vertex v0"), a hit on an edge from the back is told
/// both, a primitive given at a t where the ray does not meet it is said so, with the t where
/// it does, not told that the nearest hit wins (nor that the exact one is a back face:
/// so is the one given), and one met just past the exact hit is told so.
#[test]
fn the_hints_name_the_exact_place_and_a_given_t_that_meets_nothing() {
    let scene = "tri 0 0 0 1 0 0 0 1 0\ntri 0 0 5 1 0 5 0 1 5\ntri 0 0 1e-7 1 0 1e-7 0 1 1e-7\n";
    // Beside vertex v0 by 6e-17 and 1e-17 (inside); through the edge v0–v1 exactly; through
    // the inside, to be answered with the far triangle at t 2 (it lies at t 6), and with the
    // triangle 10⁻⁷ behind the first, where it lies.
    let rays = "6e-17 1e-17 -1 0 0 1 0 inf\n0.5 0 -1 0 0 1 0 inf\n0.25 0.25 -1 0 0 1 0 inf\n\
                0.25 0.25 -1 0 0 1 0 inf\n";
    let h = hints(scene, rays, "miss\nmiss\nhit 2 1\nhit 1.0000001 2\n");
    assert!(
        h.line(1).ends_with("[leak: the exact hit is on the triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − v0)): both sides count]"),
        "{}", h.out
    );
    assert!(
        h.line(2).ends_with(
            "[leak: the exact hit is on the edge v0–v1 of the triangle: the edges count, closed; \
             the exact hit is on the triangle's back (d·n > 0 for n = (v1 − v0) × (v2 − v0)): \
             both sides count]"
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
/// a tangent at tmin (said twice met), no index shift claimed where another answer at the
/// exact t names the exact primitive, a hit 8.9e-8 past tmin (said 1.2e-7, from its t
/// rounded to f32), and roots alike to 9 digits shown to 10 (17 claimed what f64's estimate
/// does not hold).
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
            "[leak: the ray meets the sphere twice (its discriminant is above 0), at t \
             524287.998557 and 524288.001443]"
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
            "[leak: the exact hit is only 8.9e-8 past tmin: a hit counts however near tmin, \
             where an epsilon in its place loses it]"
        ),
        "{}",
        h.out
    );
    assert!(
        h.line(6).ends_with(
            "[leak: the ray meets the sphere twice (its discriminant is above 0), at t \
             4.194303999e6 and 4.194304001e6]"
        ),
        "{}",
        h.out
    );
}
