//! The reference loop: every ray against every primitive, in primitive order. Every faster
//! path is tested against it, as a layout too ([`InOrder`], in `accel::testing::layouts`).

use super::layout::{merge, Layout};
use crate::geometry::adaptive::{widen, Estimate, Search};
use crate::geometry::triangle::WatertightRay;
use crate::geometry::{Hit, Method, Ray, Shape};
use crate::math::Real;

/// Primitives with their indices, tested one by one through the shape's own methods; with the
/// exact method every one goes to the exact search unfiltered.
#[derive(Clone, Debug, Default)]
pub struct InOrder(pub Vec<(Shape<f32>, u32)>);

/// [`Layout::closest`] over `shapes` (with their primitive indices) one by one, through the
/// shape's own test.
pub(crate) fn closest_one_by_one(
    shapes: impl IntoIterator<Item = (Shape<f32>, u32)>,
    ray: &Ray,
    method: Method,
    tmin: f32,
    tmax: f32,
    best: &mut Option<Hit>,
) {
    for (shape, prim) in shapes {
        let t_far = best.map_or(tmax, |h| h.t.next_up());
        if let Some((t, b1, b2)) = shape.intersect(ray, method, tmin, t_far) {
            merge(best, Some(Hit { t, prim, b1, b2 }));
        }
    }
}

/// [`Layout::any`] over `shapes` (with their primitive indices) one by one.
pub(crate) fn any_one_by_one(
    mut shapes: impl Iterator<Item = (Shape<f32>, u32)>,
    ray: &Ray,
    method: Method,
    tmin: f32,
    tmax: f32,
    skip: u32,
) -> bool {
    shapes.any(|(shape, prim)| prim != skip && shape.intersect(ray, method, tmin, tmax).is_some())
}

impl Layout for InOrder {
    fn closest(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, best: &mut Option<Hit>) {
        closest_one_by_one(self.0.iter().copied(), ray, method, tmin, tmax, best);
    }

    fn closest_exact(&self, _: &Ray, _: &WatertightRay<f32>, search: &mut Search) {
        for (shape, prim) in &self.0 {
            search.offer_shape(*prim, widen(shape), Estimate::Unsure);
        }
    }

    fn any(&self, ray: &Ray, method: Method, tmin: f32, tmax: f32, skip: u32) -> bool {
        any_one_by_one(self.0.iter().copied(), ray, method, tmin, tmax, skip)
    }

    fn any_exact(&self, _: &Ray, _: &WatertightRay<f32>, search: &Search, skip: u32) -> bool {
        let nearest = search.checker();
        (self.0.iter())
            .any(|(shape, prim)| *prim != skip && nearest.confirms(widen(shape), Estimate::Unsure))
    }
}

/// Nearest hit over a slice of shapes by brute force; ties go to the lower index.
pub fn closest_hit<T: Real>(
    shapes: &[Shape<T>],
    ray: &Ray<T>,
    method: Method,
    tmin: T,
    tmax: T,
) -> Option<Hit<T>> {
    if method == Method::Adaptive {
        return crate::geometry::adaptive::closest_hit_reference(shapes, ray, tmin, tmax).map(
            |h| Hit {
                t: T::of(h.t),
                prim: h.prim,
                b1: T::of(h.b1),
                b2: T::of(h.b2),
            },
        );
    }
    let mut best: Option<Hit<T>> = None;
    let mut t_far = tmax;
    for (i, s) in shapes.iter().enumerate() {
        if let Some((t, b1, b2)) = s.intersect(ray, method, tmin, t_far) {
            t_far = t;
            best = Some(Hit {
                t,
                prim: i as u32,
                b1,
                b2,
            });
        }
    }
    best
}

/// Whether a shape other than primitive `skip` (u32::MAX: none) is hit with tmin < t < tmax (a
/// shadow query). `skip` is the surface a shadow ray leaves: if it is a triangle, its exact
/// copies (the same vertices in the same order) are the same surface and are ignored too, as
/// the accelerators, which keep one of them, do.
pub fn any_hit<T: Real>(
    shapes: &[Shape<T>],
    ray: &Ray<T>,
    method: Method,
    tmin: T,
    tmax: T,
    skip: u32,
) -> bool {
    let own = shapes.get(skip as usize).filter(|s| s.is_triangle());
    shapes.iter().enumerate().any(|(i, s)| {
        i as u32 != skip && Some(s) != own && s.intersect(ray, method, tmin, tmax).is_some()
    })
}
