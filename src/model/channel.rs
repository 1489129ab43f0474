//! The channel selectors: [`Channel`], one of the opponent channels A, C1 and C2, and [`Rgb`],
//! one of a display's R, G and B. A leaf: the error type names them in its variants, and the
//! modules that return that error take them as arguments.

#![forbid(unsafe_code)]

/// One of the three opponent channels of AC1C2 space.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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

    /// The channel's symbol, `"A"`, `"C1"` or `"C2"`, as the paper writes it: the one exception
    /// to the crate's kebab-case identifiers (see the crate's conventions), a symbol being
    /// written as colour science writes it.
    pub const fn name(self) -> &'static str {
        match self {
            Channel::A => "A",
            Channel::C1 => "C1",
            Channel::C2 => "C2",
        }
    }
}

/// One of a display's three channels. Lookup tables and transfer functions take it instead of a
/// bare index, so an index out of range cannot be written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Rgb {
    /// Red.
    R,
    /// Green.
    G,
    /// Blue.
    B,
}

impl Rgb {
    /// The channels in order.
    pub const ALL: [Rgb; 3] = [Rgb::R, Rgb::G, Rgb::B];

    /// 0, 1 or 2.
    pub const fn index(self) -> usize {
        match self {
            Rgb::R => 0,
            Rgb::G => 1,
            Rgb::B => 2,
        }
    }

    /// The channel's symbol, `"R"`, `"G"` or `"B"`: like [`Channel::name`], a symbol written as
    /// colour science writes it.
    pub const fn name(self) -> &'static str {
        match self {
            Rgb::R => "R",
            Rgb::G => "G",
            Rgb::B => "B",
        }
    }
}
