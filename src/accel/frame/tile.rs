//! The queries of one tile ([`TileQueries`]): the nearest hit of camera rays, one at a time
//! and in packets of 8 or 16, with the exact answers of the lanes a packet leaves
//! ambiguous, and which shadow segments are blocked, 8 at a time.

use super::{segments_box, Plan, ShadowSegments, TileQueries, NO_HIT};
use crate::accel::cull::{Box3, Occluder};
use crate::accel::flat::FlatLoop;
use crate::accel::layout::Layout;
use crate::accel::packet::{self, OriginTriangle, PacketHits, PacketNearest, PacketSeed};
use crate::accel::prepared::Prepared;
use crate::accel::spheres::{SphereLanes, SEEDED};
use crate::accel::IndexedTriangle;
use crate::geometry::adaptive::levels::{self, Event};
use crate::geometry::adaptive::Search;
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray};
use crate::math::lanes::LaneOps;
use crate::math::simd::{each3, with_isa, Isa};
use wide::f32x8;

/// The answer of a packet started from `seed` where no triangle can show: the seed's.
#[cold]
#[inline(never)]
fn seed_only(d: &[f32x8; 3], d_max: f32, seed: Option<&PacketSeed>) -> PacketHits {
    PacketNearest::<f32x8>::seeded(d, d_max, seed).finish()
}

impl TileQueries<'_> {
    /// Whether no camera ray of the tile can hit anything: every pixel is background.
    pub fn shows_nothing(&self) -> bool {
        !self.triangles_may_show && !self.spheres_may_show
    }

    /// Whether the tile's camera rays go 8 at a time ([`TileQueries::closest_x8`]); else per
    /// ray ([`TileQueries::closest`]).
    pub fn packets(&self) -> bool {
        self.frame.packets()
    }

    /// The nearest hit of camera ray `ray` (from the eye) with 0 < t < ∞.
    pub fn closest(&mut self, ray: &Ray) -> Option<Hit> {
        let frame = self.frame;
        let method = frame.method;
        match &frame.plan {
            Plan::Culled(_) | Plan::CulledPackets { .. } if !self.spheres_may_show => {
                let subset = self.subset;
                let tris = self
                    .subset_loop
                    .get_or_insert_with(|| FlatLoop::new(subset));
                WatertightRay::new(ray.o, ray.d).and_then(|r| {
                    if method == Method::Adaptive {
                        let mut search = Search::new(ray, 0.0, f32::INFINITY);
                        tris.closest_exact(ray, &r, &mut search);
                        search.hit()
                    } else {
                        tris.closest_watertight(&r, 0.0, f32::INFINITY)
                    }
                })
            }
            Plan::Packets {
                from_eye: Some(cache),
                ..
            } => (frame.accel).closest_hit_prepared(ray, Prepared::Once(cache), 0.0, f32::INFINITY),
            _ => frame.accel.closest_hit(ray, method, 0.0, f32::INFINITY),
        }
    }

    /// The nearest primitive along each of 8 camera rays from the eye with directions `d`,
    /// for lanes `live` (bit l for lane l; the others are [`NO_HIT`]), in the frame's build
    /// ([`FrameQueries::build`](super::FrameQueries::build)).
    pub fn closest_x8(&mut self, d: &[f32x8; 3], live: u32) -> [u32; 8] {
        with_isa!(self.frame.build, |isa| self.closest_x8_in(isa, d, live))
    }

    /// [`TileQueries::closest_x8`] in the build `isa` names (a tile loop's own).
    #[inline(always)]
    pub(crate) fn closest_x8_in<I: Isa>(&mut self, isa: I, d: &[f32x8; 3], live: u32) -> [u32; 8] {
        let d_max = packet::max_component(d);
        let found = match self.spheres_may_show {
            false => self.closest_triangles_x8(isa, d, d_max, None),
            true => self.closest_with_spheres_x8(isa, d, d_max, live),
        };
        // (The lanes are handed on as the kernel stored them: a vector load of its scalar
        // stores would stall store forwarding; measured 5-10% of a Cornell flat frame.)
        let unused = !live & 0xff;
        let mut out = found.prim;
        if (found.ambiguous | unused) != 0 {
            let d = each3(|k| d[k].to_array());
            self.resolve_lanes(&d, found.ambiguous, unused, &mut out);
        }
        out
    }

    /// [`TileQueries::closest_x8`] inside a tile loop already compiled for the CPU, in lanes
    /// `V` of any width, into `out[..V::WIDTH]`: a small scene's culled triangles are tested
    /// inline (no call, no dispatch and no conversion per packet: the Cornell flat frame at
    /// 1280×720 took 1.4× as long in the default build as with AVX2 for the whole program);
    /// other plans go 8 lanes at a time through `closest_x8_in` in the build `isa` names.
    /// `d_max` bounds every |dₖ| of the packet (the generator's bound for its directions:
    /// no reduction per packet in the culled lists' kernel, 3-4% of the Cornell flat frame).
    #[inline(always)]
    pub(crate) fn closest_in<V: LaneOps, I: Isa>(
        &mut self,
        isa: I,
        d: [V; 3],
        d_max: f32,
        live: u32,
        out: &mut [u32],
    ) {
        let frame = self.frame;
        let ambiguous = match (&frame.plan, !self.spheres_may_show) {
            (Plan::CulledPackets { .. }, true) => {
                Some(packet::closest_in(self.prepared, d, d_max, out))
            }
            (Plan::Packets { from_eye, .. }, true) if self.triangles_may_show => {
                let prepared = Prepared::of(from_eye.as_ref());
                // (The packet's own max|dₖ|: with the generator's bound passed in, the
                // AVX-512 build's walk took 12% longer on the bunny at 1280×720, the same
                // lanes ambiguous: code generation.)
                let d_max = packet::max_component_in(&d);
                (frame.accel).closest_packet_in(frame.eye, prepared, d, d_max, out)
            }
            _ => None,
        };
        let Some(ambiguous) = ambiguous else {
            let lanes = lanes_of(&d);
            for h in 0..V::WIDTH / 8 {
                let half = each3(|k| f32x8::from(std::array::from_fn(|l| lanes[k][8 * h + l])));
                let prims = self.closest_x8_in(isa, &half, (live >> (8 * h)) & 0xff);
                out[8 * h..][..8].copy_from_slice(&prims);
            }
            return;
        };
        let unused = !live & V::full();
        if (ambiguous | unused) != 0 {
            self.resolve_lanes(&lanes_of(&d), ambiguous, unused, out);
        }
    }

    /// The packet kernels' answer over the tile's triangles, starting from `seed`.
    #[inline(always)]
    fn closest_triangles_x8<I: Isa>(
        &self,
        isa: I,
        d: &[f32x8; 3],
        d_max: f32,
        seed: Option<&PacketSeed>,
    ) -> PacketHits {
        let frame = self.frame;
        match &frame.plan {
            Plan::CulledPackets { .. } => {
                packet::closest_seeded_in(isa, self.prepared, d, d_max, seed)
            }
            Plan::Packets { .. } if !self.triangles_may_show => seed_only(d, d_max, seed),
            Plan::Packets { from_eye, .. } => frame.accel.closest_packet_of_triangles(
                isa,
                frame.eye,
                Prepared::of(from_eye.as_ref()),
                d,
                d_max,
                seed,
            ),
            _ => PacketHits::undecided(),
        }
    }

    /// [`TileQueries::closest_triangles_x8`] where spheres may show: their hierarchy is
    /// walked first, and the triangles offered against the nearest sphere of each lane.
    #[inline(never)]
    fn closest_with_spheres_x8<I: Isa>(
        &self,
        isa: I,
        d: &[f32x8; 3],
        d_max: f32,
        live: u32,
    ) -> PacketHits {
        let frame = self.frame;
        let Some(spheres) = &frame.spheres else {
            return self.closest_triangles_x8(isa, d, d_max, None);
        };
        let found = frame
            .accel
            .spheres()
            .seed_packet(isa, &spheres.from_eye, d, live);
        let seed = PacketSeed {
            prim: found
                .prims
                .map(|p| if p == NO_HIT { NO_HIT } else { SEEDED }),
            lo: found.lo,
            hi: found.hi,
            ambiguous: found.ambiguous,
        };
        let mut hits = self.closest_triangles_x8(isa, d, d_max, Some(&seed));
        for (prim, sphere) in hits.prim.iter_mut().zip(found.prims) {
            if *prim == SEEDED {
                *prim = sphere;
            }
        }
        hits
    }

    /// Lanes `ambiguous` of `out` decided exactly; lanes `unused` set to [`NO_HIT`].
    /// (`d`: the packet's directions by component, lane by lane; as wide as `out`.)
    #[inline(never)]
    fn resolve_lanes<const N: usize>(
        &mut self,
        d: &[[f32; N]; 3],
        ambiguous: u32,
        unused: u32,
        out: &mut [u32],
    ) {
        for (l, out) in out.iter_mut().enumerate().take(N) {
            if unused & (1 << l) != 0 {
                *out = NO_HIT;
            } else if ambiguous & (1 << l) != 0 {
                levels::note(Event::CameraLaneAmbiguous);
                *out = self
                    .resolve_lane([d[0][l], d[1][l], d[2][l]])
                    .unwrap_or(NO_HIT);
            }
        }
    }

    /// An ambiguous camera lane's primitive: exact edge signs over the tile's triangles where
    /// that decides, else the per-ray search.
    fn resolve_lane(&mut self, d: [f32; 3]) -> Option<u32> {
        let frame = self.frame;
        // (The exact resolver knows triangles only.)
        if let (Plan::CulledPackets { culling, .. }, false) = (&frame.plan, self.spheres_may_show) {
            let vertices = |p| culling.vertices(p);
            if let Some(prim) = packet::closest_exact_lane(self.prepared, vertices, frame.eye, d) {
                return prim;
            }
        }
        self.closest(&Ray::new(frame.eye, d)).map(|h| h.prim)
    }

    /// Whether shadow segment `ray` (0 < t < 1) is blocked by anything but primitive `skip`.
    pub fn any(&self, ray: &Ray, skip: u32) -> bool {
        self.frame.any(ray, skip)
    }

    /// Which live lanes of each of the tile's shadow segments are blocked: `blocked[i]` gets
    /// packet i's mask (in the frame's build, as [`TileQueries::closest_x8`]).
    pub fn any_x8<S: AsRef<ShadowSegments>>(&mut self, packets: &[S], blocked: &mut Vec<u32>) {
        with_isa!(self.frame.build, |isa| self
            .any_x8_in(isa, packets, blocked))
    }

    /// [`TileQueries::any_x8`] in the build `isa` names (a tile loop's own).
    pub(crate) fn any_x8_in<S: AsRef<ShadowSegments>, I: Isa>(
        &mut self,
        isa: I,
        packets: &[S],
        blocked: &mut Vec<u32>,
    ) {
        blocked.clear();
        blocked.resize(packets.len(), 0);
        let frame = self.frame;
        let light = frame.light;
        let per_ray = |s: &ShadowSegments, mut lanes: u32, out: &mut u32| {
            while lanes != 0 {
                let l = lanes.trailing_zeros() as usize;
                lanes &= lanes - 1;
                let ray = Ray::new(light, s.d.map(|c| c.to_array()[l]));
                if frame.any(&ray, s.skip(l)) {
                    *out |= 1 << l;
                }
            }
        };
        // The spheres the segments may meet: their hierarchy walked first; the triangles'
        // packets then take the lanes it leaves clear.
        let by_spheres = |s: &ShadowSegments| match &frame.spheres {
            None => SphereLanes {
                blocked: 0,
                unsure: 0,
            },
            Some(spheres) => match &spheres.from_light {
                Some(seen) => frame.accel.spheres().any_packet(isa, seen, s),
                None => SphereLanes {
                    blocked: 0,
                    unsure: s.live,
                },
            },
        };
        match &frame.plan {
            Plan::Packets { from_light, .. } => {
                let accel = frame.accel;
                for (s, out) in packets.iter().map(AsRef::as_ref).zip(blocked.iter_mut()) {
                    if s.live == 0 {
                        continue;
                    }
                    let by_shapes = by_spheres(s);
                    *out = by_shapes.blocked;
                    let valid = s.live & !(by_shapes.blocked | by_shapes.unsure);
                    if valid != 0 {
                        let d_max = packet::max_component(&s.d);
                        let prepared = Prepared::of(from_light.as_ref());
                        let found = accel.any_packet_of_triangles(
                            isa, light, prepared, &s.d, d_max, &s.prim, valid,
                        );
                        *out |= found.blocked;
                        note_unsure(found.unsure);
                        per_ray(s, found.unsure, out);
                    }
                    per_ray(s, by_shapes.unsure, out);
                }
            }
            Plan::CulledPackets {
                culling,
                from_light,
                occluders,
                ..
            } => {
                let near = &mut *self.near;
                near_occluders(packets, light, occluders, from_light, near);
                let mut near_loop = None;
                for (s, out) in packets.iter().map(AsRef::as_ref).zip(blocked.iter_mut()) {
                    if s.live == 0 {
                        continue;
                    }
                    let by_shapes = by_spheres(s);
                    *out = by_shapes.blocked;
                    per_ray(s, by_shapes.unsure, out);
                    let valid = s.live & !(by_shapes.blocked | by_shapes.unsure);
                    if valid == 0 {
                        continue;
                    }
                    let d_max = packet::max_component(&s.d);
                    let found = packet::any_in(isa, near, &s.d, d_max, &s.prim, valid);
                    *out |= found.blocked;
                    note_unsure(found.unsure);
                    // Unsure lanes: exact edge signs and sides where that decides.
                    let mut left = 0;
                    for l in (0..8).filter(|l| found.unsure & (1 << l) != 0) {
                        let d = s.d.map(|c| c.to_array()[l]);
                        let vertices = |p| culling.vertices(p);
                        match packet::any_exact_lane(near, vertices, light, d, s.prim[l]) {
                            Some(true) => *out |= 1 << l,
                            Some(false) => {}
                            None => left |= 1 << l,
                        }
                    }
                    // Then per ray against the same triangles.
                    for l in (0..8).filter(|l| left & (1 << l) != 0) {
                        let tris = near_loop.get_or_insert_with(|| {
                            let tris: Vec<IndexedTriangle> = near
                                .iter()
                                .map(|t| (culling.vertices(t.prim), t.prim))
                                .collect();
                            FlatLoop::new(&tris)
                        });
                        let ray = Ray::new(light, s.d.map(|c| c.to_array()[l]));
                        let search = Search::new(&ray, 0.0, 1.0);
                        let hit = WatertightRay::new(ray.o, ray.d)
                            .is_some_and(|r| tris.any_exact(&ray, &r, &search, s.prim[l]));
                        if hit {
                            *out |= 1 << l;
                        }
                    }
                }
            }
            // Per ray: the plan has no shadow packets.
            _ => {
                for (s, out) in packets.iter().map(AsRef::as_ref).zip(blocked.iter_mut()) {
                    per_ray(s, s.live, out);
                }
            }
        }
    }
}

/// Counts the shadow lanes a packet left unsure ([`levels`]).
#[inline]
fn note_unsure(unsure: u32) {
    levels::note_many(Event::ShadowLaneUnsure, unsure.count_ones());
}

/// Fills `near` with the triangles (prepared for the light) that may block one of the shadow
/// segments of `packets`: those whose bounding box meets the box around every segment (light
/// to light + direction, widened for the rounding of that end). A triangle meeting a segment
/// has a point in that box.
fn near_occluders<S: AsRef<ShadowSegments>>(
    packets: &[S],
    light: [f32; 3],
    occluders: &[Occluder],
    from_light: &[OriginTriangle],
    near: &mut Vec<OriginTriangle>,
) {
    let Box3 { lo, hi } = segments_box(packets, light);
    near.clear();
    near.extend(
        occluders
            .iter()
            .filter(|occ| occ.bounds.meets(lo, hi))
            .map(|occ| from_light[occ.slot as usize]),
    );
}
/// Lanes `d` by component as arrays (16 wide, the widest lanes; the first `V::WIDTH` used).
#[inline(always)]
fn lanes_of<V: LaneOps>(d: &[V; 3]) -> [[f32; 16]; 3] {
    let mut lanes = [[0.0f32; 16]; 3];
    for (lane, d) in lanes.iter_mut().zip(d) {
        d.store(lane);
    }
    lanes
}
