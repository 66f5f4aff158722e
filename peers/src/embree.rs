//! Embree 3 (Debian's `libembree3-3`) loaded at run time, so the example builds and runs where
//! Embree is not installed (it then says so and leaves its rows out).
//!
//! Only what a closest-hit benchmark needs: one triangle mesh, or meshes placed as instances
//! beside loose triangles (one level, Embree's `RTC_GEOMETRY_TYPE_INSTANCE`), or triangles
//! beside spheres (`RTC_GEOMETRY_TYPE_SPHERE_POINT`), a HIGH-quality build, and the single-ray,
//! 8-ray and 16-ray queries. The structs mirror
//! `embree3/rtcore_ray.h` and `rtcore_common.h` of Embree 3.13 built with `RTC_MAX_INSTANCE_LEVEL_COUNT` 1 and
//! `RTC_MIN_WIDTH` 0 (Debian's build).

use libloading::{Library, Symbol};
use std::ffi::{c_char, c_int, c_uint, c_void, CString};
use std::mem::ManuallyDrop;

const INVALID_ID: u32 = u32::MAX;
const GEOMETRY_TYPE_TRIANGLE: c_uint = 0;
const GEOMETRY_TYPE_SPHERE_POINT: c_uint = 50;
const GEOMETRY_TYPE_INSTANCE: c_uint = 121;
const BUFFER_TYPE_INDEX: c_uint = 0;
const BUFFER_TYPE_VERTEX: c_uint = 1;
const FORMAT_UINT3: c_uint = 0x5003;
const FORMAT_FLOAT3: c_uint = 0x9003;
const FORMAT_FLOAT4: c_uint = 0x9004;
const FORMAT_FLOAT3X4_COLUMN_MAJOR: c_uint = 0x9234;
const BUILD_QUALITY_HIGH: c_uint = 2;
const CONTEXT_FLAG_COHERENT: c_uint = 1;

/// `struct RTCIntersectContext`.
#[repr(C)]
struct Context {
    flags: c_uint,
    filter: *const c_void,
    inst_id: [c_uint; 1],
}

impl Context {
    /// `rtcInitIntersectContext` (an inline function in the header), marked coherent: camera
    /// rays are.
    fn coherent() -> Self {
        Context {
            flags: CONTEXT_FLAG_COHERENT,
            filter: std::ptr::null(),
            inst_id: [INVALID_ID],
        }
    }
}

/// `struct RTCRayHit` (`RTCRay` then `RTCHit`).
#[repr(C, align(16))]
#[derive(Clone, Copy)]
struct RayHit1 {
    org: [f32; 3],
    tnear: f32,
    dir: [f32; 3],
    time: f32,
    tfar: f32,
    mask: u32,
    id: u32,
    flags: u32,
    ng: [f32; 3],
    u: f32,
    v: f32,
    prim_id: u32,
    geom_id: u32,
    inst_id: u32,
}

/// `struct RTCRayHitN` for N = 8 or 16 (structure of arrays).
#[repr(C, align(64))]
#[derive(Clone, Copy)]
pub struct RayHitN<const N: usize> {
    org: [[f32; N]; 3],
    tnear: [f32; N],
    dir: [[f32; N]; 3],
    time: [f32; N],
    tfar: [f32; N],
    mask: [u32; N],
    id: [u32; N],
    flags: [u32; N],
    ng: [[f32; N]; 3],
    u: [f32; N],
    v: [f32; N],
    prim_id: [u32; N],
    geom_id: [u32; N],
    inst_id: [u32; N],
}

impl<const N: usize> RayHitN<N> {
    /// A packet with no ray in it yet.
    pub fn empty() -> Self {
        RayHitN {
            org: [[0.0; N]; 3],
            tnear: [0.0; N],
            dir: [[0.0; N]; 3],
            time: [0.0; N],
            tfar: [f32::NEG_INFINITY; N],
            mask: [u32::MAX; N],
            id: [0; N],
            flags: [0; N],
            ng: [[0.0; N]; 3],
            u: [0.0; N],
            v: [0.0; N],
            prim_id: [INVALID_ID; N],
            geom_id: [INVALID_ID; N],
            inst_id: [INVALID_ID; N],
        }
    }

    /// Puts a ray (origin, direction) in `lane`, unhit and unbounded.
    pub fn set(&mut self, lane: usize, o: [f32; 3], d: [f32; 3]) {
        for k in 0..3 {
            self.org[k][lane] = o[k];
            self.dir[k][lane] = d[k];
        }
        self.tfar[lane] = f32::INFINITY;
    }

    /// The lanes holding a ray (tfar ≥ 0, as `set` leaves them).
    pub fn valid(&self) -> ValidN<N> {
        ValidN(self.tfar.map(|t| if t >= 0.0 { -1 } else { 0 }))
    }

    /// Each lane's primitive in `scene`'s numbering, `None` where it missed.
    fn prims(&self, scene: &EmbreeScene) -> [Option<u32>; N] {
        std::array::from_fn(|i| scene.prim(self.geom_id[i], self.prim_id[i], self.inst_id[i]))
    }
}

/// The valid mask of a packet (−1 valid, 0 not), aligned as Embree requires.
#[repr(C, align(64))]
#[derive(Clone, Copy)]
pub struct ValidN<const N: usize>([c_int; N]);

type NewDevice = unsafe extern "C" fn(*const c_char) -> *mut c_void;
type ReleaseDevice = unsafe extern "C" fn(*mut c_void);
type GetDeviceError = unsafe extern "C" fn(*mut c_void) -> c_uint;
type NewScene = unsafe extern "C" fn(*mut c_void) -> *mut c_void;
type SetSceneBuildQuality = unsafe extern "C" fn(*mut c_void, c_uint);
type NewGeometry = unsafe extern "C" fn(*mut c_void, c_uint) -> *mut c_void;
type SetNewGeometryBuffer =
    unsafe extern "C" fn(*mut c_void, c_uint, c_uint, c_uint, usize, usize) -> *mut c_void;
type SetGeometryBuildQuality = unsafe extern "C" fn(*mut c_void, c_uint);
type CommitGeometry = unsafe extern "C" fn(*mut c_void);
type SetInstancedScene = unsafe extern "C" fn(*mut c_void, *mut c_void);
type SetTransform = unsafe extern "C" fn(*mut c_void, c_uint, c_uint, *const f32);
type AttachGeometry = unsafe extern "C" fn(*mut c_void, *mut c_void) -> c_uint;
type ReleaseGeometry = unsafe extern "C" fn(*mut c_void);
type CommitScene = unsafe extern "C" fn(*mut c_void);
type ReleaseScene = unsafe extern "C" fn(*mut c_void);
type Intersect1 = unsafe extern "C" fn(*mut c_void, *mut Context, *mut RayHit1);
type IntersectN<const N: usize> =
    unsafe extern "C" fn(*const ValidN<N>, *mut c_void, *mut Context, *mut RayHitN<N>);

/// The loaded library and one device.
pub struct Embree {
    /// Never unloaded: Embree's task threads (TBB) outlive the device, and unloading their
    /// code under them crashes the process at exit.
    lib: ManuallyDrop<Library>,
    device: *mut c_void,
}

// Embree's device and committed scenes may be used from any thread (its documentation).
unsafe impl Send for Embree {}
unsafe impl Sync for Embree {}

/// A committed scene: one triangle mesh, instances and loose triangles, or triangles and
/// spheres.
pub struct EmbreeScene<'a> {
    embree: &'a Embree,
    scene: *mut c_void,
    /// The scenes its instances place (released after it, as fields drop after `drop`).
    meshes: Vec<EmbreeScene<'a>>,
    /// How a hit's ids map to the caller's primitive numbers.
    numbering: Numbering,
    intersect1: Symbol<'a, Intersect1>,
    intersect8: Symbol<'a, IntersectN<8>>,
    intersect16: Symbol<'a, IntersectN<16>>,
}

/// How an Embree hit's ids become the caller's primitive numbers.
enum Numbering {
    /// One mesh: the primitive id.
    Mesh,
    /// Geometry 0 holds the loose triangles (`loose[prim id]`) if there are any; the
    /// geometries from `first_instance` on are the instances, in order, and instance k's
    /// mesh triangle i is primitive `first_prim[k] + i`.
    Instanced {
        loose: Vec<u32>,
        first_instance: u32,
        first_prim: Vec<u32>,
    },
    /// Geometry g's primitive i is primitive `loose[g][i]` (no instances).
    Loose(Vec<Vec<u32>>),
}

/// A mesh placed as an instance: which of the meshes, its object-to-world matrix (3×4,
/// column-major: the linear part's columns, then the translation), and the primitive number
/// of its first triangle.
pub struct Placement {
    pub mesh: usize,
    pub world_from_object: [f32; 12],
    pub first_prim: u32,
}

unsafe impl Send for EmbreeScene<'_> {}
unsafe impl Sync for EmbreeScene<'_> {}

impl Embree {
    /// Loads `libembree3.so.3` and makes a device with `threads` build threads, its kernels
    /// limited to instruction set `isa` if given (Embree's `isa=` setting: `"avx2"` for what
    /// a CPU without AVX-512 runs); `Err` says why not (most often: not installed).
    pub fn load(threads: usize, isa: Option<&str>) -> Result<Self, String> {
        // SAFETY: loading a system library runs its initialisers; Embree's are benign.
        let lib = unsafe { Library::new("libembree3.so.3") }
            .map_err(|e| format!("{e} (Debian: apt-get install libembree3-3)"))?;
        let isa = isa.map_or(String::new(), |isa| format!(",isa={isa}"));
        let config = CString::new(format!("threads={threads}{isa}")).expect("no NUL");
        // SAFETY: the signature is rtcNewDevice's.
        let device = unsafe {
            let new_device: Symbol<NewDevice> =
                lib.get(b"rtcNewDevice\0").map_err(|e| e.to_string())?;
            new_device(config.as_ptr())
        };
        if device.is_null() {
            return Err("rtcNewDevice failed".into());
        }
        Ok(Embree {
            lib: ManuallyDrop::new(lib),
            device,
        })
    }

    fn symbol<T>(&self, name: &[u8]) -> Symbol<'_, T> {
        // SAFETY: every caller names an Embree 3 function with the type T declares.
        unsafe { self.lib.get(name) }.unwrap_or_else(|e| panic!("Embree 3 lacks a symbol: {e}"))
    }

    /// Builds a scene of `triangles` at Embree's HIGH quality (its best BVH for tracing).
    pub fn scene(&self, triangles: &[[[f32; 3]; 3]]) -> Result<EmbreeScene<'_>, String> {
        // (Owned from the start: an error below releases it.)
        let out = self.new_scene(Vec::new(), Numbering::Mesh);
        // SAFETY: a live scene of this device.
        unsafe {
            self.add_triangles(out.scene, triangles)?;
            self.commit(out.scene)?;
        }
        Ok(out)
    }

    /// Builds a scene of `meshes` placed as instances (each mesh's own scene built once at
    /// HIGH quality) beside `loose` triangles with their primitive numbers.
    pub fn instanced_scene(
        &self,
        meshes: &[&[[[f32; 3]; 3]]],
        placements: &[Placement],
        loose: &[([[f32; 3]; 3], u32)],
    ) -> Result<EmbreeScene<'_>, String> {
        let meshes = (meshes.iter().map(|m| self.scene(m))).collect::<Result<Vec<_>, _>>()?;
        let numbering = Numbering::Instanced {
            loose: loose.iter().map(|(_, p)| *p).collect(),
            first_instance: !loose.is_empty() as u32,
            first_prim: placements.iter().map(|p| p.first_prim).collect(),
        };
        let out = self.new_scene(meshes, numbering);
        // SAFETY: as in `scene`; each instance's scene was committed before the instance is,
        // as Embree's documentation asks, and its matrix is the 12 floats the format reads.
        unsafe {
            if !loose.is_empty() {
                let tris: Vec<_> = loose.iter().map(|(t, _)| *t).collect();
                self.add_triangles(out.scene, &tris)?;
            }
            for p in placements {
                let geometry = self.symbol::<NewGeometry>(b"rtcNewGeometry\0")(
                    self.device,
                    GEOMETRY_TYPE_INSTANCE,
                );
                self.symbol::<SetInstancedScene>(b"rtcSetGeometryInstancedScene\0")(
                    geometry,
                    out.meshes[p.mesh].scene,
                );
                self.symbol::<SetTransform>(b"rtcSetGeometryTransform\0")(
                    geometry,
                    0,
                    FORMAT_FLOAT3X4_COLUMN_MAJOR,
                    p.world_from_object.as_ptr(),
                );
                self.attach(out.scene, geometry);
            }
            self.commit(out.scene)?;
        }
        Ok(out)
    }

    /// Builds a scene of `triangles` (one geometry) and `spheres` (x, y, z, radius: one
    /// geometry of Embree's sphere points), each with its primitive number.
    pub fn spheres_scene(
        &self,
        triangles: &[([[f32; 3]; 3], u32)],
        spheres: &[([f32; 4], u32)],
    ) -> Result<EmbreeScene<'_>, String> {
        let mut loose = Vec::new();
        if !triangles.is_empty() {
            loose.push(triangles.iter().map(|(_, p)| *p).collect());
        }
        if !spheres.is_empty() {
            loose.push(spheres.iter().map(|(_, p)| *p).collect());
        }
        let out = self.new_scene(Vec::new(), Numbering::Loose(loose));
        // SAFETY: as in `scene`; the vertex buffer is written within the size Embree
        // allocated, one FLOAT4 (centre, radius) per sphere.
        unsafe {
            if !triangles.is_empty() {
                let tris: Vec<_> = triangles.iter().map(|(t, _)| *t).collect();
                self.add_triangles(out.scene, &tris)?;
            }
            if !spheres.is_empty() {
                let geometry = self.symbol::<NewGeometry>(b"rtcNewGeometry\0")(
                    self.device,
                    GEOMETRY_TYPE_SPHERE_POINT,
                );
                let set_buffer = self.symbol::<SetNewGeometryBuffer>(b"rtcSetNewGeometryBuffer\0");
                let n = spheres.len();
                let vertices =
                    set_buffer(geometry, BUFFER_TYPE_VERTEX, 0, FORMAT_FLOAT4, 16, n) as *mut f32;
                if vertices.is_null() {
                    let code = self.device_error();
                    self.symbol::<ReleaseGeometry>(b"rtcReleaseGeometry\0")(geometry);
                    return Err(format!(
                        "rtcSetNewGeometryBuffer failed for the spheres (Embree error {code})"
                    ));
                }
                let vertices = std::slice::from_raw_parts_mut(vertices, 4 * n);
                for (out, (sphere, _)) in vertices.chunks_exact_mut(4).zip(spheres) {
                    out.copy_from_slice(sphere);
                }
                self.attach(out.scene, geometry);
            }
            self.commit(out.scene)?;
        }
        Ok(out)
    }

    /// An empty scene at HIGH build quality, holding `meshes` (the scenes its instances
    /// place) and answering in `numbering`.
    fn new_scene<'a>(
        &'a self,
        meshes: Vec<EmbreeScene<'a>>,
        numbering: Numbering,
    ) -> EmbreeScene<'a> {
        // SAFETY: the signatures are Embree's; the device is live while `self` is.
        let scene = unsafe {
            let scene = self.symbol::<NewScene>(b"rtcNewScene\0")(self.device);
            self.symbol::<SetSceneBuildQuality>(b"rtcSetSceneBuildQuality\0")(
                scene,
                BUILD_QUALITY_HIGH,
            );
            scene
        };
        EmbreeScene {
            embree: self,
            scene,
            meshes,
            numbering,
            intersect1: self.symbol(b"rtcIntersect1\0"),
            intersect8: self.symbol(b"rtcIntersect8\0"),
            intersect16: self.symbol(b"rtcIntersect16\0"),
        }
    }

    /// Adds a geometry of `triangles`, HIGH quality, to `scene` (Embree's documented sequence:
    /// new geometry, fill its buffers of the sizes asked for, commit, attach, release).
    ///
    /// # Safety
    /// `scene` must be a live scene of this device.
    unsafe fn add_triangles(
        &self,
        scene: *mut c_void,
        triangles: &[[[f32; 3]; 3]],
    ) -> Result<(), String> {
        // SAFETY: the buffers are written within the sizes Embree allocated.
        unsafe {
            let geometry = self.symbol::<NewGeometry>(b"rtcNewGeometry\0")(
                self.device,
                GEOMETRY_TYPE_TRIANGLE,
            );
            self.symbol::<SetGeometryBuildQuality>(b"rtcSetGeometryBuildQuality\0")(
                geometry,
                BUILD_QUALITY_HIGH,
            );
            let set_buffer = self.symbol::<SetNewGeometryBuffer>(b"rtcSetNewGeometryBuffer\0");
            let n = triangles.len();
            let vertices =
                set_buffer(geometry, BUFFER_TYPE_VERTEX, 0, FORMAT_FLOAT3, 12, 3 * n) as *mut f32;
            let indices =
                set_buffer(geometry, BUFFER_TYPE_INDEX, 0, FORMAT_UINT3, 12, n) as *mut u32;
            if vertices.is_null() || indices.is_null() {
                let code = self.device_error();
                self.symbol::<ReleaseGeometry>(b"rtcReleaseGeometry\0")(geometry);
                return Err(format!(
                    "rtcSetNewGeometryBuffer failed (Embree error {code})"
                ));
            }
            let vertices = std::slice::from_raw_parts_mut(vertices, 9 * n);
            let indices = std::slice::from_raw_parts_mut(indices, 3 * n);
            for (i, tri) in triangles.iter().enumerate() {
                for (k, v) in tri.iter().enumerate() {
                    vertices[9 * i + 3 * k..9 * i + 3 * k + 3].copy_from_slice(v);
                    indices[3 * i + k] = (3 * i + k) as u32;
                }
            }
            self.attach(scene, geometry);
            Ok(())
        }
    }

    /// Commits `geometry`, attaches it to `scene` (geometry ids 0, 1, … in attach order) and
    /// drops this handle to it (the scene keeps it).
    ///
    /// # Safety
    /// Both must be live handles of this device.
    unsafe fn attach(&self, scene: *mut c_void, geometry: *mut c_void) {
        // SAFETY: the signatures are Embree's; the caller's handles are live.
        unsafe {
            self.symbol::<CommitGeometry>(b"rtcCommitGeometry\0")(geometry);
            self.symbol::<AttachGeometry>(b"rtcAttachGeometry\0")(scene, geometry);
            self.symbol::<ReleaseGeometry>(b"rtcReleaseGeometry\0")(geometry);
        }
    }

    /// Commits `scene` (builds its BVH).
    ///
    /// # Safety
    /// `scene` must be a live scene of this device.
    unsafe fn commit(&self, scene: *mut c_void) -> Result<(), String> {
        // SAFETY: the signature is rtcCommitScene's; the caller's handle is live.
        unsafe { self.symbol::<CommitScene>(b"rtcCommitScene\0")(scene) };
        match self.device_error() {
            0 => Ok(()),
            code => Err(format!("rtcCommitScene failed (Embree error {code})")),
        }
    }

    /// The device's last error code (0: none), which reading clears.
    fn device_error(&self) -> c_uint {
        // SAFETY: the signature is rtcGetDeviceError's.
        unsafe { self.symbol::<GetDeviceError>(b"rtcGetDeviceError\0")(self.device) }
    }
}

impl Drop for Embree {
    fn drop(&mut self) {
        // SAFETY: the device was made by rtcNewDevice and every scene borrowing it is gone.
        unsafe { self.symbol::<ReleaseDevice>(b"rtcReleaseDevice\0")(self.device) }
    }
}

impl EmbreeScene<'_> {
    /// A hit's primitive number, `None` for a miss.
    fn prim(&self, geom_id: u32, prim_id: u32, inst_id: u32) -> Option<u32> {
        if geom_id == INVALID_ID {
            return None;
        }
        Some(match &self.numbering {
            Numbering::Mesh => prim_id,
            Numbering::Instanced {
                loose,
                first_instance,
                first_prim,
            } => match inst_id {
                INVALID_ID => loose[prim_id as usize],
                k => first_prim[(k - first_instance) as usize] + prim_id,
            },
            Numbering::Loose(loose) => loose[geom_id as usize][prim_id as usize],
        })
    }

    /// The nearest primitive along one ray, `rtcIntersect1`.
    pub fn closest1(&self, o: [f32; 3], d: [f32; 3]) -> Option<u32> {
        let mut rh = RayHit1 {
            org: o,
            tnear: 0.0,
            dir: d,
            time: 0.0,
            tfar: f32::INFINITY,
            mask: u32::MAX,
            id: 0,
            flags: 0,
            ng: [0.0; 3],
            u: 0.0,
            v: 0.0,
            prim_id: INVALID_ID,
            geom_id: INVALID_ID,
            inst_id: INVALID_ID,
        };
        let mut context = Context::coherent();
        // SAFETY: a committed scene, an initialised context and ray, the header's layouts.
        unsafe { (self.intersect1)(self.scene, &mut context, &mut rh) };
        self.prim(rh.geom_id, rh.prim_id, rh.inst_id)
    }

    /// A packet of 8 rays, `rtcIntersect8`: each lane's primitive.
    pub fn closest8(&self, packet: &mut RayHitN<8>, valid: &ValidN<8>) -> [Option<u32>; 8] {
        let mut context = Context::coherent();
        // SAFETY: as closest1; valid and packet are aligned as the header declares.
        unsafe { (self.intersect8)(valid, self.scene, &mut context, packet) };
        packet.prims(self)
    }

    /// A packet of 16 rays, `rtcIntersect16`: each lane's primitive.
    pub fn closest16(&self, packet: &mut RayHitN<16>, valid: &ValidN<16>) -> [Option<u32>; 16] {
        let mut context = Context::coherent();
        // SAFETY: as closest8.
        unsafe { (self.intersect16)(valid, self.scene, &mut context, packet) };
        packet.prims(self)
    }
}

impl Drop for EmbreeScene<'_> {
    fn drop(&mut self) {
        // SAFETY: the scene was made by rtcNewScene on this device; the scenes its instances
        // place (`meshes`) are released after it, as the fields drop.
        unsafe { self.embree.symbol::<ReleaseScene>(b"rtcReleaseScene\0")(self.scene) }
    }
}
