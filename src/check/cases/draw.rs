//! Fresh inputs for `grade --code --fresh SEED`: each parametrised case's
//! numbers drawn anew within its kind's stated ranges, so that no table of
//! answers prepared in advance can pass.
//!
//! A geometric case is moved whole by a [`Motion`]: a rotation, a uniform
//! scale and a shift. Every relation the case is about (a hit in front, a
//! sphere around the origin, the nearer of two roots) is kept, up to the
//! rounding of the moved inputs to `f32`, which a well-conditioned
//! checkpoint does not feel; the expectation is then worked out again by
//! the oracle on the inputs as sent. A case whose point is an exact
//! relation (a root exactly at `t_max`, a tie) says so with
//! [`super::Case::fixed`] and keeps its inputs.
//!
//! Every draw is plain arithmetic and square roots on a fixed generator,
//! so one seed gives the same inputs on every machine.

use glam::{DMat3, DQuat, DVec3, Vec3};

use crate::Ray;

/// The generator of one case's fresh inputs.
#[derive(Debug, Clone)]
pub struct Draw {
    state: u64,
}

/// The stated ranges of a [`Motion`]: the scale, and the shift on each
/// axis.
pub const MOTION_SCALE: (f64, f64) = (0.5, 2.0);
pub const MOTION_SHIFT: f64 = 8.0;

impl Draw {
    /// The draws of case `name` under the instructor's `seed`: independent
    /// of every other case, so that adding one changes no other's inputs.
    pub fn for_case(seed: u64, name: &str) -> Draw {
        let mut state = seed ^ 0x6a09_e667_f3bc_c909;
        for byte in name.bytes() {
            state = (state ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
        }
        Draw { state }
    }

    /// 64 random bits (splitmix64).
    pub fn word(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[low, high)`.
    pub fn between(&mut self, low: f64, high: f64) -> f64 {
        let unit = (self.word() >> 11) as f64 / (1u64 << 53) as f64;
        low + unit * (high - low)
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: u64) -> u64 {
        self.word() % n.max(1)
    }

    /// `value` changed by a share of itself uniform in `[-share, share]`.
    pub fn nudge(&mut self, value: f32, share: f64) -> f32 {
        (f64::from(value) * (1.0 + self.between(-share, share))) as f32
    }

    /// A rotation uniform over all rotations: a unit quaternion, from a
    /// point uniform in the unit ball (Shoemake's method needs sines; this
    /// needs only a square root).
    pub fn rotation(&mut self) -> DMat3 {
        loop {
            let q = [
                self.between(-1.0, 1.0),
                self.between(-1.0, 1.0),
                self.between(-1.0, 1.0),
                self.between(-1.0, 1.0),
            ];
            let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if norm > 0.1 && norm <= 1.0 {
                let [x, y, z, w] = q.map(|x| x / norm);
                return DMat3::from_quat(DQuat::from_xyzw(x, y, z, w));
            }
        }
    }

    /// `direction` turned by up to about `degrees` about a random axis
    /// (a quaternion near the identity: only a square root).
    pub fn tilt(&mut self, direction: Vec3, degrees: f64) -> Vec3 {
        let most = degrees * std::f64::consts::PI / 360.0;
        let axis = loop {
            let v = DVec3::new(
                self.between(-1.0, 1.0),
                self.between(-1.0, 1.0),
                self.between(-1.0, 1.0),
            );
            if v.length_squared() <= 1.0 {
                break v;
            }
        };
        let v = axis * most;
        let w = (1.0 - v.length_squared()).sqrt();
        (DQuat::from_xyzw(v.x, v.y, v.z, w) * direction.as_dvec3()).as_vec3()
    }

    /// Where the camera at `position` looking at `look_at` stands once
    /// turned about `look_at` by 3 to 8 degrees about `up`, either way,
    /// then 2 to 5 degrees upward (never down into a floor). Every pixel
    /// then sees another point, so no image rendered beforehand matches,
    /// while the scene stays in frame.
    pub fn view(&mut self, position: Vec3, look_at: Vec3, up: Vec3) -> Vec3 {
        let centre = look_at.as_dvec3();
        let up = up.as_dvec3().normalize_or_zero();
        // A quaternion's vector part is sin(angle / 2) times its axis; the
        // sines of 1.5, 4, 1 and 2.5 degrees are written out, as `sin` may
        // round differently on another machine.
        let turn = |axis: DVec3, sine: f64, offset: DVec3| {
            let w = (1.0 - sine * sine).sqrt();
            let v = axis * sine;
            DQuat::from_xyzw(v.x, v.y, v.z, w) * offset
        };
        let side = if self.below(2) == 0 { 1.0 } else { -1.0 };
        let yaw = self.between(0.026_176_948, 0.069_756_474);
        let mut offset = turn(up, side * yaw, position.as_dvec3() - centre);
        let pitch = self.between(0.017_452_406, 0.043_619_387);
        let across = offset.cross(up).normalize_or_zero();
        let [one, other] = [pitch, -pitch].map(|sine| turn(across, sine, offset));
        offset = if one.dot(up) >= other.dot(up) {
            one
        } else {
            other
        };
        (centre + offset).as_vec3()
    }

    /// A shift uniform in the cube of half side `reach`.
    pub fn shift(&mut self, reach: f64) -> DVec3 {
        DVec3::new(
            self.between(-reach, reach),
            self.between(-reach, reach),
            self.between(-reach, reach),
        )
    }

    /// One of the 48 rotations and reflections that map the axes onto
    /// the axes: boxes stay axis-aligned.
    pub fn axis_turn(&mut self) -> DMat3 {
        let order = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        let order = order[self.below(6) as usize];
        let columns = order.map(|axis| {
            let sign = if self.below(2) == 0 { 1.0 } else { -1.0 };
            let mut column = DVec3::ZERO;
            column[axis] = sign;
            column
        });
        DMat3::from_cols(columns[0], columns[1], columns[2])
    }

    /// A motion of the whole case: rotation, scale in `MOTION_SCALE`,
    /// shift within `MOTION_SHIFT` on each axis.
    pub fn motion(&mut self) -> Motion {
        let turn = self.rotation();
        self.motion_with(turn)
    }

    /// A motion that keeps boxes axis-aligned ([`Draw::axis_turn`]).
    pub fn axis_motion(&mut self) -> Motion {
        let turn = self.axis_turn();
        self.motion_with(turn)
    }

    fn motion_with(&mut self, turn: DMat3) -> Motion {
        let scale = self.between(MOTION_SCALE.0, MOTION_SCALE.1);
        let shift = DVec3::new(
            self.between(-MOTION_SHIFT, MOTION_SHIFT),
            self.between(-MOTION_SHIFT, MOTION_SHIFT),
            self.between(-MOTION_SHIFT, MOTION_SHIFT),
        );
        Motion { turn, scale, shift }
    }
}

/// `p -> scale * turn * p + shift` for points, `d -> turn * d` for
/// directions (their length, which `t` counts, is kept), so that the
/// point at `t` on a moved ray is the moved point at `t / scale` on the
/// ray: every `t` is multiplied by `scale`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    pub turn: DMat3,
    pub scale: f64,
    pub shift: DVec3,
}

impl Motion {
    /// A moved point, rounded to `f32`.
    pub fn point(&self, point: Vec3) -> Vec3 {
        (self.scale * (self.turn * point.as_dvec3()) + self.shift).as_vec3()
    }

    /// A turned direction (or normal), rounded to `f32`.
    pub fn direction(&self, direction: Vec3) -> Vec3 {
        (self.turn * direction.as_dvec3()).as_vec3()
    }

    /// A length (a radius), scaled.
    pub fn length(&self, length: f32) -> f32 {
        (f64::from(length) * self.scale) as f32
    }

    /// A ray parameter: `0` and infinities stay.
    pub fn t(&self, t: f32) -> f32 {
        if t == 0.0 || !t.is_finite() {
            t
        } else {
            (f64::from(t) * self.scale) as f32
        }
    }

    pub fn ray(&self, ray: &Ray) -> Ray {
        Ray::new(self.point(ray.origin), self.direction(ray.dir))
    }

    /// An axis-aligned box `(min, max)` moved by an axis motion: its
    /// corners moved, then sorted again axis by axis.
    pub fn aligned_box(&self, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
        let (a, b) = (self.point(min), self.point(max));
        (a.min(b), a.max(b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_depend_on_the_seed_and_the_name_only() {
        let draw = |seed, name| Draw::for_case(seed, name).word();
        assert_eq!(draw(1, "sphere-ahead"), draw(1, "sphere-ahead"));
        assert_ne!(draw(1, "sphere-ahead"), draw(2, "sphere-ahead"));
        assert_ne!(draw(1, "sphere-ahead"), draw(1, "sphere-behind"));
    }

    #[test]
    fn rotations_are_rotations() {
        let mut draw = Draw::for_case(7, "x");
        for _ in 0..100 {
            for turn in [draw.rotation(), draw.axis_turn()] {
                let product = turn * turn.transpose();
                assert!((product - DMat3::IDENTITY).abs_diff_eq(DMat3::ZERO, 1e-12));
            }
            let motion = draw.motion();
            assert!(motion.scale >= MOTION_SCALE.0 && motion.scale < MOTION_SCALE.1);
        }
    }

    #[test]
    fn a_moved_ray_meets_the_moved_point_at_the_scaled_t() {
        let mut draw = Draw::for_case(3, "y");
        let motion = draw.motion();
        let ray = Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.0, 0.6, 0.8));
        let moved = motion.ray(&ray);
        let there = moved.at(motion.t(2.5));
        assert!((there - motion.point(ray.at(2.5))).length() < 1e-4);
    }
}
