//! Embree 4 as a second intersector, for `raylab crosscheck` and
//! `raylab probe` (cargo feature `embree`; set-up in docs/embree.md).
//!
//! This is the only module with `unsafe` code: raw calls into Embree through
//! `embree4-sys`. Why not the safe `embree4-rs`: docs/embree.md.
//!
//! Each sphere and each quad of the [`Primitive`] list is an Embree geometry
//! of its own; a run of consecutive triangles is ONE triangle-mesh geometry
//! (a vertex and an index buffer), so that a mesh of a million triangles is
//! one geometry and not a million. A hit's `(geomID, primID)` is mapped back
//! to the index of the primitive in the list, the tracer's object index,
//! through a table of each geometry's first primitive ([`EmbreeScene::intersect`]).

use std::ffi::{CString, c_void};
use std::fmt;
use std::ptr;
use std::sync::atomic::{AtomicI64, Ordering};
use std::time::{Duration, Instant};

use embree4_sys as sys;

use crate::crosscheck::Primitive;
use crate::{Ray, Vec3};

/// An Embree call failed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EmbreeError(String);

impl fmt::Display for EmbreeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Embree: {}", self.0)
    }
}

impl std::error::Error for EmbreeError {}

/// Embree's answer for one ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EmbreeHit {
    /// Index of the primitive hit.
    pub object: usize,
    /// In units of the ray's direction, like every `t` in raylab.
    pub t: f32,
    /// Embree's geometric normal, not normalised.
    pub normal: Vec3,
}

/// `RTCRayHit` with room after it.
///
/// `embree4-sys` 0.0.10 was generated from the Embree 4.2 headers, where
/// `RTCRayHit` is 80 bytes. The library we load (4.4, built with instance
/// arrays) has one more field, `RTCHit::instPrimID[1]`: its `RTCRayHit` is
/// 96 bytes, and it writes past our 80 on every call. The fields we read come first
/// and are laid out the same, so padding after the struct is enough to keep
/// that write inside memory we own. 32 bytes leaves room for one more field
/// of future versions; alignment 16 is what Embree asks of `RTCRayHit`.
#[repr(C, align(16))]
struct RayHitWithRoom {
    ray_hit: sys::RTCRayHit,
    _room: [u32; 8],
}

/// How long building the Embree scene took, and the memory Embree asked
/// for while doing it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BuildStats {
    /// Creating the geometries and copying our primitives into Embree's
    /// buffers.
    pub fill: Duration,
    /// `rtcCommitScene`: Embree's BVH build.
    pub commit: Duration,
    /// The most bytes Embree had allocated at once, by its own count (the
    /// device's memory monitor callback, [`MemoryMonitor`]): buffers, BVH
    /// and the builder's temporary memory.
    pub peak_bytes: u64,
    /// The bytes still allocated once the scene is committed.
    pub bytes_after_commit: u64,
}

impl BuildStats {
    /// The whole build: filling plus committing.
    pub fn total(&self) -> Duration {
        self.fill + self.commit
    }
}

/// Counts the bytes an Embree device allocates, from its memory monitor
/// callback (`rtcSetDeviceMemoryMonitorFunction`, in the 4.2 headers and
/// the 4.4 library). Embree calls it before each allocation with the
/// positive size and after each free with the negative one, from whatever
/// thread builds (TBB's workers), hence the atomics.
#[derive(Debug, Default)]
pub struct MemoryMonitor {
    current: AtomicI64,
    peak: AtomicI64,
}

impl MemoryMonitor {
    fn add(&self, bytes: i64) {
        let now = self.current.fetch_add(bytes, Ordering::Relaxed) + bytes;
        self.peak.fetch_max(now, Ordering::Relaxed);
    }

    /// Bytes allocated now.
    pub fn current(&self) -> u64 {
        self.current.load(Ordering::Relaxed).max(0) as u64
    }

    /// The most bytes allocated at once so far.
    pub fn peak(&self) -> u64 {
        self.peak.load(Ordering::Relaxed).max(0) as u64
    }
}

/// The callback Embree calls on every allocation (`bytes > 0`) and free
/// (`bytes < 0`). Returning `true` lets the allocation go ahead.
unsafe extern "C" fn monitor_memory(user: *mut c_void, bytes: isize, _post: bool) -> bool {
    // SAFETY: `user` is the `MemoryMonitor` that `EmbreeScene::new` boxed
    // and registered; the box lives in the `EmbreeScene`, whose `Drop`
    // releases the device (the last caller) before the box is freed.
    let monitor = unsafe { &*user.cast::<MemoryMonitor>() };
    monitor.add(bytes as i64);
    true
}

/// Which primitives an Embree geometry holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct GeometryRange {
    /// The index of its first primitive in the list given to `new`.
    first: usize,
    /// A run of triangles, one Embree primitive each, so the hit's
    /// `primID` counts from `first`. Otherwise (a sphere, a quad's two
    /// triangles) every `primID` is the one primitive `first`.
    run: bool,
}

/// An Embree device and one committed scene (flag `ROBUST`: watertight
/// triangle edges, no approximate traversal shortcuts).
pub struct EmbreeScene {
    device: sys::RTCDevice,
    scene: sys::RTCScene,
    /// Indexed by `geomID`, in increasing `first`.
    geometries: Vec<GeometryRange>,
    build: BuildStats,
    /// Registered with the device as its memory monitor's user pointer:
    /// boxed so that its address does not move with the `EmbreeScene`.
    memory: Box<MemoryMonitor>,
}

// SAFETY: Embree documents a committed scene as safe to query from many
// threads at once, and device/scene handles may be released from any thread.
// The scene is built and committed in `new` and never changed afterwards
// (no method takes `&mut self`), so sharing `&EmbreeScene` only ever shares
// queries of a committed scene. The memory monitor is atomics only.
unsafe impl Send for EmbreeScene {}
unsafe impl Sync for EmbreeScene {}

/// A new Embree device limited to `threads` build threads (`None`: all
/// cores).
fn new_device(threads: Option<usize>) -> Result<sys::RTCDevice, EmbreeError> {
    // Digits and '=' only: no NUL inside, so this cannot fail.
    let config = threads.map(|n| CString::new(format!("threads={}", n.max(1))));
    let config = config
        .transpose()
        .map_err(|error| EmbreeError(format!("device config: {error}")))?;
    // SAFETY: the config is NULL ("defaults") or a NUL-terminated string
    // that lives until the call returns.
    let device = unsafe { sys::rtcNewDevice(config.as_ref().map_or(ptr::null(), |c| c.as_ptr())) };
    if device.is_null() {
        // SAFETY: NULL asks for the error of the failed device creation.
        let error = unsafe { sys::rtcGetDeviceError(ptr::null_mut()) };
        return Err(EmbreeError(format!("rtcNewDevice failed: {error:?}")));
    }
    Ok(device)
}

impl EmbreeScene {
    /// Builds and commits a scene holding `primitives`: spheres as Embree's
    /// native spheres (`RTC_GEOMETRY_TYPE_SPHERE_POINT`), quads as two
    /// triangles, and each run of consecutive triangles as one triangle
    /// mesh. A hit reports the index of the primitive in `primitives`.
    pub fn new(primitives: &[Primitive]) -> Result<EmbreeScene, EmbreeError> {
        EmbreeScene::with_threads(primitives, None)
    }

    /// [`EmbreeScene::new`] on a device limited to `threads` build threads
    /// (Embree's `threads=N` device option; `None`: all cores). The speed
    /// race builds on one thread, as ours does. Tracing always runs on the
    /// caller's thread.
    pub fn with_threads(
        primitives: &[Primitive],
        threads: Option<usize>,
    ) -> Result<EmbreeScene, EmbreeError> {
        let started = Instant::now();
        let device = new_device(threads)?;
        let memory = Box::new(MemoryMonitor::default());
        // SAFETY: `device` is live; the user pointer is the boxed monitor,
        // which outlives the device (see `Drop`). The device's own
        // allocation came before this, so the count starts after it: what
        // is counted is the scene's memory.
        unsafe {
            sys::rtcSetDeviceMemoryMonitorFunction(
                device,
                Some(monitor_memory),
                ptr::from_ref::<MemoryMonitor>(&*memory).cast_mut().cast(),
            )
        };
        // SAFETY: `device` is live; the scene holds its own reference.
        let scene = unsafe { sys::rtcNewScene(device) };
        // From here on, `Drop` releases whatever was made (NULL is allowed).
        let mut embree = EmbreeScene {
            device,
            scene,
            geometries: Vec::new(),
            build: BuildStats::default(),
            memory,
        };
        embree.check("rtcSetDeviceMemoryMonitorFunction")?;
        if scene.is_null() {
            return Err(embree.error("rtcNewScene"));
        }
        // SAFETY: `scene` is live and not yet committed. ROBUST is the 4.2
        // header's RTC_SCENE_FLAG_ROBUST (embree4-sys drops the prefix).
        // Build quality stays Embree's default, MEDIUM
        // (`rtcSetSceneBuildQuality` exists in 4.2 too): it is what a
        // renderer that builds once per frame would pick, and the speed
        // race compares builds as well as traversals.
        unsafe { sys::rtcSetSceneFlags(scene, sys::RTCSceneFlags::ROBUST) };
        embree.check("rtcSetSceneFlags")?;
        embree.attach_primitives(primitives)?;
        let filled = Instant::now();
        // SAFETY: `scene` is live; building it reads the buffers filled above.
        unsafe { sys::rtcCommitScene(scene) };
        embree.check("rtcCommitScene")?;
        embree.build = BuildStats {
            fill: filled - started,
            commit: filled.elapsed(),
            peak_bytes: embree.memory.peak(),
            bytes_after_commit: embree.memory.current(),
        };
        Ok(embree)
    }

    /// Attaches `primitives` as geometries, each run of consecutive
    /// triangles as one mesh, noting which primitives each geometry holds.
    fn attach_primitives(&mut self, primitives: &[Primitive]) -> Result<(), EmbreeError> {
        let mut index = 0;
        while index < primitives.len() {
            let run = primitives[index..]
                .iter()
                .take_while(|primitive| matches!(primitive, Primitive::Triangle(_)))
                .count();
            let count = run.max(1);
            let id = u32::try_from(self.geometries.len())
                .ok()
                .filter(|&id| id != sys::RTC_INVALID_GEOMETRY_ID)
                .ok_or_else(|| EmbreeError("too many geometries".into()))?;
            if run > 0 {
                let triangles = primitives[index..index + run]
                    .iter()
                    .filter_map(|primitive| match primitive {
                        Primitive::Triangle(corners) => Some(*corners),
                        _ => None,
                    });
                self.attach_triangles(id, run, triangles)?;
            } else {
                self.attach(id, &primitives[index])?;
            }
            self.geometries.push(GeometryRange {
                first: index,
                run: run > 0,
            });
            index += count;
        }
        Ok(())
    }

    /// How long `new` took, split into filling and Embree's BVH build, and
    /// Embree's own count of the memory it used.
    pub fn build_stats(&self) -> BuildStats {
        self.build
    }

    /// How many Embree geometries the primitives became (a run of
    /// triangles is one).
    pub fn geometry_count(&self) -> usize {
        self.geometries.len()
    }

    /// The version of the Embree library loaded, e.g. 40400 for 4.4.0.
    pub fn version(&self) -> i64 {
        // SAFETY: `device` is live; VERSION is a valid property.
        unsafe { sys::rtcGetDeviceProperty(self.device, sys::RTCDeviceProperty::VERSION) as i64 }
    }

    /// The nearest hit with `t_min <= t <= t_max` (Embree's interval is
    /// closed; ours is open, which only matters for a hit exactly at an end).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<EmbreeHit> {
        let invalid = sys::RTC_INVALID_GEOMETRY_ID;
        let mut query = RayHitWithRoom {
            ray_hit: sys::RTCRayHit {
                ray: sys::RTCRay {
                    org_x: ray.origin.x,
                    org_y: ray.origin.y,
                    org_z: ray.origin.z,
                    tnear: t_min,
                    dir_x: ray.dir.x,
                    dir_y: ray.dir.y,
                    dir_z: ray.dir.z,
                    time: 0.0,
                    tfar: t_max,
                    mask: u32::MAX,
                    id: 0,
                    flags: 0,
                },
                hit: sys::RTCHit {
                    Ng_x: 0.0,
                    Ng_y: 0.0,
                    Ng_z: 0.0,
                    u: 0.0,
                    v: 0.0,
                    primID: invalid,
                    geomID: invalid,
                    instID: [invalid],
                },
            },
            _room: [invalid; 8],
        };
        // SAFETY: the scene is committed (in `new`) and never modified. The
        // pointer is to a 16-byte aligned `RTCRayHit` followed by 32 bytes we
        // own, which covers the 96 bytes the 4.4 library writes (see
        // `RayHitWithRoom`). NULL arguments mean the default query.
        unsafe { sys::rtcIntersect1(self.scene, &mut query.ray_hit, ptr::null_mut()) };
        let RayHitWithRoom { ray_hit, .. } = query;
        let range = self.geometries.get(ray_hit.hit.geomID as usize)?;
        let object = if range.run {
            range.first + ray_hit.hit.primID as usize
        } else {
            range.first
        };
        Some(EmbreeHit {
            object,
            t: ray_hit.ray.tfar,
            normal: Vec3::new(ray_hit.hit.Ng_x, ray_hit.hit.Ng_y, ray_hit.hit.Ng_z),
        })
    }

    /// Makes `count` triangles into one triangle mesh and attaches it as
    /// `id`. The corners are written straight into Embree's buffers, three
    /// vertices per triangle (our triangles share no vertex list), so the
    /// only memory is Embree's: 36 bytes of vertices and 12 of indices per
    /// triangle, and no copy of ours in between.
    fn attach_triangles(
        &self,
        id: u32,
        count: usize,
        triangles: impl Iterator<Item = [Vec3; 3]>,
    ) -> Result<(), EmbreeError> {
        // Embree indexes vertices with u32: three per triangle must fit.
        let vertices = count
            .checked_mul(3)
            .filter(|&n| u32::try_from(n).is_ok())
            .ok_or_else(|| EmbreeError(format!("{count} triangles in one mesh: too many")))?;
        // SAFETY: `device` is live.
        let geometry = unsafe { sys::rtcNewGeometry(self.device, sys::RTCGeometryType::TRIANGLE) };
        if geometry.is_null() {
            return Err(self.error("rtcNewGeometry"));
        }
        let filled = self
            .with_new_buffer::<[f32; 3]>(
                geometry,
                sys::RTCBufferType::VERTEX,
                sys::RTCFormat::FLOAT3,
                vertices,
                |slots| {
                    for (slot, corners) in slots.chunks_exact_mut(3).zip(triangles) {
                        for (vertex, corner) in slot.iter_mut().zip(corners) {
                            *vertex = corner.to_array();
                        }
                    }
                },
            )
            .and_then(|()| {
                self.with_new_buffer::<[u32; 3]>(
                    geometry,
                    sys::RTCBufferType::INDEX,
                    sys::RTCFormat::UINT3,
                    count,
                    |indices| {
                        // Fits: 3 * count was checked against u32 above.
                        let mut next = 0u32;
                        for triangle in indices {
                            *triangle = [next, next + 1, next + 2];
                            next += 3;
                        }
                    },
                )
            });
        self.commit_and_attach(geometry, id, filled)
    }

    /// Makes `primitive` (a sphere or a quad) into a geometry and attaches
    /// it as `id`.
    fn attach(&self, id: u32, primitive: &Primitive) -> Result<(), EmbreeError> {
        let kind = match primitive {
            Primitive::Sphere { .. } => sys::RTCGeometryType::SPHERE_POINT,
            Primitive::Quad(_) => sys::RTCGeometryType::TRIANGLE,
            Primitive::Triangle(corners) => {
                return self.attach_triangles(id, 1, std::iter::once(*corners));
            }
        };
        // SAFETY: `device` is live.
        let geometry = unsafe { sys::rtcNewGeometry(self.device, kind) };
        if geometry.is_null() {
            return Err(self.error("rtcNewGeometry"));
        }
        let filled = match primitive {
            Primitive::Sphere { center, radius } => {
                let point = [center.x, center.y, center.z, *radius];
                self.fill(
                    geometry,
                    sys::RTCBufferType::VERTEX,
                    sys::RTCFormat::FLOAT4,
                    &[point],
                )
            }
            Primitive::Quad(corners) => {
                let vertices = corners.map(|corner| corner.to_array());
                self.fill(
                    geometry,
                    sys::RTCBufferType::VERTEX,
                    sys::RTCFormat::FLOAT3,
                    &vertices,
                )
                .and_then(|()| {
                    let triangles: [[u32; 3]; 2] = [[0, 1, 2], [0, 2, 3]];
                    self.fill(
                        geometry,
                        sys::RTCBufferType::INDEX,
                        sys::RTCFormat::UINT3,
                        &triangles,
                    )
                })
            }
            // Returned above: a lone triangle is a mesh of one.
            Primitive::Triangle(_) => Ok(()),
        };
        self.commit_and_attach(geometry, id, filled)
    }

    /// Commits `geometry` and attaches it as `id` if `filled` is fine, and
    /// drops our reference to it either way.
    fn commit_and_attach(
        &self,
        geometry: sys::RTCGeometry,
        id: u32,
        filled: Result<(), EmbreeError>,
    ) -> Result<(), EmbreeError> {
        // SAFETY: `geometry` and `scene` are live; attaching takes the
        // scene's own reference, so ours is released whatever happened.
        let attached = filled.and_then(|()| unsafe {
            sys::rtcCommitGeometry(geometry);
            sys::rtcAttachGeometryByID(self.scene, geometry, id);
            self.check("rtcAttachGeometryByID")
        });
        // SAFETY: we own one reference to `geometry` and drop it here.
        unsafe { sys::rtcReleaseGeometry(geometry) };
        attached
    }

    /// Allocates `geometry`'s buffer `kind` (slot 0) for `count` items of
    /// `T` and lets `write` fill it. `T` must be the plain array of `f32` or
    /// `u32` that `format` describes.
    fn with_new_buffer<T: Copy>(
        &self,
        geometry: sys::RTCGeometry,
        kind: sys::RTCBufferType,
        format: sys::RTCFormat,
        count: usize,
        write: impl FnOnce(&mut [T]),
    ) -> Result<(), EmbreeError> {
        // SAFETY: `geometry` is live; Embree allocates `count` items of
        // `size_of::<T>()` bytes each (with padding for its SIMD loads) and
        // returns NULL on failure.
        let buffer = unsafe {
            sys::rtcSetNewGeometryBuffer(geometry, kind, 0, format, std::mem::size_of::<T>(), count)
        };
        if buffer.is_null() {
            return Err(self.error("rtcSetNewGeometryBuffer"));
        }
        // SAFETY: `buffer` has room for `count` items of `T` and is aligned
        // to 16 bytes (enough for arrays of f32/u32). Embree does not read
        // it before the geometry is committed, after `write`; zeroing it
        // first makes every byte initialised, and any bit pattern is a valid
        // `T` (plain numbers), so the slice is sound for `write` to
        // overwrite. It lives only as long as this call.
        let items = unsafe {
            ptr::write_bytes(buffer.cast::<T>(), 0, count);
            std::slice::from_raw_parts_mut(buffer.cast::<T>(), count)
        };
        write(items);
        Ok(())
    }

    /// Allocates `geometry`'s buffer `kind` (slot 0) and copies `items` into it.
    fn fill<T: Copy>(
        &self,
        geometry: sys::RTCGeometry,
        kind: sys::RTCBufferType,
        format: sys::RTCFormat,
        items: &[T],
    ) -> Result<(), EmbreeError> {
        self.with_new_buffer(geometry, kind, format, items.len(), |buffer| {
            buffer.copy_from_slice(items)
        })
    }

    /// The device's pending error, if any, prefixed with `what`.
    fn check(&self, what: &str) -> Result<(), EmbreeError> {
        // SAFETY: `device` is live; reading the error also clears it.
        let error = unsafe { sys::rtcGetDeviceError(self.device) };
        if error == sys::RTCError::NONE {
            Ok(())
        } else {
            Err(EmbreeError(format!("{what} failed: {error:?}")))
        }
    }

    fn error(&self, what: &str) -> EmbreeError {
        self.check(what)
            .err()
            .unwrap_or_else(|| EmbreeError(format!("{what} failed")))
    }
}

impl Drop for EmbreeScene {
    fn drop(&mut self) {
        // SAFETY: we own one reference to each non-NULL handle. The scene
        // goes first: it holds a reference to the device. The boxed memory
        // monitor, which releasing calls back, is a field: it is freed only
        // after this function returns.
        unsafe {
            if !self.scene.is_null() {
                sys::rtcReleaseScene(self.scene);
            }
            sys::rtcReleaseDevice(self.device);
        }
    }
}
