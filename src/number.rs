//! Reading the numbers of a scene file. TOML numbers are `f64` (or `i64`);
//! serde's own `f32` turns `1e39` into infinity without a word, and glam's
//! `Vec3` reads the first three elements of any longer array and ignores
//! the rest. These refuse both, naming the value as written (in the
//! shortest form that reads back as the same number).

use std::fmt;

use serde::de::{self, Deserializer, IgnoredAny, SeqAccess, Visitor};

use crate::Vec3;

/// A TOML number as `f32`, or why it does not fit one.
fn to_f32(value: f64) -> Result<f32, String> {
    if !value.is_finite() {
        return Err(format!("{value} is not a finite number"));
    }
    let single = value as f32;
    if !single.is_finite() {
        return Err(format!(
            "{value:e} is too large: numbers are 32-bit floats, at most {:e} in size",
            f32::MAX
        ));
    }
    if single == 0.0 && value != 0.0 {
        return Err(format!(
            "{value:e} is too small: as a 32-bit float it is 0 (the smallest is {:e})",
            f32::from_bits(1)
        ));
    }
    Ok(single)
}

/// Any TOML number, as written, before it is rounded to `f32`.
struct Number(f64);

impl<'de> de::Deserialize<'de> for Number {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_f64(NumberVisitor)
    }
}

struct NumberVisitor;

impl Visitor<'_> for NumberVisitor {
    type Value = Number;

    // "f32", as serde's own message said: the README quotes it.
    fn expecting(&self, formatter: &mut fmt::Formatter) -> fmt::Result {
        formatter.write_str("f32")
    }
    fn visit_f64<E: de::Error>(self, value: f64) -> Result<Number, E> {
        Ok(Number(value))
    }
    fn visit_i64<E: de::Error>(self, value: i64) -> Result<Number, E> {
        Ok(Number(value as f64))
    }
    fn visit_u64<E: de::Error>(self, value: u64) -> Result<Number, E> {
        Ok(Number(value as f64))
    }
}

/// For `#[serde(deserialize_with)]` on `f32` fields.
pub fn f32<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f32, D::Error> {
    let Number(value) = de::Deserialize::deserialize(deserializer)?;
    to_f32(value).map_err(de::Error::custom)
}

/// For `#[serde(deserialize_with)]` on `Vec3` fields: exactly three
/// numbers, each one a finite `f32`.
pub fn vec3<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec3, D::Error> {
    deserializer.deserialize_seq(Vec3Visitor)
}

struct Vec3Visitor;

impl<'de> Visitor<'de> for Vec3Visitor {
    type Value = Vec3;

    fn expecting(&self, formatter: &mut fmt::Formatter) -> fmt::Result {
        formatter.write_str("an array of three numbers [x, y, z]")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec3, A::Error> {
        const AXES: [&str; 3] = ["x", "y", "z"];
        let mut xyz = [0.0f32; 3];
        for (index, axis) in AXES.iter().enumerate() {
            let Some(Number(value)) = seq.next_element()? else {
                return Err(de::Error::custom(format!(
                    "{index} numbers where three are needed: [x, y, z]"
                )));
            };
            xyz[index] =
                to_f32(value).map_err(|message| de::Error::custom(format!("{axis}: {message}")))?;
        }
        let mut extra = 0usize;
        while seq.next_element::<IgnoredAny>()?.is_some() {
            extra += 1;
        }
        if extra > 0 {
            return Err(de::Error::custom(format!(
                "{} elements where three numbers are needed: [x, y, z]",
                3 + extra
            )));
        }
        Ok(Vec3::from_array(xyz))
    }
}
