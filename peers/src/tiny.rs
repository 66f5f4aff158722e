//! tinybvh (the `tinybvh-rs` crate): its fastest layout this build can call, and the ray
//! buffer its C++ needs.

use anyhow::anyhow;

/// Lets a peer's BVH be shared by the rayon threads.
pub struct Shared<T>(pub T);
// SAFETY: only the peers' const queries run through it, which read the BVH and write nothing
// but the caller's ray (tinybvh's `Intersect` is a const member function).
unsafe impl<T> Sync for Shared<T> {}

/// tinybvh's C++ `Ray` as the bundled `tiny_bvh.h` (INST_IDX_BITS 32) lays it out: 128 bytes,
/// of which tinybvh-rs's `Ray` mirrors only the first 64 (the hit's t, u, v and prim at the same
/// offsets). Its `Ray::new` returns the 64-byte struct by value from C++, which writes all 128
/// and overruns the caller's stack, so the ray is made here, in a buffer of the full size.
#[repr(C, align(64))]
struct TinyRay {
    ray: tinybvh_rs::Ray,
    /// The C++ hit's auxData and user data.
    _rest: [u8; 64],
}

impl TinyRay {
    fn new(o: [f32; 3], d: [f32; 3]) -> Self {
        // As tinybvh's constructor: a unit direction, its reciprocal, every mask bit.
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let dir = d.map(|x| x / n);
        let mut ray = tinybvh_rs::Ray {
            origin: o,
            dir,
            r_d: dir.map(|x| 1.0 / x),
            hit: tinybvh_rs::Intersection::new(),
            ..Default::default()
        };
        ray.padding_0 = 0xFFFF; // the C++ ray's mask
        ray.padding_2 = 0; // the C++ hit's instance
        TinyRay {
            ray,
            _rest: [0; 64],
        }
    }

    /// The nearest primitive, `None` where the ray missed.
    fn prim(&self) -> Option<u32> {
        (self.ray.hit.t < tinybvh_rs::INFINITE).then_some(self.ray.hit.prim)
    }
}

/// A peer's closest hit for one ray (origin, direction): its primitive, if any.
pub type ClosestFn<'a> = Box<dyn Fn([f32; 3], [f32; 3]) -> Option<u32> + 'a>;

/// tinybvh's fastest layout this build can call (see the module docs), borrowing the
/// vertices it was built on.
pub struct TinyBvh<'a> {
    pub name: &'static str,
    pub closest: Shared<ClosestFn<'a>>,
}

pub fn build_tinybvh(vertices: &[[f32; 4]]) -> anyhow::Result<TinyBvh<'_>> {
    use tinybvh_rs::Intersector;
    let bvh = tinybvh_rs::bvh::BVH::new(vertices.into()).map_err(|e| anyhow!("{e:?}"))?;
    #[cfg(target_feature = "avx2")]
    {
        let mut bvh = bvh;
        bvh.split_leaves(4);
        let mbvh = tinybvh_rs::mbvh::BVH::new(&bvh);
        // BVH8_CPU keeps its own copy of the triangles.
        let bvh8 = tinybvh_rs::bvh8_cpu::BVH::new(&mbvh).map_err(|e| anyhow!("{e:?}"))?;
        Ok(TinyBvh {
            name: "tinybvh BVH8_CPU (AVX2, f32)",
            closest: Shared(Box::new(move |o, d| {
                let mut ray = TinyRay::new(o, d);
                bvh8.intersect(&mut ray.ray);
                ray.prim()
            })),
        })
    }
    #[cfg(not(target_feature = "avx2"))]
    Ok(TinyBvh {
        name: "tinybvh BVH, binary (f32; BVH8_CPU needs target-cpu=native)",
        closest: Shared(Box::new(move |o, d| {
            let mut ray = TinyRay::new(o, d);
            bvh.intersect(&mut ray.ray);
            ray.prim()
        })),
    })
}
