//! The summaries printed after the table: raylab against Embree's best mode, the builds, and
//! raylab's frame rates against the speed targets (docs/performance.md).

use std::time::Duration;

/// A row of the summary against the speed targets (docs/performance.md): raylab's render against the fastest of
/// Embree's three modes in that run (stricter than "Embree's best packet mode": on this
/// machine `rtcIntersect1` sometimes wins).
pub struct Versus {
    pub scene: String,
    pub size: String,
    pub threads: usize,
    pub raylab: Duration,
    /// The same frame with the kernels limited to AVX2 (on an AVX-512 CPU).
    pub raylab_avx2: Option<Duration>,
    pub embree_best: Duration,
    /// The fastest of Embree's modes with its kernels limited to AVX2 (on an AVX-512 CPU).
    pub embree_avx2_best: Option<Duration>,
}

/// A mesh's builds, best of the rounds (raylab's and Embree's alternating), and raylab's
/// structure's size.
pub struct Builds {
    pub scene: String,
    pub raylab: Duration,
    pub embree: Option<Duration>,
    pub raylab_bytes: usize,
}

/// What one run found, for the summaries.
#[derive(Default)]
pub struct Found {
    pub versus: Vec<Versus>,
    pub builds: Vec<Builds>,
    /// (scene, size, threads, step, best frame) of raylab's own renders.
    pub frames: Vec<(String, String, usize, &'static str, Duration)>,
    /// Lines printed under the table (what a generated scene's camera sees).
    pub notes: Vec<String>,
}

/// Prints the summaries of what the run found (each table only if it has rows).
pub fn print_summaries(found: &Found) {
    if !found.notes.is_empty() {
        println!();
        for note in &found.notes {
            println!("{note}");
        }
    }
    let versus = &found.versus;
    if !versus.is_empty() {
        println!();
        println!("| scene | size | threads | raylab render ms | Embree's best mode ms | raylab / Embree speed | both at AVX2: raylab ms | Embree ms | raylab / Embree speed | target |");
        println!("|---|---|---|---|---|---|---|---|---|---|");
        for v in versus {
            let target = match v.scene.as_str() {
                "cornell" => "≥ 2.5",
                "bunny" => "≥ 1.5",
                "igea" => "≥ 1.3",
                "igea_1m" => "≥ 1.2",
                "field" => "none (≥ 15 frames/s at 1280x720)",
                _ => "",
            };
            let ms = |t: Option<Duration>| {
                t.map_or("–".into(), |t| format!("{:.2}", t.as_secs_f64() * 1e3))
            };
            let avx2 = match (v.raylab_avx2, v.embree_avx2_best) {
                (Some(r), Some(e)) => format!("{:.2}", e.as_secs_f64() / r.as_secs_f64()),
                _ => "–".into(),
            };
            println!(
                "| {} | {} | {} | {:.2} | {:.2} | {:.2} | {} | {} | {avx2} | {target} |",
                v.scene,
                v.size,
                v.threads,
                v.raylab.as_secs_f64() * 1e3,
                v.embree_best.as_secs_f64() * 1e3,
                v.embree_best.as_secs_f64() / v.raylab.as_secs_f64(),
                ms(v.raylab_avx2),
                ms(v.embree_avx2_best),
            );
        }
    }
    if !found.builds.is_empty() {
        println!();
        println!("| scene | raylab build ms (its structure) | Embree HIGH build ms | raylab / Embree build time | raylab structure MB | targets (1M mesh) |");
        println!("|---|---|---|---|---|---|");
        for b in &found.builds {
            let embree = b
                .embree
                .map_or("–".into(), |e| format!("{:.1}", e.as_secs_f64() * 1e3));
            let ratio = b.embree.map_or("–".into(), |e| {
                format!("{:.2}", b.raylab.as_secs_f64() / e.as_secs_f64())
            });
            let target = match b.scene.as_str() {
                "igea_1m" => "build ≤ 0.5× Embree's; ≤ 100 MB",
                _ => "",
            };
            println!(
                "| {} | {:.1} | {embree} | {ratio} | {:.1} | {target} |",
                b.scene,
                b.raylab.as_secs_f64() * 1e3,
                b.raylab_bytes as f64 / 1e6
            );
        }
    }
    let targets: Vec<_> = (found.frames.iter())
        .filter_map(|(scene, size, threads, step, t)| {
            let want = match (scene.as_str(), size.as_str(), step) {
                ("cornell", "1280x720", &("shadows" | "shadows, AVX2")) => 60.0,
                ("field", "1280x720", &("flat" | "flat, AVX2")) => 15.0,
                _ => return None,
            };
            Some((scene, size, threads, step, 1.0 / t.as_secs_f64(), want))
        })
        .collect();
    if !targets.is_empty() {
        println!();
        println!("| scene | size | threads | step | raylab frames/s | target |");
        println!("|---|---|---|---|---|---|");
        for (scene, size, threads, step, fps, want) in targets {
            println!("| {scene} | {size} | {threads} | {step} | {fps:.1} | ≥ {want} |");
        }
    }
}
