//! The runtime's wavelength-set and rule types.

#![forbid(unsafe_code)]

use super::error::check_length;
use crate::{Channel, LengthOf};

/// Whether a Gauss rule of some order exists, and if not, why.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RuleStatus {
    /// All nodes real and inside the spectrum's range: the rule can be used.
    Defined,
    /// The nodes are real but at least one lies outside the range.
    Outside,
    /// Some nodes are complex (possible because C1 and C2 change sign).
    Complex,
    /// A norm ⟨P_k, P_k⟩ of the recurrence vanished, so the orthogonal polynomial of this order
    /// does not exist.
    VanishingNorm,
}

impl RuleStatus {
    /// The status's identifier, `"defined"`, `"outside"`, `"complex"` or `"vanishing-norm"`
    /// (kebab-case, stable across versions; the generator's CSV files write the same words).
    /// Its [`Display`](core::fmt::Display) is the sentence for messages.
    pub const fn name(self) -> &'static str {
        match self {
            RuleStatus::Defined => "defined",
            RuleStatus::Outside => "outside",
            RuleStatus::Complex => "complex",
            RuleStatus::VanishingNorm => "vanishing-norm",
        }
    }
}

impl core::fmt::Display for RuleStatus {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            RuleStatus::Defined => "all nodes real and inside the range",
            RuleStatus::Outside => "a node outside the range",
            RuleStatus::Complex => "complex nodes",
            RuleStatus::VanishingNorm => "the orthogonal polynomial of this order does not exist",
        })
    }
}

/// What a set's samples are, and so what its weights integrate.
///
/// A set for radiances takes samples of the spectrum that reaches the eye (emission, or
/// reflectance times light computed by the renderer). A set with a light folded in takes
/// samples of a reflectance and multiplies by that light in its weights: feeding it radiances
/// gives wrong colours, silently, so the set carries this field and the docs, `Debug` and
/// `defmt` output show it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Samples {
    /// Samples of a spectral radiance (or of any spectrum whose colour is wanted as given).
    Radiance,
    /// Samples of a reflectance lit by a light that is folded into the weights.
    Reflectance {
        /// The light's name, e.g. `"C"`, `"F11"` (a built-in illuminant), or the name a scene
        /// gave a light read from a file.
        light: &'static str,
    },
    /// The readings of a spectral sensor's channels, in the sensor's order: the set's
    /// `wavelengths_nm` are each channel's peak, not wavelengths to sample at. A reading is
    /// `∫ S_k(λ) e(λ) dλ` of the radiance e reaching the sensor, in the units of the scene's
    /// sensor file times nm.
    ///
    /// The set's XYZ from such readings is in the weights' units, dλ in nm: a calibrated white
    /// (readings equal to the golden device's on a perfect white,
    /// `tables::sensors::<NAME>_WHITE`) gives Y =
    /// [`UNIT_SPECTRUM_Y`](crate::tables::UNIT_SPECTRUM_Y) (about 106.86), not 1; divide by it
    /// for Y = 1 at white, as the folded sets do.
    Readings {
        /// The sensor's name in the scene.
        sensor: &'static str,
        /// The light the weights were fitted for (reflectances under it), or `None` (radiances).
        light: Option<&'static str>,
    },
}

impl Samples {
    /// The light folded into (or, for sensor readings, assumed by) the weights, if any.
    pub const fn light(self) -> Option<&'static str> {
        match self {
            Samples::Radiance => None,
            Samples::Reflectance { light } => Some(light),
            Samples::Readings { light, .. } => light,
        }
    }

    /// The sensor whose channel readings the samples are, if any.
    pub const fn sensor(self) -> Option<&'static str> {
        match self {
            Samples::Readings { sensor, .. } => Some(sensor),
            _ => None,
        }
    }
}

/// One channel's Gauss rule of one order, as baked by the build script.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GaussRule {
    // Private: every rule, the baked ones too, is made by `new`.
    channel: Channel,
    order: u8,
    status: RuleStatus,
    wavelengths_nm: &'static [f32],
    weights: &'static [f32],
}

impl GaussRule {
    /// A rule of `order` nodes for `channel`, checked: with `status` [`RuleStatus::Defined`]
    /// `wavelengths_nm` and `weights` have `order` entries each, otherwise none (else
    /// [`Error::LengthMismatch`](crate::Error::LengthMismatch) with
    /// [`LengthOf::RuleWavelengths`](crate::LengthOf::RuleWavelengths) or
    /// [`LengthOf::RuleWeights`](crate::LengthOf::RuleWeights), `expected` that count); every
    /// wavelength finite, positive and
    /// above the one before (else [`Error::InvalidWavelength`](crate::Error::InvalidWavelength));
    /// every weight finite (else [`Error::InvalidWeight`](crate::Error::InvalidWeight), `row`
    /// the channel's). Never panics; usable in consts.
    pub const fn new(
        channel: Channel,
        order: u8,
        status: RuleStatus,
        wavelengths_nm: &'static [f32],
        weights: &'static [f32],
    ) -> Result<GaussRule, crate::Error> {
        let expected = match status {
            RuleStatus::Defined => order as usize,
            _ => 0,
        };
        if let Err(e) = check_length(LengthOf::RuleWavelengths, expected, wavelengths_nm.len()) {
            return Err(e);
        }
        if let Err(e) = check_length(LengthOf::RuleWeights, expected, weights.len()) {
            return Err(e);
        }
        if let Err(e) = check_wavelengths(wavelengths_nm, false) {
            return Err(e);
        }
        if let Err(index) = check_finite(weights) {
            return Err(crate::Error::InvalidWeight {
                row: channel.index(),
                index,
            });
        }
        Ok(GaussRule {
            channel,
            order,
            status,
            wavelengths_nm,
            weights,
        })
    }

    /// The channel whose sensitivity is the weight function.
    pub const fn channel(&self) -> Channel {
        self.channel
    }

    /// The number of nodes n.
    pub const fn order(&self) -> u8 {
        self.order
    }

    /// Whether the rule exists; [`wavelengths_nm`](Self::wavelengths_nm) and
    /// [`weights`](Self::weights) are empty unless `Defined`.
    pub const fn status(&self) -> RuleStatus {
        self.status
    }

    /// Nodes in nm, ascending.
    pub const fn wavelengths_nm(&self) -> &'static [f32] {
        self.wavelengths_nm
    }

    /// Weights for dλ in nm: `channel ≈ Σ weights[i] · spectrum(wavelengths_nm[i])`.
    pub const fn weights(&self) -> &'static [f32] {
        self.weights
    }
}

/// `Err(Error::InvalidWavelength)` at the first wavelength that is not finite and positive or,
/// unless `any_order` (a sensor's channel peaks), not above the one before.
const fn check_wavelengths(wavelengths_nm: &[f32], any_order: bool) -> Result<(), crate::Error> {
    let mut i = 0;
    while i < wavelengths_nm.len() {
        let l = wavelengths_nm[i];
        let ordered = any_order || i == 0 || l > wavelengths_nm[i - 1];
        if !(l.is_finite() && l > 0.0 && ordered) {
            return Err(crate::Error::InvalidWavelength { index: i });
        }
        i += 1;
    }
    Ok(())
}

/// The index of the first value that is not finite.
const fn check_finite(values: &[f32]) -> Result<(), usize> {
    let mut i = 0;
    while i < values.len() {
        if !values[i].is_finite() {
            return Err(i);
        }
        i += 1;
    }
    Ok(())
}

/// [`check_wavelengths`] and [`check_finite`] on each row of a set's weights.
const fn check_set<const N: usize>(
    wavelengths_nm: &[f32; N],
    weights: &[[f32; N]; 3],
    samples: Samples,
) -> Result<(), crate::Error> {
    let any_order = matches!(samples, Samples::Readings { .. });
    if let Err(e) = check_wavelengths(wavelengths_nm, any_order) {
        return Err(e);
    }
    let mut row = 0;
    while row < 3 {
        if let Err(index) = check_finite(&weights[row]) {
            return Err(crate::Error::InvalidWeight { row, index });
        }
        row += 1;
    }
    Ok(())
}

/// The most wavelengths (or sensor channels), N, of a [`FoldedSet`] whose planar functions
/// ([`linear_rgb_planar`](FoldedSet::linear_rgb_planar),
/// [`encode_u8_planar`](FoldedSet::encode_u8_planar),
/// [`encode_u8_planar_to_interleaved`](FoldedSet::encode_u8_planar_to_interleaved),
/// [`encode_u16_planar`](FoldedSet::encode_u16_planar),
/// [`encode_u16_planar_to_interleaved`](FoldedSet::encode_u16_planar_to_interleaved)) or
/// [`encode_u8_batch`](FoldedSet::encode_u8_batch) are called: those check N against it at
/// compile time, and a call with a larger N stops the build (`cargo build`; `cargo check` does
/// not evaluate the check). The generator bakes no larger set (`UNIFORM_64`, and user and
/// sensor sets of up to 64 samples, are its largest).
///
/// The bound is on the stack: those functions' loops keep arrays of N elements on the stack for
/// the length of a call. The largest are the AVX-512 loops' (the weights broadcast to 3·N
/// registers of 64 bytes and N registers of samples: 256·N bytes, with copies of the N planes'
/// slices besides) and the AVX2 loops' (a block's partial sums, 12 KiB at every N above 4, and
/// two groups' samples, 64·N bytes); the portable loops hold 64·N bytes of samples per chunk and
/// its products. The deepest call on x86-64 takes about 1.7 KiB of stack at N = 4, 14 KiB at
/// N = 16 and 35 KiB at N = 64 (docs/performance.md, "Stack use per N", has each loop's frame
/// and the command that measures them): well inside the 2 MiB of a spawned thread, but worth
/// knowing on a small stack. On a microcontroller the scalar loop's frame grows by 12·N bytes
/// for the weights it copies.
///
/// The per-pixel functions, [`fold`](WavelengthSet::fold) and the other batch functions
/// ([`ac1c2_batch`](WavelengthSet::ac1c2_batch),
/// [`linear_rgb_batch`](FoldedSet::linear_rgb_batch),
/// [`encode_u16_batch`](FoldedSet::encode_u16_batch)) keep nothing on the stack that grows with
/// N beyond the caller's samples (`fold`: its 3×N result), and take any N: a reference
/// integration over every 1 nm (N = 391) is a set too.
///
/// With N = 0 (no samples, a set of no wavelengths) every path gives the colour of no signal:
/// `[0.0, 0.0, 0.0]` from the linear functions, the display's encoding of black from the
/// encoders, for every pixel of a batch or planar call (whose pixel count then comes from its
/// output, there being no planes).
///
/// ```compile_fail
/// use spectral_quadrature::{tables::folded::TABLE2_ROW2_SRGB as SRGB, FoldedSet};
/// let nm = core::array::from_fn(|i| 400.0 + i as f32);
/// let wide = FoldedSet::<65>::new(nm, [[0.0; 65]; 3], SRGB.samples(), SRGB.display()).unwrap();
/// let planes = [&[0.5f32][..]; 65];
/// let (mut r, mut g, mut b) = ([0.0f32], [0.0f32], [0.0f32]);
/// let _ = wide.linear_rgb_planar(planes, [&mut r, &mut g, &mut b]);
/// ```
pub const MAX_WAVELENGTHS: usize = 64;

/// Stops the build of a planar function or `encode_u8_batch` for N above [`MAX_WAVELENGTHS`]
/// (evaluated when the function is compiled for that N).
#[inline(always)]
pub(crate) const fn assert_width<const N: usize>() {
    const {
        assert!(
            N <= MAX_WAVELENGTHS,
            "the planar functions and encode_u8_batch take at most MAX_WAVELENGTHS (64) wavelengths"
        )
    }
}

/// N distinct wavelengths and a 3×N weight matrix that turns samples of a spectrum at those
/// wavelengths into A, C1 and C2.
///
/// Every set the crate offers has this type: a per-channel Gauss rule (two rows zero), Table 2's
/// merged sets, and any other set. N = 0 is allowed and gives the colour of no signal; the
/// planar and 8-bit batch loops of [`FoldedSet`] take N up to [`MAX_WAVELENGTHS`] (see there).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WavelengthSet<const N: usize> {
    // Private: every set, the baked ones too, is made by `new` (or `fold`).
    wavelengths_nm: [f32; N],
    weights: [[f32; N]; 3],
    samples: Samples,
}

impl<const N: usize> WavelengthSet<N> {
    /// The number of distinct wavelengths, N.
    pub const LEN: usize = N;

    /// A set of your own: wavelengths in nm, `weights[channel][i]` (rows A, C1, C2, for dλ in
    /// nm) and what the samples are. Checked, never a panic, usable in consts: every wavelength
    /// finite, positive and (except for [`Samples::Readings`], whose "wavelengths" are the
    /// sensor channels' peaks in the sensor's order) above the one before, else
    /// [`Error::InvalidWavelength`](crate::Error::InvalidWavelength) at the first that is not;
    /// every weight finite, else [`Error::InvalidWeight`](crate::Error::InvalidWeight).
    ///
    /// ```
    /// use spectral_quadrature::{Samples, WavelengthSet};
    /// const MINE: WavelengthSet<2> = match WavelengthSet::new(
    ///     [450.0, 600.0],
    ///     [[20.0, 80.0], [-10.0, 10.0], [30.0, -5.0]],
    ///     Samples::Radiance,
    /// ) {
    ///     Ok(set) => set,
    ///     Err(_) => panic!("not a set"),
    /// };
    /// assert_eq!(MINE.ac1c2(&[1.0, 1.0]), [100.0, 0.0, 25.0]);
    /// assert!(WavelengthSet::new([600.0, 450.0], [[0.0; 2]; 3], Samples::Radiance).is_err());
    /// ```
    pub const fn new(
        wavelengths_nm: [f32; N],
        weights: [[f32; N]; 3],
        samples: Samples,
    ) -> Result<WavelengthSet<N>, crate::Error> {
        if let Err(e) = check_set(&wavelengths_nm, &weights, samples) {
            return Err(e);
        }
        Ok(WavelengthSet {
            wavelengths_nm,
            weights,
            samples,
        })
    }

    /// Wavelengths in nm, ascending and distinct (sensor readings: each channel's peak, in the
    /// sensor's order): the order of the samples.
    pub const fn wavelengths_nm(&self) -> [f32; N] {
        self.wavelengths_nm
    }

    /// `weights[channel][i]`, rows A, C1, C2, for dλ in nm.
    pub const fn weights(&self) -> [[f32; N]; 3] {
        self.weights
    }

    /// What the samples are: radiances, or reflectances under a light folded into the weights,
    /// or a sensor's readings.
    pub const fn samples(&self) -> Samples {
        self.samples
    }

    /// [`weights`](Self::weights) by reference, for the crate's own paths (the fields are
    /// private, so that a set is made by a checked constructor; the accessors copy).
    #[inline(always)]
    pub(crate) const fn weights_ref(&self) -> &[[f32; N]; 3] {
        &self.weights
    }

    /// Folds AC1C2 → XYZ → the display's linear RGB and a `scale` into the weights, in f32, so
    /// that [`FoldedSet::linear_rgb`] is one 3×N product; the folded set keeps `display` (its
    /// encoders use it) and [`samples`](Self::samples). The baked
    /// [`folded`](crate::tables::folded) sets do the same in f64 at build time with
    /// `scale = 1 / UNIT_SPECTRUM_Y`. Non-finite weights or scale propagate into the result; with
    /// N = 0 the folded set has no weights either.
    pub fn fold(&self, display: &crate::Display, scale: f32) -> FoldedSet<N> {
        let m = super::matrix::mat3_mul(&display.xyz_to_rgb(), &crate::tables::AC1C2_TO_XYZ);
        let mut weights = [[0.0f32; N]; 3];
        for (r, row) in weights.iter_mut().enumerate() {
            for (i, w) in row.iter_mut().enumerate() {
                *w = scale
                    * (m[r][0] * self.weights[0][i]
                        + m[r][1] * self.weights[1][i]
                        + m[r][2] * self.weights[2][i]);
            }
        }
        FoldedSet {
            wavelengths_nm: self.wavelengths_nm,
            weights,
            samples: self.samples,
            display: *display,
        }
    }
}

/// A wavelength set with a display's colour matrix folded into its weights: samples → linear
/// RGB is one 3×N product. Its planar functions and `encode_u8_batch` take N up to
/// [`MAX_WAVELENGTHS`] (checked at compile time).
///
/// The set carries the display it was folded for, and its encoders use that display's transfer
/// function, so weights and encoding cannot be paired wrongly:
///
/// ```
/// use spectral_quadrature::tables::folded::TABLE2_ROW2_SRGB;
/// use spectral_quadrature::GamutMapping;
/// let px = TABLE2_ROW2_SRGB.encode_u8(GamutMapping::Clip, &[0.5; 4]);
/// assert_eq!(TABLE2_ROW2_SRGB.display().name(), "sRGB");
/// # let _ = px;
/// ```
///
/// There is no way to hand it another display (the old form, with a display argument, no longer
/// compiles):
///
/// ```compile_fail
/// use spectral_quadrature::tables::{displays, folded::TABLE2_ROW2_SRGB};
/// use spectral_quadrature::GamutMapping;
/// let px = TABLE2_ROW2_SRGB.encode_u8(&displays::DISPLAY_P3, GamutMapping::Clip, &[0.5; 4]);
/// ```
///
/// The baked sets ([`tables::folded`](crate::tables::folded)) take samples in units where a
/// spectrum of constant 1 has luminance Y = 1, the luminance of the display's white (its
/// chromaticity is that of illuminant E, not of the display's white point).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FoldedSet<const N: usize> {
    // Private: every set, the baked ones too, is made by `new` (or `WavelengthSet::fold`).
    wavelengths_nm: [f32; N],
    weights: [[f32; N]; 3],
    samples: Samples,
    display: crate::Display,
}

impl<const N: usize> FoldedSet<N> {
    /// A folded set of your own: wavelengths in nm, `weights[channel][i]` (rows R, G, B: linear
    /// RGB of `display` per unit sample), what the samples are, and the display whose transfer
    /// function encodes the output. Checked as [`WavelengthSet::new`] checks (never a panic,
    /// usable in consts). [`WavelengthSet::fold`] makes one from an AC1C2 set.
    pub const fn new(
        wavelengths_nm: [f32; N],
        weights: [[f32; N]; 3],
        samples: Samples,
        display: crate::Display,
    ) -> Result<FoldedSet<N>, crate::Error> {
        if let Err(e) = check_set(&wavelengths_nm, &weights, samples) {
            return Err(e);
        }
        Ok(FoldedSet {
            wavelengths_nm,
            weights,
            samples,
            display,
        })
    }

    /// Wavelengths in nm, ascending and distinct (sensor readings: each channel's peak, in the
    /// sensor's order): the order of the samples.
    pub const fn wavelengths_nm(&self) -> [f32; N] {
        self.wavelengths_nm
    }

    /// `weights[channel][i]`, rows R, G, B.
    pub const fn weights(&self) -> [[f32; N]; 3] {
        self.weights
    }

    /// What the samples are: radiances, or reflectances under a light folded into the weights,
    /// or a sensor's readings.
    pub const fn samples(&self) -> Samples {
        self.samples
    }

    /// The display the weights were folded for: its transfer function encodes the output.
    pub const fn display(&self) -> crate::Display {
        self.display
    }

    /// [`weights`](Self::weights) by reference, for the crate's own paths (the fields are
    /// private, so that a set is made by a checked constructor; the accessors copy).
    #[inline(always)]
    pub(crate) const fn weights_ref(&self) -> &[[f32; N]; 3] {
        &self.weights
    }

    /// [`wavelengths_nm`](Self::wavelengths_nm) by reference.
    #[inline(always)]
    pub(crate) const fn wavelengths_ref(&self) -> &[f32; N] {
        &self.wavelengths_nm
    }

    /// [`display`](Self::display) by reference.
    #[inline(always)]
    pub(crate) const fn display_ref(&self) -> &crate::Display {
        &self.display
    }

    /// A folded set of parts already checked (a light-group set's member): what
    /// [`new`](Self::new) would give for them, without checking again.
    pub(crate) const fn from_checked(
        wavelengths_nm: [f32; N],
        weights: [[f32; N]; 3],
        samples: Samples,
        display: crate::Display,
    ) -> FoldedSet<N> {
        FoldedSet {
            wavelengths_nm,
            weights,
            samples,
            display,
        }
    }
}
