//! Culling for the tiles of a frame over a small scene: which triangles can show in a screen
//! tile (camera rays) and which can block a tile's shadow segments. Both keep every triangle
//! that can answer, so a culled query gives exactly the answer over all triangles.

use super::IndexedTriangle;
use crate::camera::Projection;

/// Where a triangle can appear on screen: its projection's bounding rectangle and edge
/// lines, widened by a pixel for rounding. A camera ray through image position (x, y) can only
/// hit a triangle in front of the pinhole whose projection (a triangle) holds (x, y).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ScreenTriangle {
    /// x0, y0, x1, y1.
    bounds: [f32; 4],
    /// a·x + b·y + c ≥ −1 (a, b unit) on the triangle's side of each edge, for each edge.
    edges: [[f64; 3]; 3],
}

impl ScreenTriangle {
    /// `None` where a vertex is not in front of the camera (such a triangle is kept for
    /// every tile), unless every vertex is behind it ([`Projection::behind`]): then no tile
    /// (a camera facing away from the scene tested every triangle in every tile).
    pub(crate) fn new(v: &[[f32; 3]; 3], projection: &Projection) -> Option<Self> {
        if v.iter().all(|p| projection.behind(*p)) {
            return Some(Self {
                bounds: NOWHERE,
                edges: [[0.0, 0.0, 1.0]; 3],
            });
        }
        let mut q = [[0.0f64; 2]; 3];
        for (p, s) in v.iter().zip(&mut q) {
            *s = projection.project(*p)?;
        }
        let lo = [0, 1].map(|k| q[0][k].min(q[1][k]).min(q[2][k]) as f32 - 1.0);
        let hi = [0, 1].map(|k| q[0][k].max(q[1][k]).max(q[2][k]) as f32 + 1.0);
        let area =
            (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
        let side = if area < 0.0 { -1.0 } else { 1.0 };
        let edges = [0, 1, 2].map(|i| {
            let (p, r) = (q[i], q[(i + 1) % 3]);
            let (a, b) = (-(r[1] - p[1]) * side, (r[0] - p[0]) * side);
            let len = a.hypot(b);
            if len.is_nan() || len <= 1e-9 || !area.is_finite() || area == 0.0 {
                // Seen edge-on or degenerate on screen: the rectangle alone decides.
                return [0.0, 0.0, 1.0];
            }
            let (a, b) = (a / len, b / len);
            [a, b, -(a * p[0] + b * p[1])]
        });
        Some(Self {
            bounds: [lo[0], lo[1], hi[0], hi[1]],
            edges,
        })
    }

    /// Whether the triangle may show in the rectangle [x0, x1] × [y0, y1].
    #[inline]
    pub(crate) fn meets(&self, x0: f32, y0: f32, x1: f32, y1: f32) -> bool {
        let b = &self.bounds;
        if b[2] < x0 || b[0] > x1 || b[3] < y0 || b[1] > y1 {
            return false;
        }
        self.edges.iter().all(|[a, bb, c]| {
            // The rectangle's corner farthest along the edge's inward normal.
            let x = if *a > 0.0 { x1 } else { x0 } as f64;
            let y = if *bb > 0.0 { y1 } else { y0 } as f64;
            a * x + bb * y + c >= -1.0
        })
    }
}

/// The screen rectangle (x0, y0, x1, y1) of what lies behind the camera: it meets no tile.
const NOWHERE: [f32; 4] = [
    f32::INFINITY,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
];

/// A triangle that may block shadow rays, with its bounding box and its position among the
/// scene's triangles.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Occluder {
    pub slot: u32,
    pub bounds: Box3,
}

impl Occluder {
    pub(crate) fn new(slot: usize, (v, _): &IndexedTriangle) -> Self {
        Self {
            slot: slot as u32,
            bounds: Box3 {
                lo: [0, 1, 2].map(|k| v[0][k].min(v[1][k]).min(v[2][k])),
                hi: [0, 1, 2].map(|k| v[0][k].max(v[1][k]).max(v[2][k])),
            },
        }
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Box3 {
    pub lo: [f32; 3],
    pub hi: [f32; 3],
}

impl Box3 {
    /// The part of [t0, t1] along which a ray (origin `o`, inverse direction `inv` in f64)
    /// lies within the box widened by `pad`, in f64 and widened by 2⁻²⁰ relative: every f32
    /// input and its inverse direction are f64 values far from f64's limits, so the distances
    /// are within a few f64 roundings of exact and the interval holds every exact crossing.
    /// Empty where t0 > t1.
    pub(crate) fn slab_interval_f64(
        &self,
        pad: f32,
        o: [f32; 3],
        inv: &[f64; 3],
        (mut t0, mut t1): (f64, f64),
    ) -> (f64, f64) {
        const WIDEN: f64 = 1.0 / (1u64 << 20) as f64;
        let pad = f64::from(pad);
        for (k, &inv) in inv.iter().enumerate() {
            let (lo, hi) = (f64::from(self.lo[k]) - pad, f64::from(self.hi[k]) + pad);
            let (near, far) = if inv < 0.0 { (hi, lo) } else { (lo, hi) };
            let o = f64::from(o[k]);
            let (tn, tf) = ((near - o) * inv, (far - o) * inv);
            // f64::min/max ignore a NaN (0·∞ for a ray in a slab's plane): conservative.
            t0 = t0.max(tn - tn.abs() * WIDEN);
            t1 = t1.min(tf + tf.abs() * WIDEN);
        }
        (t0, t1)
    }

    /// Whether the box meets [lo, hi] widened by 1e-6 relative (plus 1e-30): a box built
    /// from segment ends computed in f32 (origin + direction, rounded) then holds the exact
    /// segments.
    pub(crate) fn meets(&self, lo: [f32; 3], hi: [f32; 3]) -> bool {
        let slack = |x: f32| x.abs() * 1e-6 + 1e-30;
        (0..3).all(|k| !(self.hi[k] < lo[k] - slack(lo[k]) || self.lo[k] > hi[k] + slack(hi[k])))
    }
}

/// Where a box (of a hierarchy's node) can appear on screen: the rectangle of its projection
/// widened by a pixel (`None`: the box reaches behind the pinhole, so it may cover any tile;
/// [`NOWHERE`] where it lies wholly behind, [`Projection::behind`]).
/// A camera ray through a tile the rectangle does not meet cannot hit what the box holds
/// (the box is convex).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ScreenBox {
    screen: Option<[f32; 4]>,
}

impl ScreenBox {
    /// `projection` `None`: no culling, the shape may show in any tile.
    pub(crate) fn new((lo, hi): ([f32; 3], [f32; 3]), projection: Option<&Projection>) -> Self {
        let Some(projection) = projection else {
            return Self { screen: None };
        };
        let corners = (0..8).map(|corner: usize| {
            [0, 1, 2].map(|k| if corner & (1 << k) == 0 { lo[k] } else { hi[k] })
        });
        if corners.clone().all(|p| projection.behind(p)) {
            return Self {
                screen: Some(NOWHERE),
            };
        }
        let mut screen = Some(NOWHERE);
        for p in corners {
            screen = match (screen, projection.project(p)) {
                (Some(r), Some([x, y])) => Some([
                    r[0].min(x as f32 - 1.0),
                    r[1].min(y as f32 - 1.0),
                    r[2].max(x as f32 + 1.0),
                    r[3].max(y as f32 + 1.0),
                ]),
                _ => None,
            };
        }
        Self { screen }
    }

    /// Whether what the box holds may show in the rectangle [x0, x1] × [y0, y1].
    pub(crate) fn meets_tile(&self, x0: f32, y0: f32, x1: f32, y1: f32) -> bool {
        self.screen
            .is_none_or(|r| !(r[2] < x0 || r[0] > x1 || r[3] < y0 || r[1] > y1))
    }
}

/// The top levels of a hierarchy of boxes on screen ([`ScreenBox`] per node). A tile may
/// show a primitive only where some node without children (a leaf, or a node at the cut)
/// has a rectangle meeting it, found by descending only into nodes whose rectangle meets it:
/// every primitive lies in such a node's box. Far tighter than the root's rectangle around a
/// mesh's silhouette.
#[derive(Clone, Debug)]
pub(crate) struct ScreenTree {
    /// Breadth first from the root.
    nodes: Vec<ScreenNode>,
}

#[derive(Clone, Copy, Debug)]
struct ScreenNode {
    cull: ScreenBox,
    /// Positions of the children in the list: the first, and how many.
    children: Option<(u32, u32)>,
}

/// The nodes of a [`ScreenTree`] as given: box (lo, hi), and the children's positions (the
/// first, and how many; after their parent).
pub(crate) type TreeNode = (([f32; 3], [f32; 3]), Option<(u32, u32)>);

impl ScreenTree {
    /// From the nodes of a hierarchy's top levels, breadth first from the root: projected
    /// in parallel (585 boxes of 8 corners for a mesh, before any tile can start: 4.8% of
    /// the bunny's flat frame at 320×180 on one thread, in a sampling profile).
    pub(crate) fn new(nodes: Vec<TreeNode>, projection: Option<&Projection>) -> Self {
        use rayon::prelude::*;
        Self {
            nodes: (nodes.into_par_iter())
                .with_min_len(64)
                .map(|(b, children)| ScreenNode {
                    cull: ScreenBox::new(b, projection),
                    children,
                })
                .collect(),
        }
    }

    /// Whether a primitive may show in the tile [x0, x1] × [y0, y1].
    pub(crate) fn may_show(&self, [x0, y0, x1, y1]: [f32; 4]) -> bool {
        let mut todo: Vec<u32> = Vec::with_capacity(32);
        if !self.nodes.is_empty() {
            todo.push(0);
        }
        while let Some(i) = todo.pop() {
            let n = &self.nodes[i as usize];
            if !n.cull.meets_tile(x0, y0, x1, y1) {
                continue;
            }
            match n.children {
                Some((first, count)) => todo.extend(first..first + count),
                None => return true,
            }
        }
        false
    }
}
