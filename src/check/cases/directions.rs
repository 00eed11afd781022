//! Cases on how light turns and fades: the mirror and refracted directions,
//! the reflected share and the transmitted light.

use super::*;

/// `reflect(d, n)`: expected the exact mirror image.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ReflectCase {
    pub d: Vec3,
    pub n: Vec3,
}

impl Kind for ReflectCase {
    type Call = ReflectCase;
    type Answer = Vec3;

    fn function(&self) -> &'static str {
        "reflect"
    }

    fn inputs(&self) -> String {
        let ReflectCase { d, n } = self;
        format!("reflect({}, {})", vec(*d), vec(*n))
    }

    fn call(&self) -> ReflectCase {
        self.clone()
    }

    fn ask<C: Chapters>(call: &ReflectCase) -> Result<Vec3, String> {
        Ok(C::reflect(call.d, call.n))
    }

    fn judge(&self, got: Vec3, robust: bool) -> Outcome {
        let ReflectCase { d, n } = self;
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

    /// Both vectors turned, each scaled by its own factor: the mirror
    /// image is worked out again by the oracle.
    fn fresh(&self, draw: &mut Draw) -> Option<ReflectCase> {
        let turn = draw.rotation();
        let (d_scale, n_scale) = (draw.between(0.5, 2.0), draw.between(0.5, 2.0));
        Some(ReflectCase {
            d: (d_scale * (turn * self.d.as_dvec3())).as_vec3(),
            n: (n_scale * (turn * self.n.as_dvec3())).as_vec3(),
        })
    }
}

/// `refract(d, n, eta)`: expected the exact unit direction, or `None`.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct RefractCase {
    pub d: Vec3,
    pub n: Vec3,
    pub eta: f32,
}

impl Kind for RefractCase {
    type Call = RefractCase;
    type Answer = Option<Vec3>;

    fn function(&self) -> &'static str {
        "refract"
    }

    fn inputs(&self) -> String {
        let RefractCase { d, n, eta } = self;
        format!("refract({}, {}, eta = {})", vec(*d), vec(*n), num(*eta))
    }

    fn call(&self) -> RefractCase {
        self.clone()
    }

    fn ask<C: Chapters>(call: &RefractCase) -> Result<Option<Vec3>, String> {
        Ok(C::refract(call.d, call.n, call.eta))
    }

    fn judge(&self, got: Option<Vec3>, robust: bool) -> Outcome {
        let RefractCase { d, n, eta } = self;
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

    /// Both vectors turned together, each scaled (the angle between them,
    /// and so total internal reflection, is kept); `eta` as it is.
    fn fresh(&self, draw: &mut Draw) -> Option<RefractCase> {
        let turn = draw.rotation();
        let (d_scale, n_scale) = (draw.between(0.5, 2.0), draw.between(0.5, 2.0));
        Some(RefractCase {
            d: (d_scale * (turn * self.d.as_dvec3())).as_vec3(),
            n: (n_scale * (turn * self.n.as_dvec3())).as_vec3(),
            eta: self.eta,
        })
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

/// `fresnel` or `schlick`'s inputs.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ReflectanceCall {
    pub schlick: bool,
    pub cos_i: f32,
    pub n1: f32,
    pub n2: f32,
}

impl Kind for ReflectanceCase {
    type Call = ReflectanceCall;
    type Answer = f32;

    fn function(&self) -> &'static str {
        if self.schlick { "schlick" } else { "fresnel" }
    }

    fn inputs(&self) -> String {
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

    fn call(&self) -> ReflectanceCall {
        ReflectanceCall {
            schlick: self.schlick,
            cos_i: self.cos_i,
            n1: self.n1,
            n2: self.n2,
        }
    }

    fn ask<C: Chapters>(call: &ReflectanceCall) -> Result<f32, String> {
        Ok(if call.schlick {
            C::schlick(call.cos_i, call.n1, call.n2)
        } else {
            C::fresnel(call.cos_i, call.n1, call.n2)
        })
    }

    /// The same tolerance at both levels.
    fn judge(&self, got: f32, _robust: bool) -> Outcome {
        let expect = &self.expect;
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

    /// The cosine and both indices nudged by up to 2% (the cosine kept in
    /// `(0, 1]`), the value worked out again by the oracle: Fresnel's
    /// equations, or Schlick's formula with the cosine of the less dense
    /// side. Near the critical angle a nudge could cross it: the cases
    /// there are hard cases, which keep their inputs.
    fn fresh(&self, draw: &mut Draw) -> Option<ReflectanceCase> {
        if !self.expect.is_finite() {
            return None;
        }
        let cos_i = draw.nudge(self.cos_i, 0.02).clamp(1e-3, 1.0);
        let (n1, n2) = (draw.nudge(self.n1, 0.02), draw.nudge(self.n2, 0.02));
        let (c, a, b) = (f64::from(cos_i), f64::from(n1), f64::from(n2));
        let expect = if self.schlick {
            exact::schlick(c, a, b)
        } else {
            exact::fresnel(c, a, b)
        };
        Some(ReflectanceCase {
            schlick: self.schlick,
            cos_i,
            n1,
            n2,
            expect,
        })
    }
}

/// `transmittance(absorption, distance)`: expected `exp(-a d)` per
/// channel, within `1e-6` relative.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct TransmittanceCase {
    pub absorption: Vec3,
    pub distance: f32,
}

impl Kind for TransmittanceCase {
    type Call = TransmittanceCase;
    type Answer = Vec3;

    fn function(&self) -> &'static str {
        "transmittance"
    }

    fn inputs(&self) -> String {
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

    fn call(&self) -> TransmittanceCase {
        self.clone()
    }

    fn ask<C: Chapters>(call: &TransmittanceCase) -> Result<Vec3, String> {
        Ok(C::transmittance(call.absorption, call.distance))
    }

    /// The same tolerance at both levels.
    fn judge(&self, got: Vec3, _robust: bool) -> Outcome {
        let TransmittanceCase {
            absorption,
            distance,
        } = self;
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

    /// Each channel's absorption and the distance nudged by up to 20%
    /// (a zero stays zero, an infinity infinite).
    fn fresh(&self, draw: &mut Draw) -> Option<TransmittanceCase> {
        Some(TransmittanceCase {
            absorption: Vec3::from_array(self.absorption.to_array().map(|a| draw.nudge(a, 0.2))),
            distance: draw.nudge(self.distance, 0.2),
        })
    }
}
