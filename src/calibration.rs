//! Per-device calibration of a sensor's readings: a dark offset and a gain per channel, so that
//! one device reads like the golden device its set was fitted for.
//!
//! Two forms with the same meaning: [`Calibration`] in f32 (readings as floats, the set's own
//! units out) and [`CountCalibration`] in integers (16-bit counts in, 16-bit counts out, for the
//! integer path on cores without an FPU). Either comes from a reading in the dark and a reading
//! of a white reference at run time, or from the build, which fits one to a device's readings
//! of known reflectances (`[sensors.X] calibration = "readings.csv"`, baked as
//! `tables::sensors::X_CALIBRATION`). Nothing allocates and nothing panics.

#![forbid(unsafe_code)]

use crate::{CalibrationProblem, Error};

/// A device's dark offsets and gains: `apply` gives `(reading − dark) · gain` per channel, the
/// readings the golden device would have given, in the units of the reference it was formed
/// against.
///
/// Formed against a baked sensor's white (`tables::sensors::<NAME>_WHITE`), a calibrated white
/// tile gives the sensor set's XYZ with Y = [`UNIT_SPECTRUM_Y`](crate::tables::UNIT_SPECTRUM_Y)
/// (about 106.86, the weights being for dλ in nm), not 1: divide by it for Y = 1 at white.
///
/// ```
/// use spectral_quadrature::Calibration;
/// // A two-channel device: 12 and 30 counts in the dark, 812 and 630 on a white tile the
/// // golden device reads as 0.8 and 0.6.
/// let cal = Calibration::from_dark_white(&[12.0, 30.0], &[812.0, 630.0], &[0.8, 0.6]).unwrap();
/// assert_eq!(cal.apply(&[412.0, 330.0]), [0.4, 0.3]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Calibration<const N: usize> {
    // Private: every calibration, a sensor's fitted `<NAME>_CALIBRATION` too, is made by `new`
    // (or `from_dark_white`).
    /// Each channel's reading in the dark, subtracted first: finite.
    dark: [f32; N],
    /// Each channel's gain, multiplied after the dark offset is subtracted: finite and
    /// positive.
    gain: [f32; N],
}

impl<const N: usize> Calibration<N> {
    /// No correction: dark 0, gain 1.
    pub const IDENTITY: Calibration<N> = Calibration {
        dark: [0.0; N],
        gain: [1.0; N],
    };

    /// A calibration of your own: each channel's dark offset and gain, in the readings' units.
    /// Checked, never a panic, usable in consts: [`Error::Calibration`] with
    /// [`CalibrationProblem::OutOfRange`] for the first channel whose dark offset is not finite
    /// or whose gain is not finite and positive.
    ///
    /// ```
    /// use spectral_quadrature::{Calibration, CalibrationProblem, Error};
    /// const DEVICE: Calibration<2> = match Calibration::new([12.0, 30.0], [0.001, 0.0012]) {
    ///     Ok(cal) => cal,
    ///     Err(_) => panic!("not a calibration"),
    /// };
    /// assert_eq!(DEVICE.dark(), [12.0, 30.0]);
    /// assert_eq!(
    ///     Calibration::new([0.0, 0.0], [1.0, -1.0]),
    ///     Err(Error::Calibration { channel_index: 1, problem: CalibrationProblem::OutOfRange })
    /// );
    /// ```
    pub const fn new(dark: [f32; N], gain: [f32; N]) -> Result<Calibration<N>, Error> {
        let mut k = 0;
        while k < N {
            if !(dark[k].is_finite() && gain[k].is_finite() && gain[k] > 0.0) {
                return Err(Error::Calibration {
                    channel_index: k,
                    problem: CalibrationProblem::OutOfRange,
                });
            }
            k += 1;
        }
        Ok(Calibration { dark, gain })
    }

    /// Each channel's reading in the dark, subtracted first.
    pub const fn dark(&self) -> [f32; N] {
        self.dark
    }

    /// Each channel's gain, multiplied after the dark offset is subtracted.
    pub const fn gain(&self) -> [f32; N] {
        self.gain
    }

    /// From a reading in the dark and a reading of a white reference, and `reference`, what the
    /// golden device reads on that white under that light: `dark` as it is, and
    /// `gain = reference / (white − dark)`, so that the white then reads as `reference`.
    ///
    /// For a sensor set baked by a scene, `tables::sensors::<NAME>_WHITE` is the golden
    /// device's reading of a perfect white under the set's light, at the luminance the folded
    /// sets show as the display's white; scale it by the white tile's reflectance. Read the
    /// dark and the white with the device's usual gain and integration time, averaged over a
    /// few frames if the readings are noisy.
    ///
    /// # Errors
    /// [`Error::Calibration`] naming the first channel at fault:
    /// [`CalibrationProblem::NoSignal`] where `white − dark` is not positive and finite,
    /// [`CalibrationProblem::Reference`] where `reference` is not positive and finite,
    /// [`CalibrationProblem::OutOfRange`] where the gain overflows.
    pub fn from_dark_white(
        dark: &[f32; N],
        white: &[f32; N],
        reference: &[f32; N],
    ) -> Result<Calibration<N>, Error> {
        let mut gain = [0.0f32; N];
        for (k, g) in gain.iter_mut().enumerate() {
            let fail = |problem| {
                Err(Error::Calibration {
                    channel_index: k,
                    problem,
                })
            };
            let signal = white[k] - dark[k];
            if !(signal > 0.0 && signal.is_finite() && dark[k].is_finite()) {
                return fail(CalibrationProblem::NoSignal);
            }
            if !(reference[k] > 0.0 && reference[k].is_finite()) {
                return fail(CalibrationProblem::Reference);
            }
            *g = reference[k] / signal;
            if !g.is_finite() {
                return fail(CalibrationProblem::OutOfRange);
            }
        }
        Ok(Calibration { dark: *dark, gain })
    }

    /// `(readings − dark) · gain`, channel by channel, in f32. IEEE arithmetic: NaN and ±Inf
    /// propagate, readings below the dark offset give negative values (noise around a dark
    /// channel averages out instead of being cut off); never panics.
    #[inline]
    pub fn apply(&self, readings: &[f32; N]) -> [f32; N] {
        core::array::from_fn(|k| (readings[k] - self.dark[k]) * self.gain[k])
    }

    /// The same calibration for integer counts: readings in counts in, the golden device's
    /// readings in counts of `sample_unit` out, dark offsets rounded to whole counts and gains
    /// `gain / sample_unit` to 16 fractional bits.
    ///
    /// `sample_unit` is what one output count stands for, in the golden device's units: the
    /// convention of [`IntegerSet::new`](crate::IntegerSet::new), so that
    /// `cal.to_counts(set.sample_unit())` feeds the integer set `set`.
    ///
    /// # Errors
    /// [`Error::Calibration`] with [`CalibrationProblem::OutOfRange`] for the first channel
    /// whose dark offset, rounded, is outside 0..=65 535 or whose gain / `sample_unit` is
    /// negative, not finite or 65 536 or more, and for channel 0 where `sample_unit` is not
    /// finite and positive.
    pub fn to_counts(&self, sample_unit: f32) -> Result<CountCalibration<N>, Error> {
        let mut out = CountCalibration {
            dark: [0; N],
            gain_q16: [0; N],
        };
        for k in 0..N {
            let out_of_range = Err(Error::Calibration {
                channel_index: k,
                problem: CalibrationProblem::OutOfRange,
            });
            if !(sample_unit.is_finite() && sample_unit > 0.0) {
                return out_of_range;
            }
            let dark = self.dark[k] + 0.5;
            let gain = self.gain[k] / sample_unit * 65_536.0 + 0.5;
            // 65 536 · 65 536 = 2³²: the largest gain that fits u32 with 16 fractional bits.
            if !((0.0..65_536.0).contains(&dark) && (0.0..4_294_967_296.0).contains(&gain)) {
                return out_of_range;
            }
            out.dark[k] = dark as u16;
            out.gain_q16[k] = gain as u32;
        }
        Ok(out)
    }
}

/// A device's dark offsets and gains for 16-bit counts, in integer arithmetic only: `apply`
/// gives `(counts − dark) · gain_q16 / 2¹⁶` per channel, rounded to nearest (ties up) and
/// saturated to 0..=65 535. The same on every target, bit for bit.
///
/// ```
/// use spectral_quadrature::CountCalibration;
/// // 100 counts of dark, a white at 40 100 that the golden device reads as 30 000.
/// let cal = CountCalibration::from_dark_white(&[100], &[40_100], &[30_000]).unwrap();
/// assert_eq!(cal.apply(&[20_100]), [15_000]);
/// assert_eq!(cal.apply(&[50]), [0]); // below the dark offset
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CountCalibration<const N: usize> {
    /// Each channel's counts in the dark, subtracted first (saturating at 0).
    dark: [u16; N],
    /// Each channel's gain with 16 fractional bits: 65 536 is 1.
    gain_q16: [u32; N],
}

impl<const N: usize> CountCalibration<N> {
    /// No correction: dark 0, gain 1.
    pub const IDENTITY: CountCalibration<N> = CountCalibration {
        dark: [0; N],
        gain_q16: [1 << 16; N],
    };

    /// A calibration of your own: each channel's dark offset in counts and gain with 16
    /// fractional bits (65 536 is 1). Every value is valid (`apply` cannot overflow for any),
    /// so there is nothing to check: a `const fn` that cannot fail.
    pub const fn new(dark: [u16; N], gain_q16: [u32; N]) -> CountCalibration<N> {
        CountCalibration { dark, gain_q16 }
    }

    /// Each channel's counts in the dark, subtracted first (saturating at 0).
    pub const fn dark(&self) -> [u16; N] {
        self.dark
    }

    /// Each channel's gain with 16 fractional bits: 65 536 is 1.
    pub const fn gain_q16(&self) -> [u32; N] {
        self.gain_q16
    }

    /// From counts in the dark, counts of a white reference, and `reference`, the golden
    /// device's counts on that white: `dark` as it is and
    /// `gain_q16 = round(reference · 2¹⁶ / (white − dark))`, so that the white then reads as
    /// `reference` (to within one count). Integer arithmetic only (one 32-bit division a
    /// channel).
    ///
    /// # Errors
    /// [`Error::Calibration`] naming the first channel at fault:
    /// [`CalibrationProblem::NoSignal`] where `white ≤ dark`, [`CalibrationProblem::Reference`]
    /// where `reference` is 0.
    pub fn from_dark_white(
        dark: &[u16; N],
        white: &[u16; N],
        reference: &[u16; N],
    ) -> Result<CountCalibration<N>, Error> {
        let mut gain_q16 = [0u32; N];
        for (k, g) in gain_q16.iter_mut().enumerate() {
            let signal = u32::from(white[k].saturating_sub(dark[k]));
            if signal == 0 {
                return Err(Error::Calibration {
                    channel_index: k,
                    problem: CalibrationProblem::NoSignal,
                });
            }
            if reference[k] == 0 {
                return Err(Error::Calibration {
                    channel_index: k,
                    problem: CalibrationProblem::Reference,
                });
            }
            // reference · 2¹⁶ + signal / 2 ≤ 65 535 · 65 536 + 32 767 < 2³²: no overflow.
            *g = ((u32::from(reference[k]) << 16) + signal / 2) / signal;
        }
        Ok(CountCalibration {
            dark: *dark,
            gain_q16,
        })
    }

    /// `(counts − dark) · gain_q16 / 2¹⁶`, rounded to nearest, saturated to 0..=65 535, per
    /// channel. Two 16 × 16-bit multiplications a channel, no division; never panics.
    #[inline]
    pub fn apply(&self, counts: &[u16; N]) -> [u16; N] {
        core::array::from_fn(|k| {
            let x = u32::from(counts[k].saturating_sub(self.dark[k]));
            let g = self.gain_q16[k];
            // x · g = x · g_hi · 2¹⁶ + x · g_lo, with g_hi, g_lo < 2¹⁶: each product fits u32,
            // and so do x · g_lo + 2¹⁵ (at most 65 535² + 32 768) and the sum below.
            let high = x * (g >> 16);
            let low = (x * (g & 0xffff) + 0x8000) >> 16;
            (high + low).min(u32::from(u16::MAX)) as u16
        })
    }
}
