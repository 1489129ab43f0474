//! Section 7: against random wavelengths. What spectral renderers do instead of a fixed set
//! (pbrt-v4's visible-wavelength sampling, hero sampling, plain uniform sampling), by samples
//! per pixel, beside the fixed sets at the same numbers of wavelengths, with the cost of each.
//! `docs/random-wavelengths.md` explains the setup and reads the results.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use spectral_quadrature::{tables, GamutMapping};

use crate::inputs::Reflectances;
use crate::plot::plot_err;
use crate::progress::Meter;
use crate::timing::time_set;
use crate::tools::budget;
use crate::tools::csv_table::Table;
use crate::tools::random_wavelengths::{
    pixel_rng, reach, run_trials, Cells, Config, Estimator, Reach, Sampler, SensorRgb, Summary,
    Target, Trials,
};
use crate::Error;
use spectral_quadrature_generator::Derivation;
use spectral_quadrature_spectra::{
    surfaces_under_lights, Curve, EvalSet, Reference, Spectra, Stimulus,
};

/// The samples per pixel measured: one pixel of the last is read after each.
pub const SPP: [usize; 6] = [1, 4, 16, 64, 256, 1024];

/// The samples per pixel the picture shows for pbrt-v4's sampler.
const PICTURE_SPP: [usize; 3] = [1, 16, 256];

/// The fixed sets' sizes: the random samplers' wavelengths per sample.
const SIZES: [usize; 2] = [4, 8];

/// Trials are added in rounds of this many (a multiple of the threads) until the means are
/// stable.
pub const ROUND: usize = 16;

/// The largest standard error, relative to its mean, that the section accepts for any mean
/// it reports (all stimuli and each light, every sampler and level) before it stops adding
/// trials.
pub const TARGET_RELATIVE_ERROR: f64 = 0.02;

/// The most trials a sampler gets without `--trials`.
pub const MAX_TRIALS: usize = 512;

/// The default lights with narrow peaks (a fluorescent lamp's lines, a white LED's blue
/// pump) that a fixed set's few nodes can miss: each gets a table of its own.
const SPIKY: [&str; 2] = ["F11", "LED_B2"];

/// What the section measures on.
pub struct Inputs<'a> {
    /// The derivation (the shared sets are searched with it).
    pub d: &'a Derivation,
    /// Every stimulus of the report.
    pub stimuli: &'a [Stimulus],
    /// Their reference (the 1 nm integration).
    pub reference: &'a Reference,
    /// Where the surfaces come from, in words.
    pub surfaces_from: &'a str,
    /// The lights the surfaces are under (empty for lights seen directly).
    pub lights: &'a [Curve],
    /// Whether the lights are the user's (each gets a table of its own then; of the report's
    /// default lights only the spiky ones do).
    pub users_lights: bool,
    /// The paper's 4-wavelength set (Table 2 row 2).
    pub table2_row2: &'a EvalSet,
    /// Trials per sampler; `None`: rounds of [`ROUND`] trials until every mean the section
    /// reports has a standard error within [`TARGET_RELATIVE_ERROR`] of itself (at most
    /// [`MAX_TRIALS`]).
    pub trials: Option<usize>,
    /// The seed of every trial's random numbers.
    pub seed: u64,
    /// Timing runs (the median is reported).
    pub runs: usize,
    /// The reflectances, when `stimuli` are a seeded sample of them under each light (light
    /// by light, the sample's reflectances in the same order under each).
    pub sample: Option<&'a Reflectances>,
}

/// The random samplers: pbrt-v4's, hero and uniform at 4 wavelengths a sample, then at 8.
/// Hero and uniform draw on `span` (the reference's cells).
pub fn configs(span: [f64; 2]) -> Vec<Config> {
    let mut v = Vec::new();
    for wavelengths in SIZES {
        for sampler in [
            Sampler::Visible,
            Sampler::Hero { range_nm: span },
            Sampler::Uniform { range_nm: span },
        ] {
            v.push(Config {
                sampler,
                wavelengths,
            });
        }
    }
    v
}

/// The stimuli a row is judged on: all, or those under one light.
#[derive(Clone, PartialEq)]
enum Group {
    All,
    Light(String),
}

impl Group {
    fn label(&self) -> String {
        match self {
            Group::All => "all stimuli".into(),
            Group::Light(l) => format!("under {l}"),
        }
    }
}

/// A fixed set, judged on a group.
struct Fixed {
    set: EvalSet,
    group: Group,
    mean_de00: f64,
    mean_de76: f64,
    ns_per_pixel: f64,
    /// The light folded in, and how long its node search took in this run.
    search_s: Option<f64>,
    /// The standard error a sample of the reflectances adds to `mean_de00` (zero for all).
    sampling_se: f64,
}

/// One sampler's trials and what they cost.
struct Random {
    config: Config,
    trials: Trials,
    ns_per_sample: f64,
}

/// Text, and the files written.
pub fn section(x: &Inputs, out: &Path) -> Result<(String, Vec<PathBuf>), Error> {
    let start = Instant::now();
    let reference = x.reference;
    let targets: Vec<Target> = x
        .stimuli
        .iter()
        .zip(&reference.levels)
        .zip(&reference.labs)
        .map(|((s, &level), &lab)| {
            Ok(Target {
                cells: Cells::weighted(&reference.set, |l| s.radiance(l))?,
                white: reference.set.xyz(|l| s.white(l, level)),
                lab,
            })
        })
        .collect::<Result<_, Error>>()?;
    let span = targets
        .first()
        .map(|t| t.cells.span_nm())
        .ok_or_else(|| Error::Sampling("no stimuli".into()))?;
    let mut groups: Vec<(Group, Vec<usize>)> = vec![(Group::All, (0..x.stimuli.len()).collect())];
    // A light under which every stimulus lies (the user's only light) has no group of its own:
    // its stimuli are all of them, and its rows say "all stimuli" like every other row judged on
    // them, not "under" it for the same stimuli.
    let mut covering_all: Vec<&Curve> = Vec::new();
    for l in x.lights {
        let which: Vec<usize> = (0..x.stimuli.len())
            .filter(|&k| x.stimuli[k].reflectance.is_some() && x.stimuli[k].light.name == l.name)
            .collect();
        if which.len() == x.stimuli.len() {
            covering_all.push(l);
        } else if !which.is_empty() {
            groups.push((Group::Light(l.name.clone()), which));
        }
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());

    // The random samplers: trials, then the per-sample cost of the f32 colour path.
    // The reference's weights are x̄ȳz̄ times its step: per nm again for the sensor.
    let w = &reference.set.wavelengths_nm;
    let step = w[1] - w[0];
    let xyz_bar: Vec<[f64; 3]> = (0..w.len())
        .map(|k| [0, 1, 2].map(|c| reference.set.xyz_weights[c][k] / step))
        .collect();
    let sensor = SensorRgb::new(
        reference.set.wavelengths_nm[0],
        &xyz_bar,
        tables::displays::SRGB.xyz_to_rgb(),
        1.0,
    );
    let mut randoms = Vec::new();
    let group_targets: Vec<Vec<usize>> = groups.iter().map(|(_, w)| w.clone()).collect();
    let samplers = configs(span);
    // Trials counted as they finish: a round (or `--trials`) per sampler to begin with, more
    // when a sampler's means need another round.
    let first = x.trials.unwrap_or(ROUND);
    let meter = Meter::new("random trials", samplers.len() * first, "trials");
    for (i, config) in samplers.into_iter().enumerate() {
        // A few trials at a time (each on every thread), for the progress line: the trials are
        // the same however they are split (`run_trials`).
        let run = |r: std::ops::Range<usize>| -> Result<Trials, Error> {
            let mut t = Trials {
                spp: SPP.to_vec(),
                errors: Vec::new(),
            };
            let step = threads.max(1);
            let mut k = r.start;
            while k < r.end {
                let more = run_trials(
                    config,
                    &targets,
                    &SPP,
                    k..(k + step).min(r.end),
                    x.seed,
                    i as u64,
                    threads,
                )?;
                meter.add(more.len());
                k += more.len();
                t.append(more)?;
            }
            Ok(t)
        };
        let trials = match x.trials {
            Some(n) => run(0..n)?,
            None => {
                let mut t = run(0..ROUND)?;
                while t.len() < MAX_TRIALS
                    && t.worst_relative_error(&group_targets) > TARGET_RELATIVE_ERROR
                {
                    meter.more(ROUND);
                    t.append(run(t.len()..t.len() + ROUND)?)?;
                }
                t
            }
        };
        randoms.push(Random {
            config,
            trials,
            ns_per_sample: f64::NAN,
        });
    }
    let trials_s = start.elapsed().as_secs_f64();
    // Timed after the trials, one sampler after another, with nine times the runs of a fixed
    // set: each run lasts about half a millisecond, and the median of many resists the busy
    // moments of a shared machine.
    for r in randoms.iter_mut() {
        let runs = 9 * x.runs;
        r.ns_per_sample = match r.config.wavelengths {
            4 => time_random::<4>(r.config.sampler, &sensor, x.stimuli, runs),
            8 => time_random::<8>(r.config.sampler, &sensor, x.stimuli, runs),
            n => return Err(Error::NoTimingPath(n)),
        };
    }
    let timing_s = start.elapsed().as_secs_f64() - trials_s;

    // The fixed sets: Table 2 row 2 and the shared sets for radiances on every stimulus and
    // under each light; the shared sets with each light folded in under that light.
    let mut fixed = Vec::new();
    let radiance = budget::shared_sets_sized(x.d, None, SIZES)?;
    let judge = |set: &EvalSet,
                 group: &Group,
                 which: &[usize],
                 search_s: Option<f64>|
     -> Result<Fixed, Error> {
        let stimuli: Vec<Stimulus> = which.iter().map(|&k| x.stimuli[k].clone()).collect();
        let e = Reference::new(reference.set.clone(), &stimuli).errors(set, &stimuli);
        let sampling_se = sampling_se(x.sample, which, |k| e.de00[k]);
        Ok(Fixed {
            sampling_se,
            set: set.clone(),
            group: group.clone(),
            mean_de00: e.mean_de00(),
            mean_de76: e.mean_de76(),
            ns_per_pixel: time_set(set, &stimuli, x.runs)?,
            search_s,
        })
    };
    for (group, which) in &groups {
        if *group == Group::All {
            fixed.push(judge(x.table2_row2, group, which, None)?);
        }
        for set in &radiance {
            fixed.push(judge(set, group, which, None)?);
        }
        let folded: Vec<&Curve> = match group {
            Group::Light(name) => x.lights.iter().filter(|l| &l.name == name).collect(),
            Group::All => covering_all.clone(),
        };
        for light in folded {
            for n in SIZES {
                // Searched, never from the node cache: the time is the search's.
                let t = Instant::now();
                let set = budget::shared_sets_sized_with(
                    x.d,
                    &crate::tools::node_cache::NodeCache::empty(),
                    Some(light),
                    [n],
                )?
                .remove(0);
                let search = t.elapsed().as_secs_f64();
                fixed.push(judge(&set, group, which, Some(search))?);
            }
        }
    }

    let summaries: Vec<Vec<Vec<Summary>>> = randoms
        .iter()
        .map(|r| groups.iter().map(|(_, w)| r.trials.summarize(w)).collect())
        .collect();

    // What a sample of the reflectances adds to the means: the largest standard error, and the
    // largest relative to its mean, over the samplers at every level and the fixed sets.
    let mut sampling = (0.0f64, 0.0f64);
    if x.sample.is_some_and(|r| r.sampled()) {
        let mut add = |se: f64, mean: f64| {
            sampling = (sampling.0.max(se), sampling.1.max(se / mean));
        };
        for (r, per_group) in randoms.iter().zip(&summaries) {
            for ((_, which), levels) in groups.iter().zip(per_group) {
                for (level, summary) in levels.iter().enumerate() {
                    // A stimulus' error averaged over the trials (their noise left in: the
                    // spread, and so the standard error, is if anything overstated).
                    let se = sampling_se(x.sample, which, |k| {
                        r.trials
                            .errors
                            .iter()
                            .map(|t| t[level][which[k]].0)
                            .sum::<f64>()
                            / r.trials.len() as f64
                    });
                    add(se, summary.mean_de00);
                }
            }
        }
        for f in &fixed {
            add(f.sampling_se, f.mean_de00);
        }
    }

    let mut o = String::new();
    let mut files = Vec::new();
    let statement = x
        .sample
        .filter(|r| r.sampled())
        .map(|r| r.statement(sampling.0, sampling.1));
    text(
        &mut o, x, &groups, &randoms, &summaries, &fixed, span, statement,
    );
    files.push(summary_csv(&groups, &randoms, &summaries).write(out, "random_wavelengths.csv")?);
    files.push(reach_csv(&groups, &randoms, &summaries, &fixed).write(out, "random_vs_fixed.csv")?);
    files.push(plot(out, &groups, &randoms, &summaries, &fixed)?);
    if !x.lights.is_empty() {
        files.push(picture(out, x, &fixed)?);
    }
    writeln!(
        o,
        "   ({trials_s:.1} s for the trials, {timing_s:.2} s to time the samplers, {:.1} s in all)",
        start.elapsed().as_secs_f64()
    )
    .ok();
    Ok((o, files))
}

/// The standard error that a sample of the reflectances adds to a mean over the stimuli
/// `which` (indices into the section's stimuli, the sample's reflectances under each light in
/// turn), `error(i)` the error of `which[i]`: the errors averaged per reflectance (over the
/// lights in `which`), their spread over the reflectances, and the sample's standard error of
/// it (zero when the reflectances are not a sample).
fn sampling_se(
    sample: Option<&Reflectances>,
    which: &[usize],
    error: impl Fn(usize) -> f64,
) -> f64 {
    let Some(r) = sample.filter(|r| r.sampled()) else {
        return 0.0;
    };
    let m = r.curves.len();
    let mut sum = vec![0.0; m];
    let mut count = vec![0usize; m];
    for (i, &k) in which.iter().enumerate() {
        sum[k % m] += error(i);
        count[k % m] += 1;
    }
    let means: Vec<f64> = sum
        .iter()
        .zip(&count)
        .filter(|(_, &c)| c > 0)
        .map(|(s, &c)| s / c as f64)
        .collect();
    r.standard_error(crate::tools::light_groups::standard_deviation(&means))
}

/// The cell of a reach table: `12`, `≤1`, `~3.1k` (extrapolated past the last level, two
/// significant digits), `never`.
fn reach_cell(r: Reach) -> String {
    match r {
        Reach::AtFirst => "≤1".into(),
        Reach::Between(s) => format!("{s:.0}"),
        Reach::Beyond(s) => {
            let (v, unit) = if s >= 1e6 {
                (s / 1e6, "M")
            } else if s >= 1e3 {
                (s / 1e3, "k")
            } else {
                (s, "")
            };
            if v >= 10.0 {
                format!("~{:.0}{unit}", v)
            } else {
                format!("~{v:.1}{unit}")
            }
        }
        Reach::Never => "never".into(),
    }
}

fn curve(s: &[Summary]) -> Vec<(usize, f64)> {
    s.iter().map(|x| (x.spp, x.mean_de00)).collect()
}

fn short(c: &Config) -> String {
    let name = match c.sampler {
        Sampler::Visible => "pbrt",
        Sampler::Hero { .. } => "hero",
        Sampler::Uniform { .. } => "unif",
    };
    format!("{name}×{}", c.wavelengths)
}

#[allow(clippy::too_many_arguments)]
fn text(
    o: &mut String,
    x: &Inputs,
    groups: &[(Group, Vec<usize>)],
    randoms: &[Random],
    summaries: &[Vec<Vec<Summary>>],
    fixed: &[Fixed],
    span: [f64; 2],
    sampling: Option<String>,
) {
    let n = x.stimuli.len();
    let what = if x.lights.is_empty() {
        "lights seen directly".to_string()
    } else {
        format!(
            "{} under {}",
            x.surfaces_from,
            x.lights
                .iter()
                .map(|l| l.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    let trials = match x.trials {
        Some(t) => format!("   {t} seeded trials per sampler (--trials; seed {}).", x.seed),
        None => format!(
            "   Seeded trials (seed {}) in rounds of {ROUND}, until every mean below, on all stimuli and under each\n   light, has a standard error within {:.0} % of itself.",
            x.seed,
            100.0 * TARGET_RELATIVE_ERROR
        ),
    };
    let lines = [
        "7. Against random wavelengths: what renderers do instead, by samples per pixel (spp)".to_string(),
        format!("   {n} stimuli: {what}."),
        "   In direct view, so the error is the spectral part of a renderer's only. The exact colour is the 1 nm".to_string(),
        "   integration. A random sampler's pixel is normalised by the exact white (a renderer's film has a fixed".to_string(),
        "   white), a fixed set's by its own white (as in sections 1-5).".to_string(),
        trials,
        format!(
            "   In each trial every stimulus gets one pixel of {} samples, read after {} samples.",
            SPP[SPP.len() - 1],
            SPP.map(|s| s.to_string()).join(", ")
        ),
        format!(
            "   pbrt-v4 draws on 360-830 nm (its own range), hero and uniform on {}-{} nm (the reference's cells).",
            span[0], span[1]
        ),
    ];
    for l in lines {
        writeln!(o, "{l}").ok();
    }
    if let Some(s) = sampling {
        writeln!(o, "{s}").ok();
    }

    let all = 0;
    writeln!(o, "\n   7a. mean ΔE00 on all stimuli ± its standard error over the trials; ns/sample: the f32 colour path per sample").ok();
    let mut header = format!("   {:<21}", "sampler");
    for s in SPP {
        write!(header, " {:>13}", format!("{s} spp")).ok();
    }
    writeln!(o, "{header} {:>10} {:>7}", "ns/sample", "trials").ok();
    for (r, s) in randoms.iter().zip(summaries) {
        let mut line = format!("   {:<21}", r.config.label());
        for m in &s[all] {
            write!(
                line,
                " {:>13}",
                format!("{:.3} ±{:.3}", m.mean_de00, m.standard_error)
            )
            .ok();
        }
        writeln!(o, "{line} {:>10.1} {:>7}", r.ns_per_sample, r.trials.len()).ok();
    }
    let on_all: Vec<&Fixed> = fixed.iter().filter(|f| f.group == Group::All).collect();
    let names: Vec<String> = on_all
        .iter()
        .map(|f| format!("{} ({} λ) {:.3}", f.set.name, f.set.len(), f.mean_de00))
        .collect();
    let times: Vec<String> = on_all
        .iter()
        .map(|f| format!("{:.1}", f.ns_per_pixel))
        .collect();
    writeln!(
        o,
        "   fixed sets, the same at every spp (no noise): {}",
        names.join(", ")
    )
    .ok();
    writeln!(
        o,
        "   their colour path (f32, the 3×N product, batches of 2048 pixels): {} ns/pixel",
        times.join(", ")
    )
    .ok();
    // The largest relative standard error on all stimuli, and under any one light.
    let worst = |lights: bool| {
        summaries
            .iter()
            .flat_map(|s| {
                s.iter()
                    .enumerate()
                    .filter(move |(i, _)| (*i != all) == lights)
                    .flat_map(|(_, v)| v.iter())
            })
            .map(|m| m.standard_error / m.mean_de00)
            .fold(f64::NAN, f64::max)
    };
    let (on_all, by_light) = (worst(false), worst(true));
    let mut line = format!(
        "   largest standard error: {:.1} % of its mean on all stimuli",
        100.0 * on_all
    );
    if !by_light.is_nan() {
        write!(line, ", {:.1} % under one light", 100.0 * by_light).ok();
    }
    if on_all.max(by_light) > TARGET_RELATIVE_ERROR {
        write!(
            line,
            " (above {:.0} %: more --trials would steady it)",
            100.0 * TARGET_RELATIVE_ERROR
        )
        .ok();
    }
    writeln!(o, "{line}").ok();

    writeln!(o, "\n   7b. spread: the 90th percentile of single pixels' ΔE00 (what a viewer sees as colour noise), all stimuli").ok();
    let mut header = format!("   {:<21}", "sampler");
    for s in SPP {
        write!(header, " {:>9}", format!("{s} spp")).ok();
    }
    writeln!(o, "{header}").ok();
    for (r, s) in randoms.iter().zip(summaries) {
        let mut line = format!("   {:<21}", r.config.label());
        for m in &s[all] {
            write!(line, " {:>9.3}", m.p90_pixel).ok();
        }
        writeln!(o, "{line}").ok();
    }

    writeln!(o, "\n   7c. samples per pixel at which each sampler's mean ΔE00 reaches each fixed set's (interpolated in log-log;").ok();
    writeln!(o, "       ~: extrapolated past {} spp along the last step). A sample costs a renderer the same shading at N random", SPP[SPP.len() - 1]).ok();
    writeln!(o, "       or N fixed wavelengths, so these are also the ratios of render time at equal error (cost per sample in 7a).").ok();
    let mut header = format!(
        "   {:<16} {:<13} {:>9} {:>8}",
        "fixed set", "judged on", "mean ΔE00", "ns/pixel"
    );
    for r in randoms {
        write!(header, " {:>7}", short(&r.config)).ok();
    }
    writeln!(o, "{header}").ok();
    for f in fixed
        .iter()
        .filter(|f| f.group == Group::All || f.search_s.is_some())
    {
        let g = groups
            .iter()
            .position(|(g, _)| *g == f.group)
            .unwrap_or(all);
        let mut line = format!(
            "   {:<16} {:<13} {:>9.3} {:>8.1}",
            f.set.name,
            f.group.label(),
            f.mean_de00,
            f.ns_per_pixel
        );
        for s in summaries {
            write!(
                line,
                " {:>7}",
                reach_cell(reach(&curve(&s[g]), f.mean_de00))
            )
            .ok();
        }
        writeln!(o, "{line}").ok();
    }

    let spiky: Vec<usize> = groups
        .iter()
        .enumerate()
        .filter(|(_, (g, _))| match g {
            Group::Light(l) => x.users_lights || SPIKY.contains(&l.as_str()),
            // The user's only light: its folded sets are judged on all stimuli.
            Group::All => x.users_lights && groups.len() == 1 && !x.lights.is_empty(),
        })
        .map(|(i, _)| i)
        .collect();
    for &g in &spiky {
        let label = groups[g].0.label();
        writeln!(o, "\n   7d. {label}: random sampling stays unbiased; a fixed set needs the light folded in").ok();
        let mut header = format!("   {:<21}", "sampler, mean ΔE00");
        for s in SPP {
            write!(header, " {:>9}", format!("{s} spp")).ok();
        }
        writeln!(o, "{header}").ok();
        for (r, s) in randoms.iter().zip(summaries) {
            let mut line = format!("   {:<21}", r.config.label());
            for m in &s[g] {
                write!(line, " {:>9.3}", m.mean_de00).ok();
            }
            writeln!(o, "{line}").ok();
        }
        for f in fixed.iter().filter(|f| f.group == groups[g].0) {
            let how = match f.search_s {
                Some(t) => format!("fixed, light folded in; its nodes searched in {t:.2} s here"),
                None => "fixed, for radiances under any light".to_string(),
            };
            writeln!(o, "   {:<21} {:>9.3}   ({how})", f.set.name, f.mean_de00).ok();
        }
    }
    if !spiky.is_empty() {
        writeln!(o, "   A set with the light folded in exists only for a light known at build time: a scene names it, and the").ok();
        writeln!(o, "   build searches its nodes (times above: this release build; a downstream build runs the search at").ok();
        writeln!(o, "   opt-level 0, seconds per set, unless the node cache holds it). Random sampling needs no such step.").ok();
    }
}

fn summary_csv(
    groups: &[(Group, Vec<usize>)],
    randoms: &[Random],
    summaries: &[Vec<Vec<Summary>>],
) -> Table {
    let mut t = Table::new("sampler,wavelengths_per_sample,spp,judged_on,stimuli,trials,mean_de00,standard_error_de00,sd_trials_de00,p90_pixel_de00,mean_de76,ns_per_sample");
    for (r, per_group) in randoms.iter().zip(summaries) {
        for ((g, which), sums) in groups.iter().zip(per_group) {
            for x in sums {
                t.row([
                    r.config.sampler.name().to_string(),
                    r.config.wavelengths.to_string(),
                    x.spp.to_string(),
                    g.label(),
                    which.len().to_string(),
                    x.trials.to_string(),
                    format!("{:.4}", x.mean_de00),
                    format!("{:.4}", x.standard_error),
                    format!("{:.4}", x.sd_trials),
                    format!("{:.4}", x.p90_pixel),
                    format!("{:.4}", x.mean_de76),
                    format!("{:.2}", r.ns_per_sample),
                ]);
            }
        }
    }
    t
}

fn reach_csv(
    groups: &[(Group, Vec<usize>)],
    randoms: &[Random],
    summaries: &[Vec<Vec<Summary>>],
    fixed: &[Fixed],
) -> Table {
    let mut t = Table::new("fixed_set,wavelengths,judged_on,mean_de00,mean_de76,ns_per_pixel,light_search_s,sampler,wavelengths_per_sample,spp_to_reach,how,ns_per_sample");
    for f in fixed {
        let g = groups.iter().position(|(g, _)| *g == f.group).unwrap_or(0);
        for (r, per_group) in randoms.iter().zip(summaries) {
            let (spp, how) = match reach(&curve(&per_group[g]), f.mean_de00) {
                Reach::AtFirst => (1.0, "at one"),
                Reach::Between(v) => (v, "interpolated"),
                Reach::Beyond(v) => (v, "extrapolated"),
                Reach::Never => (f64::NAN, "never"),
            };
            t.row([
                f.set.name.clone(),
                f.set.len().to_string(),
                f.group.label(),
                format!("{:.4}", f.mean_de00),
                format!("{:.4}", f.mean_de76),
                format!("{:.2}", f.ns_per_pixel),
                f.search_s.map_or(String::new(), |t| format!("{t:.3}")),
                r.config.sampler.name().to_string(),
                r.config.wavelengths.to_string(),
                format!("{spp:.1}"),
                how.to_string(),
                format!("{:.2}", r.ns_per_sample),
            ]);
        }
    }
    t
}

/// Median ns per sample of the f32 colour path of a random sampler: the sample's wavelengths
/// and densities from one PCG draw (N for uniform), then the sensor's matching functions at
/// them times the radiance over the density, added to the pixel. The radiance comes from a
/// buffer, as a fixed set's samples do in `time_set`: shading is the renderer's either way.
fn time_random<const N: usize>(
    sampler: Sampler,
    sensor: &SensorRgb,
    stimuli: &[Stimulus],
    runs: usize,
) -> f64 {
    // A small block of pixels (their samples stay in the first-level cache, as a fixed set's
    // do in `time_set`), and short runs: about a tenth of a millisecond each, calibrated on
    // one pass, so that few of the many runs share their time with another process.
    const PIXELS: usize = 256;
    let radiance: Vec<[f32; N]> = (0..PIXELS)
        .map(|p| {
            let s = &stimuli[p % stimuli.len()];
            std::array::from_fn(|i| s.radiance(400.0 + 300.0 * i as f64 / N as f64) as f32)
        })
        .collect();
    let mut pixels = vec![[0.0f32; 3]; PIXELS];
    let mut rng = pixel_rng(0, &[N as u64]);
    let mut pass = |reps: usize| {
        let t = Instant::now();
        for _ in 0..reps {
            for (px, r) in pixels.iter_mut().zip(std::hint::black_box(&radiance)) {
                let (l, p) = sampler.wavelengths_f32::<N, _>(&mut rng);
                sensor.add_sample(&l, &p, r, px);
            }
            std::hint::black_box(&mut pixels);
        }
        t.elapsed().as_nanos() as f64 / (reps * PIXELS) as f64
    };
    let once = pass(1);
    let reps = (100_000.0 / (once * PIXELS as f64)).clamp(1.0, 1000.0) as usize;
    let mut times: Vec<f64> = (0..runs).map(|_| pass(reps)).collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

// ---------------------------------------------------------------------------------------------
// The plot: mean ΔE00 against samples per pixel, fixed sets as horizontal lines.

fn colour_of(c: &Config) -> RGBColor {
    match c.sampler {
        Sampler::Visible => RGBColor(200, 30, 30),
        Sampler::Hero { .. } => RGBColor(30, 90, 200),
        Sampler::Uniform { .. } => RGBColor(40, 150, 60),
    }
}

fn plot(
    out: &Path,
    groups: &[(Group, Vec<usize>)],
    randoms: &[Random],
    summaries: &[Vec<Vec<Summary>>],
    fixed: &[Fixed],
) -> Result<PathBuf, Error> {
    let path = out.join("random_wavelengths.svg");
    // All stimuli first, then the spiky lights and C (or the user's first lights).
    let mut shown: Vec<usize> = vec![0];
    for want in ["F11", "LED_B2", "C"] {
        if let Some(i) = groups
            .iter()
            .position(|(g, _)| *g == Group::Light(want.into()))
        {
            shown.push(i);
        }
    }
    for i in 1..groups.len() {
        if shown.len() < 4 && !shown.contains(&i) {
            shown.push(i);
        }
    }
    let rows = shown.len().div_ceil(2);
    const LEGEND_H: u32 = 64;
    let root = SVGBackend::new(&path, (1100, 420 * rows as u32 + LEGEND_H)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let (top, legend) = root.split_vertically(420 * rows as u32);
    let panels = top.split_evenly((rows, 2));
    const FLOOR: f64 = 0.01;
    let spp_max = SPP[SPP.len() - 1] as f64;
    for (panel, &g) in panels.iter().zip(&shown) {
        let mut here: Vec<&Fixed> = fixed.iter().filter(|f| f.group == groups[g].0).collect();
        // Highest first, for the labels below.
        here.sort_by(|a, b| b.mean_de00.total_cmp(&a.mean_de00));
        let emax = summaries
            .iter()
            .flat_map(|s| s[g].iter().map(|x| x.p90_pixel))
            .chain(here.iter().map(|f| f.mean_de00))
            .fold(FLOOR, f64::max);
        let emin = summaries
            .iter()
            .flat_map(|s| s[g].iter().map(|x| x.mean_de00))
            .chain(here.iter().map(|f| f.mean_de00))
            .fold(f64::MAX, f64::min)
            .max(FLOOR);
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!(
                    "{}: mean ΔE00 against samples per pixel",
                    groups[g].0.label()
                ),
                ("sans-serif", 16),
            )
            .margin(10)
            .x_label_area_size(34)
            .y_label_area_size(50)
            .build_cartesian_2d(
                (0.8f64..spp_max * 1.25).log_scale(),
                (emin * 0.6..emax * 1.4).log_scale(),
            )
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc("samples per pixel (log)")
            .x_label_formatter(&crate::plot::whole)
            .y_desc("ΔE00 (log)")
            .draw()
            .map_err(plot_err)?;
        for (r, s) in randoms.iter().zip(summaries) {
            let colour = colour_of(&r.config);
            let style = colour.stroke_width(2);
            let pts: Vec<(f64, f64)> = s[g].iter().map(|x| (x.spp as f64, x.mean_de00)).collect();
            // 4 wavelengths a sample solid, 8 dashed.
            if r.config.wavelengths == 4 {
                chart.draw_series(LineSeries::new(pts.clone(), style))
            } else {
                chart.draw_series(DashedLineSeries::new(pts.clone(), 8, 4, style))
            }
            .map_err(plot_err)?;
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 3, colour.filled())))
                .map_err(plot_err)?;
            // The spread for pbrt-v4 at 4 wavelengths: single pixels' 90th percentile.
            if r.config.sampler == Sampler::Visible && r.config.wavelengths == 4 {
                let p90: Vec<(f64, f64)> =
                    s[g].iter().map(|x| (x.spp as f64, x.p90_pixel)).collect();
                chart
                    .draw_series(DashedLineSeries::new(p90, 2, 3, colour.stroke_width(1)))
                    .map_err(plot_err)?;
            }
        }
        // The fixed sets: horizontal lines, named at their right end; a name goes under its
        // line when the line above is too close to leave room between them.
        let mut above = f64::MAX;
        for f in &here {
            let y = f.mean_de00.max(FLOOR);
            let grey = RGBColor(90, 90, 90);
            chart
                .draw_series(LineSeries::new(
                    vec![(0.8, y), (spp_max * 1.25, y)],
                    grey.stroke_width(1),
                ))
                .map_err(plot_err)?;
            let v = if y * 1.35 > above {
                VPos::Top
            } else {
                VPos::Bottom
            };
            above = y;
            chart
                .draw_series(std::iter::once(Text::new(
                    format!(
                        "{} ({} λ, fixed) {:.2}",
                        f.set.name,
                        f.set.len(),
                        f.mean_de00
                    ),
                    (spp_max * 1.2, y),
                    TextStyle::from(("sans-serif", 10).into_font()).pos(Pos::new(HPos::Right, v)),
                )))
                .map_err(plot_err)?;
        }
    }
    // One legend for every panel, below them.
    // (label, colour, width, dashes: on and off lengths)
    type Entry = (String, RGBColor, u32, Option<(u32, u32)>);
    let mut entries: Vec<Entry> = randoms
        .iter()
        .map(|r| {
            let dash = (r.config.wavelengths != 4).then_some((8, 4));
            (
                format!("{} (mean)", r.config.label()),
                colour_of(&r.config),
                2,
                dash,
            )
        })
        .collect();
    entries.push((
        "pbrt-v4 visible ×4: 90 % of single pixels below".into(),
        colour_of(&randoms[0].config),
        1,
        Some((2, 3)),
    ));
    entries.push(("fixed set (no noise)".into(), RGBColor(90, 90, 90), 1, None));
    for (k, (label, colour, width, dash)) in entries.iter().enumerate() {
        let (x, y) = (20 + (k as i32 % 4) * 270, 14 + (k as i32 / 4) * 22);
        let style = colour.stroke_width(*width);
        match dash {
            None => legend
                .draw(&PathElement::new(vec![(x, y), (x + 32, y)], style))
                .map_err(plot_err)?,
            Some((on, off)) => {
                let mut a = x;
                while a < x + 32 {
                    let b = (a + *on as i32).min(x + 32);
                    legend
                        .draw(&PathElement::new(vec![(a, y), (b, y)], style))
                        .map_err(plot_err)?;
                    a = b + *off as i32;
                }
            }
        }
        legend
            .draw(&Text::new(
                label.clone(),
                (x + 40, y),
                TextStyle::from(("sans-serif", 12).into_font())
                    .pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(plot_err)?;
    }
    root.present().map_err(plot_err)?;
    drop(panels);
    drop(top);
    drop(legend);
    drop(root);
    Ok(path)
}

// ---------------------------------------------------------------------------------------------
// The picture: the ColorChecker under each light as a renderer shows it.

/// The ColorChecker under each light: the truth, pbrt-v4's sampler (4 wavelengths a sample)
/// at [`PICTURE_SPP`], each patch a block of pixels with their own random numbers, and the
/// light's folded shared sets at 4 and 8 wavelengths.
fn picture(out: &Path, x: &Inputs, fixed: &[Fixed]) -> Result<PathBuf, Error> {
    const PX: i32 = 8; // one rendered pixel, in SVG units
    const BLOCK: i32 = 3; // pixels per patch side
    let patch = PX * BLOCK;
    let (cols, rows) = (6i32, 4i32);
    let panel_w = cols * (patch + 2) + 14;
    let panel_h = rows * (patch + 2) + 24;
    let panels = 2 + PICTURE_SPP.len() as i32 + SIZES.len() as i32;
    let path = out.join("random_swatches.svg");
    let width = (panels * panel_w + 90) as u32;
    let height = (x.lights.len() as i32 * panel_h + 40) as u32;
    let root = SVGBackend::new(&path, (width, height)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    root.draw(&Text::new(
        "ColorChecker (Ohta) under each light, sRGB (the light's white at Y = 1, no adaptation): the truth, pbrt-v4's random wavelengths (4 a sample; each patch 3×3 pixels with samples of their own), the light's shared sets",
        (10, 8),
        ("sans-serif", 13),
    ))
    .map_err(plot_err)?;
    let d = x.d;
    let cc = Spectra::builtin(&d.settings.data_dir, budget::JUDGE_FILE)
        .and_then(|s| s.curves(d.settings.range_nm))?;
    let reference = &x.reference.set;
    let srgb = tables::displays::SRGB;
    let rgb = |xyz: [f64; 3], white_y: f64| {
        let px = srgb.encode_u8(
            GamutMapping::Clip,
            srgb.linear_from_xyz(xyz.map(|v| (v / white_y) as f32)),
        );
        RGBColor(px[0], px[1], px[2])
    };
    let spp_max = PICTURE_SPP[PICTURE_SPP.len() - 1];
    for (li, light) in x.lights.iter().enumerate() {
        let y0 = 30 + li as i32 * panel_h;
        root.draw(&Text::new(
            light.name.clone(),
            (10, y0 + panel_h / 2),
            ("sans-serif", 14),
        ))
        .map_err(plot_err)?;
        let stimuli = surfaces_under_lights(&cc, std::slice::from_ref(light));
        let white = reference.xyz(|l| light.at(l));
        let folded: Vec<&Fixed> = fixed
            .iter()
            .filter(|f| f.search_s.is_some() && f.group == Group::Light(light.name.clone()))
            .collect();
        let mut titles = vec!["truth (1 nm)".to_string()];
        titles.extend(PICTURE_SPP.map(|s| format!("pbrt-v4 ×4, {s} spp")));
        titles.extend(folded.iter().map(|f| format!("{} (fixed)", f.set.name)));
        for (p, t) in titles.iter().enumerate() {
            root.draw(&Text::new(
                t.clone(),
                (80 + p as i32 * panel_w, y0),
                ("sans-serif", 11),
            ))
            .map_err(plot_err)?;
        }
        let mut scratch = [0.0; 4];
        // Every stimulus' cells lie on the reference's grid: one estimator serves them all.
        let estimator = Estimator::new(Sampler::Visible, &Cells::weighted(reference, |_| 1.0)?);
        for (k, s) in stimuli.iter().enumerate().take((cols * rows) as usize) {
            let cells = Cells::weighted(reference, |l| s.radiance(l))?;
            let (cx, cy) = (
                (k as i32 % cols) * (patch + 2),
                14 + (k as i32 / cols) * (patch + 2),
            );
            let at = |p: usize| (80 + p as i32 * panel_w + cx, y0 + cy);
            let solid = |p: usize, c: RGBColor| {
                let (x0, y) = at(p);
                Rectangle::new([(x0, y), (x0 + patch, y + patch)], c.filled())
            };
            root.draw(&solid(0, rgb(reference.xyz(|l| s.radiance(l)), white[1])))
                .map_err(plot_err)?;
            for (q, f) in folded.iter().enumerate() {
                let own_white = f.set.xyz(|l| light.at(l))[1];
                root.draw(&solid(
                    1 + PICTURE_SPP.len() + q,
                    rgb(f.set.xyz(|l| s.radiance(l)), own_white),
                ))
                .map_err(plot_err)?;
            }
            for py in 0..BLOCK {
                for pxx in 0..BLOCK {
                    let mut rng = pixel_rng(
                        x.seed,
                        &[1000 + li as u64, k as u64, (py * BLOCK + pxx) as u64],
                    );
                    let mut sum = [0.0; 3];
                    let mut level = 0;
                    for n in 1..=spp_max {
                        let e = estimator.estimate(&cells, &mut rng, &mut scratch);
                        for (a, e) in sum.iter_mut().zip(e) {
                            *a += e;
                        }
                        if n == PICTURE_SPP[level] {
                            let (x0, y) = at(1 + level);
                            let (x0, y) = (x0 + pxx * PX, y + py * PX);
                            root.draw(&Rectangle::new(
                                [(x0, y), (x0 + PX, y + PX)],
                                rgb(sum.map(|v| v / n as f64), white[1]).filled(),
                            ))
                            .map_err(plot_err)?;
                            level += 1;
                        }
                    }
                }
            }
        }
    }
    root.present().map_err(plot_err)?;
    drop(root);
    Ok(path)
}
