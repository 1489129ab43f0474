//! The baked model of a scene: every constant the scene bakes, computed once from the derivation
//! and rounded to f32 as the runtime holds it, with the names, docs and provenance the formatters
//! need. [`Model::bake`] is the only place the emitters reach into the derivation; the
//! formatters (`codegen` for the Rust tables, `shader` for WGSL and GLSL, `upsampling` for the
//! maps' shader files, and the section emitters beside them) read this plain data and call
//! nothing else, so no two targets can disagree about a number.
//!
//! Each kind of item is its own list, in the order the generated files hold them: the opponent
//! matrices, the Planckian locus, the sensitivities and rules (the scene's extras), the rule and
//! colour sets, the displays, the folded sets (each colour set for each display), the light
//! groups, the lights at the sets for radiances, the upsampling maps, the sensors' whites and
//! calibrations, the integer sets and the power laws' 8-bit encoders. Where a doc quotes a figure
//! measured in f64 (a map's Lipschitz constant, a display's condition number), the model keeps
//! that f64 beside the f32 the runtime holds, so that the text is the measurement's, not its
//! rounding's. Items refer to each other by index (a folded set to its colour set and display,
//! an integer set to its folded set), never by copying, so that a target names each item one
//! way. Another target is one more formatter: it reads these lists in their order and writes
//! each kind, with nothing to compute but its own syntax.

use spectral_quadrature_spectra::Spectra;
use std::string::{String, ToString};
use std::vec::Vec;

use crate::base::error::Error;
use crate::derivation::derive::Derivation;
use crate::derivation::display::Transfer as SpecTransfer;
use crate::derivation::planckian::{standard_range_nm, PlanckianLocus};
use crate::derivation::quadrature::Rule as DerivedRule;
use crate::derivation::sets::{WavelengthSet, CHANNELS};
use crate::scenes::scene::Resolved;
use crate::shared::GroupTraining;

/// The largest count, what the samples of white become.
pub const FULL_SCALE: f64 = 65535.0;

/// The sample one count stands for in `set`'s integer form: the largest of its white samples
/// over [`FULL_SCALE`]. White is a reflectance (or a radiance) of 1 for a wavelength set, and a
/// sensor's readings of it for a sensor set (`scene.white_samples`: the golden device's readings
/// of a perfect white, the same numbers as the sensor's `tables::sensors::<NAME>_WHITE`).
pub fn sample_unit(set: &WavelengthSet, scene: &Resolved) -> f64 {
    let white = scene
        .white_samples
        .iter()
        .find(|(name, _)| *name == set.name)
        .map_or(1.0, |(_, w)| w.iter().copied().fold(0.0, f64::max));
    white / FULL_SCALE
}

/// Everything a scene bakes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Model {
    /// Where the tables come from.
    pub(crate) provenance: Provenance,
    /// The range, the grid step, the AC1C2 matrices (Eq. 9), the eigenvalues (Eq. 10) and the
    /// unit spectrum's Y.
    pub(crate) opponent: Opponent,
    /// The Planckian locus (`[extras] cct`).
    pub(crate) locus: Option<Locus>,
    /// The grid and the opponent sensitivities on it (`[extras] sensitivities`).
    pub(crate) sensitivities: Option<Sensitivities>,
    /// Every channel's Gauss rules (`[extras] rules`).
    pub(crate) rules: Option<Rules>,
    /// The scene's per-channel rules as sets (`tables::rules`).
    pub(crate) rule_sets: Vec<Set>,
    /// The scene's colour sets, at the top of `tables`.
    pub(crate) colour_sets: Vec<Set>,
    /// The scene's displays.
    pub(crate) displays: Vec<Display>,
    /// Each colour set folded for each display, set by set.
    pub(crate) folded: Vec<Folded>,
    /// Each light group, with its members folded for each display.
    pub(crate) groups: Vec<Group>,
    /// Each scene light at each colour set for radiances, set by set.
    pub(crate) lights: Vec<LightAtSet>,
    /// The RGB upsamplings.
    pub(crate) upsamplings: Vec<Upsampling>,
    /// The sensors' white references and fitted calibrations.
    pub(crate) sensors: Vec<Sensor>,
    /// Each folded set in fixed point, in the order of [`Model::folded`].
    pub(crate) integer: Vec<Integer>,
    /// The 8-bit encoders of the displays' power laws, one per distinct γ.
    pub(crate) gamma_encoders: Vec<GammaEncoder>,
}

/// The provenance: what the tables were made from.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Provenance {
    /// The scene file, or `default`.
    pub(crate) scene: String,
    /// The observer's name.
    pub(crate) observer: String,
    /// The derivation's settings, as one line.
    pub(crate) settings: String,
    /// The header, one item a line: the generator, the settings, the scene, what a planned scene
    /// chose, and each input with its SHA-256.
    pub(crate) header: String,
    /// The input files and their SHA-256 checksums.
    pub(crate) inputs: Vec<(String, String)>,
}

/// The opponent space and the grid's constants.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Opponent {
    /// The spectrum's limits in nm.
    pub(crate) range_nm: [f32; 2],
    /// The grid step in nm.
    pub(crate) step_nm: f32,
    /// Eq. 9.
    pub(crate) xyz_to_ac1c2: [[f32; 3]; 3],
    /// Its inverse.
    pub(crate) ac1c2_to_xyz: [[f32; 3]; 3],
    /// Eq. 10, largest first.
    pub(crate) eigenvalues: [f32; 3],
    /// ∫ ȳ dλ over the grid.
    pub(crate) unit_spectrum_y: f32,
}

/// One node of the Planckian locus table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LocusNode {
    /// μ = 10⁶ / T.
    pub(crate) mired: f32,
    /// CIE 1960 (u, v).
    pub(crate) uv: [f32; 2],
    /// d(u, v)/dμ.
    pub(crate) tangent: [f32; 2],
    /// The chord to the next node, computed before rounding; `[0, 0]` at the last node.
    pub(crate) chord: [f32; 2],
    /// The unit tangent in 1.14 fixed point.
    pub(crate) unit_tangent_q14: [i16; 2],
    /// `L · T̂` in 30 fractional bits.
    pub(crate) along_q30: i32,
}

/// The Planckian locus table, and what its doc says of it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Locus {
    /// The observer's name and its data file.
    pub(crate) observer: [String; 2],
    /// The wavelengths integrated over, nm (CIE 015's 360-830, clipped to the observer's table).
    pub(crate) range_nm: [f64; 2],
    /// The first and last nodes' mired, as computed (for the doc).
    pub(crate) mired_ends: [f64; 2],
    /// The nodes.
    pub(crate) nodes: Vec<LocusNode>,
}

/// The grid and the opponent sensitivities on it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Sensitivities {
    /// The grid wavelengths in nm.
    pub(crate) grid_nm: Vec<f32>,
    /// `[ā, c̄1, c̄2]` at each grid wavelength.
    pub(crate) rows: Vec<[f32; 3]>,
}

/// One Gauss rule.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Rule {
    /// The number of nodes.
    pub(crate) order: usize,
    /// The runtime's `RuleStatus` variant (`"Defined"`, ...).
    pub(crate) status: &'static str,
    /// Nodes and weights, empty unless the rule is defined.
    pub(crate) nodes_nm: Vec<f32>,
    /// The weights.
    pub(crate) weights: Vec<f32>,
}

/// Every channel's rules.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Rules {
    /// Rules were formed for orders 1..=max_order in each channel.
    pub(crate) max_order: usize,
    /// `channels[c][order − 1]`, channels A, C1, C2 ([`CHANNEL_NAMES`]).
    pub(crate) channels: [Vec<Rule>; 3],
}

/// The channels' names, as the runtime's `Channel` variants.
pub(crate) const CHANNEL_NAMES: [&str; 3] = CHANNELS;

/// What a set's samples are.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Samples {
    /// Radiances.
    Radiance,
    /// Reflectances under the light folded into the weights.
    Reflectance {
        /// The light's name.
        light: String,
    },
    /// A sensor's readings.
    Readings {
        /// The sensor's name.
        sensor: String,
        /// The light the weights were fitted for, if any.
        light: Option<String>,
    },
}

/// A wavelength set: a rule set or a colour set.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Set {
    /// The const name.
    pub(crate) name: String,
    /// One line for the doc comment.
    pub(crate) doc: String,
    /// Wavelengths in nm (a sensor's channel peaks).
    pub(crate) wavelengths_nm: Vec<f32>,
    /// `weights[channel][i]`, A, C1, C2.
    pub(crate) weights: [Vec<f32>; 3],
    /// What the samples are.
    pub(crate) samples: Samples,
}

impl Set {
    /// The number of wavelengths.
    pub(crate) fn len(&self) -> usize {
        self.wavelengths_nm.len()
    }

    /// Whether the set takes radiances (no light folded in, not a sensor's readings).
    pub(crate) fn is_radiance(&self) -> bool {
        self.samples == Samples::Radiance
    }
}

/// How a display encodes linear light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Transfer {
    /// No encoding.
    Linear,
    /// The sRGB curve.
    Srgb,
    /// A power law: `gamma` as the runtime holds it, `given` as the scene wrote it.
    Gamma {
        /// γ rounded to f32.
        gamma: f32,
        /// γ as given (for text).
        given: f64,
    },
}

/// A display.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Display {
    /// The const name (`SRGB`).
    pub(crate) name: String,
    /// The human name (`sRGB`), the runtime display's `name`.
    pub(crate) label: String,
    /// One line for the doc comment.
    pub(crate) doc: String,
    /// Chromaticities of red, green and blue.
    pub(crate) primaries_xy: [[f32; 2]; 3],
    /// Chromaticity of white.
    pub(crate) white_xy: [f32; 2],
    /// Linear RGB → XYZ.
    pub(crate) rgb_to_xyz: [[f32; 3]; 3],
    /// XYZ → linear RGB.
    pub(crate) xyz_to_rgb: [[f32; 3]; 3],
    /// A of one unit of R, G and B.
    pub(crate) a_from_rgb: [f32; 3],
    /// The transfer function.
    pub(crate) transfer: Transfer,
    /// The white balance Y_r : Y_g : Y_b (for the doc).
    pub(crate) luminance: [f64; 3],
    /// The primaries' condition number (for the doc).
    pub(crate) condition: f64,
}

/// A colour set folded for a display.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Folded {
    /// The index of the set in [`Model::colour_sets`].
    pub(crate) set: usize,
    /// The index of the display in [`Model::displays`].
    pub(crate) display: usize,
    /// `weights[channel][i]`, R, G, B.
    pub(crate) weights: [Vec<f32>; 3],
}

/// A light group: one node set shared by several lights.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Group {
    /// The group's name.
    pub(crate) name: String,
    /// The shared nodes in nm.
    pub(crate) wavelengths_nm: Vec<f32>,
    /// The lights, in the order of the accumulators.
    pub(crate) lights: Vec<String>,
    /// The objective the nodes were searched for (its name).
    pub(crate) objective: &'static str,
    /// Whether the fit trained on the reflectances' bounce forms too.
    pub(crate) bounces: bool,
    /// `folded[display][light]`: each light's weights folded for each display of
    /// [`Model::displays`], R, G, B.
    pub(crate) folded: Vec<Vec<[Vec<f32>; 3]>>,
}

/// A scene light at a set for radiances's nodes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LightAtSet {
    /// The light's name.
    pub(crate) light: String,
    /// The index of the set in [`Model::colour_sets`].
    pub(crate) set: usize,
    /// The fitted values at the set's nodes.
    pub(crate) values: Vec<f32>,
}

/// The figures a build measures of an upsampling, in f64 as measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Measured {
    /// The Lipschitz constant of the interpolation.
    pub(crate) lipschitz: f64,
    /// The largest round-trip ΔE00 at the reachable grid points.
    pub(crate) max_round_trip_de00: f64,
    /// The share of the grid's points the set reaches.
    pub(crate) reachable_share: f64,
}

/// An RGB upsampling of a folded set.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Upsampling {
    /// The set's name.
    pub(crate) set: String,
    /// The display's const name.
    pub(crate) display: String,
    /// The display's human name.
    pub(crate) display_label: String,
    /// The reference light.
    pub(crate) light: String,
    /// The number of nodes.
    pub(crate) n: usize,
    /// Points per axis.
    pub(crate) grid: usize,
    /// `grid³` entries of n codes.
    pub(crate) codes: Vec<Vec<u16>>,
    /// The round trip's weights, R, G, B.
    pub(crate) encoding: [Vec<f32>; 3],
    /// The display's RGB → XYZ.
    pub(crate) rgb_to_xyz: [[f32; 3]; 3],
    /// The edge cells' bits.
    pub(crate) edge_cells: Vec<u32>,
    /// The measured figures as f32 (`[lipschitz, max_round_trip_de00, reachable_share]`).
    pub(crate) figures: [f32; 3],
    /// The measured figures as measured.
    pub(crate) measured: Measured,
}

impl Upsampling {
    /// The const name: `<SET>_<DISPLAY>`.
    pub(crate) fn name(&self) -> String {
        std::format!("{}_{}", self.set, self.display)
    }
}

/// A sensor's calibration fitted to a device's readings.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SensorCalibration {
    /// Each channel's dark offset.
    pub(crate) dark: Vec<f32>,
    /// Each channel's gain.
    pub(crate) gain: Vec<f32>,
    /// Each channel's root-mean-square residual (for the doc).
    pub(crate) rms_residual: Vec<f64>,
}

/// A sensor's white reference and calibration.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Sensor {
    /// The sensor's name.
    pub(crate) name: String,
    /// What the golden device reads on a perfect white.
    pub(crate) white: Vec<f32>,
    /// The fitted calibration, where the scene gives readings.
    pub(crate) calibration: Option<SensorCalibration>,
}

/// A folded set in fixed point.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Integer {
    /// The index of the folded set in [`Model::folded`].
    pub(crate) folded: usize,
    /// The sample one count stands for, as the runtime holds it.
    pub(crate) sample_unit: f32,
    /// The same, as computed (for the doc).
    pub(crate) sample_unit_f64: f64,
    /// Whether the counts' full scale is a sensor's reading of white (else the samples of
    /// white, 1).
    pub(crate) sensor_white: bool,
}

/// An 8-bit encoder of a power law.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GammaEncoder {
    /// γ as the runtime holds it.
    pub(crate) gamma: f32,
    /// Entry k (1..=255): the bits of the smallest f32 x with x^(1/γ) · 255 ≥ k − ½; entry 0
    /// is 0.
    pub(crate) thresholds: [u32; 256],
}

/// `v` rounded to f32 as the runtime holds it (`as f32`), which must be finite.
pub(crate) fn f32_of(v: f64) -> Result<f32, Error> {
    let x = v as f32;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::Literal {
            value: v,
            language: "Rust",
        })
    }
}

fn f32s(v: &[f64]) -> Result<Vec<f32>, Error> {
    v.iter().map(|&x| f32_of(x)).collect()
}

fn rows(w: &[Vec<f64>; 3]) -> Result<[Vec<f32>; 3], Error> {
    Ok([f32s(&w[0])?, f32s(&w[1])?, f32s(&w[2])?])
}

fn array<const K: usize>(v: &[f64; K]) -> Result<[f32; K], Error> {
    let mut out = [0.0f32; K];
    for (o, &x) in out.iter_mut().zip(v) {
        *o = f32_of(x)?;
    }
    Ok(out)
}

fn matrix(m: &[[f64; 3]; 3]) -> Result<[[f32; 3]; 3], Error> {
    Ok([array(&m[0])?, array(&m[1])?, array(&m[2])?])
}

fn set(s: &WavelengthSet) -> Result<Set, Error> {
    Ok(Set {
        name: s.name.clone(),
        doc: s.doc.clone(),
        wavelengths_nm: f32s(&s.wavelengths_nm)?,
        weights: rows(&s.weights)?,
        samples: match (&s.sensor, &s.light) {
            (Some(sensor), light) => Samples::Readings {
                sensor: sensor.clone(),
                light: light.clone(),
            },
            (None, Some(light)) => Samples::Reflectance {
                light: light.clone(),
            },
            (None, None) => Samples::Radiance,
        },
    })
}

fn rule(r: &DerivedRule) -> Result<Rule, Error> {
    let (nodes_nm, weights) = if r.is_defined() {
        (f32s(&r.nodes_nm)?, f32s(&r.weights)?)
    } else {
        (Vec::new(), Vec::new())
    };
    Ok(Rule {
        order: r.order,
        status: r.status.variant(),
        nodes_nm,
        weights,
    })
}

/// The bits of the smallest f32 at or above `t` (t ≥ 0 and finite): 1 (the smallest subnormal)
/// for a `t` that rounds to 0 as f32.
pub(crate) fn ceil_f32_bits(t: f64) -> u32 {
    let f = t as f32;
    if f64::from(f) < t {
        f.to_bits() + 1
    } else {
        f.to_bits()
    }
}

/// Thresholds of the power law x^(1/γ) with γ the f32 `gamma` (as the runtime holds it):
/// entry k (1..=255) is the bits of the smallest f32 x with x^(1/γ) · 255 ≥ k − ½, i.e.
/// x ≥ ((k − ½)/255)^γ, computed in f64; entry 0 is 0. Non-decreasing (equal where two
/// boundaries fall on one f32).
pub(crate) fn gamma_thresholds(gamma: f32) -> [u32; 256] {
    let g = f64::from(gamma);
    let mut t = [0u32; 256];
    for (k, slot) in t.iter_mut().enumerate().skip(1) {
        *slot = ceil_f32_bits(((k as f64 - 0.5) / 255.0).powf(g));
    }
    t
}

impl Model {
    /// The model of `scene`, resolved against `d`; `inputs` lists (file label, SHA-256) for the
    /// header. Errors where a value is not finite as f32, and where a light's samples at a set's
    /// nodes cannot be fitted.
    pub(crate) fn bake(
        d: &Derivation,
        inputs: &[(String, String)],
        scene: &Resolved,
    ) -> Result<Model, Error> {
        let s = &d.settings;
        let provenance = Provenance {
            scene: scene.file.clone(),
            observer: s.observer.name().to_string(),
            settings: s.to_string(),
            header: header(d, inputs, scene),
            inputs: inputs.to_vec(),
        };
        let opponent = Opponent {
            range_nm: array(&s.range_nm)?,
            step_nm: f32_of(s.step_nm)?,
            xyz_to_ac1c2: matrix(&d.opponent.xyz_to_ac1c2)?,
            ac1c2_to_xyz: matrix(&d.opponent.ac1c2_to_xyz)?,
            eigenvalues: array(&d.opponent.eigenvalues)?,
            unit_spectrum_y: f32_of(d.unit_spectrum_y)?,
        };
        let locus = if scene.extras.cct {
            Some(locus(d)?)
        } else {
            None
        };
        let sensitivities = if scene.extras.sensitivities {
            Some(Sensitivities {
                grid_nm: f32s(&d.grid_nm)?,
                rows: d
                    .sensitivities
                    .iter()
                    .map(array)
                    .collect::<Result<_, _>>()?,
            })
        } else {
            None
        };
        let rules = if scene.extras.rules {
            let channel = |c: usize| d.rules[c].iter().map(rule).collect::<Result<Vec<_>, _>>();
            Some(Rules {
                max_order: s.max_order,
                channels: [channel(0)?, channel(1)?, channel(2)?],
            })
        } else {
            None
        };
        let rule_sets = scene.rule_sets.iter().map(set).collect::<Result<_, _>>()?;
        let colour_sets: Vec<Set> = scene
            .colour_sets
            .iter()
            .map(set)
            .collect::<Result<_, _>>()?;
        let displays = scene
            .displays
            .iter()
            .map(|(spec, m)| {
                let a_from_rgb: Vec<f64> = (0..3)
                    .map(|j| {
                        (0..3)
                            .map(|k| d.opponent.xyz_to_ac1c2[0][k] * m.rgb_to_xyz[k][j])
                            .sum()
                    })
                    .collect();
                Ok(Display {
                    name: spec.name.clone(),
                    label: spec.label.clone(),
                    doc: spec.doc.clone(),
                    primaries_xy: [
                        array(&spec.primaries_xy[0])?,
                        array(&spec.primaries_xy[1])?,
                        array(&spec.primaries_xy[2])?,
                    ],
                    white_xy: array(&spec.white_xy)?,
                    rgb_to_xyz: matrix(&m.rgb_to_xyz)?,
                    xyz_to_rgb: matrix(&m.xyz_to_rgb)?,
                    a_from_rgb: array(&[a_from_rgb[0], a_from_rgb[1], a_from_rgb[2]])?,
                    transfer: match spec.transfer {
                        SpecTransfer::Linear => Transfer::Linear,
                        SpecTransfer::Srgb => Transfer::Srgb,
                        SpecTransfer::Gamma(g) => Transfer::Gamma {
                            gamma: f32_of(g)?,
                            given: g,
                        },
                    },
                    luminance: m.luminance,
                    condition: m.condition,
                })
            })
            .collect::<Result<Vec<_>, Error>>()?;
        let mut folded = Vec::new();
        let mut integer = Vec::new();
        if !displays.is_empty() {
            for (i, cs) in scene.colour_sets.iter().enumerate() {
                let unit = sample_unit(cs, scene);
                let unit32 = unit as f32;
                if !(unit32.is_finite() && unit32 > 0.0) {
                    return Err(Error::Literal {
                        value: unit,
                        language: "Rust",
                    });
                }
                let sensor_white = scene.white_samples.iter().any(|(n, _)| *n == cs.name);
                for (k, (_, m)) in scene.displays.iter().enumerate() {
                    integer.push(Integer {
                        folded: folded.len(),
                        sample_unit: unit32,
                        sample_unit_f64: unit,
                        sensor_white,
                    });
                    folded.push(Folded {
                        set: i,
                        display: k,
                        weights: rows(&d.folded(cs, m))?,
                    });
                }
            }
        }
        let mut groups = Vec::new();
        for (name, group) in &scene.groups {
            let members: Vec<WavelengthSet> = group
                .members
                .iter()
                .map(|member| member.wavelength_set(d, name, &group.wavelengths_nm))
                .collect();
            let folded = scene
                .displays
                .iter()
                .map(|(_, m)| {
                    members
                        .iter()
                        .map(|set| rows(&d.folded(set, m)))
                        .collect::<Result<Vec<_>, Error>>()
                })
                .collect::<Result<Vec<_>, Error>>()?;
            groups.push(Group {
                name: name.clone(),
                wavelengths_nm: f32s(&group.wavelengths_nm)?,
                lights: group.members.iter().map(|m| m.light.clone()).collect(),
                objective: group.objective.name(),
                bounces: matches!(group.training, GroupTraining::Bounces),
                folded,
            });
        }
        let mut lights = Vec::new();
        let radiance: Vec<usize> = (0..colour_sets.len())
            .filter(|&i| colour_sets[i].is_radiance())
            .collect();
        if !radiance.is_empty() && !scene.lights.is_empty() {
            let training =
                Spectra::builtin(&s.data_dir, crate::shared::TRAINING_FILE)?.curves(s.range_nm)?;
            for &i in &radiance {
                for light in &scene.lights {
                    let l = crate::derivation::relight::light_at_nodes(
                        d,
                        &scene.colour_sets[i],
                        light,
                        &training,
                    )?;
                    lights.push(LightAtSet {
                        light: light.name.clone(),
                        set: i,
                        values: f32s(&l)?,
                    });
                }
            }
        }
        let upsamplings = scene
            .upsamplings
            .iter()
            .map(|u| {
                let (spec, m) = scene
                    .displays
                    .iter()
                    .find(|(s, _)| s.name == u.display)
                    .ok_or_else(|| Error::UnknownDisplay {
                        name: u.display.clone(),
                        valid: scene.displays.iter().map(|(s, _)| s.name.clone()).collect(),
                    })?;
                let share = u.reachable_share();
                Ok(Upsampling {
                    set: u.set.clone(),
                    display: u.display.clone(),
                    display_label: spec.label.clone(),
                    light: u.light.clone(),
                    n: u.wavelengths_nm.len(),
                    grid: u.grid,
                    codes: u.codes.clone(),
                    encoding: rows(&u.encoding)?,
                    rgb_to_xyz: matrix(&m.rgb_to_xyz)?,
                    edge_cells: u.edge_cells(),
                    figures: [
                        f32_of(u.lipschitz)?,
                        f32_of(u.max_round_trip_de00)?,
                        f32_of(share)?,
                    ],
                    measured: Measured {
                        lipschitz: u.lipschitz,
                        max_round_trip_de00: u.max_round_trip_de00,
                        reachable_share: share,
                    },
                })
            })
            .collect::<Result<Vec<_>, Error>>()?;
        let sensors = scene
            .sensors
            .iter()
            .map(|s| {
                Ok(Sensor {
                    name: s.name.clone(),
                    white: f32s(&s.white)?,
                    calibration: match &s.calibration {
                        Some(fit) => Some(SensorCalibration {
                            dark: f32s(&fit.dark)?,
                            gain: f32s(&fit.gain)?,
                            rms_residual: fit.rms_residual.clone(),
                        }),
                        None => None,
                    },
                })
            })
            .collect::<Result<Vec<_>, Error>>()?;
        let mut gamma_encoders: Vec<GammaEncoder> = Vec::new();
        for (spec, _) in &scene.displays {
            if let SpecTransfer::Gamma(g) = spec.transfer {
                let g = g as f32;
                let new = !gamma_encoders
                    .iter()
                    .any(|e| e.gamma.to_bits() == g.to_bits());
                if g.is_finite() && g > 0.0 && new {
                    gamma_encoders.push(GammaEncoder {
                        gamma: g,
                        thresholds: gamma_thresholds(g),
                    });
                }
            }
        }
        Ok(Model {
            provenance,
            opponent,
            locus,
            sensitivities,
            rules,
            rule_sets,
            colour_sets,
            displays,
            folded,
            groups,
            lights,
            upsamplings,
            sensors,
            integer,
            gamma_encoders,
        })
    }

    /// The name of folded set `f`: `<SET>_<DISPLAY>`.
    pub(crate) fn folded_name(&self, f: &Folded) -> String {
        std::format!(
            "{}_{}",
            self.colour_sets[f.set].name,
            self.displays[f.display].name
        )
    }
}

/// The Planckian locus for `d`'s observer over CIE 015's range (360-830 nm, clipped to the
/// observer's table), whatever `d`'s range.
fn locus(d: &Derivation) -> Result<Locus, Error> {
    let locus = PlanckianLocus::standard(&d.observer)?;
    let nodes = locus.table();
    let out = nodes
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let chord = match nodes.get(i + 1) {
                Some(next) => [0, 1].map(|c| next.uv[c] - n.uv[c]),
                None => [0.0; 2],
            };
            let (unit_tangent_q14, along_q30) = n.fixed_point();
            Ok(LocusNode {
                mired: f32_of(n.mired)?,
                uv: array(&n.uv)?,
                tangent: array(&n.tangent)?,
                chord: array(&chord)?,
                unit_tangent_q14,
                along_q30,
            })
        })
        .collect::<Result<Vec<_>, Error>>()?;
    Ok(Locus {
        observer: [d.observer.name.to_string(), d.observer.file.to_string()],
        range_nm: standard_range_nm(&d.observer),
        mired_ends: [nodes[0].mired, nodes[nodes.len() - 1].mired],
        nodes: out,
    })
}

/// The provenance of the generated tables, one item a line: the generator, the settings, the
/// scene, what a planned scene chose, and each input with its SHA-256. The Rust tables write it
/// as the file's leading comment and as the const `HEADER`.
pub(crate) fn header(d: &Derivation, inputs: &[(String, String)], scene: &Resolved) -> String {
    use std::fmt::Write as _;
    let mut o = String::new();
    writeln!(
        o,
        "@generated by spectral-quadrature's build.rs (spectral-quadrature-generator, emit/codegen.rs): do not edit."
    )
    .ok();
    writeln!(o, "`cargo build` regenerates it whenever an input below, the scene or the generator crate changes.").ok();
    writeln!(o, "Settings: {}", d.settings).ok();
    writeln!(o, "Scene: {}", scene.file).ok();
    if let Some(p) = &scene.planned {
        writeln!(o, "Planned: {p}").ok();
    }
    writeln!(o, "Inputs:").ok();
    for (file, sha) in inputs {
        writeln!(o, "  {file} sha256={sha}").ok();
    }
    o
}
