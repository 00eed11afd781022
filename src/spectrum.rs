//! Wavelengths and the colours they are seen as, for chapter 14's
//! dispersion: the CIE 1931 colour-matching functions (the analytic fit of
//! Wyman, Sloan and Shirley, JCGT 2013), their conversion to linear sRGB,
//! and the colour one wavelength carries when white light is split.
//!
//! raylab's lights and materials are RGB. White light split into
//! wavelengths is modelled as: wavelength `lambda`, drawn uniformly in
//! [`VISIBLE`], carries the linear sRGB colour [`rgb_weight`]`(lambda)`,
//! scaled so that its mean over the visible range is exactly `(1, 1, 1)`.
//! A path that draws one wavelength and multiplies what it carries by
//! that colour is then, on average, the RGB path of chapter 13: with an
//! index of refraction that does not depend on the wavelength the image
//! converges to the same one (chapter 14's tests), and a prism spreads the
//! white into the colours of the spectrum.

use std::sync::OnceLock;

use crate::Vec3;

/// The wavelengths drawn, in nanometres: the CIE's conventional visible
/// range. With [`cie_xyz`]'s fit, `x` and `y` fall below 0.5% of their
/// peaks past about 700 nm and `z` below 383 nm, so about a fifth of the
/// draws (380 to 383 nm and 700 to 780 nm) carry almost no colour. They add
/// a little noise but no bias, since [`rgb_weight`] is scaled to average
/// to white over this whole range.
pub const VISIBLE: (f32, f32) = (380.0, 780.0);

/// The helium d line (587.56 nm), where glass catalogues quote the index
/// `n_d`: the index a non-dispersive stage takes for a dispersive glass.
pub const D_LINE_NM: f32 = 587.56;

/// A piecewise Gaussian: `exp(-(x - mean)^2 / 2 sigma^2)`, with `sigma`
/// one value left of the mean and another right of it. Written with the
/// inverse widths the paper tabulates.
fn lobe(x: f32, mean: f32, inverse_left: f32, inverse_right: f32) -> f32 {
    let scaled = (x - mean)
        * if x < mean {
            inverse_left
        } else {
            inverse_right
        };
    // `libm`'s `expf`: the same bits on every platform, so that pinned
    // images do not depend on the machine's maths library.
    libm::expf(-0.5 * scaled * scaled)
}

/// The CIE 1931 2-degree colour-matching functions `(x, y, z)` at
/// `nanometres`, by the multi-lobe fit of Wyman, Sloan and Shirley
/// ("Simple Analytic Approximations to the CIE XYZ Color Matching
/// Functions", JCGT 2(2), 2013, equation 2 and table 1): within a few
/// thousandths of the tabulated functions across the visible range.
pub fn cie_xyz(nanometres: f32) -> Vec3 {
    let x = 1.056 * lobe(nanometres, 599.8, 0.0264, 0.0323)
        + 0.362 * lobe(nanometres, 442.0, 0.0624, 0.0374)
        - 0.065 * lobe(nanometres, 501.1, 0.0490, 0.0382);
    let y = 0.821 * lobe(nanometres, 568.8, 0.0213, 0.0247)
        + 0.286 * lobe(nanometres, 530.9, 0.0613, 0.0322);
    let z = 1.217 * lobe(nanometres, 437.0, 0.0845, 0.0278)
        + 0.681 * lobe(nanometres, 459.0, 0.0385, 0.0725);
    Vec3::new(x, y, z)
}

/// CIE XYZ to linear sRGB (IEC 61966-2-1, D65 white): the rows of the
/// standard's matrix.
pub fn xyz_to_linear_srgb(xyz: Vec3) -> Vec3 {
    Vec3::new(
        3.2406 * xyz.x - 1.5372 * xyz.y - 0.4986 * xyz.z,
        -0.9689 * xyz.x + 1.8758 * xyz.y + 0.0415 * xyz.z,
        0.0557 * xyz.x - 0.2040 * xyz.y + 1.0570 * xyz.z,
    )
}

/// Steps of the midpoint rule that normalises [`rgb_weight`]: the
/// functions are smooth, and 4,000 steps of 0.1 nm put the mean within
/// `1e-6` of itself at twice as many.
const NORMALISING_STEPS: u32 = 4_000;

/// The mean over [`VISIBLE`] of each channel of the unscaled colour of a
/// wavelength, computed once.
fn channel_means() -> Vec3 {
    static MEANS: OnceLock<Vec3> = OnceLock::new();
    *MEANS.get_or_init(|| {
        let (low, high) = VISIBLE;
        let step = (high - low) / NORMALISING_STEPS as f32;
        let mut sum = glam::DVec3::ZERO;
        for index in 0..NORMALISING_STEPS {
            let nanometres = low + (index as f32 + 0.5) * step;
            sum += xyz_to_linear_srgb(cie_xyz(nanometres)).as_dvec3();
        }
        (sum / f64::from(NORMALISING_STEPS)).as_vec3()
    })
}

/// The linear sRGB colour that wavelength `nanometres` carries when white
/// light is split: its colour-matching values in sRGB, each channel divided
/// by that channel's mean over [`VISIBLE`], so that the mean of the weight
/// over a uniformly drawn wavelength is `(1, 1, 1)`. Some channels are
/// negative (a spectral colour lies outside sRGB's triangle of colours):
/// they cancel in the mean, as they must for white to come out white.
/// Zero outside [`VISIBLE`].
pub fn rgb_weight(nanometres: f32) -> Vec3 {
    let (low, high) = VISIBLE;
    if !(low..=high).contains(&nanometres) {
        return Vec3::ZERO;
    }
    xyz_to_linear_srgb(cie_xyz(nanometres)) / channel_means()
}

/// The wavelength, in nanometres, of `u` uniform in `[0, 1)`: uniform over
/// [`VISIBLE`].
pub fn wavelength_of(u: f32) -> f32 {
    let (low, high) = VISIBLE;
    low + u * (high - low)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_peaks_where_the_cie_tables_do() {
        // CIE 1931: y peaks at 555 nm with 1.0; x's main lobe at about
        // 600 nm with 1.06; z at about 445 nm with 1.78.
        let peak = |channel: fn(Vec3) -> f32| {
            (3800..7800)
                .map(|tenth| tenth as f32 / 10.0)
                .max_by(|a, b| channel(cie_xyz(*a)).total_cmp(&channel(cie_xyz(*b))))
                .unwrap_or(0.0)
        };
        assert!((peak(|c| c.y) - 555.0).abs() < 4.0, "{}", peak(|c| c.y));
        assert!((peak(|c| c.x) - 599.0).abs() < 4.0, "{}", peak(|c| c.x));
        assert!((peak(|c| c.z) - 445.0).abs() < 8.0, "{}", peak(|c| c.z));
        assert!((cie_xyz(555.0).y - 1.0).abs() < 0.01);
        assert!((cie_xyz(600.0).x - 1.062).abs() < 0.02);
    }

    #[test]
    fn white_split_into_wavelengths_averages_back_to_white() {
        // A finer rule than the one that normalised: the mean is still 1.
        let steps = 20_000;
        let mut sum = glam::DVec3::ZERO;
        for index in 0..steps {
            let u = (index as f32 + 0.5) / steps as f32;
            sum += rgb_weight(wavelength_of(u)).as_dvec3();
        }
        let mean = sum / f64::from(steps);
        assert!(
            (mean - glam::DVec3::ONE).abs().max_element() < 1e-4,
            "{mean}"
        );
    }

    #[test]
    fn wavelengths_have_the_colours_of_the_rainbow() {
        let dominant = |nanometres: f32| rgb_weight(nanometres).max_position();
        assert_eq!(dominant(450.0), 2, "450 nm is blue");
        assert_eq!(dominant(530.0), 1, "530 nm is green");
        assert_eq!(dominant(640.0), 0, "640 nm is red");
        assert_eq!(rgb_weight(300.0), Vec3::ZERO);
        assert_eq!(rgb_weight(f32::NAN), Vec3::ZERO);
    }

    #[test]
    fn srgb_white_is_d65() {
        // D65's XYZ (0.9505, 1, 1.089) is sRGB's white, (1, 1, 1).
        let white = xyz_to_linear_srgb(Vec3::new(0.9505, 1.0, 1.089));
        assert!((white - Vec3::ONE).abs().max_element() < 2e-3, "{white}");
    }
}
