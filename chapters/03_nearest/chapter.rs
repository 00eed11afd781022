use raylab::Ray;
use raylab::course::{Chapters, Hit, Objects};

/// The closest hit with `t_min < t < t_max` among all `objects`.
///
/// Each hit found becomes the new upper bound, so every later object is only
/// asked for hits in front of the best one so far: no sorting, no list of
/// candidates, and the answer does not depend on the order of the objects
/// (except between two at exactly the same `t`, where the first wins).
///
/// `C` is whoever's chapters are running (yours, in your workspace):
/// `objects.intersect` calls its chapter 1 and 2 tests.
pub fn nearest_hit<C: Chapters>(
    objects: &Objects<C>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let mut nearest = None;
    let mut closest_so_far = t_max;
    for object in 0..objects.len() {
        if let Some(t) = objects.intersect(object, ray, t_min, closest_so_far) {
            closest_so_far = t;
            nearest = Some(Hit { object, t });
        }
    }
    nearest
}

#[cfg(test)]
mod tests;
