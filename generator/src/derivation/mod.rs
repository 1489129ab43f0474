//! Meyer's derivation, in the paper's order: the observer's x̄ȳz̄ ([`observer`]), the cone
//! fundamentals (Eq. 1), the covariance (Eq. 4-5) and the KL transform to AC1C2 (Eq. 9-10)
//! ([`opponent`]), each channel's recurrence (Eq. 16) and Gauss rules ([`quadrature`]), and the
//! wavelength sets merged from them (Table 2, [`sets`]); [`derive`] runs the steps from
//! [`settings`]. Beside them: the display matrices ([`display`], from `spectral-quadrature-math`),
//! the exact integration on the observer's grid and the uniform sets
//! ([`Observer::full_integration`](observer::Observer::full_integration)), by which
//! `spectral-quadrature-spectra` measures every set in CIELAB; the Planckian locus, the exact
//! correlated colour temperature and the locus table the runtime interpolates ([`planckian`]);
//! a light's fitted samples at a radiance set's nodes, for relighting (`relight`).

pub(crate) mod derive;
pub mod display;
pub(crate) mod observer;
pub(crate) mod opponent;
pub(crate) mod planckian;
pub mod quadrature;
pub(crate) mod relight;
pub(crate) mod sets;
pub(crate) mod settings;
