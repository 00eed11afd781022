//! Embree 4 as a second intersector, for `raylab crosscheck` and
//! `raylab probe` (cargo feature `embree`; set-up in docs/embree.md).
//!
//! This is the only module with `unsafe` code: raw calls into Embree through
//! `embree4-sys`. Why not the safe `embree4-rs`: docs/embree.md.
//!
//! Object `i` of the [`Primitive`] list becomes Embree geometry `i`, so a hit's
//! `geomID` is the index of the object in the tracer's shapes.

use std::fmt;
use std::ptr;

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

/// An Embree device and one committed scene (flag `ROBUST`: watertight
/// triangle edges, no approximate traversal shortcuts).
pub struct EmbreeScene {
    device: sys::RTCDevice,
    scene: sys::RTCScene,
}

// SAFETY: Embree documents a committed scene as safe to query from many
// threads at once, and device/scene handles may be released from any thread.
// The scene is built and committed in `new` and never changed afterwards
// (no method takes `&mut self`), so sharing `&EmbreeScene` only ever shares
// queries of a committed scene.
unsafe impl Send for EmbreeScene {}
unsafe impl Sync for EmbreeScene {}

impl EmbreeScene {
    /// Builds and commits a scene holding `primitives`, primitive `i` as
    /// geometry `i`: spheres as Embree's native spheres
    /// (`RTC_GEOMETRY_TYPE_SPHERE_POINT`), quads as two triangles.
    pub fn new(primitives: &[Primitive]) -> Result<EmbreeScene, EmbreeError> {
        // SAFETY: a NULL config means "defaults" (a non-NULL one would have to
        // be NUL-terminated).
        let device = unsafe { sys::rtcNewDevice(ptr::null()) };
        if device.is_null() {
            // SAFETY: NULL asks for the error of the failed device creation.
            let error = unsafe { sys::rtcGetDeviceError(ptr::null_mut()) };
            return Err(EmbreeError(format!("rtcNewDevice failed: {error:?}")));
        }
        // SAFETY: `device` is a live device; the scene holds its own reference.
        let scene = unsafe { sys::rtcNewScene(device) };
        // From here on, `Drop` releases whatever was made (NULL is allowed).
        let embree = EmbreeScene { device, scene };
        if scene.is_null() {
            return Err(embree.error("rtcNewScene"));
        }
        // SAFETY: `scene` is live and not yet committed.
        unsafe { sys::rtcSetSceneFlags(scene, sys::RTCSceneFlags::ROBUST) };
        embree.check("rtcSetSceneFlags")?;
        for (index, primitive) in primitives.iter().enumerate() {
            let id = u32::try_from(index)
                .ok()
                .filter(|&id| id != sys::RTC_INVALID_GEOMETRY_ID)
                .ok_or_else(|| EmbreeError("too many primitives".into()))?;
            embree.attach(id, primitive)?;
        }
        // SAFETY: `scene` is live; building it reads the buffers filled above.
        unsafe { sys::rtcCommitScene(scene) };
        embree.check("rtcCommitScene")?;
        Ok(embree)
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
        (ray_hit.hit.geomID != invalid).then(|| EmbreeHit {
            object: ray_hit.hit.geomID as usize,
            t: ray_hit.ray.tfar,
            normal: Vec3::new(ray_hit.hit.Ng_x, ray_hit.hit.Ng_y, ray_hit.hit.Ng_z),
        })
    }

    /// Makes `primitive` into a geometry and attaches it as `id`.
    fn attach(&self, id: u32, primitive: &Primitive) -> Result<(), EmbreeError> {
        let kind = match primitive {
            Primitive::Sphere { .. } => sys::RTCGeometryType::SPHERE_POINT,
            Primitive::Quad(_) | Primitive::Triangle(_) => sys::RTCGeometryType::TRIANGLE,
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
            Primitive::Triangle(corners) => {
                let vertices = corners.map(|corner| corner.to_array());
                self.fill(
                    geometry,
                    sys::RTCBufferType::VERTEX,
                    sys::RTCFormat::FLOAT3,
                    &vertices,
                )
                .and_then(|()| {
                    self.fill(
                        geometry,
                        sys::RTCBufferType::INDEX,
                        sys::RTCFormat::UINT3,
                        &[[0u32, 1, 2]],
                    )
                })
            }
        };
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

    /// Allocates `geometry`'s buffer `kind` (slot 0) and copies `items` into it.
    /// `T` must be the plain array of `f32` or `u32` that `format` describes.
    fn fill<T: Copy>(
        &self,
        geometry: sys::RTCGeometry,
        kind: sys::RTCBufferType,
        format: sys::RTCFormat,
        items: &[T],
    ) -> Result<(), EmbreeError> {
        // SAFETY: `geometry` is live; Embree allocates `items.len()` items of
        // `size_of::<T>()` bytes each (with padding for its SIMD loads) and
        // returns NULL on failure.
        let buffer = unsafe {
            sys::rtcSetNewGeometryBuffer(
                geometry,
                kind,
                0,
                format,
                std::mem::size_of::<T>(),
                items.len(),
            )
        };
        if buffer.is_null() {
            return Err(self.error("rtcSetNewGeometryBuffer"));
        }
        // SAFETY: `buffer` has room for `items.len()` items of `T`, is aligned
        // to 16 bytes (enough for arrays of f32/u32) and is not `items`.
        unsafe { ptr::copy_nonoverlapping(items.as_ptr(), buffer.cast::<T>(), items.len()) };
        Ok(())
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
        // goes first: it holds a reference to the device.
        unsafe {
            if !self.scene.is_null() {
                sys::rtcReleaseScene(self.scene);
            }
            sys::rtcReleaseDevice(self.device);
        }
    }
}
