//! Secondary rays built from a surface point as chapters 4, 6 and 8 build
//! them (with the reference functions), with the origin rule chosen per call.
#![allow(dead_code)]

use raylab::render::RayOffset;
use raylab::shapes::SurfacePoint;
use raylab::{Ray, Vec3};

pub fn shadow_ray_from(surface: &SurfacePoint, light: Vec3, offset: RayOffset) -> Ray {
    let origin = offset.origin(surface, light - surface.point);
    Ray::new(origin, light - origin)
}

pub fn reflected_ray(surface: &SurfacePoint, incoming: Vec3, offset: RayOffset) -> Ray {
    let dir = raylab::reflect(incoming, surface.normal);
    Ray::new(offset.origin(surface, dir), dir)
}

pub fn refracted_ray(
    surface: &SurfacePoint,
    incoming: Vec3,
    ior: f32,
    offset: RayOffset,
) -> Option<Ray> {
    let entering = incoming.dot(surface.normal) < 0.0;
    let eta = if entering { 1.0 / ior } else { ior };
    let dir = raylab::refract(incoming, surface.normal, eta)?;
    Some(Ray::new(offset.origin(surface, dir), dir))
}
