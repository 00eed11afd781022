#![doc = include_str!("03_nearest.md")]

use crate::{Ray, Shape};

/// Which object a ray met, and where along the ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Index of the shape in the slice that was searched.
    pub object: usize,
    /// Ray parameter of the hit, in units of the ray's direction.
    pub t: f32,
}

/// The closest hit with `t_min < t < t_max` among all `shapes`.
///
/// Each hit found becomes the new upper bound, so every later shape is only
/// asked for hits in front of the best one so far: no sorting, no list of
/// candidates, and the answer does not depend on the order of `shapes`
/// (except between two shapes at exactly the same `t`, where the first wins).
pub fn nearest_hit(shapes: &[Shape], ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
    let mut nearest = None;
    let mut closest_so_far = t_max;
    for (object, shape) in shapes.iter().enumerate() {
        if let Some(t) = shape.intersect(ray, t_min, closest_so_far) {
            closest_so_far = t;
            nearest = Some(Hit { object, t });
        }
    }
    nearest
}

/// The first shape in list order that the ray hits, wherever it is.
///
/// Chapters 1 and 2 draw with this, and it is wrong for drawing: a far
/// object listed early hides a near one listed late. It is exactly right for
/// shadow rays (chapter 4), where any blocker will do and stopping at the
/// first saves work.
pub fn first_hit(shapes: &[Shape], ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
    shapes.iter().enumerate().find_map(|(object, shape)| {
        shape
            .intersect(ray, t_min, t_max)
            .map(|t| Hit { object, t })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Plane, Sphere, Vec3};

    /// Three shapes on the +z axis, listed far to near: a wall at z = 10,
    /// a sphere spanning z in [5, 7] and a sphere spanning z in [2, 4].
    fn three_in_a_row() -> Vec<Shape> {
        vec![
            Plane::new(Vec3::new(0.0, 0.0, 10.0), Vec3::Z).into(),
            Sphere::new(Vec3::new(0.0, 0.0, 6.0), 1.0).into(),
            Sphere::new(Vec3::new(0.0, 0.0, 3.0), 1.0).into(),
        ]
    }

    #[test]
    fn nearest_of_three_is_the_last_listed() {
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        let hit = nearest_hit(&three_in_a_row(), &ray, 0.0, f32::INFINITY);
        assert_eq!(hit, Some(Hit { object: 2, t: 2.0 }));
    }

    #[test]
    fn first_hit_takes_list_order_instead() {
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        let hit = first_hit(&three_in_a_row(), &ray, 0.0, f32::INFINITY);
        assert_eq!(hit, Some(Hit { object: 0, t: 10.0 }));
    }

    #[test]
    fn t_max_excludes_everything_beyond() {
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(nearest_hit(&three_in_a_row(), &ray, 0.0, 1.5), None);
        let hit = nearest_hit(&three_in_a_row(), &ray, 4.5, f32::INFINITY);
        assert_eq!(hit, Some(Hit { object: 1, t: 5.0 }));
    }

    #[test]
    fn empty_scene_has_no_hit() {
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(nearest_hit(&[], &ray, 0.0, f32::INFINITY), None);
    }
}
