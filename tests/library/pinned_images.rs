//! Pinned image hashes: every lab step, method, supersampling, tile culling on and off, the
//! cracks view and every accelerator path (flat SIMD loop, BVH culled per tile, BVH packets
//! with triangles prepared per frame and as met, spheres mixed with triangles), rendered small
//! and hashed with the render's hit and shadow-ray counts.
//!
//! Pinned before the first architecture refactor so that moving code cannot change a
//! pixel. A change that is meant to alter images must say so in its commit and re-pin:
//! `RAYLAB_PIN_PRINT=1 cargo test --test library pinned_images:: -- --nocapture` prints the table.

use crate::common;

use raylab::accel::AccelChoice;
use raylab::geometry::{Method, Shape, Sphere};
use raylab::render::{render_image, LabStep, RenderSettings, Stage};
use raylab::{Camera, Scene};

/// FNV-1a, 64 bits: stable across Rust versions (std's hasher is not).
fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// (name, scene, image width, height).
fn scenes() -> Vec<(&'static str, Stage, u32, u32)> {
    let bvh_cornell = Stage::new(Scene::cornell(), AccelChoice::Bvh);
    let spheres = vec![
        Shape::Sphere(Sphere {
            centre: [0.35, 0.55, 0.2],
            radius: 0.3,
        }),
        Shape::Sphere(Sphere {
            centre: [-0.4, 0.4, -0.1],
            radius: 0.25,
        }),
    ];
    vec![
        // 30 triangles: the flat SIMD loop, tiles culled, packets; odd size: partial tiles.
        ("cornell", Stage::from(Scene::cornell()), 83, 57),
        // The same through a BVH (small enough to be culled per tile too).
        ("cornell-bvh", bvh_cornell, 64, 48),
        // 1310 triangles: BVH, culled per tile.
        (
            "ico3",
            common::cornell_with_blue(
                common::icosphere(3, 0.4, [0.2, 0.5, 0.1]),
                AccelChoice::Auto,
            ),
            64,
            48,
        ),
        // 5150 triangles at 3072 camera rays: BVH packets, prepared as met (spp 1) and per
        // frame (spp 2).
        (
            "ico4",
            common::cornell_with_blue(
                common::icosphere(4, 0.5, [0.1, 0.3, 0.2]),
                AccelChoice::Auto,
            ),
            64,
            48,
        ),
        // Spheres beside triangles: per-ray paths.
        (
            "spheres",
            common::cornell_with_blue(spheres, AccelChoice::Auto),
            64,
            48,
        ),
    ]
}

/// (what, hash) for every rendering pinned.
fn hashes() -> Vec<(String, u64)> {
    let mut out = Vec::new();
    for (name, scene, width, height) in scenes() {
        let cam = Camera::cornell(width);
        for method in Method::ALL {
            for step in LabStep::ALL {
                for spp in [1, 2] {
                    let mut variants = vec![(true, false)];
                    if spp == 1 {
                        variants.extend([(false, false), (true, true)]);
                    }
                    for (tile_culling, cracks) in variants {
                        let settings = RenderSettings {
                            width,
                            height,
                            step,
                            spp,
                            method,
                            tile_culling,
                            cracks,
                        };
                        let (img, stats) = render_image(&scene, &cam, &settings).unwrap();
                        let mut h = fnv1a(&img, 0xcbf2_9ce4_8422_2325);
                        h = fnv1a(&stats.hits.to_le_bytes(), h);
                        h = fnv1a(&stats.shadow_rays.to_le_bytes(), h);
                        let what = format!(
                            "{name} {method} {step} spp{spp}{}{}",
                            if tile_culling { "" } else { " nocull" },
                            if cracks { " cracks" } else { "" }
                        );
                        out.push((what, h));
                    }
                }
            }
        }
    }
    out
}

#[test]
fn images_are_the_pinned_ones() {
    let got = hashes();
    if std::env::var_os("RAYLAB_PIN_PRINT").is_some() {
        for (what, h) in &got {
            println!("    (\"{what}\", {h:#018x}),");
        }
    }
    assert_eq!(got.len(), PINNED.len(), "the table covers every rendering");
    let wrong: Vec<String> = got
        .iter()
        .zip(PINNED)
        .filter(|((what, h), (pw, ph))| what != pw || h != ph)
        .map(|((what, h), (_, ph))| format!("{what}: {h:#018x}, pinned {ph:#018x}"))
        .collect();
    assert!(
        wrong.is_empty(),
        "{} differ:\n{}",
        wrong.len(),
        wrong.join("\n")
    );
    // The scenes do exercise what they are named for.
    let distinct: std::collections::HashSet<u64> = got.iter().map(|g| g.1).collect();
    assert!(distinct.len() > got.len() / 3, "too many equal images");
}

/// Generated by `RAYLAB_PIN_PRINT=1` on the code before the first architecture refactor (commit 213edf1).
const PINNED: &[(&str, u64)] = &[
    ("cornell adaptive flat spp1", 0x96afca491569fb5c),
    ("cornell adaptive flat spp1 nocull", 0x96afca491569fb5c),
    ("cornell adaptive flat spp1 cracks", 0x96afca491569fb5c),
    ("cornell adaptive flat spp2", 0xffaad5528b59654c),
    ("cornell adaptive direct spp1", 0x5283884237821591),
    ("cornell adaptive direct spp1 nocull", 0x5283884237821591),
    ("cornell adaptive direct spp1 cracks", 0x5283884237821591),
    ("cornell adaptive direct spp2", 0xcaff37a6c86e05a1),
    ("cornell adaptive shadows spp1", 0x9b6639a8a060452f),
    ("cornell adaptive shadows spp1 nocull", 0x9b6639a8a060452f),
    ("cornell adaptive shadows spp1 cracks", 0x9b6639a8a060452f),
    ("cornell adaptive shadows spp2", 0x028a2139cbfb8956),
    ("cornell adaptive indirect spp1", 0x297bac8a0738cedc),
    ("cornell adaptive indirect spp1 nocull", 0x297bac8a0738cedc),
    ("cornell adaptive indirect spp1 cracks", 0x297bac8a0738cedc),
    ("cornell adaptive indirect spp2", 0xe86e93112395bc00),
    ("cornell watertight flat spp1", 0x96afca491569fb5c),
    ("cornell watertight flat spp1 nocull", 0x96afca491569fb5c),
    ("cornell watertight flat spp1 cracks", 0x96afca491569fb5c),
    ("cornell watertight flat spp2", 0xd0ce2d5dca94fd30),
    ("cornell watertight direct spp1", 0x5283884237821591),
    ("cornell watertight direct spp1 nocull", 0x5283884237821591),
    ("cornell watertight direct spp1 cracks", 0x5283884237821591),
    ("cornell watertight direct spp2", 0x3e59fd1ce572ee95),
    ("cornell watertight shadows spp1", 0xae74fc1acabb657a),
    ("cornell watertight shadows spp1 nocull", 0xae74fc1acabb657a),
    ("cornell watertight shadows spp1 cracks", 0xae74fc1acabb657a),
    ("cornell watertight shadows spp2", 0x8612028ab0f97875),
    ("cornell watertight indirect spp1", 0xcb9b15423bd4dd07),
    (
        "cornell watertight indirect spp1 nocull",
        0xcb9b15423bd4dd07,
    ),
    (
        "cornell watertight indirect spp1 cracks",
        0xcb9b15423bd4dd07,
    ),
    ("cornell watertight indirect spp2", 0xdd81cd2ce2ac4460),
    ("cornell moller flat spp1", 0x1d6b388b57cf9785),
    ("cornell moller flat spp1 nocull", 0x1d6b388b57cf9785),
    ("cornell moller flat spp1 cracks", 0x1d6b388b57cf9785),
    ("cornell moller flat spp2", 0xa979fd6da3a76ebc),
    ("cornell moller direct spp1", 0x9dfb5b852b5e8fa1),
    ("cornell moller direct spp1 nocull", 0x9dfb5b852b5e8fa1),
    ("cornell moller direct spp1 cracks", 0x9dfb5b852b5e8fa1),
    ("cornell moller direct spp2", 0x84f25bc378953325),
    ("cornell moller shadows spp1", 0x9b6639a8a060452f),
    ("cornell moller shadows spp1 nocull", 0x9b6639a8a060452f),
    ("cornell moller shadows spp1 cracks", 0x9b6639a8a060452f),
    ("cornell moller shadows spp2", 0x7b4d082c33d5ea86),
    ("cornell moller indirect spp1", 0x28d9673a77635a24),
    ("cornell moller indirect spp1 nocull", 0x28d9673a77635a24),
    ("cornell moller indirect spp1 cracks", 0x28d9673a77635a24),
    ("cornell moller indirect spp2", 0xe995d2f6b730265e),
    ("cornell cramer flat spp1", 0x1a13a6fea333ad73),
    ("cornell cramer flat spp1 nocull", 0x1a13a6fea333ad73),
    ("cornell cramer flat spp1 cracks", 0x3d28432dda07b3d6),
    ("cornell cramer flat spp2", 0xbf0cf2552e807f07),
    ("cornell cramer direct spp1", 0x3af0fd8943edacd0),
    ("cornell cramer direct spp1 nocull", 0x3af0fd8943edacd0),
    ("cornell cramer direct spp1 cracks", 0xfc66cb0d6f69fed5),
    ("cornell cramer direct spp2", 0x71d2a935a5d3a9ce),
    ("cornell cramer shadows spp1", 0xd70cc75b727c4e60),
    ("cornell cramer shadows spp1 nocull", 0xd70cc75b727c4e60),
    ("cornell cramer shadows spp1 cracks", 0xd63a7e20b070e0f9),
    ("cornell cramer shadows spp2", 0x1ca05cf63da10143),
    ("cornell cramer indirect spp1", 0x9b9373de78c2e4da),
    ("cornell cramer indirect spp1 nocull", 0x9b9373de78c2e4da),
    ("cornell cramer indirect spp1 cracks", 0xe360751503805cf3),
    ("cornell cramer indirect spp2", 0xca150e9f9710b30a),
    ("cornell-bvh adaptive flat spp1", 0x00b5abbcae400bdf),
    ("cornell-bvh adaptive flat spp1 nocull", 0x00b5abbcae400bdf),
    ("cornell-bvh adaptive flat spp1 cracks", 0x00b5abbcae400bdf),
    ("cornell-bvh adaptive flat spp2", 0x42933624edea9ef4),
    ("cornell-bvh adaptive direct spp1", 0xafd9e3719216189a),
    (
        "cornell-bvh adaptive direct spp1 nocull",
        0xafd9e3719216189a,
    ),
    (
        "cornell-bvh adaptive direct spp1 cracks",
        0xafd9e3719216189a,
    ),
    ("cornell-bvh adaptive direct spp2", 0xd1931141b0748a6c),
    ("cornell-bvh adaptive shadows spp1", 0x7e956f6276bdbc0d),
    (
        "cornell-bvh adaptive shadows spp1 nocull",
        0x7e956f6276bdbc0d,
    ),
    (
        "cornell-bvh adaptive shadows spp1 cracks",
        0x7e956f6276bdbc0d,
    ),
    ("cornell-bvh adaptive shadows spp2", 0xf6e877bd58436c0a),
    ("cornell-bvh adaptive indirect spp1", 0x14c9038b3a3991a3),
    (
        "cornell-bvh adaptive indirect spp1 nocull",
        0x14c9038b3a3991a3,
    ),
    (
        "cornell-bvh adaptive indirect spp1 cracks",
        0x14c9038b3a3991a3,
    ),
    ("cornell-bvh adaptive indirect spp2", 0x872a900f3918a600),
    ("cornell-bvh watertight flat spp1", 0x7b60316477c7ecab),
    (
        "cornell-bvh watertight flat spp1 nocull",
        0x7b60316477c7ecab,
    ),
    (
        "cornell-bvh watertight flat spp1 cracks",
        0x7b60316477c7ecab,
    ),
    ("cornell-bvh watertight flat spp2", 0x582054aee50e1fda),
    ("cornell-bvh watertight direct spp1", 0x9f4b8b0bcf3c24e3),
    (
        "cornell-bvh watertight direct spp1 nocull",
        0x9f4b8b0bcf3c24e3,
    ),
    (
        "cornell-bvh watertight direct spp1 cracks",
        0x9f4b8b0bcf3c24e3,
    ),
    ("cornell-bvh watertight direct spp2", 0x9a29e956eecb6755),
    ("cornell-bvh watertight shadows spp1", 0x17cfca2de73220a0),
    (
        "cornell-bvh watertight shadows spp1 nocull",
        0x17cfca2de73220a0,
    ),
    (
        "cornell-bvh watertight shadows spp1 cracks",
        0x17cfca2de73220a0,
    ),
    ("cornell-bvh watertight shadows spp2", 0x3ccab93c96c3a4bc),
    ("cornell-bvh watertight indirect spp1", 0x16be6b0fa594aef2),
    (
        "cornell-bvh watertight indirect spp1 nocull",
        0x16be6b0fa594aef2,
    ),
    (
        "cornell-bvh watertight indirect spp1 cracks",
        0x16be6b0fa594aef2,
    ),
    ("cornell-bvh watertight indirect spp2", 0x9e755d3cecbc82bc),
    ("cornell-bvh moller flat spp1", 0x18d9c7b414f42026),
    ("cornell-bvh moller flat spp1 nocull", 0x18d9c7b414f42026),
    ("cornell-bvh moller flat spp1 cracks", 0x18d9c7b414f42026),
    ("cornell-bvh moller flat spp2", 0x714acc2f4c4c1f08),
    ("cornell-bvh moller direct spp1", 0xb49c4fd50998a322),
    ("cornell-bvh moller direct spp1 nocull", 0xb49c4fd50998a322),
    ("cornell-bvh moller direct spp1 cracks", 0xb49c4fd50998a322),
    ("cornell-bvh moller direct spp2", 0xf565c8f79467942c),
    ("cornell-bvh moller shadows spp1", 0x7e956f6276bdbc0d),
    ("cornell-bvh moller shadows spp1 nocull", 0x7e956f6276bdbc0d),
    ("cornell-bvh moller shadows spp1 cracks", 0x7e956f6276bdbc0d),
    ("cornell-bvh moller shadows spp2", 0x4a3024adfcb5bb03),
    ("cornell-bvh moller indirect spp1", 0xd3c4fc65eeb1236b),
    (
        "cornell-bvh moller indirect spp1 nocull",
        0xd3c4fc65eeb1236b,
    ),
    (
        "cornell-bvh moller indirect spp1 cracks",
        0xd3c4fc65eeb1236b,
    ),
    ("cornell-bvh moller indirect spp2", 0x16f97f1f99a13c18),
    ("cornell-bvh cramer flat spp1", 0x5e3dd94758a773dc),
    ("cornell-bvh cramer flat spp1 nocull", 0x5e3dd94758a773dc),
    ("cornell-bvh cramer flat spp1 cracks", 0x5e3dd94758a773dc),
    ("cornell-bvh cramer flat spp2", 0x209334eb4d129514),
    ("cornell-bvh cramer direct spp1", 0x717dee536822b116),
    ("cornell-bvh cramer direct spp1 nocull", 0x717dee536822b116),
    ("cornell-bvh cramer direct spp1 cracks", 0x717dee536822b116),
    ("cornell-bvh cramer direct spp2", 0x4fbe673aeaf65750),
    ("cornell-bvh cramer shadows spp1", 0x05800946dcb6085f),
    ("cornell-bvh cramer shadows spp1 nocull", 0x05800946dcb6085f),
    ("cornell-bvh cramer shadows spp1 cracks", 0x05800946dcb6085f),
    ("cornell-bvh cramer shadows spp2", 0xe71662fff58596ee),
    ("cornell-bvh cramer indirect spp1", 0x92f07e1d8ab6d2ef),
    (
        "cornell-bvh cramer indirect spp1 nocull",
        0x92f07e1d8ab6d2ef,
    ),
    (
        "cornell-bvh cramer indirect spp1 cracks",
        0x92f07e1d8ab6d2ef,
    ),
    ("cornell-bvh cramer indirect spp2", 0x8e136a4924da701a),
    ("ico3 adaptive flat spp1", 0x01613273ad8709f7),
    ("ico3 adaptive flat spp1 nocull", 0x01613273ad8709f7),
    ("ico3 adaptive flat spp1 cracks", 0x01613273ad8709f7),
    ("ico3 adaptive flat spp2", 0xb705b709676ee4e6),
    ("ico3 adaptive direct spp1", 0x3be92dbaf7e374a9),
    ("ico3 adaptive direct spp1 nocull", 0x3be92dbaf7e374a9),
    ("ico3 adaptive direct spp1 cracks", 0x3be92dbaf7e374a9),
    ("ico3 adaptive direct spp2", 0x89fa11bcdaeb31cb),
    ("ico3 adaptive shadows spp1", 0x019d93766aa62aff),
    ("ico3 adaptive shadows spp1 nocull", 0x019d93766aa62aff),
    ("ico3 adaptive shadows spp1 cracks", 0x019d93766aa62aff),
    ("ico3 adaptive shadows spp2", 0xec453f6e8ee879c2),
    ("ico3 adaptive indirect spp1", 0xb8b44f0ab2fdfa03),
    ("ico3 adaptive indirect spp1 nocull", 0xb8b44f0ab2fdfa03),
    ("ico3 adaptive indirect spp1 cracks", 0xb8b44f0ab2fdfa03),
    ("ico3 adaptive indirect spp2", 0x44ee09be88d20a79),
    ("ico3 watertight flat spp1", 0xf98c4bd0ab3a1f83),
    ("ico3 watertight flat spp1 nocull", 0xf98c4bd0ab3a1f83),
    ("ico3 watertight flat spp1 cracks", 0xf98c4bd0ab3a1f83),
    ("ico3 watertight flat spp2", 0xa01ca0193df27018),
    ("ico3 watertight direct spp1", 0x285c6e0b026cf8c8),
    ("ico3 watertight direct spp1 nocull", 0x285c6e0b026cf8c8),
    ("ico3 watertight direct spp1 cracks", 0x285c6e0b026cf8c8),
    ("ico3 watertight direct spp2", 0xc7593577d06e117e),
    ("ico3 watertight shadows spp1", 0x68a6fa015d98b11a),
    ("ico3 watertight shadows spp1 nocull", 0x68a6fa015d98b11a),
    ("ico3 watertight shadows spp1 cracks", 0x68a6fa015d98b11a),
    ("ico3 watertight shadows spp2", 0xe091a9353fd967c1),
    ("ico3 watertight indirect spp1", 0x6e11bc2aec66cf1a),
    ("ico3 watertight indirect spp1 nocull", 0x6e11bc2aec66cf1a),
    ("ico3 watertight indirect spp1 cracks", 0x6e11bc2aec66cf1a),
    ("ico3 watertight indirect spp2", 0x7ab3dc619da43526),
    ("ico3 moller flat spp1", 0xb0ffb4e74c152a2e),
    ("ico3 moller flat spp1 nocull", 0xb0ffb4e74c152a2e),
    ("ico3 moller flat spp1 cracks", 0xb0ffb4e74c152a2e),
    ("ico3 moller flat spp2", 0x91bf568e91c7e882),
    ("ico3 moller direct spp1", 0x995baace1184da89),
    ("ico3 moller direct spp1 nocull", 0x995baace1184da89),
    ("ico3 moller direct spp1 cracks", 0x995baace1184da89),
    ("ico3 moller direct spp2", 0x0e22fbbc83740b07),
    ("ico3 moller shadows spp1", 0x019d93766aa62aff),
    ("ico3 moller shadows spp1 nocull", 0x019d93766aa62aff),
    ("ico3 moller shadows spp1 cracks", 0x019d93766aa62aff),
    ("ico3 moller shadows spp2", 0x992198779ff8ded6),
    ("ico3 moller indirect spp1", 0xf5cf8fa3e485cacb),
    ("ico3 moller indirect spp1 nocull", 0xf5cf8fa3e485cacb),
    ("ico3 moller indirect spp1 cracks", 0xf5cf8fa3e485cacb),
    ("ico3 moller indirect spp2", 0x81c8a12afd29901d),
    ("ico3 cramer flat spp1", 0x3cd0fa9089caf264),
    ("ico3 cramer flat spp1 nocull", 0x3cd0fa9089caf264),
    ("ico3 cramer flat spp1 cracks", 0x3cd0fa9089caf264),
    ("ico3 cramer flat spp2", 0x4530aa7c212ce04e),
    ("ico3 cramer direct spp1", 0xbce25cf6302b92b5),
    ("ico3 cramer direct spp1 nocull", 0xbce25cf6302b92b5),
    ("ico3 cramer direct spp1 cracks", 0xbce25cf6302b92b5),
    ("ico3 cramer direct spp2", 0x4d6dbee1efabd8f3),
    ("ico3 cramer shadows spp1", 0x849b6edbaeeccb59),
    ("ico3 cramer shadows spp1 nocull", 0x849b6edbaeeccb59),
    ("ico3 cramer shadows spp1 cracks", 0x849b6edbaeeccb59),
    ("ico3 cramer shadows spp2", 0x9dd2ff61b270ae63),
    ("ico3 cramer indirect spp1", 0x9b8a0db83067a00f),
    ("ico3 cramer indirect spp1 nocull", 0x9b8a0db83067a00f),
    ("ico3 cramer indirect spp1 cracks", 0x9b8a0db83067a00f),
    ("ico3 cramer indirect spp2", 0x8fdda1c1db1ab2ef),
    ("ico4 adaptive flat spp1", 0x61f9da50ae8cca21),
    ("ico4 adaptive flat spp1 nocull", 0x61f9da50ae8cca21),
    ("ico4 adaptive flat spp1 cracks", 0x61f9da50ae8cca21),
    ("ico4 adaptive flat spp2", 0xc78ee7c74aae2eea),
    ("ico4 adaptive direct spp1", 0x4f9a51f2e6c9b983),
    ("ico4 adaptive direct spp1 nocull", 0x4f9a51f2e6c9b983),
    ("ico4 adaptive direct spp1 cracks", 0x4f9a51f2e6c9b983),
    ("ico4 adaptive direct spp2", 0xdec60e6c934e0663),
    ("ico4 adaptive shadows spp1", 0xee10fd20cf4c9ffb),
    ("ico4 adaptive shadows spp1 nocull", 0xee10fd20cf4c9ffb),
    ("ico4 adaptive shadows spp1 cracks", 0xee10fd20cf4c9ffb),
    ("ico4 adaptive shadows spp2", 0x62527581cecd2342),
    ("ico4 adaptive indirect spp1", 0xb891329190f3bb4d),
    ("ico4 adaptive indirect spp1 nocull", 0xb891329190f3bb4d),
    ("ico4 adaptive indirect spp1 cracks", 0xb891329190f3bb4d),
    ("ico4 adaptive indirect spp2", 0x4723a2b1cff3e4ca),
    ("ico4 watertight flat spp1", 0x0f8d045c6a17260d),
    ("ico4 watertight flat spp1 nocull", 0x0f8d045c6a17260d),
    ("ico4 watertight flat spp1 cracks", 0x0f8d045c6a17260d),
    ("ico4 watertight flat spp2", 0xa196fe9d1454ce44),
    ("ico4 watertight direct spp1", 0x1560aa2bd67337a2),
    ("ico4 watertight direct spp1 nocull", 0x1560aa2bd67337a2),
    ("ico4 watertight direct spp1 cracks", 0x1560aa2bd67337a2),
    ("ico4 watertight direct spp2", 0xfcfbf2496f88e44e),
    ("ico4 watertight shadows spp1", 0x0106e78e61202a3e),
    ("ico4 watertight shadows spp1 nocull", 0x0106e78e61202a3e),
    ("ico4 watertight shadows spp1 cracks", 0x0106e78e61202a3e),
    ("ico4 watertight shadows spp2", 0xf9a81d4fdb88d353),
    ("ico4 watertight indirect spp1", 0xa221d7894aaa3600),
    ("ico4 watertight indirect spp1 nocull", 0xa221d7894aaa3600),
    ("ico4 watertight indirect spp1 cracks", 0xa221d7894aaa3600),
    ("ico4 watertight indirect spp2", 0xf1da913cee8638d7),
    ("ico4 moller flat spp1", 0xd213c3d9bff943b8),
    ("ico4 moller flat spp1 nocull", 0xd213c3d9bff943b8),
    ("ico4 moller flat spp1 cracks", 0xd213c3d9bff943b8),
    ("ico4 moller flat spp2", 0x16afe80160cf5abe),
    ("ico4 moller direct spp1", 0xc3cd89858d249ca7),
    ("ico4 moller direct spp1 nocull", 0xc3cd89858d249ca7),
    ("ico4 moller direct spp1 cracks", 0xc3cd89858d249ca7),
    ("ico4 moller direct spp2", 0xf76fda57059c364f),
    ("ico4 moller shadows spp1", 0xee10fd20cf4c9ffb),
    ("ico4 moller shadows spp1 nocull", 0xee10fd20cf4c9ffb),
    ("ico4 moller shadows spp1 cracks", 0xee10fd20cf4c9ffb),
    ("ico4 moller shadows spp2", 0x15a1ab4c5dccd086),
    ("ico4 moller indirect spp1", 0x0f9f93017650da95),
    ("ico4 moller indirect spp1 nocull", 0x0f9f93017650da95),
    ("ico4 moller indirect spp1 cracks", 0x0f9f93017650da95),
    ("ico4 moller indirect spp2", 0x2e8b9ce6d40f0a76),
    ("ico4 cramer flat spp1", 0x0dc1819f163a859a),
    ("ico4 cramer flat spp1 nocull", 0x0dc1819f163a859a),
    ("ico4 cramer flat spp1 cracks", 0x0dc1819f163a859a),
    ("ico4 cramer flat spp2", 0x7047bad09d9ee162),
    ("ico4 cramer direct spp1", 0xba02984ca4097863),
    ("ico4 cramer direct spp1 nocull", 0xba02984ca4097863),
    ("ico4 cramer direct spp1 cracks", 0xba02984ca4097863),
    ("ico4 cramer direct spp2", 0x4fb4d5d87b63c23b),
    ("ico4 cramer shadows spp1", 0x97ed0a0e38358749),
    ("ico4 cramer shadows spp1 nocull", 0x97ed0a0e38358749),
    ("ico4 cramer shadows spp1 cracks", 0x97ed0a0e38358749),
    ("ico4 cramer shadows spp2", 0x2ac8bf01c39fd65b),
    ("ico4 cramer indirect spp1", 0xeae56f4fdd85b3d1),
    ("ico4 cramer indirect spp1 nocull", 0xeae56f4fdd85b3d1),
    ("ico4 cramer indirect spp1 cracks", 0xeae56f4fdd85b3d1),
    ("ico4 cramer indirect spp2", 0x32ec14b02ca12d10),
    ("spheres adaptive flat spp1", 0x328b7531b9eed09f),
    ("spheres adaptive flat spp1 nocull", 0x328b7531b9eed09f),
    ("spheres adaptive flat spp1 cracks", 0x328b7531b9eed09f),
    ("spheres adaptive flat spp2", 0xe0945054f7edfc8c),
    ("spheres adaptive direct spp1", 0xdb8b360a842e0278),
    ("spheres adaptive direct spp1 nocull", 0xdb8b360a842e0278),
    ("spheres adaptive direct spp1 cracks", 0xdb8b360a842e0278),
    ("spheres adaptive direct spp2", 0x2a511d16b4e26ecf),
    ("spheres adaptive shadows spp1", 0x3bb3e3b773d0a4ef),
    ("spheres adaptive shadows spp1 nocull", 0x3bb3e3b773d0a4ef),
    ("spheres adaptive shadows spp1 cracks", 0x3bb3e3b773d0a4ef),
    ("spheres adaptive shadows spp2", 0x607332ea75e684f4),
    ("spheres adaptive indirect spp1", 0xd6a425d14ba2fb0c),
    ("spheres adaptive indirect spp1 nocull", 0xd6a425d14ba2fb0c),
    ("spheres adaptive indirect spp1 cracks", 0xd6a425d14ba2fb0c),
    ("spheres adaptive indirect spp2", 0xacdfbe43394c4acf),
    ("spheres watertight flat spp1", 0xd11a92b25ddae8eb),
    ("spheres watertight flat spp1 nocull", 0xd11a92b25ddae8eb),
    ("spheres watertight flat spp1 cracks", 0xd11a92b25ddae8eb),
    ("spheres watertight flat spp2", 0xe25208bf81691af2),
    ("spheres watertight direct spp1", 0xdc19c6578cffbce5),
    ("spheres watertight direct spp1 nocull", 0xdc19c6578cffbce5),
    ("spheres watertight direct spp1 cracks", 0xdc19c6578cffbce5),
    ("spheres watertight direct spp2", 0xdfbcf766a5960f46),
    ("spheres watertight shadows spp1", 0x4ac1dd70466ddc30),
    ("spheres watertight shadows spp1 nocull", 0x4ac1dd70466ddc30),
    ("spheres watertight shadows spp1 cracks", 0x4ac1dd70466ddc30),
    ("spheres watertight shadows spp2", 0xbac5f6732d58ab79),
    ("spheres watertight indirect spp1", 0x48ded8f6f8aabdbb),
    (
        "spheres watertight indirect spp1 nocull",
        0x48ded8f6f8aabdbb,
    ),
    (
        "spheres watertight indirect spp1 cracks",
        0x48ded8f6f8aabdbb,
    ),
    ("spheres watertight indirect spp2", 0x4965354ee2954d3c),
    ("spheres moller flat spp1", 0xa0908d66b0daeae6),
    ("spheres moller flat spp1 nocull", 0xa0908d66b0daeae6),
    ("spheres moller flat spp1 cracks", 0xa0908d66b0daeae6),
    ("spheres moller flat spp2", 0x0bd7c3df1a8cb020),
    ("spheres moller direct spp1", 0x986d7d62a0d45d34),
    ("spheres moller direct spp1 nocull", 0x986d7d62a0d45d34),
    ("spheres moller direct spp1 cracks", 0x986d7d62a0d45d34),
    ("spheres moller direct spp2", 0xc3c1337369037263),
    ("spheres moller shadows spp1", 0x3bb3e3b773d0a4ef),
    ("spheres moller shadows spp1 nocull", 0x3bb3e3b773d0a4ef),
    ("spheres moller shadows spp1 cracks", 0x3bb3e3b773d0a4ef),
    ("spheres moller shadows spp2", 0x1799a85b46aa0288),
    ("spheres moller indirect spp1", 0xc828432019312b44),
    ("spheres moller indirect spp1 nocull", 0xc828432019312b44),
    ("spheres moller indirect spp1 cracks", 0xc828432019312b44),
    ("spheres moller indirect spp2", 0x61e0e95037cf35b6),
    ("spheres cramer flat spp1", 0x1a2d732c9f44cec4),
    ("spheres cramer flat spp1 nocull", 0x1a2d732c9f44cec4),
    ("spheres cramer flat spp1 cracks", 0x1a2d732c9f44cec4),
    ("spheres cramer flat spp2", 0xcfaf7ca0c32aa23c),
    ("spheres cramer direct spp1", 0x01442bb217e31d14),
    ("spheres cramer direct spp1 nocull", 0x01442bb217e31d14),
    ("spheres cramer direct spp1 cracks", 0x01442bb217e31d14),
    ("spheres cramer direct spp2", 0x258836cba911521f),
    ("spheres cramer shadows spp1", 0x03b07f2ba6677805),
    ("spheres cramer shadows spp1 nocull", 0x03b07f2ba6677805),
    ("spheres cramer shadows spp1 cracks", 0x03b07f2ba6677805),
    ("spheres cramer shadows spp2", 0x94bfc71fe30386b7),
    ("spheres cramer indirect spp1", 0xddf4e430f6a9e0c8),
    ("spheres cramer indirect spp1 nocull", 0xddf4e430f6a9e0c8),
    ("spheres cramer indirect spp1 cracks", 0xddf4e430f6a9e0c8),
    ("spheres cramer indirect spp2", 0x5c85e4dece6fd79e),
];
