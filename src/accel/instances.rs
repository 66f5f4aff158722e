//! The two-level structure over a scene's instances ([`crate::geometry::instance::Instance`]): one BVH per
//! mesh in the mesh's own frame, built once however often the mesh is placed, and one BVH over
//! the instances' world boxes.
//!
//! A ray reaching an instance's box is carried into the mesh's frame (o′ = C·o, d′ = C·d with
//! C the f64 inverse of the instance's matrix, rounded to f32) and walks the mesh's hierarchy
//! there; at the leaves the triangles are carried into the world exactly as the flattened
//! scene computes them ([`crate::geometry::instance::Instance::world_vertex`]) and tested in the world with
//! the query's own method and primitive index. So every answer is the flattened scene's: the
//! object frame only decides which leaves are visited.
//!
//! That culling must never drop a leaf the exact world ray reaches. Each object box is widened
//! by a pad per instance and ray, `pad = 2⁻²⁰·(B + |o′|∞ + ‖C‖∞·(W + |o|∞ + |b|∞))` (B the
//! mesh's largest object coordinate, W the instance's largest world coordinate, b its
//! translation), which covers with room to spare: the world vertices' rounding to f32 carried
//! back by C (≤ 2⁻²⁴·‖C‖·W), the inverse's own error (condition ≤ 2²⁰, so ≤ 2⁻³² relative,
//! [`crate::geometry::instance::MAX_CONDITION`]), the rounding of o′ and d′ to f32 (≤ 2⁻²⁴·|o′|,
//! and t·2⁻²¹·‖C‖·|d| ≤ 2⁻²¹·‖C‖·(W + |o|) at any point of the box) and of the padded box's
//! own corners. The slab test itself is conservative as in [`super::bvh`]. Those roundings
//! are relative only in f32's normal range: where the carried direction leaves it (a
//! direction of 2⁻⁵⁰ under a scale of 2⁻¹⁰⁰ underflows, one of 2³⁰ under 2¹⁰⁰ overflows), the
//! ray, or the packet, tests every triangle of the instance instead
//! (`tests/library/instances_at_any_scale.rs`).

use super::bvh::{approach, Aabb, Approached, Bvh, Leaves, PacketSlabs, WideStack, MAX_LEAF};
use super::layout::{merge, Layout};
use super::packet::{quad_indices, OriginBlock, OriginTriangle, PacketSink, PreciseTriangle};
use super::without_copies;
use crate::geometry::adaptive::{box_extent, classify_f32, round_down, Estimate, Search};
use crate::geometry::instance::{linear_norm, world_bounds, Instance, Mesh};
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray, Shape};
use crate::math::lanes::{f32x8, LaneOps, Lanes};
use crate::math::simd::{each3, Isa, Outlined};
use glam::{DMat4, DVec3};
use rayon::prelude::*;
use std::sync::Arc;

/// 2⁻²⁰: the pad's relative size (see the module docs).
const PAD: f64 = 1.0 / (1u64 << 20) as f64;

/// The share of a mesh's size beyond which a packet's pad culls too little in its frame
/// ([`MeshWalk`]).
const COARSE_PAD: f64 = 1.0 / 64.0;

/// Packets' directions are carried into an instance's frame in f32 ([`Placed::carry_directions`])
/// where both ‖C‖∞ and every lane's largest component lie within 2⁻⁶⁰…2⁶⁰ (this bound): then
/// no product overflows and none underflows by more than 2⁻¹⁵⁰, far below the pad's allowance
/// of 2⁻²¹·‖C‖·|d|. Elsewhere (a direction of 2⁻¹²⁵ by a scale of 2⁻³⁰ underflows to 0, which
/// the slab test would trust) the packet tests every triangle of the instance.
const CARRY_SAFE: f32 = (1u64 << 60) as f32;

/// One instance as the structure walks it.
#[derive(Clone, Debug)]
struct Placed {
    /// Which mesh hierarchy.
    mesh: u32,
    world_from_object: DMat4,
    object_from_world: DMat4,
    /// `object_from_world`'s first three rows in f32 (for packets' directions).
    to_object32: [[f32; 4]; 3],
    /// ‖C‖∞ of the linear part of `object_from_world`.
    c_norm: f64,
    /// Whether packets' directions are carried into the object frame in f32
    /// ([`Placed::carry_directions`]): ‖C‖∞ within 2⁻⁶⁰…2⁶⁰ ([`CARRY_SAFE`]).
    carries: bool,
    /// B: the mesh's largest object coordinate.
    object_max: f64,
    /// W + |b|∞: the instance's largest world coordinate and its translation.
    world_max: f64,
    first_prim: u32,
    /// The instance's world box (as the top hierarchy has it).
    world_box: Aabb,
}

impl Placed {
    /// Object triangle `v` in the world, as the flattened scene has it.
    #[inline(always)]
    fn world(&self, v: &[[f32; 3]; 3]) -> [[f32; 3]; 3] {
        // (`each3`, not array `map`: in the AVX2 build `map` stayed a call, 3.6% of a field
        // frame.)
        each3(|i| Instance::world_vertex(&self.world_from_object, v[i]))
    }

    /// Four object triangles in the world as [`Placed::world`] has them, by vertex and
    /// coordinate in 8 lanes (lanes 4–7 repeat 0–3): glam's `transform_point3` order,
    /// ((x·c₀ + y·c₁) + z·c₂) + c₃ rounded in f64, then to f32, for 4 triangles in f64 lanes
    /// at once (2.8% fewer instructions in a field frame than one vertex at a time).
    #[inline(always)]
    fn world_lanes<V: Lanes>(&self, t: [&[[f32; 3]; 3]; 4]) -> [[V; 3]; 3] {
        use crate::math::lanes::Lanes64;
        // (Loops, not closures: in the AVX2 kernel those stayed calls.)
        let m = &self.world_from_object;
        let cols = [m.x_axis, m.y_axis, m.z_axis, m.w_axis];
        let mut w = [[V::zero(); 3]; 3];
        for (j, wj) in w.iter_mut().enumerate() {
            let mut x = [V::F64::splat(0.0); 3];
            for (k, xk) in x.iter_mut().enumerate() {
                *xk = V::F64::from_array([
                    t[0][j][k] as f64,
                    t[1][j][k] as f64,
                    t[2][j][k] as f64,
                    t[3][j][k] as f64,
                ]);
            }
            for (k, wjk) in wj.iter_mut().enumerate() {
                let c = |col: usize| V::F64::splat(cols[col][k]);
                let f = (((x[0] * c(0) + x[1] * c(1)) + x[2] * c(2)) + c(3)).to_f32();
                *wjk = V::from_array([f[0], f[1], f[2], f[3], f[0], f[1], f[2], f[3]]);
            }
        }
        w
    }

    /// The origin `o` in the object frame, and the pad for rays from it; `None` where they
    /// are not finite (the ray then tests every triangle of the instance).
    #[inline]
    fn carry_origin(&self, o: [f32; 3]) -> Option<([f32; 3], f32)> {
        let w = DVec3::new(o[0] as f64, o[1] as f64, o[2] as f64);
        let obj = self
            .object_from_world
            .transform_point3(w)
            .to_array()
            .map(|c| c as f32);
        let o_max = o.iter().fold(0f64, |m, c| m.max((*c as f64).abs()));
        let obj_max = obj.iter().fold(0f64, |m, c| m.max((*c as f64).abs()));
        let pad =
            PAD * (self.object_max + obj_max + self.c_norm * (self.world_max + o_max)) + 1e-37;
        let pad = (pad * (1.0 + PAD)) as f32;
        (obj.iter().all(|c| c.is_finite()) && pad.is_finite()).then_some((obj, pad))
    }

    /// A ray in the object frame (same t), and its pad (for a world ray whose points may lie
    /// `world_pad` off the query's in each coordinate: ‖C‖∞ times that more); `None` where the
    /// carried direction leaves f32's normal range (the pad allows for its rounding relative
    /// to its largest component only: a direction of 2⁻⁵⁰ carried by a scale of 2⁻¹⁰⁰
    /// underflows), and where the origin's carry is not finite.
    #[inline]
    fn carry_ray(&self, ray: &Ray, world_pad: f32) -> Option<(Ray, f32)> {
        let (o, pad) = self.carry_origin(ray.o)?;
        let pad = match world_pad {
            0.0 => pad,
            _ => ((pad as f64 + self.c_norm * world_pad as f64) * (1.0 + PAD)) as f32,
        };
        let d = DVec3::new(ray.d[0] as f64, ray.d[1] as f64, ray.d[2] as f64);
        let d = self.object_from_world.transform_vector3(d);
        let largest = d.abs().max_element();
        let normal = (f32::MIN_POSITIVE as f64..=f32::MAX as f64 / 2.0).contains(&largest);
        normal.then(|| (Ray::new(o, d.to_array().map(|c| c as f32)), pad))
    }

    /// A packet's directions in the object frame (f32 arithmetic: within the pad's
    /// allowance), in the kernel's lanes (in `wide`'s f32x8 they were SSE halves in the AVX
    /// builds).
    #[inline(always)]
    fn carry_directions<V: LaneOps>(&self, d: &[V; 3]) -> [V; 3] {
        let m = &self.to_object32;
        each3(|r| d[0] * V::splat(m[r][0]) + d[1] * V::splat(m[r][1]) + d[2] * V::splat(m[r][2]))
    }
}

/// The two-level structure (see the module docs).
#[derive(Clone, Debug)]
pub struct Instances {
    /// One per distinct mesh, object frame; its items are the mesh's triangle indices.
    meshes: Vec<Bvh>,
    placed: Vec<Placed>,
    /// Over the instances' world boxes; its items are indices into `placed`.
    top: Bvh,
    /// The box around every instance (for the adaptive filter's magnitude bound).
    world: Aabb,
    /// Triangles of the meshes left out as copies, times their uses.
    copies: usize,
    /// Triangles answered for (copies left out).
    triangles: usize,
}

impl Instances {
    /// The box around every instance.
    pub(crate) fn world_bounds(&self) -> Aabb {
        self.world
    }

    /// Builds over `instances` (their matrices must be [`Instance::placeable`]).
    pub fn build(instances: &[Instance]) -> Self {
        let (kept, placed_copies) = placements_without_copies(instances);
        let mut built = Self::build_distinct(kept.as_deref().unwrap_or(instances));
        built.copies += placed_copies;
        built
    }

    /// [`Instances::build`] over placements that repeat none.
    fn build_distinct(instances: &[Instance]) -> Self {
        let mut distinct: Vec<&Arc<Mesh>> = Vec::new();
        let mesh_of: Vec<u32> = instances
            .iter()
            .map(
                |inst| match distinct.iter().position(|m| Arc::ptr_eq(m, &inst.mesh)) {
                    Some(k) => k as u32,
                    None => {
                        distinct.push(&inst.mesh);
                        distinct.len() as u32 - 1
                    }
                },
            )
            .collect();
        let built: Vec<(Bvh, usize)> = distinct
            .par_iter()
            .map(|mesh| {
                let tris = (mesh.triangles.iter().enumerate())
                    .map(|(i, t)| (*t, i as u32))
                    .collect();
                let (tris, copies) = without_copies(tris);
                (Bvh::build_placed(&tris), copies)
            })
            .collect();
        let boxes: Vec<([f32; 3], [f32; 3])> = instances.iter().map(world_bounds).collect();
        let placed: Vec<Placed> = (instances.iter().zip(&mesh_of).zip(&boxes))
            .map(|((inst, &mesh), &(wlo, whi))| {
                let m = inst.world_from_object;
                let inv = m.inverse();
                let (lo, hi) = inst.mesh.bounds();
                let max_abs = |a: [f32; 3], b: [f32; 3]| {
                    (0..3).fold(0f64, |acc, k| {
                        acc.max((a[k] as f64).abs()).max((b[k] as f64).abs())
                    })
                };
                let rows = [0, 1, 2].map(|r| inv.row(r).to_array().map(|c| c as f32));
                let b = m.w_axis.truncate().abs().max_element();
                let c_norm = linear_norm(&inv);
                Placed {
                    mesh,
                    world_from_object: m,
                    object_from_world: inv,
                    to_object32: rows,
                    c_norm,
                    carries: (CARRY_SAFE.recip() as f64..=CARRY_SAFE as f64).contains(&c_norm),
                    object_max: max_abs(lo, hi),
                    world_max: max_abs(wlo, whi) + b,
                    first_prim: inst.first_prim,
                    world_box: Aabb { lo: wlo, hi: whi },
                }
            })
            .collect();
        let top = Bvh::build_over_boxes(&boxes);
        let world = top.root_bounds().unwrap_or(Aabb {
            lo: [0.0; 3],
            hi: [0.0; 3],
        });
        let copies = mesh_of.iter().map(|&k| built[k as usize].1).sum();
        let triangles = mesh_of.iter().map(|&k| built[k as usize].0.len()).sum();
        Self {
            meshes: built.into_iter().map(|(b, _)| b).collect(),
            placed,
            top,
            world,
            copies,
            triangles,
        }
    }

    /// Triangles left out as copies of an earlier one in their mesh, over all placements.
    pub fn copies_left_out(&self) -> usize {
        self.copies
    }

    /// How many triangles it answers for.
    pub fn triangle_count(&self) -> usize {
        self.triangles
    }

    /// Bytes held: the meshes' hierarchies once, the instances and the top hierarchy.
    pub fn memory_bytes(&self) -> usize {
        self.meshes.iter().map(Bvh::memory_bytes).sum::<usize>()
            + self.placed.len() * std::mem::size_of::<Placed>()
            + self.top.memory_bytes()
    }

    /// Visits the instances whose world box the ray may reach before t_far, and in each the
    /// mesh leaves the carried ray may reach: `leaf(placement, its mesh's hierarchy, the
    /// leaf's item range in it, t_far)` per leaf returns the new t_far and whether to stop.
    fn walk(
        &self,
        ray: &Ray,
        (tmin, tmax): (f32, f32),
        exact: bool,
        mut leaf: impl FnMut(&Placed, &Bvh, std::ops::Range<usize>, f32) -> (f32, bool),
    ) {
        if !exact {
            return self.walk_from(ray, (tmin, tmax), 0.0, leaf);
        }
        // (For the exact queries, a ray from far away walks from just before the instances:
        // carried from there, its pad stays a rounding of the scene's size, not its own.)
        match approach(&self.world, ray, (tmin, tmax)) {
            Approached::AsItIs => self.walk_from(ray, (tmin, tmax), 0.0, leaf),
            Approached::Misses => {}
            Approached::Moved(a) => {
                self.walk_from(&a.ray, a.range(tmin, tmax), a.pad, |p, m, items, t_far| {
                    a.visit(t_far, |given| leaf(p, m, items, given))
                })
            }
        }
    }

    /// [`Instances::walk`] for a ray whose points may lie `pad` off the query's in each
    /// coordinate.
    fn walk_from(
        &self,
        ray: &Ray,
        (tmin, tmax): (f32, f32),
        pad: f32,
        mut leaf: impl FnMut(&Placed, &Bvh, std::ops::Range<usize>, f32) -> (f32, bool),
    ) {
        let (_, items) = self.top.triangles();
        let mut stop = false;
        self.top
            .traverse(ray, tmin, tmax, pad, |first, count, t_far| {
                let mut t_far = t_far;
                for &k in &items[first..first + count] {
                    let placed = &self.placed[k as usize];
                    let mesh = &self.meshes[placed.mesh as usize];
                    match placed.carry_ray(ray, pad) {
                        Some((obj, pad)) => mesh.traverse(&obj, tmin, t_far, pad, |f, c, tf| {
                            (t_far, stop) = leaf(placed, mesh, f..f + c, tf);
                            (t_far, stop)
                        }),
                        None => (t_far, stop) = leaf(placed, mesh, 0..mesh.len(), t_far),
                    }
                    if stop {
                        break;
                    }
                }
                (t_far, stop)
            });
    }

    /// Offers to `sink` every instanced triangle the 8 rays from `o` (directions `d`) may
    /// reach before their limits, prepared for `o` in the world.
    #[inline(always)]
    pub(crate) fn packet<V: Lanes, S: PacketSink<V>, I: Isa>(
        &self,
        isa: I,
        o: [f32; 3],
        d: &[f32x8; 3],
        sink: &mut S,
    ) {
        let d = each3(|k| V::from_wide(d[k]));
        let slabs = PacketSlabs::<V>::new_in(o, d, self.top.boxes_tame());
        // (A dead shadow lane's direction may be 0: the live lanes.)
        let largest = d[0].abs().max(d[1].abs()).max(d[2].abs());
        let (lo, hi) = (V::splat(CARRY_SAFE.recip()), V::splat(CARRY_SAFE));
        let tame = (largest.simd_ge(lo) & largest.simd_le(hi)).to_bitmask();
        let mut leaves = TopLeaves {
            isa,
            inst: self,
            o,
            lanes_carry: tame & sink.live() == sink.live(),
            slabs: &slabs,
            d: &d,
            block: OriginBlock::default(),
            stack: WideStack::new(),
        };
        self.top.walk_packet(&slabs, 0.0, sink, &mut leaves);
    }
}

/// `instances` without the placements that repeat an earlier one (the same mesh by the same
/// matrix, to the bit; `None` where none does), and how many triangles those held. Such a
/// copy is never the answer, as an exact copy of a triangle is not
/// ([`super::without_copies`]): kept, 100 placements at one spot cost every ray that meets
/// them 100 walks and the exact tie-breaks between them. The order of the rest is unchanged.
fn placements_without_copies(instances: &[Instance]) -> (Option<Vec<Instance>>, usize) {
    let key = |inst: &Instance| {
        let m = inst
            .world_from_object
            .to_cols_array()
            .map(|c| (c + 0.0).to_bits());
        (Arc::as_ptr(&inst.mesh), m)
    };
    let mut seen = std::collections::HashSet::with_capacity(instances.len());
    let first: Vec<bool> = instances.iter().map(|i| seen.insert(key(i))).collect();
    let copies: usize = (instances.iter().zip(&first))
        .filter(|(_, &first)| !first)
        .map(|(i, _)| i.len())
        .sum();
    if first.iter().all(|&f| f) {
        return (None, 0);
    }
    let kept = (instances.iter().zip(&first))
        .filter(|(_, &first)| first)
        .map(|(i, _)| i.clone())
        .collect();
    (Some(kept), copies)
}

impl Layout for Instances {
    fn closest(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, best: &mut Option<Hit>) {
        let far = |best: &Option<Hit>| best.map_or(tmax, |h| h.t.next_up());
        self.walk(ray, (tmin, far(best)), false, |placed, mesh, leaf, _| {
            let (tris, locals) = mesh.triangles();
            for i in leaf {
                let shape = Shape::from(placed.world(&tris[i]));
                if let Some((t, b1, b2)) = shape.intersect(ray, method, tmin, far(best)) {
                    let prim = placed.first_prim + locals[i];
                    merge(best, Some(Hit { t, prim, b1, b2 }));
                }
            }
            (far(best), false)
        });
    }

    fn closest_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &mut Search) {
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        let e = box_extent(ray.o, self.world.lo, self.world.hi);
        self.walk(ray, (tmin, tmax), true, |placed, mesh, leaf, _| {
            let (tris, locals) = mesh.triangles();
            for i in leaf {
                let world = placed.world(&tris[i]);
                let est = classify_f32(r, &world, e);
                if est != Estimate::Miss {
                    search.offer_triangle(placed.first_prim + locals[i], &world, est);
                }
            }
            (search.t_far32(), false)
        });
    }

    fn any(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool {
        let mut hit = false;
        self.walk(ray, (tmin, tmax), false, |placed, mesh, leaf, t_far| {
            let (tris, locals) = mesh.triangles();
            hit = leaf.into_iter().any(|i| {
                placed.first_prim + locals[i] != skip
                    && Shape::from(placed.world(&tris[i]))
                        .intersect(ray, method, tmin, tmax)
                        .is_some()
            });
            (t_far, hit)
        });
        hit
    }

    fn any_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &Search, skip: u32) -> bool {
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        let e = box_extent(ray.o, self.world.lo, self.world.hi);
        let mut hit = false;
        self.walk(ray, (tmin, tmax), true, |placed, mesh, leaf, t_far| {
            let (tris, locals) = mesh.triangles();
            hit = leaf.into_iter().any(|i| {
                placed.first_prim + locals[i] != skip && {
                    let world = placed.world(&tris[i]);
                    search.confirms_triangle(&world, classify_f32(r, &world, e))
                }
            });
            (t_far, hit)
        });
        hit
    }
}

/// The top hierarchy's leaves: instances, each walked in its mesh's frame.
struct TopLeaves<'a, V, I> {
    /// The build the mesh walks are compiled for (one function per build: [`MeshWalk`]).
    isa: I,
    inst: &'a Instances,
    /// The packet in the world, as the top walk tests it.
    slabs: &'a PacketSlabs<V>,
    o: [f32; 3],
    d: &'a [V; 3],
    /// Whether every live lane's largest direction component is within
    /// 2⁻⁶⁰…2⁶⁰ ([`CARRY_SAFE`]).
    lanes_carry: bool,
    /// Where the mesh leaves prepare their triangles.
    block: OriginBlock,
    /// The mesh walks' stack (one walk at a time, inside a visit of the top walk).
    stack: WideStack,
}

impl<V: LaneOps, S: PacketSink<V>, I: Isa> Leaves<V, S> for TopLeaves<'_, V, I> {
    #[inline(always)]
    fn visit(&mut self, sink: &mut S, first: usize, count: usize, lanes: u32) {
        let items = &self.inst.top.triangles().1[first..first + count];
        // A top leaf holds a few instances (3.4 per visit in the bunny field); no lane enters
        // the box of 64% of those the packets visit. The others go nearest box first (a
        // lane's hit there can rule out the boxes behind it), each with the lanes that
        // enter it: found here for the first, tested again for the rest against the limits
        // the walks before them left.
        let mut nearest = [(0.0, 0, 0); MAX_LEAF];
        let mut n = 0;
        for &k in items {
            let (mut t, mut m) = (0.0, lanes & sink.live());
            if self.slabs.trusted {
                let placed = &self.inst.placed[k as usize];
                let t0;
                (m, t0) = self.slabs.enter(&placed.world_box, sink.limit(), m);
                if m == 0 {
                    continue;
                }
                t = V::from_bitmask(m)
                    .bitselect(t0, V::splat(f32::INFINITY))
                    .reduce_min();
            }
            let mut at = n;
            while at > 0 && nearest[at - 1].0 > t {
                nearest[at] = nearest[at - 1];
                at -= 1;
            }
            nearest[at] = (t, k, m);
            n += 1;
        }
        for (i, &(_, k, entered)) in nearest[..n].iter().enumerate() {
            let placed = &self.inst.placed[k as usize];
            let mut only = entered;
            if i > 0 {
                only &= sink.live();
                if self.slabs.trusted {
                    only = self.slabs.enter(&placed.world_box, sink.limit(), only).0;
                }
                if only == 0 {
                    continue;
                }
            }
            self.isa.outline(MeshWalk {
                placed,
                mesh: &self.inst.meshes[placed.mesh as usize],
                o: self.o,
                d: self.d,
                lanes_carry: self.lanes_carry,
                only,
                sink: &mut *sink,
                block: &mut self.block,
                stack: &mut self.stack,
            });
            if sink.live() == 0 {
                return;
            }
        }
    }
}

/// One placed mesh's walk for the lanes `only` of a packet, inside a visit of the walk over
/// the placements: one function per build and sink ([`Isa::outline`]), called from each
/// variant of that walk (inlined into each, it was most of the library's machine code).
struct MeshWalk<'a, V, S> {
    placed: &'a Placed,
    mesh: &'a Bvh,
    o: [f32; 3],
    d: &'a [V; 3],
    lanes_carry: bool,
    only: u32,
    sink: &'a mut S,
    block: &'a mut OriginBlock,
    stack: &'a mut WideStack,
}

impl<V: LaneOps, S: PacketSink<V>> Outlined for MeshWalk<'_, V, S> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        let (placed, mesh, only) = (self.placed, self.mesh, self.only);
        let mut leaves = MeshLeaves {
            placed,
            mesh,
            o: self.o,
            block: self.block,
        };
        let carried = match self.lanes_carry && placed.carries {
            true => placed.carry_origin(self.o),
            false => None,
        };
        match carried {
            // From so far that the pad is a good part of the mesh, the walk would cull
            // nothing: the lanes go to the per-ray walk, which moves up to the scene first.
            Some((_, pad)) if f64::from(pad) > placed.object_max * COARSE_PAD => {
                self.sink.per_ray()
            }
            Some((obj, pad)) => {
                let d = placed.carry_directions(self.d);
                let inner = PacketSlabs::<V>::new_in(obj, d, mesh.boxes_tame());
                mesh.walk_packet_lone(&inner, pad, self.sink, &mut leaves, self.stack, only);
            }
            None => Leaves::<V, S>::visit(&mut leaves, self.sink, 0, mesh.len(), only),
        }
    }
}

/// A mesh hierarchy's leaves: its triangles carried into the world and prepared for `o`.
struct MeshLeaves<'a> {
    placed: &'a Placed,
    mesh: &'a Bvh,
    o: [f32; 3],
    block: &'a mut OriginBlock,
}

impl<V: LaneOps, S: PacketSink<V>> Leaves<V, S> for MeshLeaves<'_> {
    /// Four at a time, prepared in f32 ([`OriginTriangle::new8`], lanes 4–7 repeating 0–3);
    /// a short quad repeats its last triangle. A leaf one lane reaches goes to that lane in
    /// one pass where it decides it; otherwise each triangle goes to every lane, again
    /// prepared in f64 where the f32 bounds would leave a lane undecided (as the BVH's own
    /// leaves do).
    #[inline(always)]
    fn visit(&mut self, sink: &mut S, first: usize, count: usize, lanes: u32) {
        let (tris, locals) = self.mesh.triangles();
        let end = first + count;
        let mut start = first;
        while start < end {
            let [i0, i1, i2, i3] = quad_indices(start, end);
            let place = self.placed;
            let object = [&tris[i0], &tris[i1], &tris[i2], &tris[i3]];
            let first_prim = place.first_prim;
            let p = [
                first_prim + locals[i0],
                first_prim + locals[i1],
                first_prim + locals[i2],
                first_prim + locals[i3],
            ];
            // (The quad's triangles in the build's 8 lanes, whatever the packet's width.)
            OriginTriangle::new8_from_lanes::<V::Eight>(
                place.world_lanes::<V::Eight>(object),
                self.o,
                [p[0], p[1], p[2], p[3], p[0], p[1], p[2], p[3]],
                self.block,
            );
            let n = (end - start).min(4);
            let one_lane = lanes.is_power_of_two()
                && sink.take_block_for_lane(
                    self.block,
                    (1 << n) - 1,
                    lanes.trailing_zeros() as usize,
                );
            if !one_lane {
                for (l, v) in object.iter().enumerate().take(n) {
                    if !sink.take_decided(&self.block.get(l)) {
                        sink.take_precise(&precise(place, v, self.o, p[l]));
                    }
                }
            }
            start += 4;
        }
    }
}

/// Object triangle `v` placed in the world and prepared for `o` in f64
/// ([`PreciseTriangle`]), for the rays the f32 preparation leaves undecided (rare: out of
/// the way of the kernels).
#[cold]
#[inline(never)]
fn precise(place: &Placed, v: &[[f32; 3]; 3], o: [f32; 3], prim: u32) -> PreciseTriangle {
    PreciseTriangle::new(&place.world(v), o, prim)
}

#[cfg(feature = "unit-tests")]
#[deny(dead_code)]
pub(crate) mod tests {
    use super::*;

    /// `world_lanes` gives `world`'s bits in every lane, in both builds, on random placements
    /// and triangles with huge, tiny, signed-zero and non-finite coordinates.
    #[allow(unsafe_code)]
    fn world_lanes_are_world_bit_for_bit() {
        #[cfg(target_arch = "x86_64")]
        crate::math::simd::avx2_features! {
            fn avx(p: &Placed, t: [&[[f32; 3]; 3]; 4]) -> [[[f32; 8]; 3]; 3] {
                let w = p.world_lanes::<crate::math::lanes::Avx8>(t);
                w.map(|v| v.map(|c| c.to_array()))
            }
        }
        let mut seed = 7u64;
        let mut next = |scale: f64| {
            let r = crate::math::xorshift(&mut seed);
            ((r >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * scale
        };
        let special = [0.0, -0.0, 1e-45, -3e38, 3e38, f32::INFINITY, f32::NAN, 1.0];
        // Case 0: x·c₀ and y·c₁ cancel exactly, so only glam's order ((x·c₀ + y·c₁) + z·c₂)
        // keeps z·c₂ (a shear; every other case a placement T·R·S).
        let shear = DMat4::from_cols(
            glam::DVec4::new(1.0, 1.0, 1.0, 0.0),
            glam::DVec4::new(-1.0, -1.0, -1.0, 0.0),
            glam::DVec4::new(1.0, 1.0, 1.0, 0.0),
            glam::DVec4::W,
        );
        for case in 0..300usize {
            let scale = 10f64.powi((case % 7) as i32 - 3);
            let m = match case {
                0 => shear,
                _ => DMat4::from_scale_rotation_translation(
                    DVec3::new(next(2.0), next(2.0), next(2.0)),
                    glam::DQuat::from_euler(glam::EulerRot::XYZ, next(3.0), next(3.0), next(3.0)),
                    DVec3::new(next(1e3), next(1.0), next(1e-3)),
                ),
            };
            let placed = Placed {
                mesh: 0,
                world_from_object: m,
                object_from_world: m.inverse(),
                to_object32: [[0.0; 4]; 3],
                c_norm: 1.0,
                carries: true,
                object_max: 1.0,
                world_max: 1.0,
                first_prim: 0,
                world_box: Aabb {
                    lo: [0.0; 3],
                    hi: [0.0; 3],
                },
            };
            let tris: [[[f32; 3]; 3]; 4] = std::array::from_fn(|i| {
                std::array::from_fn(|j| {
                    std::array::from_fn(|k| match (case + i + j + k) % 11 {
                        0 => special[(case + j) % special.len()],
                        _ => next(scale) as f32,
                    })
                })
            });
            let mut tris = tris;
            if case == 0 {
                tris[1][2] = [1e20, 1e20, 1.0];
            }
            let t = [&tris[0], &tris[1], &tris[2], &tris[3]];
            let want: Vec<[[f32; 3]; 3]> = tris.iter().map(|v| placed.world(v)).collect();
            let mut builds = vec![placed
                .world_lanes::<f32x8>(t)
                .map(|v| v.map(|c| c.to_array()))];
            #[cfg(target_arch = "x86_64")]
            if crate::math::simd::has_avx2() {
                // SAFETY: the CPU has AVX2 and FMA.
                builds.push(unsafe { avx(&placed, t) });
            }
            for got in &builds {
                for l in 0..8 {
                    for j in 0..3 {
                        for k in 0..3 {
                            assert_eq!(
                                got[j][k][l].to_bits(),
                                want[l % 4][j][k].to_bits(),
                                "lane {l} vertex {j} coordinate {k}: {:?} by {m:?}",
                                tris[l % 4]
                            );
                        }
                    }
                }
            }
        }
    }

    /// This module's tests, for tests/unit.rs to run.
    pub(crate) const TESTS: &[(&str, fn())] = &[(
        "world_lanes_are_world_bit_for_bit",
        world_lanes_are_world_bit_for_bit,
    )];
}
