//! Instances: a mesh stored once and placed in the world by a matrix, as often as a `.scene`
//! file uses it.
//!
//! An instance is only a way of storing: its triangles are, to the last bit, the triangles a
//! `.scene` file would have flattened into the world (each object vertex transformed by the
//! f64 matrix, then rounded to f32: [`Instance::world_vertex`], the same arithmetic as
//! the parser's), and their primitive indices are their places in the file's order. The
//! accelerator ([`crate::accel`]) keeps one hierarchy per mesh in object space and one over
//! the instances, and tests the world triangles it computes at the leaves; every answer
//! equals the flattened scene's.

use crate::math::real::V3;
use glam::{DMat4, DVec3};
use std::sync::Arc;

/// A mesh as loaded once: its triangles in its own (object) frame and their colours.
#[derive(Debug, PartialEq)]
pub struct Mesh {
    /// The file it came from, for messages.
    pub name: String,
    /// Triangles in the mesh's frame, in file order.
    pub triangles: Vec<[[f32; 3]; 3]>,
    /// One linear-RGB colour per triangle, `None` where its material gives none (the
    /// placing statement's current colour then applies).
    pub colors: Vec<Option<V3<f32>>>,
    /// The box around its vertices (object frame).
    bounds: ([f32; 3], [f32; 3]),
    /// Whether some triangle has a colour of its own (else each instance shows one colour).
    own_colors: bool,
}

impl Mesh {
    /// A mesh of `triangles` with one colour each.
    pub fn new(name: String, triangles: Vec<[[f32; 3]; 3]>, colors: Vec<Option<V3<f32>>>) -> Self {
        assert_eq!(triangles.len(), colors.len(), "one colour per triangle");
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for v in triangles.iter().flatten() {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
        }
        let own_colors = colors.iter().any(Option::is_some);
        Self {
            name,
            triangles,
            colors,
            bounds: (lo, hi),
            own_colors,
        }
    }

    /// The box around its vertices in its own frame.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        self.bounds
    }
}

/// Largest condition number ‖A‖∞·‖A⁻¹‖∞ of an instance's linear part: up to it the f64
/// inverse used to carry rays into the mesh's frame is accurate to 2⁻³² (relative), which
/// the accelerator's padding of object-space boxes allows for. A placement beyond it (a
/// scale of 10⁶ on one axis and 10⁻⁶ on another) is flattened instead.
pub const MAX_CONDITION: f64 = (1u64 << 20) as f64;

/// One placement of a mesh: the primitives `first_prim..first_prim + mesh.triangles.len()`.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// The mesh, shared by all its instances.
    pub mesh: Arc<Mesh>,
    /// Object frame to world (the `.scene` stack's matrix at the `mesh` statement).
    pub world_from_object: DMat4,
    /// The primitive index of the mesh's first triangle.
    pub first_prim: u32,
    /// The colour of the mesh's faces without one of their own (the `.scene` file's current
    /// colour at the `mesh` statement).
    pub color: V3<f32>,
    /// A colour replacing the mesh's for this instance (the viewer's highlight), if any.
    pub tint: Option<V3<f32>>,
}

impl Instance {
    /// How many primitives it adds.
    pub fn len(&self) -> usize {
        self.mesh.triangles.len()
    }

    /// Whether the mesh has no triangles.
    pub fn is_empty(&self) -> bool {
        self.mesh.triangles.is_empty()
    }

    /// The primitives it holds.
    pub fn prims(&self) -> std::ops::Range<u32> {
        self.first_prim..self.first_prim + self.len() as u32
    }

    /// An object vertex in the world: the matrix applied in f64, then rounded to f32 (what
    /// the `.scene` parser computes for a flattened mesh).
    #[inline]
    pub fn world_vertex(m: &DMat4, v: [f32; 3]) -> [f32; 3] {
        let w = m.transform_point3(DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64));
        [w.x as f32, w.y as f32, w.z as f32]
    }

    /// Triangle `local` of the mesh in the world.
    #[inline]
    pub fn world_triangle(&self, local: usize) -> [[f32; 3]; 3] {
        // (Written out: as an array `map` its closure was left uninlined in some builds, a
        // third more work on the shading of instanced scenes.)
        let [a, b, c] = self.mesh.triangles[local];
        let m = &self.world_from_object;
        [
            Self::world_vertex(m, a),
            Self::world_vertex(m, b),
            Self::world_vertex(m, c),
        ]
    }

    /// Whether all its triangles show one colour (a tint, or a mesh without colours of its
    /// own).
    pub fn one_color(&self) -> bool {
        self.tint.is_some() || !self.mesh.own_colors
    }

    /// The colour of triangle `local`.
    pub fn color(&self, local: usize) -> V3<f32> {
        (self.tint).unwrap_or(self.mesh.colors[local].unwrap_or(self.color))
    }

    /// Whether `m` can place an instance: finite, affine, invertible and with a condition
    /// number up to [`MAX_CONDITION`].
    pub fn placeable(m: &DMat4) -> bool {
        let affine = m.row(3) == glam::DVec4::new(0.0, 0.0, 0.0, 1.0);
        let inv = m.inverse();
        affine
            && m.is_finite()
            && inv.is_finite()
            && linear_norm(m) * linear_norm(&inv) <= MAX_CONDITION
    }
}

/// A box around instance `inst`'s world triangles: its mesh's box carried into the world
/// (the 8 corners in f64), widened by 2⁻²⁰ of its largest magnitude for the rounding of the
/// world vertices, and rounded outwards to f32.
pub fn world_bounds(inst: &Instance) -> ([f32; 3], [f32; 3]) {
    let (lo, hi) = inst.mesh.bounds();
    if inst.is_empty() {
        return (lo, hi);
    }
    let m = &inst.world_from_object;
    let mut wlo = [f64::INFINITY; 3];
    let mut whi = [f64::NEG_INFINITY; 3];
    for c in 0..8 {
        let p = [0, 1, 2].map(|k| if c & (1 << k) != 0 { hi[k] } else { lo[k] } as f64);
        let w = m.transform_point3(DVec3::from_array(p)).to_array();
        for k in 0..3 {
            wlo[k] = wlo[k].min(w[k]);
            whi[k] = whi[k].max(w[k]);
        }
    }
    let big = (0..3).fold(0f64, |acc, k| acc.max(wlo[k].abs()).max(whi[k].abs()));
    let pad = big * (1.0 / (1u64 << 20) as f64) + f64::from(f32::MIN_POSITIVE);
    let down = |x: f64| {
        let f = x as f32;
        if f as f64 > x {
            f.next_down()
        } else {
            f
        }
    };
    let up = |x: f64| {
        let f = x as f32;
        if (f as f64) < x {
            f.next_up()
        } else {
            f
        }
    };
    (wlo.map(|x| down(x - pad)), whi.map(|x| up(x + pad)))
}

/// ‖A‖∞ (largest row sum of magnitudes) of the linear part of `m`.
pub fn linear_norm(m: &DMat4) -> f64 {
    (0..3)
        .map(|r| {
            let row = m.row(r);
            row.x.abs() + row.y.abs() + row.z.abs()
        })
        .fold(0.0, f64::max)
}

/// Where primitive `prim` is stored: the `index`-th explicit shape, or triangle `local` of
/// instance `instance`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stored {
    Explicit(usize),
    Instanced { instance: usize, local: usize },
}

/// Where `prim` is stored, given the instances in primitive order and their [`index`]; the
/// explicit shapes fill the gaps between instances, in order.
pub fn locate(instances: &[Instance], index: &[InstanceStart], prim: u32) -> Stored {
    let k = index.partition_point(|i| i.first_prim <= prim);
    if k == 0 {
        return Stored::Explicit(prim as usize);
    }
    let inst = &instances[k - 1];
    let local = (prim - index[k - 1].first_prim) as usize;
    if local < inst.len() {
        return Stored::Instanced {
            instance: k - 1,
            local,
        };
    }
    let instanced = index[k - 1].instanced_before as usize + inst.len();
    Stored::Explicit(prim as usize - instanced)
}

/// Where an instance starts: what [`locate`] searches, 8 bytes an instance. (Searched through
/// the instances themselves, 180 bytes each, the search missed the cache at each step:
/// finding each pixel's colour was 4% of the field of 1,000 bunnies' flat frame in a profile;
/// this index made the frame about 1% faster.)
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InstanceStart {
    /// Its first primitive.
    pub first_prim: u32,
    /// How many primitives the instances before it hold.
    pub instanced_before: u32,
}

/// The [`InstanceStart`]s of `instances` (in primitive order).
pub fn index(instances: &[Instance]) -> Vec<InstanceStart> {
    let mut sum = 0u32;
    instances
        .iter()
        .map(|i| {
            let start = InstanceStart {
                first_prim: i.first_prim,
                instanced_before: sum,
            };
            sum += i.len() as u32;
            start
        })
        .collect()
}
