//! Exact answers for one ray a packet left ambiguous ([`closest_exact_lane`],
//! [`any_exact_lane`]): the f32 tests where they are certain, exact signs and plane sides
//! where not. Apart from the packets: one ray at a time, in f64 and expansions, off the hot
//! path.

use super::{OriginTriangle, EDGE_ABS, MAX_PRODUCT};
use crate::geometry::exact;
use std::cmp::Ordering;

/// The exact nearest of `tris` (prepared for origin `o`) along direction `d` for
/// 0 < t < ∞, for a ray the packet kernel left ambiguous: `Some(None)` for a miss,
/// `Some(Some(prim))`, or `None` where this cannot tell (the per-ray search then does).
/// `vertices(prim)` gives a triangle's vertices.
///
/// The kernel's f32 edge tests and t intervals stand where they are certain; an edge sign
/// they leave unsure is computed exactly (expansions, [`exact::orient`]), which settles rays
/// exactly through an edge or vertex. Candidates are ordered by their t intervals where
/// those do not overlap, else by exact plane sides (`nearer`): a quad's two halves (one
/// plane) are hit at the same t, where the lower index wins, as in the per-ray search; of
/// two walls meeting at an edge, the one whose plane the other's crossing point lies behind
/// is nearer. Most ambiguous camera rays of a box-like scene are of those kinds: whole lines
/// of pixel centres run exactly along a wall's diagonal or into the box's corner edges, and
/// the per-ray search costs ~30 times more for each (Cornell box, 1280×720: 160 rays a frame
/// went per ray before the walls' edges were settled here, none now).
///
/// [`exact::orient`]: crate::geometry::exact::orient
pub fn closest_exact_lane(
    tris: &[OriginTriangle],
    vertices: impl Fn(u32) -> [[f32; 3]; 3],
    o: [f32; 3],
    d: [f32; 3],
) -> Option<Option<u32>> {
    let lane = ExactLane::new(o, d)?;
    // Each triangle certainly hit in front, with its t interval.
    let mut hits: Vec<LaneHit> = Vec::new();
    for tri in tris {
        let v = vertices(tri.prim);
        let (crossing, weighs) = lane.crossing_where(tri, &v)?;
        if crossing != Crossing::Front {
            continue;
        }
        let (lo, hi) = lane.t_interval(tri)?;
        hits.push(LaneHit {
            prim: tri.prim,
            lo,
            hi,
            v,
            weighs,
        });
    }
    let Some(first) = hits.iter().min_by(|a, b| a.hi.total_cmp(&b.hi)) else {
        return Some(None);
    };
    // The nearest of those that may be as near as `first` (the others are certainly
    // farther), ties to the lower index: (t, prim) is a total order, so one pass does.
    let mut best = first;
    for hit in &hits {
        if hit.prim == first.prim || hit.lo > first.hi {
            continue;
        }
        best = match nearer(&lane.o, best, hit)? {
            Ordering::Less => best,
            Ordering::Greater => hit,
            Ordering::Equal if hit.prim < best.prim => hit,
            Ordering::Equal => best,
        };
    }
    Some(Some(best.prim))
}

/// A triangle an ambiguous lane certainly crosses in front ([`closest_exact_lane`]).
struct LaneHit {
    prim: u32,
    /// Bounds on t.
    lo: f32,
    hi: f32,
    v: [[f32; 3]; 3],
    /// Which vertices weigh in the crossing point ([`ExactLane::crossing_where`]).
    weighs: [bool; 3],
}

/// How `a`'s t compares with `b`'s along the lane from `o` (both crossed in front), exactly,
/// without computing t: `None` where this cannot tell.
///
/// The lane crosses a's plane once, at t_a, with `o` strictly on one side; a point of the
/// lane is on `o`'s side exactly when its t is below t_a. b's crossing point is a mix of
/// b's weighing vertices, so where those lie on one side of a's plane (or on it) so does
/// the point: on `o`'s side, t_b < t_a; on the other, t_b > t_a; on the plane, the same t
/// (a coplanar pair, or a ray through the edge two triangles share). Where b's vertices
/// straddle a's plane, the same with the roles swapped.
fn nearer(o: &[f64; 3], a: &LaneHit, b: &LaneHit) -> Option<Ordering> {
    if let Some(side) = side_of_crossing(b, &a.v)? {
        return Some(compare_from(o, &a.v, side)?.reverse());
    }
    compare_from(o, &b.v, side_of_crossing(a, &b.v)??)
}

/// t of the lane's crossing point on `hit` against t of its crossing with plane `v`, given
/// the side of `v`'s plane that point lies on: `Less` where it is nearer.
fn compare_from(o: &[f64; 3], v: &[[f32; 3]; 3], side: Ordering) -> Option<Ordering> {
    let own = exact::plane_side(v, *o)?;
    match (side, own) {
        (_, Ordering::Equal) => None,
        (Ordering::Equal, _) => Some(Ordering::Equal),
        _ if side == own => Some(Ordering::Less),
        _ => Some(Ordering::Greater),
    }
}

/// The side of plane `v` that `hit`'s crossing point lies on: `Some(None)` where its
/// weighing vertices straddle the plane (the point may lie either side).
fn side_of_crossing(hit: &LaneHit, v: &[[f32; 3]; 3]) -> Option<Option<Ordering>> {
    let mut side = Ordering::Equal;
    for (p, weighs) in hit.v.iter().zip(hit.weighs) {
        if !weighs {
            continue;
        }
        // (A shared vertex is on the plane: the usual case, and the expansions' slowest.)
        let on = match v.contains(p) {
            true => Ordering::Equal,
            false => exact::plane_side(v, p.map(f64::from))?,
        };
        match (side, on) {
            (_, Ordering::Equal) => {}
            (Ordering::Equal, s) => side = s,
            (s, t) if s != t => return Some(None),
            _ => {}
        }
    }
    Some(Some(side))
}

/// Whether the segment from `o` (the origin `tris` were prepared for) to o + d is blocked
/// for 0 < t < 1 by one of `tris` other than `skip`, for a shadow ray
/// [`packet::any`](super::any) left unsure; `None` where this cannot tell (the per-ray search then
/// does). Edge signs as in [`closest_exact_lane`]; t against 1 by the f32 interval where it
/// decides, else exactly: the end o + d (exact in f64) lies strictly on the other side of
/// the triangle's plane than o. That settles the usual case, the other half of the quad a
/// shadow ray's end point was offset from (t within rounding of 1).
///
/// [`any`]: super::any
pub fn any_exact_lane(
    tris: &[OriginTriangle],
    vertices: impl Fn(u32) -> [[f32; 3]; 3],
    o: [f32; 3],
    d: [f32; 3],
    skip: u32,
) -> Option<bool> {
    let lane = ExactLane::new(o, d)?;
    let mut end = [0.0; 3];
    for ((end, o), d) in end.iter_mut().zip(lane.o).zip(lane.d) {
        let (sum, err) = exact::two_sum(o, d);
        if err != 0.0 {
            return None;
        }
        *end = sum;
    }
    for tri in tris.iter().filter(|t| t.prim != skip) {
        let v = vertices(tri.prim);
        if lane.crossing(tri, &v)? != Crossing::Front {
            continue;
        }
        match lane.t_interval(tri) {
            Some((_, hi)) if hi < 1.0 => return Some(true),
            Some((lo, _)) if lo >= 1.0 => continue,
            _ => {}
        }
        let side = |x| exact::plane_side(&v, x);
        let (from, to) = (side(lane.o)?, side(end)?);
        if from == Ordering::Equal {
            return None;
        }
        if to != Ordering::Equal && to != from {
            return Some(true);
        }
    }
    Some(false)
}

/// How the line o + t·d meets a triangle, decided exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Crossing {
    /// Misses it, or crosses its plane at t < 0.
    Away,
    /// Crosses it (interior, edge or vertex) at t > 0.
    Front,
}

/// One ray of a packet, for the exact edge tests of the ambiguous lanes.
pub(super) struct ExactLane {
    d32: [f32; 3],
    /// max|dₖ| rounded up.
    pub(super) dm: f32,
    o: [f64; 3],
    d: [f64; 3],
}

impl ExactLane {
    pub(super) fn new(o: [f32; 3], d: [f32; 3]) -> Option<Self> {
        let dm = d.iter().fold(0f32, |m, c| m.max(c.abs())) * (1.0 + 1e-6);
        if !dm.is_finite() || d.iter().any(|c| c.is_nan()) || o.iter().any(|c| !c.is_finite()) {
            return None;
        }
        Some(Self {
            d32: d,
            dm,
            o: o.map(f64::from),
            d: d.map(f64::from),
        })
    }

    /// The kernel's edge tests where certain, exact signs ([`exact::orient`]) where not.
    pub(super) fn crossing(&self, tri: &OriginTriangle, v: &[[f32; 3]; 3]) -> Option<Crossing> {
        self.crossing_where(tri, v).map(|(crossing, _)| crossing)
    }

    /// [`ExactLane::crossing`] with which of the triangle's vertices weigh in the crossing
    /// point (barycentric weight > 0: the edge opposite vertex i has a nonzero sign; on an
    /// edge or at a vertex the others weigh nothing).
    fn crossing_where(
        &self,
        tri: &OriginTriangle,
        v: &[[f32; 3]; 3],
    ) -> Option<(Crossing, [bool; 3])> {
        if !tri.usable || tri.n_max * self.dm >= MAX_PRODUCT {
            return None;
        }
        let d = self.d32;
        let mut sign = [0i8; 3];
        for i in 0..3 {
            let n = &tri.n[i];
            let e = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
            let bound = tri.k[i] * self.dm + EDGE_ABS;
            sign[i] = if e > bound {
                1
            } else if e < -bound {
                -1
            } else {
                let (a, b) = (v[(i + 1) % 3].map(f64::from), v[(i + 2) % 3].map(f64::from));
                match exact::orient(self.d, self.o, a, b)? {
                    Ordering::Greater => 1,
                    Ordering::Less => -1,
                    Ordering::Equal => 0,
                }
            };
        }
        let weighs = sign.map(|s| s != 0);
        if sign.contains(&1) && sign.contains(&-1) {
            return Some((Crossing::Away, weighs));
        }
        let s = sign.iter().sum::<i8>().signum();
        if s == 0 {
            return None; // all three zero: the line lies in the triangle's plane
        }
        // In front where det (of the eᵢ's sign) and the numerator agree.
        let crossing = match (tri.num > 0.0) == (s > 0) {
            true => Crossing::Front,
            false => Crossing::Away,
        };
        Some((crossing, weighs))
    }

    /// t's interval for a triangle crossed in front, as `PacketNearest::offer` bounds it
    /// (`None` where that bound is loose).
    fn t_interval(&self, tri: &OriginTriangle) -> Option<(f32, f32)> {
        let d = self.d32;
        let e = tri.n.map(|n| d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
        let n = tri.normal;
        let (det, bound) = match tri.det_from_normal {
            false => (e[0] + e[1] + e[2], tri.k_sum * self.dm + 3.0 * EDGE_ABS),
            true => (
                d[0] * n[0] + d[1] * n[1] + d[2] * n[2],
                tri.k_det * self.dm + EDGE_ABS,
            ),
        };
        let rcp = 1.0 / det;
        let t = tri.num * rcp;
        let r_det = (bound * 1.0001) * rcp.abs();
        if r_det.is_nan() || r_det > 0.25 {
            return None;
        }
        let err = t.abs() * (tri.c_t + 1.4 * r_det) + 1e-37;
        Some((t - err, t + err))
    }
}
