//! Illuminance in lux from a set's luminance Y.

#![forbid(unsafe_code)]

use crate::Error;

/// Lux per unit of a set's Y: what turns the luminance a set gives into illuminance.
///
/// Two ways to know it: from the units of the samples (spectral irradiance in W·m⁻²·nm⁻¹
/// through a set whose weights are for dλ in nm: [`SPECTRAL_IRRADIANCE`](Self::SPECTRAL_IRRADIANCE)),
/// or from one reading of a known light ([`from_reading`](Self::from_reading)): a sensor's
/// readings carry its own gain, so its set is calibrated once against a lamp whose illuminance
/// a reference meter gives (lux meters are calibrated with CIE illuminant A).
///
/// ```
/// use spectral_quadrature::LuxScale;
/// // The set gave Y = 0.0125 for a lamp a meter reads at 500 lx...
/// let scale = LuxScale::from_reading(0.0125, 500.0).unwrap();
/// // ...so a reading with Y = 0.004 is 160 lx.
/// assert!((scale.lux([0.0038, 0.004, 0.0031]) - 160.0).abs() < 1e-3);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LuxScale {
    /// Illuminance in lux for Y = 1, finite and positive.
    lux_per_y: f32,
}

impl LuxScale {
    /// For samples of spectral irradiance in W·m⁻²·nm⁻¹ through a set whose weights are for dλ
    /// in nm (every [`WavelengthSet`](crate::WavelengthSet) the scene bakes; not the folded sets,
    /// which divide by [`UNIT_SPECTRUM_Y`](crate::tables::UNIT_SPECTRUM_Y)): Y is then
    /// ∫ ȳ E dλ in W·m⁻², and K_m = 683.002 lm/W (CIE 015) turns it into lux.
    ///
    /// The V(λ) this assumes is the scene's ȳ over the scene's range (CIE 1931 2° over
    /// 380-770 nm by default): a set approximates that integral, where CIE 015 integrates
    /// V(λ) = ȳ(λ) over 360-830 nm. For the CIE illuminants and LED lights in `data/` the
    /// scene's range leaves out less than 10⁻⁵ of the standard's illuminance (at most
    /// 6.5 × 10⁻⁶, illuminant E; `cargo test --test integration -- sensor_lights:: --nocapture`),
    /// far below a set's own error, so the scale is not corrected for it. With another observer
    /// the scene's ȳ is that observer's, not V(λ).
    pub const SPECTRAL_IRRADIANCE: LuxScale = LuxScale { lux_per_y: 683.002 };

    /// A scale of your own: `lux_per_y`, the illuminance in lux for Y = 1. Checked, never a
    /// panic, usable in consts: [`Error::InvalidLuxScale`] unless it is finite and positive.
    ///
    /// ```
    /// use spectral_quadrature::{Error, LuxScale};
    /// const METER: LuxScale = match LuxScale::new(40_000.0) {
    ///     Ok(scale) => scale,
    ///     Err(_) => panic!("not a scale"),
    /// };
    /// assert_eq!(METER.lux_per_y(), 40_000.0);
    /// assert_eq!(LuxScale::new(0.0), Err(Error::InvalidLuxScale));
    /// ```
    pub const fn new(lux_per_y: f32) -> Result<LuxScale, Error> {
        if lux_per_y.is_finite() && lux_per_y > 0.0 {
            Ok(LuxScale { lux_per_y })
        } else {
            Err(Error::InvalidLuxScale)
        }
    }

    /// From one reading of a known light: `y`, the Y the set gave for it, and `lux`, its
    /// illuminance. Never panics: [`Error::InvalidLuxScale`] unless both are finite and
    /// positive and their ratio is finite (a tiny `y` can overflow it).
    pub fn from_reading(y: f32, lux: f32) -> Result<LuxScale, Error> {
        if !(y > 0.0 && lux > 0.0 && y.is_finite() && lux.is_finite()) {
            return Err(Error::InvalidLuxScale);
        }
        LuxScale::new(lux / y)
    }

    /// Illuminance in lux for Y = 1: finite and positive.
    pub const fn lux_per_y(&self) -> f32 {
        self.lux_per_y
    }

    /// The illuminance of `xyz`: [`lux_per_y`](Self::lux_per_y) · Y, in f32. IEEE arithmetic:
    /// a negative Y (noise in the dark) gives negative lux (clamp with `.max(0.0)` to report
    /// it), NaN and ±Inf propagate; never panics.
    #[inline]
    pub fn lux(&self, xyz: [f32; 3]) -> f32 {
        self.lux_per_y * xyz[1]
    }
}
