//! The runtime's wavelength-set and rule types.

/// One of the three opponent channels of AC1C2 space.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    /// The achromatic channel, close to luminance ȳ.
    A,
    /// The red–green channel: positive in the green, negative in the red.
    C1,
    /// The yellow–blue channel: positive in the blue.
    C2,
}

impl Channel {
    /// The channels in row order.
    pub const ALL: [Channel; 3] = [Channel::A, Channel::C1, Channel::C2];

    /// The row of this channel in a weight matrix: 0, 1 or 2.
    pub const fn index(self) -> usize {
        match self {
            Channel::A => 0,
            Channel::C1 => 1,
            Channel::C2 => 2,
        }
    }

    /// `"A"`, `"C1"` or `"C2"`.
    pub const fn name(self) -> &'static str {
        match self {
            Channel::A => "A",
            Channel::C1 => "C1",
            Channel::C2 => "C2",
        }
    }
}

/// Whether a Gauss rule of some order exists, and if not, why.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
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
    /// `"defined"`, `"outside"`, `"complex"` or `"vanishing-norm"`.
    pub const fn as_str(self) -> &'static str {
        match self {
            RuleStatus::Defined => "defined",
            RuleStatus::Outside => "outside",
            RuleStatus::Complex => "complex",
            RuleStatus::VanishingNorm => "vanishing-norm",
        }
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
pub struct GaussRule {
    /// The channel whose sensitivity is the weight function.
    pub channel: Channel,
    /// The number of nodes n.
    pub order: u8,
    /// Whether the rule exists; `wavelengths_nm` and `weights` are empty unless `Defined`.
    pub status: RuleStatus,
    /// Nodes in nm, ascending.
    pub wavelengths_nm: &'static [f32],
    /// Weights for dλ in nm: `channel ≈ Σ weights[i] · spectrum(wavelengths_nm[i])`.
    pub weights: &'static [f32],
}

/// N distinct wavelengths and a 3×N weight matrix that turns samples of a spectrum at those
/// wavelengths into A, C1 and C2.
///
/// Every set the crate offers has this type: a per-channel Gauss rule (two rows zero), Table 2's
/// merged sets, and any other set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WavelengthSet<const N: usize> {
    /// Wavelengths in nm, ascending and distinct.
    pub wavelengths_nm: [f32; N],
    /// `weights[channel][i]`, rows A, C1, C2, for dλ in nm.
    pub weights: [[f32; N]; 3],
    /// What the samples are: radiances, or reflectances under a light folded into the weights.
    pub samples: Samples,
}

impl<const N: usize> WavelengthSet<N> {
    /// The number of distinct wavelengths, N.
    pub const LEN: usize = N;

    /// `[A, C1, C2]` from samples of a spectrum at [`wavelengths_nm`](Self::wavelengths_nm):
    /// the 3×N product `weights · samples`, in f32.
    ///
    /// Never panics. Each output is a plain sum of products over all N samples, so IEEE rules
    /// apply: a NaN sample makes every channel NaN, and an infinite sample makes every channel
    /// ±Inf or NaN (NaN where its weight is 0, since 0 · ∞ = NaN, or where infinities of both
    /// signs meet); subnormal and negative samples are used as they are; products or sums beyond
    /// `f32::MAX` overflow to ±Inf.
    ///
    /// # Accuracy
    /// For finite samples whose products do not overflow, each channel is within
    /// [`f32_budget`](crate::f32_budget)`(N, Σ_i |w_i · s_i|)` of the exact sum with the f64
    /// weights of the derivation: the weights' rounding to f32 (½ ε each), N products (½ ε
    /// each) and N − 1 additions (½ ε each, times the running sum), ε = `f32::EPSILON`, plus
    /// N half-units of the smallest subnormal for products that underflow.
    ///
    /// The budget is absolute (relative to Σ|w_i · s_i|) and holds for every finite input with
    /// Σ|w_i · s_i| · (1 + (N + 1)ε) < `f32::MAX`: ±`f32::MAX` in some samples, subnormals,
    /// mixtures of 1e38 and 1e-45, and samples that make C1 or C2 cancel. Under cancellation the
    /// relative error of a signed channel can be large (tests/extremes.rs measures up to 7e3 for
    /// C1 at the rounding level, and at most 0.35 of the budget over 194 985 extreme inputs).
    /// Beyond that bound a channel may overflow to ±Inf or NaN.
    #[inline]
    pub fn ac1c2(&self, samples: &[f32; N]) -> [f32; 3] {
        mat_vec(&self.weights, samples)
    }

    /// `[X, Y, Z]` from samples: [`ac1c2`](Self::ac1c2) followed by
    /// [`AC1C2_TO_XYZ`](crate::tables::AC1C2_TO_XYZ). XYZ are in the units of the weights (dλ in
    /// nm): a spectrum of constant 1 has Y ≈ [`UNIT_SPECTRUM_Y`](crate::tables::UNIT_SPECTRUM_Y).
    /// IEEE arithmetic, as [`ac1c2`](Self::ac1c2).
    #[inline]
    pub fn xyz(&self, samples: &[f32; N]) -> [f32; 3] {
        crate::xyz_from_ac1c2(self.ac1c2(samples))
    }

    /// Folds AC1C2 → XYZ → the display's linear RGB and a `scale` into the weights, in f32, so
    /// that [`FoldedSet::linear_rgb`] is one 3×N product; the folded set keeps `display` (its
    /// encoders use it) and [`samples`](Self::samples). The baked
    /// [`folded`](crate::tables::folded) sets do the same in f64 at build time with
    /// `scale = 1 / UNIT_SPECTRUM_Y`. Non-finite weights or scale propagate into the result.
    pub fn fold(&self, display: &crate::Display, scale: f32) -> FoldedSet<N> {
        let m = crate::mat3_mul(&display.xyz_to_rgb, &crate::tables::AC1C2_TO_XYZ);
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
/// RGB is one 3×N product.
///
/// The set carries the display it was folded for, and its encoders use that display's transfer
/// function, so weights and encoding cannot be paired wrongly:
///
/// ```
/// use spectral_quadrature::tables::folded::TABLE2_ROW2_SRGB;
/// use spectral_quadrature::GamutMapping;
/// let px = TABLE2_ROW2_SRGB.encode_u8(GamutMapping::Clip, &[0.5; 4]);
/// assert_eq!(TABLE2_ROW2_SRGB.display.name, "sRGB");
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
pub struct FoldedSet<const N: usize> {
    /// Wavelengths in nm, ascending and distinct.
    pub wavelengths_nm: [f32; N],
    /// `weights[channel][i]`, rows R, G, B.
    pub weights: [[f32; N]; 3],
    /// What the samples are: radiances, or reflectances under a light folded into the weights.
    pub samples: Samples,
    /// The display the weights were folded for: its transfer function encodes the output.
    pub display: crate::Display,
}

impl<const N: usize> FoldedSet<N> {
    /// Linear RGB from samples at [`wavelengths_nm`](Self::wavelengths_nm).
    ///
    /// Never panics. IEEE arithmetic, as [`WavelengthSet::ac1c2`]: a NaN sample makes every
    /// channel NaN, an infinite one makes every channel ±Inf or NaN, subnormal and negative
    /// samples are used as they are, products or sums beyond `f32::MAX` overflow to ±Inf. Out-of-gamut colours have channels below 0 or above 1; see
    /// [`Display::map_gamut`](crate::Display::map_gamut).
    ///
    /// # Accuracy
    /// As [`WavelengthSet::ac1c2`]: each channel within
    /// [`f32_budget`](crate::f32_budget)`(N, Σ_i |w_i · s_i|)` of the exact product with the f64
    /// folded weights. The colour matrices were multiplied into the weights in f64, so they add
    /// no f32 error of their own.
    #[inline]
    pub fn linear_rgb(&self, samples: &[f32; N]) -> [f32; 3] {
        mat_vec(&self.weights, samples)
    }

    /// Samples → gamut-mapped, encoded 8-bit RGB with the set's [`display`](Self::display).
    /// NaN anywhere → black; see [`Display::encode_u8`](crate::Display::encode_u8).
    ///
    /// The bytes of `self.display.encode_u8(self.linear_rgb(samples), mapping)`. Each channel's
    /// sum starts from its first product instead of 0.0 (one addition less), which differs
    /// only where the sum is an exact zero (−0.0 instead of +0.0, and both encode to 0). On
    /// x86-64, the sRGB curve with `Clip` runs with the three channels in one SSE2 register:
    /// the same f32 operations, so the same bytes.
    #[inline]
    pub fn encode_u8(&self, mapping: crate::GamutMapping, samples: &[f32; N]) -> [u8; 3] {
        // x86-64: the product and the encoder with the channels in the lanes of one SSE2
        // register (the same operations, so the same bytes; see `simd`).
        #[cfg(target_arch = "x86_64")]
        if self.display.is_srgb_clip(mapping) {
            return crate::simd::sse2::encode_srgb8(&self.weights, samples);
        }
        self.display
            .encode_u8(mat_vec_for_encoding(&self.weights, samples), mapping)
    }

    /// As [`encode_u8`](Self::encode_u8), 16 bits.
    #[inline]
    pub fn encode_u16(&self, mapping: crate::GamutMapping, samples: &[f32; N]) -> [u16; 3] {
        self.display.encode_u16(self.linear_rgb(samples), mapping)
    }
}

/// `weights · samples` for a 3×N matrix, accumulated in index order in f32.
///
/// One pass over the samples with the three rows side by side (each row's sum is still
/// 0 + w₀s₀ + w₁s₁ + … in that order): where the loop is not unrolled (opt-level "s" on a
/// microcontroller) its overhead is paid N times instead of 3N.
#[inline]
pub(crate) fn mat_vec<const N: usize>(weights: &[[f32; N]; 3], samples: &[f32; N]) -> [f32; 3] {
    let [w0, w1, w2] = weights;
    let (mut a, mut b, mut c) = (0.0f32, 0.0f32, 0.0f32);
    for i in 0..N {
        let s = samples[i];
        a += w0[i] * s;
        b += w1[i] * s;
        c += w2[i] * s;
    }
    [a, b, c]
}

/// [`mat_vec`] starting each sum from its first product instead of 0.0: one addition less on
/// each channel's chain, and the same value except that an exact zero may come out as −0.0
/// where `mat_vec` gives +0.0 (0.0 + (−0.0) = +0.0). Every encoder maps both zeros to code 0,
/// so the encoded colour is the same.
#[inline]
pub(crate) fn mat_vec_for_encoding<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: &[f32; N],
) -> [f32; 3] {
    if N == 0 {
        return [0.0; 3];
    }
    let [w0, w1, w2] = weights;
    let s = samples[0];
    let (mut a, mut b, mut c) = (w0[0] * s, w1[0] * s, w2[0] * s);
    for i in 1..N {
        let s = samples[i];
        a += w0[i] * s;
        b += w1[i] * s;
        c += w2[i] * s;
    }
    [a, b, c]
}
