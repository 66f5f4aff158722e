//! A floor with N balls, the scene a student writes to see many spheres: the `spheresN`
//! scenes (`--scenes spheres100,spheres1000,spheres10000`; any N from 1 to 1,000,000), run
//! only when named.
//!
//! A 20×20 floor (two triangles at y = 0; y points down, so the balls are at y < 0) and N balls
//! resting on it, scattered by a fixed-seed xorshift generator: radius r₀·(0.75 … 1.25), with r₀
//! such that the balls' footprints (N·π·r₀²) cover a quarter of the floor, each thrown at a
//! random place on the floor and thrown again (up to 64 times) where it would overlap a ball
//! already placed; a ball that found no room in 64 throws keeps its last place (the scene's
//! description says how many did: none at these densities). The camera looks down over the
//! floor's near edge (pitch −42°, horizontal field of view 60°): at 16:9 the whole floor is in
//! view.
//!
//! The scene is written as `.scene` text twice: the balls as `sphere` statements (exact
//! spheres), and each ball as the shipped icosphere (`assets/meshes/icosphere.obj`: an
//! icosahedron subdivided 3 times, 1,280 triangles, unit radius) placed by `translate` and
//! `scale`: one mesh named N times, so it is stored once and placed by N instances. Both are
//! loaded as the app loads a scene file (parsed with the default instancing, made a scene,
//! its ranges checked), so they are what a student would write; `--write-scenes DIR` writes
//! both files, to render them with `raylab render --scene`.

use anyhow::{anyhow, Context as _};
use raylab::geometry::Shape;
use raylab::scene::file::{load_obj_mesh, parse_with, Instancing};
use raylab::Scene;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The prefix of the family's scene names.
const PREFIX: &str = "spheres";
/// The most balls a scene name may ask for.
const MAX_BALLS: usize = 1_000_000;
/// Half the floor's side.
const HALF: f64 = 10.0;
/// The share of the floor the balls' footprints cover.
const COVER: f64 = 0.25;
/// Throws per ball before it keeps a place that overlaps another.
const THROWS: usize = 64;
/// The generator's seed (every scene of the family is the same from run to run).
const SEED: u64 = 0x9E37_79B9_7F4A_7C15;
/// The icosphere the instanced twin places, relative to the repository's root.
const ICOSPHERE: &str = "assets/meshes/icosphere.obj";

/// The number of balls a scene name asks for (`spheres1000`: 1000), if it is of the family.
pub fn count(name: &str) -> Option<usize> {
    let n: usize = name.strip_prefix(PREFIX)?.parse().ok()?;
    (1..=MAX_BALLS).contains(&n).then_some(n)
}

/// xorshift64*: small, fast and the same everywhere.
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// One ball on the floor: its centre's x and z, radius and colour (its centre's y is −r).
struct Ball {
    x: f64,
    z: f64,
    r: f64,
    color: [f64; 3],
}

/// The N balls, and how many of them overlap a ball placed before (found no room).
fn scatter(n: usize) -> (Vec<Ball>, usize) {
    let mut rng = XorShift(SEED);
    let r0 = (COVER * (2.0 * HALF) * (2.0 * HALF) / (n as f64 * std::f64::consts::PI)).sqrt();
    // Balls overlap only if their centres are closer than 2·1.25·r₀: within a cell's
    // neighbours on a grid of that size.
    let cell = 2.5 * r0;
    let key = |x: f64, z: f64| ((x / cell).floor() as i64, (z / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    let mut balls: Vec<Ball> = Vec::with_capacity(n);
    let mut crowded = 0;
    for _ in 0..n {
        let r = r0 * rng.range(0.75, 1.25);
        let color = [0.3, 0.3, 0.3].map(|lo| rng.range(lo, 0.95));
        let mut place = (0.0, 0.0);
        let mut free = false;
        for _ in 0..THROWS {
            place = (
                rng.range(-HALF + r, HALF - r),
                rng.range(-HALF + r, HALF - r),
            );
            let (i, k) = key(place.0, place.1);
            free = (i - 1..=i + 1)
                .flat_map(|a| (k - 1..=k + 1).map(move |b| (a, b)))
                .filter_map(|c| grid.get(&c))
                .flatten()
                .all(|&j| {
                    let o: &Ball = &balls[j];
                    let (dx, dz) = (o.x - place.0, o.z - place.1);
                    dx * dx + dz * dz >= (o.r + r) * (o.r + r)
                });
            if free {
                break;
            }
        }
        crowded += !free as usize;
        grid.entry(key(place.0, place.1))
            .or_default()
            .push(balls.len());
        balls.push(Ball {
            x: place.0,
            z: place.1,
            r,
            color,
        });
    }
    (balls, crowded)
}

/// The `.scene` text of a floor with `balls`: exact spheres, or each ball the icosphere at
/// `icosphere` (a path as the file writes it) placed by an instance.
fn scene_text(n: usize, balls: &[Ball], icosphere: Option<&str>) -> String {
    use std::fmt::Write as _;
    let what = match icosphere {
        None => "each a sphere statement",
        Some(_) => "each the icosphere (1,280 triangles) placed by translate and scale",
    };
    let mut s = format!(
        "# A floor with {n} balls, {what}: scattered by peers/src/spheres.rs (a fixed seed).\n\
         ambient 0.4 0.4 0.4\n\
         light 0 -16 -4 3000\n\
         camera 0 -16 -20 pitch -42 fov 60\n\
         color 0.55 0.55 0.5\n\
         tri -{HALF} 0 -{HALF}  {HALF} 0 -{HALF}  {HALF} 0 {HALF}\n\
         tri -{HALF} 0 -{HALF}  {HALF} 0 {HALF}  -{HALF} 0 {HALF}\n"
    );
    for b in balls {
        let [cr, cg, cb] = b.color;
        let (x, y, z, r) = (b.x, -b.r, b.z, b.r);
        // (Writing to a String cannot fail.)
        let _ = match icosphere {
            None => writeln!(
                s,
                "color {cr:.3} {cg:.3} {cb:.3}\nsphere {x:.6} {y:.6} {z:.6} {r:.6}"
            ),
            Some(path) => writeln!(
                s,
                "push\n  translate {x:.6} {y:.6} {z:.6}\n  scale {r:.6}\n  \
                 color {cr:.3} {cg:.3} {cb:.3}\n  mesh \"{path}\"\npop"
            ),
        };
    }
    s
}

/// Loads `.scene` text as the app loads a file: parsed with the default instancing, meshes
/// relative to `dir`, made a scene, its ranges checked.
fn load_text(name: &str, text: &str, dir: &Path) -> anyhow::Result<Scene> {
    let d = parse_with::<f32>(name, text, dir, &load_obj_mesh, Instancing::DEFAULT)
        .map_err(|e| anyhow!("{e}"))?;
    let scene = Scene::from_description(name, d).map_err(|e| anyhow!(e))?;
    scene.check_ranges().map_err(|e| anyhow!(e))?;
    Ok(scene)
}

/// A scene of the family: the exact spheres, their icosphere twin, and a line saying what
/// it is.
pub struct Balls {
    pub exact: Scene,
    pub icospheres: Scene,
    pub description: String,
}

/// The scene `name` (of the family: see [`count`]) asks for; with `write`, both `.scene` files
/// are written there too.
pub fn load(name: &str, write: Option<&Path>) -> anyhow::Result<Balls> {
    let n = count(name).with_context(|| format!("{name}: not a {PREFIX}N scene"))?;
    let icosphere = PathBuf::from(ICOSPHERE);
    anyhow::ensure!(
        icosphere.exists(),
        "{ICOSPHERE} not found (run from the repository's root)"
    );
    let (balls, crowded) = scatter(n);
    let exact_text = scene_text(n, &balls, None);
    let ico_text = scene_text(n, &balls, Some("icosphere.obj"));
    let dir = icosphere.parent().expect("a file in a directory");
    let exact = load_text(name, &exact_text, dir)?;
    let icospheres = load_text(&format!("{name}_icospheres"), &ico_text, dir)?;
    anyhow::ensure!(
        n < 2 || icospheres.instances().len() == n,
        "{name}: the icospheres were not placed as {n} instances"
    );
    if let Some(out) = write {
        std::fs::create_dir_all(out)?;
        let abs = std::fs::canonicalize(&icosphere)?;
        let abs = abs.to_str().context("the icosphere's path is not UTF-8")?;
        let abs = abs.replace('\\', "\\\\").replace('"', "\\\"");
        for (file, text) in [
            (format!("{name}.scene"), exact_text),
            (
                format!("{name}_icospheres.scene"),
                scene_text(n, &balls, Some(&abs)),
            ),
        ] {
            let path = out.join(file);
            std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
            println!("({name}: wrote {})", path.display());
        }
    }
    let (lo, hi) = (balls.iter().map(|b| b.r)).fold((f64::INFINITY, 0.0f64), |(lo, hi), r| {
        (lo.min(r), hi.max(r))
    });
    let description = format!(
        "{name}: a {side}×{side} floor (2 triangles) and {n} balls of radius {lo:.3}–{hi:.3} \
         ({crowded} found no room and overlap another); twin: {n} instances of a \
         {tris}-triangle icosphere, {total} triangles in all",
        side = 2.0 * HALF,
        tris = (icospheres.len() - 2) / n,
        total = icospheres.len(),
    );
    Ok(Balls {
        exact,
        icospheres,
        description,
    })
}

/// What a camera sees of a floor with balls: the balls hit, the rays hitting a ball and the
/// floor, by the exact per-ray answers.
pub fn seen(scene: &Scene, (w, h): (u32, u32), reference: &[Option<u32>]) -> String {
    let mut balls = vec![false; scene.len()];
    let (mut on_balls, mut on_floor) = (0usize, 0usize);
    for &p in reference.iter().flatten() {
        match scene.shape(p) {
            Shape::Sphere(_) => {
                on_balls += 1;
                balls[p as usize] = true;
            }
            Shape::Triangle(_) => on_floor += 1,
        }
    }
    let total = scene.shapes.iter().filter(|s| !s.is_triangle()).count();
    let pct = |k: usize| 100.0 * k as f64 / reference.len() as f64;
    format!(
        "{} at {w}x{h}: {} of its {total} balls seen; {:.1}% of the rays hit a ball, {:.1}% the floor",
        scene.name,
        balls.iter().filter(|&&b| b).count(),
        pct(on_balls),
        pct(on_floor)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        assert_eq!(count("spheres1000"), Some(1000));
        assert_eq!(count("spheres0"), None);
        assert_eq!(count("spheres"), None);
        assert_eq!(count("bunny"), None);
    }

    #[test]
    fn balls_rest_on_the_floor_apart() {
        let (balls, crowded) = scatter(1000);
        assert_eq!(crowded, 0);
        for (i, a) in balls.iter().enumerate() {
            assert!(a.x.abs() + a.r <= HALF && a.z.abs() + a.r <= HALF);
            for b in &balls[..i] {
                let d = ((a.x - b.x).powi(2) + (a.z - b.z).powi(2)).sqrt();
                assert!(d >= a.r + b.r);
            }
        }
    }
}
