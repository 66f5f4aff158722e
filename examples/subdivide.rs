//! Writes a 1:4 subdivision of an OBJ mesh (each triangle split at its edge midpoints, shared
//! midpoints shared), for benchmarks: `igea.obj` (268,686 triangles) becomes the 1,074,744-
//! triangle test mesh of shared/scenes/SOURCES.md.
//!
//! `cargo run --release --example subdivide -- ../shared/scenes/igea.obj /tmp/igea_1m.obj`

use std::collections::HashMap;
use std::io::Write;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    anyhow::ensure!(args.len() == 3, "usage: subdivide IN.obj OUT.obj");
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj(&args[1], &options)?;
    let mut out = std::io::BufWriter::new(std::fs::File::create(&args[2])?);
    let mut base = 1usize;
    let mut triangles = 0usize;
    for m in &models {
        let p = &m.mesh.positions;
        let mut verts: Vec<[f32; 3]> = p.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let mut midpoints = HashMap::new();
        let mut mid = |a: u32, b: u32, verts: &mut Vec<[f32; 3]>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (u, v) = (verts[a as usize], verts[b as usize]);
                verts.push([0, 1, 2].map(|k| (u[k] + v[k]) * 0.5));
                (verts.len() - 1) as u32
            })
        };
        let mut faces = Vec::new();
        for t in m.mesh.indices.chunks_exact(3) {
            let (a, b, c) = (t[0], t[1], t[2]);
            let (ab, bc, ca) = (
                mid(a, b, &mut verts),
                mid(b, c, &mut verts),
                mid(c, a, &mut verts),
            );
            faces.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        for v in &verts {
            writeln!(out, "v {} {} {}", v[0], v[1], v[2])?;
        }
        for f in &faces {
            writeln!(
                out,
                "f {} {} {}",
                f[0] as usize + base,
                f[1] as usize + base,
                f[2] as usize + base
            )?;
        }
        base += verts.len();
        triangles += faces.len();
    }
    out.flush()?;
    println!("wrote {} ({triangles} triangles)", args[2]);
    Ok(())
}
