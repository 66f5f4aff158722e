//! Every kind of shape through its one trait (`geometry::Primitive`): a hit readied for shading
//! on its own (`Lit`, from the shape's own surface point) is bit for bit the lane the shading
//! packets make of it, the skip of the shadow test is the shape's answer, and each shape's
//! scene line reads back through the parser as the same shape.

use crate::common;

use common::Rng;
use raylab::geometry::{
    sphere, triangle, Location, Method, Primitive, Ray, Shape, Sphere, Triangle,
};
use raylab::math::lanes::f32x8;
use raylab::render::shade::{shade_packet, shading_point, Lit, ShadeTri};
use raylab::render::Stage;
use raylab::scene::file::parse;
use raylab::scene::ObjFrame;
use raylab::Scene;
use std::path::Path;

/// The Cornell box with two spheres, one of them around a point of the light's side.
fn scene() -> Scene {
    let mut scene = Scene::cornell();
    scene.shapes.push(Shape::sphere([0.35, 0.55, 0.2], 0.3));
    scene.shapes.push(Shape::sphere([-0.4, 0.4, -0.1], 0.25));
    scene
        .colors_mut()
        .extend([[0.2, 0.5, 0.9], [0.9, 0.5, 0.2]]);
    scene
}

#[test]
fn a_triangle_hit_readied_alone_is_its_packet_lane() {
    let stage = Stage::from(scene());
    let scene = stage.scene();
    let mut rng = Rng(11);
    let mut lanes_checked = [0usize; 2];
    for _ in 0..400 {
        // 8 rays from one origin (inside the box or in front of it) to random points.
        let o = [0, 1, 2].map(|_| rng.range(-0.9, 0.9) as f32);
        let dirs: [[f32; 3]; 8] = std::array::from_fn(|_| {
            let target = [0, 1, 2].map(|_| rng.range(-1.2, 1.2) as f32);
            [0, 1, 2].map(|k| target[k] - o[k])
        });
        let rays = dirs.map(|d| Ray::new(o, d));
        let hits = rays.map(|r| {
            stage
                .accel()
                .closest_hit(&r, Method::Adaptive, 0.0, f32::INFINITY)
        });
        let tris: [Option<ShadeTri>; 8] = std::array::from_fn(|l| {
            let prim = hits[l]?.prim;
            let v = *scene.shape(prim).triangle()?;
            Some(ShadeTri::new(&v, o, prim))
        });
        let lanes: [Option<&ShadeTri>; 8] = std::array::from_fn(|l| tris[l].as_ref());
        let d = std::array::from_fn(|k| f32x8::from(dirs.map(|d| d[k])));
        let packet = shade_packet(scene, &d, &lanes);
        for l in 0..8 {
            let Some(hit) = hits[l] else { continue };
            let lit = Lit::new(scene, &rays[l], &hit);
            let shape = scene.shape(hit.prim);
            if !shape.is_triangle() {
                // Another shape: its skip is its own answer for the light's side.
                let sp = shading_point(scene, &rays[l], hit.prim);
                let light = scene.light.position;
                let end_outside =
                    (0..3).map(|k| (light[k] - sp.p[k]) * sp.n[k]).sum::<f32>() >= 0.0;
                let clear = shape.shadow_clear_of_itself(light, end_outside);
                assert_eq!(lit.skip == hit.prim, clear);
                lanes_checked[1] += 1;
                continue;
            }
            lanes_checked[0] += 1;
            assert_eq!(packet.prim(l), hit.prim);
            assert_eq!(
                lit.skip, hit.prim,
                "a triangle never blocks its own shadow ray"
            );
            let live = packet.shadow.live & (1 << l) != 0;
            assert_eq!(live, lit.shadow.is_some(), "lane {l}");
            if let Some(shadow) = lit.shadow {
                assert_eq!(lit.k.to_bits(), packet.k[l].to_bits(), "lane {l}");
                assert_eq!(shadow.o, scene.light.position);
                let packet_d = packet.shadow.d.map(|c| c.to_array()[l]);
                assert_eq!(shadow.d.map(f32::to_bits), packet_d.map(f32::to_bits));
            }
        }
    }
    assert!(lanes_checked[0] > 1000, "{lanes_checked:?} lanes checked");
    assert!(lanes_checked[1] > 50, "{lanes_checked:?} lanes checked");
}

#[test]
fn each_shape_s_scene_line_reads_back_as_the_same_shape() {
    let no_meshes = |p: &Path, _: ObjFrame, _: [f32; 3]| -> Result<Scene, String> {
        Err(format!("{}: no meshes here", p.display()))
    };
    let shapes = [
        Shape::from([[0.1, -0.0, 3.0], [1e-7, 2.5, 3.0], [-4.0, 0.5, 1e6]]),
        Shape::sphere([0.35, -5.5, 1e-3], 0.3),
    ];
    for shape in shapes {
        let line = shape.scene_line();
        let d = parse::<f32>("t.scene", &line, Path::new(""), &no_meshes).expect(&line);
        assert_eq!(d.shapes.len(), 1, "{line}");
        assert_eq!(d.shapes[0].key(), shape.key(), "{line}");
        assert_eq!(d.shapes[0].scene_line(), line);
    }
    // The keyword leads the line; the numbers follow in the order `numbers` gives them.
    let tri = Triangle([[1.0f32, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.5]]);
    let ball = Sphere {
        centre: [1.0f32, 2.0, 3.0],
        radius: 0.5,
    };
    assert_eq!(
        Shape::from(tri.0).scene_line(),
        format!("{} 1 2 3 4 5 6 7 8 9.5", Triangle::<f32>::KEYWORD)
    );
    assert_eq!(
        Shape::sphere(ball.centre, ball.radius).scene_line(),
        format!("{} 1 2 3 0.5", Sphere::<f32>::KEYWORD)
    );
    assert_ne!(Triangle::<f32>::KIND, Sphere::<f32>::KIND);
    assert_eq!(ball.numbers().collect::<Vec<_>>(), [1.0, 2.0, 3.0, 0.5]);
}

#[test]
fn the_shape_list_gives_the_parser_every_keyword_and_each_its_own_checks() {
    let no_meshes = |p: &Path, _: ObjFrame, _: [f32; 3]| -> Result<Scene, String> {
        Err(format!("{}: no meshes here", p.display()))
    };
    let keywords = [Triangle::<f32>::KEYWORD, Sphere::<f32>::KEYWORD];
    assert_eq!(Shape::<f32>::KEYWORDS, keywords);
    let error = (parse::<f32>("t.scene", "cone 0 0 0 1", Path::new(""), &no_meshes).unwrap_err())
        .to_string();
    assert!(error.contains("expected tri, sphere, mesh"), "{error}");
    // Each shape reads its own numbers, through the transform stack's current frame.
    let cases = [
        ("tri 0 0 0 1 0 0", "t.scene:1: tri needs 9 numbers, found 6"),
        ("sphere 0 0 0 -1", "t.scene:1: sphere radius -1 must be > 0"),
        (
            "scale 1 2 1\nsphere 0 0 0 1",
            "t.scene:2: a sphere under a non-uniform scale",
        ),
        (
            "sphere 0 0 0 1e39",
            "t.scene:1: sphere radius 1e39 is inf in the world",
        ),
    ];
    for (text, want) in cases {
        let error =
            (parse::<f32>("t.scene", text, Path::new(""), &no_meshes).unwrap_err()).to_string();
        assert!(error.starts_with(want), "{text}: {error}");
    }
    let d = parse::<f32>(
        "t.scene",
        "translate 1 0 0\nscale 2 2 2\nsphere 1 0 0 0.25",
        Path::new(""),
        &no_meshes,
    )
    .unwrap();
    assert_eq!(d.shapes, [Shape::sphere([3.0, 0.0, 0.0], 0.5)]);
}

/// Where a ray meets a triangle ([`Shape::locate`]), decided exactly: what the inspector says.
#[test]
fn inside_on_an_edge_at_a_vertex_and_outside_are_told_apart_exactly() {
    let tri = Shape::from([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]);
    let at = |x: f32, y: f32| tri.locate(&Ray::new([x, y, 0.0], [0.0, 0.0, 1.0]));
    assert!(matches!(
        at(0.25, 0.25),
        Location::Triangle(triangle::Location::Inside { .. })
    ));
    assert_eq!(at(0.5, 0.0), tri_at(triangle::Location::Edge(0)));
    assert_eq!(at(0.5, 0.5), tri_at(triangle::Location::Edge(1)));
    assert_eq!(at(0.0, 0.5), tri_at(triangle::Location::Edge(2)));
    assert_eq!(at(0.0, 0.0), tri_at(triangle::Location::Vertex(0)));
    assert_eq!(at(1.0, 0.0), tri_at(triangle::Location::Vertex(1)));
    assert_eq!(at(0.0, 1.0), tri_at(triangle::Location::Vertex(2)));
    assert_eq!(at(0.6, 0.6), tri_at(triangle::Location::Outside(vec![1])));
    assert_eq!(
        at(-0.5, -0.5),
        tri_at(triangle::Location::Outside(vec![0, 2]))
    );
    // Just off the edge v1–v2, by one f32 step: outside, not on it.
    let next = f32::from_bits(0.5f32.to_bits() + 1);
    assert_eq!(at(next, 0.5), tri_at(triangle::Location::Outside(vec![1])));
    // Seen from behind: the same answers (two-sided).
    let back = tri.locate(&Ray::new([0.5, 0.0, 2.0], [0.0, 0.0, -1.0]));
    assert_eq!(back, tri_at(triangle::Location::Edge(0)));
    // In the triangle's plane.
    let flat = tri.locate(&Ray::new([-1.0, 0.25, 1.0], [1.0, 0.0, 0.0]));
    assert_eq!(flat, tri_at(triangle::Location::EdgeOn));
    assert_eq!(at(0.0, 1.0).to_string(), "at vertex v2");
    assert_eq!(at(0.5, 0.0).to_string(), "on the edge v0–v1");
    // A hit 1.2e-17 (barycentric) inside an edge, in f64 (the check suite's fan of 12, its
    // triangle 9): the weight is told as it is (f64's own sum gave 0 and -0).
    let (a, b, c, d) = (
        0.3f32.into(),
        (-0.2f32).into(),
        (-0.8660254f32).into(),
        1.836_970_146_528_853_8e-16,
    );
    let fan: Shape<f64> = Shape::from([[a, b, 0.5], [-d, -1.0, a], [0.5, c, d]]);
    let ray = Ray::new([2.0, -1.5, 1.0], [-2.0, 0.5, (-0.7f32).into()]);
    let Location::Triangle(triangle::Location::Inside { nearest, weight }) = fan.locate(&ray)
    else {
        panic!("{}", fan.locate(&ray));
    };
    assert_eq!(triangle::EDGES[nearest], "v1–v2");
    assert!((1.1e-17..1.3e-17).contains(&weight), "{weight:e}");
}

/// A sphere is met, touched or missed by the exact discriminant's sign, at every scale.
#[test]
fn a_sphere_is_met_touched_or_missed() {
    let ball = Shape::sphere([0.0, 0.0, 5.0], 1.0);
    let at = |x: f32| ball.locate(&Ray::new([x, 0.0, 0.0], [0.0, 0.0, 1.0]));
    assert_eq!(at(0.5), Location::Sphere(sphere::Location::Through));
    assert_eq!(at(1.0), Location::Sphere(sphere::Location::Tangent));
    assert_eq!(at(-1.0), Location::Sphere(sphere::Location::Tangent));
    assert_eq!(
        at(f32::from_bits(1.0f32.to_bits() + 1)),
        Location::Sphere(sphere::Location::Misses)
    );
    // Tangent at f32's extremes, where f64 products of the inputs would overflow or
    // underflow: the exact discriminant still tells a touch from a crossing or a miss.
    for scale in [1e-38f32, 1e37] {
        let ball = Shape::sphere([0.0, 0.0, 30.0 * scale], scale);
        let at = |x: f32| ball.locate(&Ray::new([x, 0.0, 0.0], [0.0, 0.0, 1.0]));
        assert_eq!(at(scale), Location::Sphere(sphere::Location::Tangent));
        assert_eq!(at(0.5 * scale), Location::Sphere(sphere::Location::Through));
        let beyond = f32::from_bits(scale.to_bits() + 1);
        assert_eq!(at(beyond), Location::Sphere(sphere::Location::Misses));
    }
    assert_eq!(at(0.5).to_string(), "on the sphere");
}

fn tri_at(at: triangle::Location) -> Location {
    Location::Triangle(at)
}
