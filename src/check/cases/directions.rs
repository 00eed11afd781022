//! Cases on how light turns and fades: the mirror and refracted directions,
//! the reflected share and the transmitted light.

use super::*;

/// `reflect(d, n)`: expected the exact mirror image.
#[derive(Debug, Clone)]
pub struct ReflectCase {
    pub d: Vec3,
    pub n: Vec3,
}

impl ReflectCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "reflect"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let ReflectCase { d, n } = self;
        format!("reflect({}, {})", vec(*d), vec(*n))
    }

    /// Asks the question of the chapters `C`; `robust`: at the robustness
    /// level's tolerance.
    pub(super) fn evaluate<C: Chapters>(&self, robust: bool) -> Outcome {
        let ReflectCase { d, n } = self;
        let got = C::reflect(*d, *n);
        let expected = exact::reflect(wide(*d), wide(*n));
        if !expected.is_finite() {
            // A zero or non-finite normal has no mirror: the answer
            // must not look like a direction.
            return verdict(
                got.is_nan(),
                "a NaN component (no mirror without a normal)".into(),
                vec(got),
            );
        }
        let g = wide(got);
        let pass = got.is_finite()
            && if robust {
                // Direction and length apart, as tests/course/hard_cases.rs.
                let length = expected.length();
                exact::angle(g, expected) <= ROUNDINGS * U
                    && (g.length() - length).abs() <= ROUNDINGS * U * length
            } else {
                (g - expected).length() <= CHECKPOINT_TOLERANCE * expected.length()
            };
        verdict(pass, vec64(expected), vec(got))
    }
}

/// `refract(d, n, eta)`: expected the exact unit direction, or `None`.
#[derive(Debug, Clone)]
pub struct RefractCase {
    pub d: Vec3,
    pub n: Vec3,
    pub eta: f32,
}

impl RefractCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "refract"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let RefractCase { d, n, eta } = self;
        format!("refract({}, {}, eta = {})", vec(*d), vec(*n), num(*eta))
    }

    /// Asks the question of the chapters `C`; `robust`: at the robustness
    /// level's tolerance.
    pub(super) fn evaluate<C: Chapters>(&self, robust: bool) -> Outcome {
        let RefractCase { d, n, eta } = self;
        let got = C::refract(*d, *n, *eta);
        let expected = if eta.is_finite() && *eta > 0.0 {
            exact::refract(wide(*d), wide(*n), f64::from(*eta)).filter(|t| t.is_finite())
        } else {
            None
        };
        let show = |t: Option<String>| t.unwrap_or_else(|| "None (no refracted ray)".into());
        match (expected, got) {
            (None, None) => Outcome::Pass,
            (Some(want), Some(t)) => {
                let d64 = wide(*d).normalize();
                let n64 = wide(*n).normalize();
                let cos_i = d64.dot(n64).abs();
                let cos_t = want.dot(n64).abs();
                let tolerance = if robust {
                    ROUNDINGS * U * (1.0 + f64::from(*eta) * cos_i / cos_t.max(1e-300))
                } else {
                    CHECKPOINT_TOLERANCE
                };
                let t64 = wide(t);
                let unit = (t64.length() - 1.0).abs() <= tolerance.max(ROUNDINGS * U);
                let pass = t.is_finite() && unit && exact::angle(t64, want) <= tolerance;
                verdict(
                    pass,
                    format!("Some({}) (unit length)", vec64(want)),
                    format!("Some({}) (length {})", vec(t), num64(t64.length())),
                )
            }
            (want, t) => Outcome::Fail {
                expected: show(want.map(|w| format!("Some({})", vec64(w)))),
                got: show(t.map(|t| format!("Some({})", vec(t)))),
            },
        }
    }
}

/// `fresnel(cos_i, n1, n2)` (or `schlick`, when `schlick` is set):
/// expected the `f64` value of the formula, within `1e-6` absolute, or
/// NaN (for an index that is not a finite number > 0) when `expect` is.
#[derive(Debug, Clone)]
pub struct ReflectanceCase {
    pub schlick: bool,
    pub cos_i: f32,
    pub n1: f32,
    pub n2: f32,
    pub expect: f64,
}

impl ReflectanceCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        if self.schlick { "schlick" } else { "fresnel" }
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let ReflectanceCase {
            schlick,
            cos_i,
            n1,
            n2,
            ..
        } = self;
        format!(
            "{}(cos_i = {}, n1 = {}, n2 = {})",
            if *schlick { "schlick" } else { "fresnel" },
            num(*cos_i),
            num(*n1),
            num(*n2)
        )
    }

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let ReflectanceCase {
            schlick,
            cos_i,
            n1,
            n2,
            expect,
        } = self;
        let got = if *schlick {
            C::schlick(*cos_i, *n1, *n2)
        } else {
            C::fresnel(*cos_i, *n1, *n2)
        };
        // A reflectance is a share in [0, 1]: 1e-6 absolute is a few
        // f32 roundings of it, far below what any image shows.
        // An expected NaN is the answer to an invalid index: only NaN
        // passes.
        let pass = if expect.is_nan() {
            got.is_nan()
        } else {
            (f64::from(got) - expect).abs() <= 1e-6
        };
        verdict(pass, num64(*expect), num(got))
    }
}

/// `transmittance(absorption, distance)`: expected `exp(-a d)` per
/// channel, within `1e-6` relative.
#[derive(Debug, Clone)]
pub struct TransmittanceCase {
    pub absorption: Vec3,
    pub distance: f32,
}

impl TransmittanceCase {
    /// The course function this case calls.
    pub fn function(&self) -> &'static str {
        "transmittance"
    }

    /// The inputs, as the call would receive them.
    pub fn inputs(&self) -> String {
        let TransmittanceCase {
            absorption,
            distance,
        } = self;
        format!(
            "transmittance(absorption {}, distance {})",
            vec(*absorption),
            num(*distance)
        )
    }

    /// Asks the question of the chapters `C`, with the same tolerance at
    /// both levels.
    pub(super) fn evaluate<C: Chapters>(&self, _robust: bool) -> Outcome {
        let TransmittanceCase {
            absorption,
            distance,
        } = self;
        let got = C::transmittance(*absorption, *distance);
        let want = wide(*absorption).map(|a| {
            if a == 0.0 {
                1.0
            } else {
                (-a * f64::from(*distance)).exp()
            }
        });
        let pass = got.is_finite()
            && (wide(got) - want)
                .abs()
                .cmple(want.abs() * 1e-6 + DVec3::splat(1e-30))
                .all();
        verdict(pass, vec64(want), vec(got))
    }
}
