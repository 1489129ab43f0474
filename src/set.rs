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
}

impl<const N: usize> WavelengthSet<N> {
    /// The number of distinct wavelengths, N.
    pub const LEN: usize = N;

    /// `[A, C1, C2]` from samples of a spectrum at [`wavelengths_nm`](Self::wavelengths_nm):
    /// the 3×N product `weights · samples`, in f32.
    ///
    /// Never panics. Each output is a plain sum of products, so IEEE rules apply: a NaN sample
    /// gives NaN in every channel whose weight for it is non-zero; ±Inf gives ±Inf or NaN (when
    /// infinities of both signs meet); subnormal and negative samples are used as they are;
    /// products beyond `f32::MAX` overflow to ±Inf.
    pub fn ac1c2(&self, samples: &[f32; N]) -> [f32; 3] {
        let mut out = [0.0f32; 3];
        for (o, row) in out.iter_mut().zip(&self.weights) {
            *o = row.iter().zip(samples).map(|(w, s)| w * s).sum();
        }
        out
    }
}
