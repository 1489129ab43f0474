//! Section 9: several lights in one scene. A light group (one node set shared by the lights, a
//! weight matrix folded per light, `spectral_quadrature_generator::shared::GroupFit`) against each
//! light's own folded set and against one radiance set fitted on the same lights, judged by
//! five-fold cross-validation on reflectances no fit saw (`tools::light_groups`).
//!
//! By default the reflectances judged are the ColorChecker and the 190 rawtoaces patches (the
//! CIE test colours, the folded sets' own training, are trained on in every fold); with
//! `--reflectances`, the user's file, or a seeded sample of `--sample` of them (each fold refits
//! on the others, so the time grows with their number): the text then says so and gives the
//! standard error the sample adds. The lights are D65, A, F11 and LED_B2 unless
//! `--illuminants` names others (two or more); with `--scene`, the scene's own light groups
//! (`[groups.*]`) are judged instead, each at its own size, each light against that light's own
//! folded set.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use spectral_quadrature_generator::shared::TRAINING_FILE;
use spectral_quadrature_generator::Derivation;
use spectral_quadrature_spectra::{Curve, Spectra};
use spectral_quadrature_tools as tools;
use tools::csv_table::Table;

use crate::inputs::Reflectances;
use crate::progress::Meter;
use crate::user::SceneGroup;
use tools::light_groups::{self, Comparison, GROUP_MEAN, GROUP_WORST, OWN, RADIANCE};
use tools::Error;

/// The targets at N = 8: the group's mean error within 15 % of the mean of the lights' own
/// folded sets, no light above 1.5 times its own set, every light below the radiance set.
const TARGET_MEAN: f64 = 1.15;
const TARGET_WORST: f64 = 1.5;

/// What section 9 measures on.
pub struct Inputs<'a> {
    /// The derivation.
    pub d: &'a Derivation,
    /// The reflectances judged.
    pub judged: &'a Reflectances,
    /// The user's lights, if `--illuminants` was given with two or more.
    pub lights: Option<&'a [Curve]>,
    /// The set sizes.
    pub sizes: &'a [usize],
    /// The scene's light groups (`--scene`), judged instead of the lights above when there
    /// are any.
    pub scene_groups: &'a [SceneGroup],
}

/// One group of lights the section judges, and how it names it.
struct Judged {
    /// The scene's group name, or `None` for the section's own lights.
    name: Option<String>,
    lights: Vec<Curve>,
    sizes: Vec<usize>,
    /// Whether the scene fits the group on bounce forms (judged here on reflectances).
    bounces: bool,
}

/// Runs section 9: its text and the files it wrote.
pub fn section(inputs: &Inputs, out: &Path) -> Result<(String, Vec<PathBuf>), Error> {
    let d = inputs.d;
    let range = d.settings.range_nm;
    let dir = &d.settings.data_dir;
    let groups: Vec<Judged> = if inputs.scene_groups.is_empty() {
        let lights: Vec<Curve> = match inputs.lights {
            Some(l) if l.len() >= 2 => l.to_vec(),
            _ => light_groups::builtin_lights(d, &light_groups::LIGHTS)?,
        };
        vec![Judged {
            name: None,
            lights,
            sizes: inputs.sizes.to_vec(),
            bounces: false,
        }]
    } else {
        inputs
            .scene_groups
            .iter()
            .map(|g| Judged {
                name: Some(g.name.clone()),
                lights: g.lights.clone(),
                sizes: vec![g.n],
                bounces: g.bounces,
            })
            .collect()
    };
    let training = Spectra::builtin(dir, TRAINING_FILE)?.curves(range)?;
    let judged = inputs.judged;
    let meter = Meter::new(
        "cross-validating",
        light_groups::FOLDS * groups.iter().map(|g| g.sizes.len()).sum::<usize>(),
        "folds",
    );
    let mut o = String::new();
    let mut table = Table::new(CSV_HEADER);
    for (k, g) in groups.iter().enumerate() {
        let comparisons = light_groups::compare(
            d,
            &g.lights,
            &training,
            &judged.curves,
            &g.sizes,
            &meter.counter(),
        )?;
        print(&mut o, &comparisons, judged, g, k == 0);
        let label = g.name.clone().unwrap_or_else(|| {
            g.lights
                .iter()
                .map(|l| l.name.as_str())
                .collect::<Vec<_>>()
                .join("+")
        });
        csv(&mut table, &label, &comparisons);
    }
    let file = table.write(out, "light_groups.csv")?;
    Ok((o, std::vec![file]))
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

fn print(
    o: &mut String,
    comparisons: &[Comparison],
    judged: &Reflectances,
    group: &Judged,
    heading: bool,
) {
    let Some(first) = comparisons.first() else {
        return;
    };
    let lights = first.lights.join(", ");
    if heading {
        let _ = writeln!(
            o,
            "9. Several lights in one scene: light groups ({} reflectances from {}, five-fold cross-validation: each fold judged by fits on the other four and the CIE test colours)\n",
            first.judged, judged.from
        );
    }
    if let Some(name) = &group.name {
        let _ = writeln!(
            o,
            "The scene's light group {name} ([groups.{name}], {} wavelengths){}.\n",
            first.n,
            if group.bounces {
                ": the scene fits it on bounce forms too (training = \"bounces\"); judged here as every group is, fitted on reflectances as they are (section 10 measures bounced light)"
            } else {
                ""
            }
        );
    }
    if heading && judged.sampled() {
        // The largest standard error over every mean of the tables, and relative to its mean.
        let (worst, relative) = comparisons
            .iter()
            .flat_map(|c| &c.methods)
            .flat_map(|m| m.mean_de00.iter().zip(&m.sd_de00))
            .map(|(mean, sd)| {
                let se = judged.standard_error(*sd);
                (se, se / mean)
            })
            .fold((0.0, 0.0), |a: (f64, f64), b| (a.0.max(b.0), a.1.max(b.1)));
        let _ = writeln!(o, "{}\n", judged.statement(worst, relative));
    }
    let _ = writeln!(
        o,
        "Lights: {lights}. A light group shares N nodes among the lights and folds each light into its own weights (least squares, white pinned); the radiance set has one weight matrix for radiances under every light. Mean ΔE00 per light (95th percentile), and the ratio to the light's own folded set.\n"
    );
    for c in comparisons {
        let own = &c.method(OWN).map_or(Vec::new(), |m| m.mean_de00.clone());
        let _ = writeln!(o, "N = {}", c.n);
        let mut header = std::format!("  {:<36}", "method");
        for l in &c.lights {
            header += &std::format!(" {l:>21}");
        }
        let _ = writeln!(o, "{header}  {:>6}  {:>6}", "mean", "/own");
        for m in &c.methods {
            let mut line = std::format!("  {:<36}", m.name);
            for (l, (v, p)) in m.mean_de00.iter().zip(&m.p95_de00).enumerate() {
                let cell = std::format!("{v:.3} ({p:.2}) {:.2}×", v / own[l]);
                line += &std::format!(" {cell:>21}");
            }
            let _ = writeln!(
                o,
                "{line}  {:>6.3}  {:>6.3}",
                mean(&m.mean_de00),
                mean(&m.mean_de00) / mean(own)
            );
        }
        if let (Some(g), Some(r)) = (c.method(GROUP_MEAN), c.method(RADIANCE)) {
            let ratio = mean(&g.mean_de00) / mean(own);
            let worst = g
                .mean_de00
                .iter()
                .zip(own)
                .map(|(a, b)| a / b)
                .fold(0.0, f64::max);
            let below = g.mean_de00.iter().zip(&r.mean_de00).all(|(a, b)| a < b);
            let verdict = |ok: bool| if ok { "met" } else { "missed" };
            let _ = writeln!(
                o,
                "  group (mean) against the targets: mean {ratio:.3}× the own sets' (target ≤ {TARGET_MEAN}: {}), worst light {worst:.2}× (≤ {TARGET_WORST}: {}), every light below the radiance set: {}",
                verdict(ratio <= TARGET_MEAN),
                verdict(worst <= TARGET_WORST),
                verdict(below)
            );
        }
        let _ = writeln!(o);
    }
    // Which objective generalised better, over every size measured.
    let total = |name: &str| -> f64 {
        comparisons
            .iter()
            .filter_map(|c| c.method(name))
            .map(|m| mean(&m.mean_de00))
            .sum()
    };
    let (by_mean, by_worst) = (total(GROUP_MEAN), total(GROUP_WORST));
    let over = if comparisons.len() > 1 {
        "Summed over the sizes".to_string()
    } else {
        format!("At N = {}", first.n)
    };
    let _ = writeln!(
        o,
        "{over}, the group searched for the mean ratio has a mean error of {by_mean:.3} and the one searched for the worst ratio {by_worst:.3}: `{}` generalises better on these reflectances (scenes default to `mean`).\n",
        if by_mean <= by_worst { "mean" } else { "worst" }
    );
}

/// The header of `light_groups.csv`.
const CSV_HEADER: &str = "group,n,method,light,mean_de00,p95_de00,ratio_to_own,nodes_nm_fold1";

/// The rows of `light_groups.csv` for the group called `group`.
fn csv(t: &mut Table, group: &str, comparisons: &[Comparison]) {
    for c in comparisons {
        let own = c.method(OWN).map_or(Vec::new(), |m| m.mean_de00.clone());
        for m in &c.methods {
            let nodes: Vec<String> = m.nodes_nm.first().map_or(Vec::new(), |n| {
                n.iter().map(|v| std::format!("{v}")).collect()
            });
            for (l, light) in c.lights.iter().enumerate() {
                t.row([
                    group.to_string(),
                    c.n.to_string(),
                    m.name.clone(),
                    light.clone(),
                    std::format!("{:.4}", m.mean_de00[l]),
                    std::format!("{:.4}", m.p95_de00[l]),
                    std::format!("{:.4}", m.mean_de00[l] / own[l]),
                    nodes.join(" "),
                ]);
            }
        }
    }
}
