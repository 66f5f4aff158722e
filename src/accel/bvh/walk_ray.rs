//! The walk of one ray ([`Bvh::traverse`]) and the per-ray queries on it: nearest hit and
//! any hit, for every method, and the adaptive search's f32 level from triangles prepared for
//! the ray's origin.

use super::approach::{approach, Approached};
use super::leaf_triangles::LeafTriangles;
use super::node::{leaf_range, WideNode, WideStack, LEAF, NONE, WIDTH};
use super::slabs::{box_safe, enter_f64, slab_safe, RaySlabs};
use super::Bvh;
use crate::accel::layout::{merge, Layout};
use crate::accel::packet::PacketSink;
use crate::accel::prepared::Prepared;
use crate::geometry::adaptive::{box_extent, classify_f32, round_down, Estimate, Search};
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray, Shape};
use crate::math::lanes::{f32x8, LaneOps};

impl Bvh {
    /// The adaptive filter's M for this ray, from the root box (once per ray: per leaf it
    /// cost more than its tighter bound saved).
    fn extent(&self, ray: &Ray) -> f32 {
        match self.wide.is_empty() {
            true => f32::INFINITY,
            false => box_extent(ray.o, self.bounds.lo, self.bounds.hi),
        }
    }

    /// [`Layout::closest_exact`] for a ray leaving the origin `prepared` was made for
    /// (from [`Bvh::triangles`]): the f32 level is the shared-origin test of
    /// [`super::packet`], three dot products per triangle instead of the sheared test.
    ///
    /// [`super::packet`]: crate::accel::packet
    pub(crate) fn closest_from_origin(
        &self,
        ray: &Ray,
        prepared: Prepared<'_>,
        search: &mut Search,
    ) {
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        let d_max = ray.d.iter().fold(0.0f32, |m, c| m.max(c.abs()));
        let d_max = if ray.d.iter().any(|c| c.is_nan()) {
            f32::NAN
        } else {
            d_max
        };
        let mut scratch = None;
        self.traverse_exact(ray, tmin, tmax, |first, count, _| {
            let leaf = first..first + count;
            // (Per ray for the lanes packets leave ambiguous: the baseline lanes, the same bits.)
            let tris =
                self.leaf_triangles::<f32x8>(prepared, first, first + count, ray.o, &mut scratch);
            for (j, (tri, prim)) in (self.tris[leaf.clone()].iter())
                .zip(&self.prims[leaf])
                .enumerate()
            {
                let est = match tris {
                    LeafTriangles::Listed(list) => list[j].estimate(ray.d, d_max),
                    LeafTriangles::Leaf { .. } | LeafTriangles::Blocks { .. } => {
                        match tris.get(j).estimate(ray.d, d_max) {
                            Estimate::Unsure => self
                                .precise(first + j, ray.o)
                                .rounded
                                .estimate(ray.d, d_max),
                            est => est,
                        }
                    }
                };
                if est != Estimate::Miss {
                    search.offer_triangle(*prim, tri, est);
                }
            }
            (search.t_far32(), false)
        });
    }

    /// Visits the leaves the ray may reach, nearer child first, every box widened by `pad`
    /// on each side (0 but for a mesh's hierarchy walked in its own frame by a ray carried
    /// there with rounding, see `accel::instances`). `leaf(first, count, t_far)` returns the
    /// new t_far and whether to stop.
    pub(crate) fn traverse(
        &self,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        pad: f32,
        leaf: impl FnMut(usize, usize, f32) -> (f32, bool),
    ) {
        self.traverse_padded(ray, (tmin, tmax), (pad, |_| pad), leaf);
    }

    /// [`Bvh::traverse`] for the exact queries: a ray from far away walks moved up to the
    /// hierarchy's box ([`approach`]), its leaves visited with distances on the given ray.
    pub(crate) fn traverse_exact(
        &self,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        mut leaf: impl FnMut(usize, usize, f32) -> (f32, bool),
    ) {
        match approach(&self.bounds, ray, (tmin, tmax)) {
            Approached::AsItIs => self.traverse(ray, tmin, tmax, 0.0, leaf),
            Approached::Misses => {}
            Approached::Moved(a) => {
                let (tmin, tmax) = a.range(tmin, tmax);
                self.traverse(&a.ray, tmin, tmax, a.pad, |first, count, t_far| {
                    a.visit(t_far, |given| leaf(first, count, given))
                });
            }
        }
    }

    /// [`Bvh::traverse`] with each node's children widened by `pad_of(node)`, never more
    /// than `pad` (which decides the slab test's precision): the spheres' pad, which grows
    /// with the size of the coordinates under the node.
    #[inline]
    pub(crate) fn traverse_padded(
        &self,
        ray: &Ray,
        (tmin, tmax): (f32, f32),
        (pad, pad_of): (f32, impl Fn(usize) -> f32),
        mut leaf: impl FnMut(usize, usize, f32) -> (f32, bool),
    ) {
        if self.wide.is_empty() {
            return;
        }
        // The f32 test widens far distances by a factor, which widens only a positive t: an
        // interval reaching behind the origin (tmin < 0) takes the f64 test, which widens by
        // |t| (a flat box at tmin < t < 0 was skipped).
        let in_f32 = tmin >= 0.0
            && self.tame
            && (ray.o.iter().chain(&ray.d)).all(|&x| slab_safe(x))
            && box_safe(pad);
        let inv = ray.d.map(|c| 1.0 / c);
        let slabs = RaySlabs {
            o: ray.o,
            inv,
            near_hi: inv.map(|c| c < 0.0),
            tmin,
            pad,
        };
        // Only the f64 test needs these divisions.
        let inv64 = (!in_f32).then(|| ray.d.map(|c| 1.0 / f64::from(c)));
        let enter = |n: &WideNode, limit: f32, pad: f32| -> (u32, [f32; WIDTH]) {
            let Some(inv64) = &inv64 else {
                return RaySlabs { pad, ..slabs }.enter(n, limit);
            };
            let mut hits = 0;
            let mut t = [f32::INFINITY; WIDTH];
            for c in (0..WIDTH).take_while(|&c| n.child[c] != NONE) {
                if let Some(t0) = enter_f64(&n.bounds(c), pad, ray, inv64, tmin, limit) {
                    hits |= 1 << c;
                    t[c] = t0;
                }
            }
            (hits, t)
        };
        let mut t_far = tmax;
        // Culling margin against the best hit so far (see the module docs of `bvh`).
        let cull = |t: f32| {
            if t < tmax {
                (t + t.abs() * (1.0 / 65536.0)).min(tmax)
            } else {
                tmax
            }
        };
        let mut stack = WideStack::new();
        let mut top = 0;
        let mut node = 0usize;
        loop {
            let n = &self.wide[node];
            let (hits, t0) = enter(n, cull(t_far), pad_of(node));
            stack.push(&mut top, n, hits, &t0, 1);
            loop {
                let r = stack.pop_above(0, &mut top, cull(t_far));
                if r == NONE {
                    return;
                }
                if r & LEAF == 0 {
                    node = r as usize;
                    break;
                }
                let (first, count) = leaf_range(r);
                let stop;
                (t_far, stop) = leaf(first, count, t_far);
                if stop {
                    return;
                }
            }
        }
    }
}

impl Layout for Bvh {
    fn closest(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, best: &mut Option<Hit>) {
        let mut nearest: Option<Hit> = None;
        self.traverse(ray, tmin, tmax, 0.0, |first, count, t_far| {
            for i in first..first + count {
                let shape = Shape::from(self.tris[i]);
                if let Some((t, b1, b2)) = shape.intersect(ray, method, tmin, t_far) {
                    let prim = self.prims[i];
                    merge(&mut nearest, Some(Hit { t, prim, b1, b2 }));
                }
            }
            // Hits at t equal to the best stay possible (for the index tie-break).
            (nearest.map_or(tmax, |h| h.t.next_up()), false)
        });
        merge(best, nearest);
    }

    fn closest_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &mut Search) {
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        let e = self.extent(ray);
        self.traverse_exact(ray, tmin, tmax, |first, count, _| {
            for i in first..first + count {
                let est = classify_f32(r, &self.tris[i], e);
                if est != Estimate::Miss {
                    search.offer_triangle(self.prims[i], &self.tris[i], est);
                }
            }
            (search.t_far32(), false)
        });
    }

    /// Stops at the first hit.
    fn any(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool {
        let mut hit = false;
        self.traverse(ray, tmin, tmax, 0.0, |first, count, t_far| {
            hit = (first..first + count).any(|i| {
                self.prims[i] != skip
                    && Shape::from(self.tris[i])
                        .intersect(ray, method, tmin, t_far)
                        .is_some()
            });
            (t_far, hit)
        });
        hit
    }

    fn any_exact(&self, ray: &Ray, r: &WatertightRay<f32>, search: &Search, skip: u32) -> bool {
        let mut hit = false;
        let (tmin, tmax) = (round_down(search.tmin()), search.t_far32());
        let e = self.extent(ray);
        self.traverse_exact(ray, tmin, tmax, |first, count, t_far| {
            hit = (first..first + count).any(|i| {
                self.prims[i] != skip
                    && search.confirms_triangle(&self.tris[i], classify_f32(r, &self.tris[i], e))
            });
            (t_far, hit)
        });
        hit
    }

    #[inline(always)]
    fn packet_into<V: LaneOps, S: PacketSink<V>>(
        &self,
        sink: &mut S,
        o: [f32; 3],
        prepared: Prepared<'_>,
        d: [V; 3],
    ) {
        self.walk_into(sink, o, prepared, d);
    }
}
