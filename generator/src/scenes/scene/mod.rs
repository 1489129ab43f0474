//! Scenes: what one application uses, so the build bakes only that.
//!
//! A scene is a TOML file whose path `build.rs` reads from the environment variable
//! [`SCENE_ENV`] (set it in `.cargo/config.toml`'s `[env]`, with `relative = true` so the path
//! is absolute). Without it the default scene applies: every set, display and table.
//!
//! ```toml
//! observer = "cie1931_2deg"        # optional; also range_nm = [380, 770], step_nm = 5
//! sets = ["TABLE2_ROW2", "A_3"]    # names from the catalog module
//! clamp_negatives = false          # optional: true reads every negative value in the files
//!                                  # below (lights, sensors, plan spectra) as 0
//! displays = ["SRGB"]              # SRGB, DISPLAY_P3, REC2020, MEYER_1987
//!
//! [transfer]                       # optional: another transfer function for a display
//! SRGB = "gamma 2.2"               # "srgb", "linear" or "gamma <γ>"
//!
//! [extras]                         # optional, all false by default
//! sensitivities = true             # GRID_NM and SENSITIVITIES
//! rules = true                     # the rule tables (A_RULES, ..., RULES, MAX_ORDER)
//! cct = true                       # PLANCKIAN_LOCUS: colour temperature and Duv from XYZ
//!
//! [plan]                           # optional: add the set the planner picks for a budget
//! max_delta_e00 = 1.0
//! metric = "mean"                  # or "max"
//! reflectances = "surfaces.csv"    # relative to the scene file
//! illuminants = "lamps.csv"        # or emission = "leds.csv"
//!
//! [lights]                         # optional: lights read from files (one column of power)
//! SHOP_LED = "shop_led.csv"        # KQ_SHOP_LED_<n> folds it in; light = "SHOP_LED" below
//!
//! [fixed.BINS8]                    # optional: the best weights for exactly these wavelengths
//! wavelengths_nm = [450, 550, 650]
//! light = "C"                      # optional: fold a light in (else radiances)
//!
//! [sensors.AS7341]                 # optional: the best matrix from a sensor's readings
//! file = "as7341.csv"              # wavelength, then one column per channel
//! light = "C"                      # optional: fit for reflectances under it (else radiances)
//! calibration = "device.csv"       # optional: a device's readings of known reflectances
//! calibration_reflectances = "chart.csv"  # optional: their spectra (else the ColorChecker)
//!
//! [groups.STUDIO]                  # optional: one node set for several lights
//! lights = ["D65", "A", "SHOP_LED"] # built-in or [lights] names; two or more (one for "bounces")
//! wavelengths = 8                  # 3 to 16
//! objective = "mean"               # optional: or "worst" (the largest ratio to a light's own set)
//! training = "reflectances"        # optional: or "bounces" (ρ, ρ², ρ³ and two enclosures)
//!
//! [upsampling]                     # optional: RGB → node reflectances (crate::upsampling)
//! sets = ["KQ_C_8", "STUDIO"]      # sets and light groups (RGB under a group's first light);
//!                                  # default: every colour set (sensor sets excepted) and group
//! displays = ["SRGB"]              # default: every display of the scene
//! grid = 9                         # points per axis, 2..=65
//! ```
//!
//! `[fixed.*]` and `[sensors.*]` sets are baked whenever declared ([`crate::user`]), and so are
//! `[groups.*]` (`tables::groups`, [`crate::shared::GroupFit`]).
//!
//! The spectra files a scene names follow the readers' rule for negative values
//! ([`Negatives`](spectral_quadrature_spectra::Negatives)): rounding noise (at or above −1e-6
//! of the file's largest value) is read as 0 and reported as a warning ([`Resolved::warnings`]);
//! a more negative value is an error naming the file, line and column, unless
//! `clamp_negatives = true` reads it as 0 as well (for measured data whose noise is larger;
//! still reported).
//!
//! Every mistake (unknown key, set, observer or display, an undefined order, a bad budget) is
//! an error naming the file, the line and the valid choices.
//!
//! The file is read in two steps, each a module: [`Scene::parse`] reads it (and
//! [`Scene::default_scene`] stands for no file), `parse`; [`Scene::resolve`] turns the names it
//! holds into the very sets, displays and tables to bake ([`Resolved`]), `resolve`.

mod parse;
mod resolve;

#[cfg(test)]
pub(crate) use parse::DEFAULT_SHARED_SETS;
pub use parse::{
    PlanRequest, Scene, SceneFixed, SceneGroup, SceneLight, SceneSensor, UserInputs, SCENE_ENV,
};
pub use resolve::{user_warnings, Resolved};
