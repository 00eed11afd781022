//! The checks of a scene file's values that its parts share: finite,
//! within the coordinates a 32-bit float serves ([`crate::limits`]), a
//! colour in range. Each error names the value as the file gave it.

use crate::Vec3;
use crate::limits::{MAX_COORDINATE, MAX_LIGHT, MAX_SHAPE_COORDINATE};

pub(super) fn check_finite(what: &str, value: Vec3) -> Result<(), String> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(format!(
            "{what} = {value}: every component must be a finite number"
        ))
    }
}

/// A point: finite, and within [`MAX_COORDINATE`] on every axis.
pub(super) fn check_point(what: &str, value: Vec3) -> Result<(), String> {
    check_finite(what, value)?;
    if value.abs().max_element() > MAX_COORDINATE {
        return Err(format!(
            "{what} = [{}, {}, {}]: each coordinate must be at most {MAX_COORDINATE:e} \
             in size, so that squared distances fit a 32-bit float",
            readable(value.x),
            readable(value.y),
            readable(value.z)
        ));
    }
    Ok(())
}

pub(super) fn check_coordinates(what: &str, value: Vec3) -> Result<(), String> {
    if value.abs().max_element() > MAX_SHAPE_COORDINATE {
        return Err(format!(
            "{what} = [{}, {}, {}]: shape coordinates must be within {MAX_SHAPE_COORDINATE:e} of \
             the origin; f32 resolves a surface there to 0.06 units, and beyond that the picture \
             degrades (use a plane for a floor that should look infinite)",
            readable(value.x),
            readable(value.y),
            readable(value.z)
        ));
    }
    Ok(())
}

/// `x` as a person would write it: `2e19` rather than twenty digits, `0.5`
/// rather than `5e-1`.
pub(super) fn readable(x: f32) -> String {
    if x == 0.0 || (1e-4..1e7).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A colour of light (a light's colour, the background, the ambient light).
pub(super) fn check_light_color(what: &str, value: Vec3) -> Result<(), String> {
    check_finite(what, value)?;
    if !(value.min_element() >= 0.0 && value.max_element() <= MAX_LIGHT) {
        return Err(format!(
            "{what} = {value}: colour components must be between 0 and {MAX_LIGHT:e}"
        ));
    }
    Ok(())
}

/// A surface's colour: the share of light it returns, so at most 1.
pub(super) fn check_albedo(what: &str, value: Vec3) -> Result<(), String> {
    check_finite(what, value)?;
    if !(value.min_element() >= 0.0 && value.max_element() <= 1.0) {
        return Err(format!(
            "{what} = {value}: a surface returns a share of the light, so each \
             component must be between 0 and 1"
        ));
    }
    Ok(())
}

pub(super) fn check_coefficient(what: &str, value: f32, max: f32) -> Result<(), String> {
    if !(value >= 0.0 && value <= max) {
        return Err(format!("{what} = {value}: must be between 0 and {max}"));
    }
    Ok(())
}
