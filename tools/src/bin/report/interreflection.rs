//! Section 10: light that bounces. The fixed sets and the random samplers of section 7 on the
//! forms of reflectance a path carries after several surfaces (`ρᵏ`, products of different
//! reflectances, an enclosure of one material), and a light group fitted for bounced light
//! beside the plain fit (`tools::interreflection`, `docs/interreflection.md`).
//!
//! By default the reflectances judged are the ColorChecker and the 190 rawtoaces patches, which
//! no set saw (the sets and the groups train on the CIE test colours); with `--reflectances`,
//! the user's file, or a seeded sample of `--sample` of them, as section 9 judges (10d refits
//! on each fold's others, and 10b runs a pixel per form of each): the text then says so and
//! gives the standard error the sample adds to 10a's means. The lights are the report's C, D65, A, F11 and LED_B2; the random samplers
//! run under C, F11 and LED_B2.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use plotters::prelude::*;
use spectral_quadrature_generator::shared::TRAINING_FILE;
use spectral_quadrature_generator::Derivation;
use spectral_quadrature_spectra::{builtin_illuminant, Curve, Spectra};

use crate::inputs::Reflectances;
use crate::plot::{legend, legend_height, plot_err};
use crate::progress::Meter;
use crate::random_wavelengths::ROUND;
use crate::tools::csv_table::Table;
use crate::tools::interreflection::{
    self as ir, fixed_sets, forms, mean_p95, Form, Judged, Sets, METHODS, POWERS,
};
use crate::tools::light_groups;
use crate::tools::random_wavelengths::{reach, run_trials, Cells, Config, Reach, Sampler, Target};
use crate::Error;

/// The lights: C (the paper's), the light group's four.
const LIGHTS: [&str; 5] = ["C", "D65", "A", "F11", "LED_B2"];

/// The lights the random samplers run under: C and the spiky ones (as section 7 tables them).
const RANDOM_LIGHTS: [&str; 3] = ["C", "F11", "LED_B2"];

/// The samples per pixel measured.
const SPP: [usize; 11] = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024];
const QUICK_SPP: [usize; 3] = [1, 4, 16];

/// The size of the cross-validated comparison of the fits (10d).
const CV_SIZE: usize = 8;

/// What section 10 measures on.
pub struct Inputs<'a> {
    /// The derivation.
    pub d: &'a Derivation,
    /// The reflectances judged.
    pub judged: &'a Reflectances,
    /// The set sizes.
    pub sizes: &'a [usize],
    /// Trials per sampler (`None`: half of one of section 7's rounds, [`ROUND`] / 2).
    pub trials: Option<usize>,
    /// The seed of the trials and of the products' choice of reflectances.
    pub seed: u64,
    /// A quick run: few samples per pixel.
    pub quick: bool,
}

/// One random sampler's mean ΔE00 per (form, light) group and level.
struct Random {
    config: Config,
    trials: usize,
    /// `curves[g]`: (spp, mean ΔE00) for group g of `random_groups`.
    curves: Vec<Vec<(usize, f64)>>,
    worst_relative: f64,
}

/// Runs section 10: its text and the files it wrote.
pub fn section(x: &Inputs, out: &Path) -> Result<(String, Vec<PathBuf>), Error> {
    let start = Instant::now();
    let d = x.d;
    let range = d.settings.range_nm;
    let dir = &d.settings.data_dir;
    let lights: Vec<Curve> = LIGHTS
        .iter()
        .map(|n| builtin_illuminant(dir, n, range))
        .collect::<Result<_, _>>()?;
    let training = Spectra::builtin(dir, TRAINING_FILE)?.curves(range)?;
    let (judged, judged_from) = (&x.judged.curves, x.judged.from.as_str());
    if judged.len() < 3 {
        return Err(Error::Sampling(format!(
            "section 10 needs at least three reflectances for its products, {judged_from} has {}",
            judged.len()
        )));
    }
    let all_forms = Form::all();
    let form_curves: Vec<Vec<Curve>> = all_forms
        .iter()
        .map(|&f| forms(f, judged, x.seed, range))
        .collect();
    let full = d.observer.full_integration(range, 1.0)?;

    // The fixed sets and their errors: errors[size][method][light][form] = (mean, p95).
    let sets = fixed_sets(d, &lights, &light_groups::LIGHTS, &training, x.sizes)?;
    let fit_s = start.elapsed().as_secs_f64();
    let pairs: Vec<(usize, usize)> = (0..lights.len())
        .flat_map(|l| (0..all_forms.len()).map(move |f| (l, f)))
        .collect();
    let judges: Vec<Judged> = crate::tools::par_map(&pairs, |&(l, f)| {
        Judged::new(&full, &lights[l], &form_curves[f])
    });
    let judge = |l: usize, f: usize| &judges[l * all_forms.len() + f];
    type Cell = Option<(f64, f64)>;
    // The largest standard error a sample of the reflectances adds to a mean of 10a, and the
    // largest relative to its mean.
    let mut sampling = (0.0f64, 0.0f64);
    let errors: Vec<Vec<Vec<Vec<Cell>>>> = sets
        .iter()
        .map(|s| {
            s.methods
                .iter()
                .map(|per_light| {
                    per_light
                        .iter()
                        .enumerate()
                        .map(|(l, set)| {
                            (0..all_forms.len())
                                .map(|f| {
                                    set.as_ref().map(|s| {
                                        let de = judge(l, f).de00(s);
                                        let (mean, p95) = mean_p95(&de);
                                        if x.judged.sampled() {
                                            let se = x.judged.standard_error(
                                                light_groups::standard_deviation(&de),
                                            );
                                            sampling =
                                                (sampling.0.max(se), sampling.1.max(se / mean));
                                        }
                                        (mean, p95)
                                    })
                                })
                                .collect()
                        })
                        .collect()
                })
                .collect()
        })
        .collect();

    // The random samplers on the tabled forms under C, F11 and LED_B2.
    let tabled = Form::tabled();
    let random_lights: Vec<usize> = RANDOM_LIGHTS
        .iter()
        .filter_map(|n| lights.iter().position(|l| l.name == *n))
        .collect();
    let mut targets = Vec::new();
    let mut random_groups: Vec<((usize, usize), Vec<usize>)> = Vec::new();
    for &l in &random_lights {
        let white = full.xyz(|nm| lights[l].at(nm));
        for form in &tabled {
            let f = all_forms.iter().position(|g| g == form).unwrap_or(0);
            let j = judge(l, f);
            let first = targets.len();
            for (s, lab) in j.stimuli().iter().zip(&j.reference().labs) {
                targets.push(Target {
                    cells: Cells::weighted(&full, |nm| s.radiance(nm))?,
                    white,
                    lab: *lab,
                });
            }
            random_groups.push(((l, f), (first..targets.len()).collect()));
        }
    }
    let spp: &[usize] = if x.quick { &QUICK_SPP } else { &SPP };
    let span = targets
        .first()
        .map(|t| t.cells.span_nm())
        .ok_or_else(|| Error::Sampling("no targets".into()))?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let which: Vec<Vec<usize>> = random_groups.iter().map(|g| g.1.clone()).collect();
    let mut randoms = Vec::new();
    // Half of one of section 7's rounds: each trial is every tabled form under three lights
    // (5136 pixels of 1024 samples by default), and eight give means with standard errors of a
    // few per cent (printed with them), enough for the reach.
    let trial_count = x.trials.unwrap_or(ROUND / 2);
    let meter = Meter::new("random trials", 2 * trial_count, "trials");
    for (i, sampler) in [Sampler::Visible, Sampler::Hero { range_nm: span }]
        .into_iter()
        .enumerate()
    {
        let config = Config {
            sampler,
            wavelengths: 4,
        };
        // Streams 100 and up: none of section 7's.
        let run = |r: std::ops::Range<usize>| {
            run_trials(config, &targets, spp, r, x.seed, 100 + i as u64, threads)
        };
        // A few trials at a time (each on every thread), for the progress line: the trials are
        // the same however they are split (`run_trials`).
        let mut trials = run(0..threads.min(trial_count))?;
        meter.add(trials.len());
        while trials.len() < trial_count {
            let more = run(trials.len()..(trials.len() + threads).min(trial_count))?;
            meter.add(more.len());
            trials.append(more)?;
        }
        randoms.push(Random {
            config,
            trials: trials.len(),
            curves: which
                .iter()
                .map(|w| {
                    trials
                        .summarize(w)
                        .iter()
                        .map(|s| (s.spp, s.mean_de00))
                        .collect()
                })
                .collect(),
            worst_relative: trials.worst_relative_error(&which),
        });
    }
    let random_s = start.elapsed().as_secs_f64() - fit_s;

    // The crate's own training (the CIE test colours and measured reflectances),
    // cross-validated, at one size.
    let group: Vec<Curve> = lights
        .iter()
        .filter(|l| light_groups::LIGHTS.contains(&l.name.as_str()))
        .cloned()
        .collect();
    // Not in a quick run: ten group searches, on up to five times the training reflectances.
    let cv = if !x.quick && group.len() >= 2 && judged.len() >= 3 * light_groups::FOLDS {
        let meter = Meter::new("cross-validating", light_groups::FOLDS, "folds");
        let counter = meter.counter();
        let cv = ir::cross_validated(d, &group, &training, judged, CV_SIZE, x.seed, &counter)?;
        Some(cv)
    } else {
        None
    };
    let cv_s = start.elapsed().as_secs_f64() - fit_s - random_s;

    let mut o = String::new();
    let names: Vec<String> = lights.iter().map(|l| l.name.clone()).collect();
    text(
        &mut o,
        x,
        judged_from,
        judged.len(),
        &names,
        &sets,
        &errors,
        &randoms,
        &random_groups,
        cv.as_deref(),
        x.judged
            .sampled()
            .then(|| x.judged.statement(sampling.0, sampling.1)),
    );
    writeln!(
        o,
        "   ({fit_s:.1} s for the sets and groups, {random_s:.1} s for the random trials, {cv_s:.1} s for the cross-validation, {:.1} s in all)",
        start.elapsed().as_secs_f64()
    )
    .ok();
    let files = vec![
        csv(&names, &sets, &errors, &randoms, &random_groups).write(out, "interreflection.csv")?,
        plot(out, &names, &sets, &errors)?,
    ];
    Ok((o, files))
}

type Errors = Vec<Vec<Vec<Vec<Option<(f64, f64)>>>>>;

/// One size of a plain-against-bounce-trained table: N, then per form of [`Form::all`] per light
/// (plain, bounce-trained) mean ΔE00.
type Block = (usize, Vec<Vec<(f64, f64)>>);

fn form_index(form: Form) -> usize {
    Form::all().iter().position(|g| *g == form).unwrap_or(0)
}

fn cell(c: Option<(f64, f64)>) -> String {
    c.map_or("-".into(), |(m, p)| format!("{m:.3} ({p:.2})"))
}

/// The cell of a reach table: `12`, `≤1`, `~3.1k`, `never`.
fn reach_cell(r: Reach) -> String {
    match r {
        Reach::AtFirst => "≤1".into(),
        Reach::Between(s) => format!("{s:.0}"),
        Reach::Beyond(s) if s >= 1e3 => format!("~{:.1}k", s / 1e3),
        Reach::Beyond(s) => format!("~{s:.0}"),
        Reach::Never => "never".into(),
    }
}

#[allow(clippy::too_many_arguments)]
fn text(
    o: &mut String,
    x: &Inputs,
    judged_from: &str,
    judged: usize,
    lights: &[String],
    sets: &[Sets],
    errors: &Errors,
    randoms: &[Random],
    random_groups: &[((usize, usize), Vec<usize>)],
    cv: Option<&[Vec<(f64, f64)>]>,
    sampling: Option<String>,
) {
    let lines = [
        format!("10. Light that bounces: {judged} reflectances from {judged_from}, in the forms a path carries after several surfaces"),
        "   ρ^k: k bounces off one material; ρi·ρj, ρi·ρj·ρl: off different ones (each reflectance with seeded others);".to_string(),
        "   sphere a: an enclosure of one material, every bounce summed, ρ(1−a)/(1−aρ). Each judged like a reflectance".to_string(),
        "   under the light (white: the light). The sets and groups train on the CIE test colours; the bounce-trained group".to_string(),
        "   on their ρ, ρ², ρ³ and sphere forms. Mean ΔE00 (95th percentile).".to_string(),
    ];
    for l in lines {
        writeln!(o, "{l}").ok();
    }
    if let Some(s) = sampling {
        writeln!(o, "{s}").ok();
    }
    let tabled = Form::tabled();
    for (l, light) in lights.iter().enumerate() {
        writeln!(o, "\n   10a. under {light}").ok();
        for (s, set) in sets.iter().enumerate() {
            let present: Vec<usize> = (0..METHODS.len())
                .filter(|&m| set.methods[m][l].is_some())
                .collect();
            let mut header = format!("   N = {:<2} {:<11}", set.n, "form");
            for &m in &present {
                write!(header, " {:>22}", METHODS[m]).ok();
            }
            writeln!(o, "{header}").ok();
            for form in &tabled {
                let f = form_index(*form);
                let mut line = format!("          {:<11}", form.label());
                for &m in &present {
                    write!(line, " {:>22}", cell(errors[s][m][l][f])).ok();
                }
                writeln!(o, "{line}").ok();
            }
        }
    }

    // Reach: the spp at which each sampler's mean meets each fixed set's.
    if !randoms.is_empty() {
        writeln!(
            o,
            "\n   10b. samples per pixel at which a random sampler (4 wavelengths a sample) reaches each fixed set's mean ΔE00"
        )
        .ok();
        let trials: Vec<String> = randoms
            .iter()
            .map(|r| {
                format!(
                    "{}: {} trials (largest standard error {:.1} % of its mean)",
                    r.config.label(),
                    r.trials,
                    100.0 * r.worst_relative
                )
            })
            .collect();
        writeln!(o, "   {}; levels {:?} spp.", trials.join(", "), x.spp()).ok();
        for r in randoms {
            for (g, ((l, f), _)) in random_groups.iter().enumerate() {
                if g == 0 || random_groups[g - 1].0 .0 != *l {
                    let mut header = format!(
                        "   {:<18} {:<11}",
                        format!("{} {}", short(&r.config), lights[*l]),
                        "form"
                    );
                    for set in sets {
                        for m in 0..METHODS.len() {
                            if set.methods[m][*l].is_some() {
                                write!(header, " {:>8}", format!("{}{}", tag(m), set.n)).ok();
                            }
                        }
                    }
                    write!(header, " {:>10}", "1 spp").ok();
                    writeln!(o, "{header}").ok();
                }
                let mut line = format!("   {:<18} {:<11}", "", Form::all()[*f].label());
                for (set, per_method) in sets.iter().zip(errors) {
                    for (m, per_light) in per_method.iter().enumerate() {
                        if let Some(Some((mean, _))) =
                            set.methods[m][*l].as_ref().map(|_| per_light[*l][*f])
                        {
                            write!(line, " {:>8}", reach_cell(reach(&r.curves[g], mean))).ok();
                        }
                    }
                }
                let first = r.curves[g].first().map_or(f64::NAN, |c| c.1);
                write!(line, " {first:>10.3}").ok();
                writeln!(o, "{line}").ok();
            }
        }
        writeln!(
            o,
            "   (own: the light's own folded set; grp: the light group; bnc: the bounce-trained group; rad: the radiance set; 1 spp: the sampler's mean ΔE00 at one sample)"
        )
        .ok();
    }

    // The bounce-trained group against the plain one.
    writeln!(
        o,
        "\n   10c. the light group trained on the bounce forms of the 14 CIE test colours against the plain fit on the 14 (10a's): mean ΔE00 plain → bounce-trained, ratio (below 1: bounce-trained better)"
    )
    .ok();
    let group_lights: Vec<usize> = (0..lights.len())
        .filter(|&l| sets.first().is_some_and(|s| s.methods[1][l].is_some()))
        .collect();
    if group_lights.is_empty() {
        return;
    }
    let names: Vec<String> = group_lights.iter().map(|&l| lights[l].clone()).collect();
    let blocks: Vec<Block> = sets
        .iter()
        .enumerate()
        .map(|(s, set)| {
            let rows = Form::all()
                .iter()
                .map(|&form| {
                    let f = form_index(form);
                    group_lights
                        .iter()
                        .map(|&l| match (errors[s][1][l][f], errors[s][2][l][f]) {
                            (Some((p, _)), Some((b, _))) => (p, b),
                            _ => (f64::NAN, f64::NAN),
                        })
                        .collect()
                })
                .collect();
            (set.n, rows)
        })
        .collect();
    plain_against_bounced(o, &names, &blocks);
    if let Some(cv) = cv {
        writeln!(
            o,
            "\n   10d. the same with the crate's own training: five-fold cross-validation as in section 9, each fold's fits on the CIE test colours and the other four folds (as they are, or their bounce forms), judged on the fold"
        )
        .ok();
        plain_against_bounced(o, &names, &[(CV_SIZE, cv.to_vec())]);
        writeln!(
            o,
            "   10c's fits see the 14 CIE test colours only, 10d's four fifths of the judged reflectances too (the crate's groups train on every reflectance file it has): where the two disagree, 10d is the crate's case."
        )
        .ok();
    }
}

/// Prints plain → bounce-trained per form and light for each size (`blocks`: N, then per form
/// of [`Form::all`] per light (plain, bounce-trained) mean ΔE00), and which fit the numbers
/// support as the default.
fn plain_against_bounced(o: &mut String, lights: &[String], blocks: &[Block]) {
    let (mut wins, mut losses) = (0, 0);
    let mut direct = Vec::new();
    let mut bounced = Vec::new();
    for (n, rows) in blocks {
        let mut header = format!("   N = {:<2} {:<11}", n, "form");
        for l in lights {
            write!(header, " {:>22}", l).ok();
        }
        writeln!(o, "{header} {:>7}", "mean").ok();
        for (form, row) in Form::all().into_iter().zip(rows) {
            let mut line = format!("          {:<11}", form.label());
            let mut ratios = Vec::new();
            for &(p, b) in row {
                ratios.push(b / p);
                if b < p {
                    wins += 1;
                } else {
                    losses += 1;
                }
                write!(line, " {:>22}", format!("{p:.3} → {b:.3} {:.2}×", b / p)).ok();
            }
            let m = ratios.iter().sum::<f64>() / ratios.len().max(1) as f64;
            if form == Form::Power(1) {
                direct.push(m);
            } else {
                bounced.push(m);
            }
            writeln!(o, "{line} {m:>7.3}").ok();
        }
    }
    let avg = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let (d, b) = (avg(&direct), avg(&bounced));
    writeln!(
        o,
        "   The bounce-trained group beats the plain fit in {wins} of {} (N, form, light) cells. Direct view (ρ^1): {d:.3}× the plain fit's error on average over N and lights; bounced forms: {b:.3}×.",
        wins + losses
    )
    .ok();
    let verdict = if d <= 1.0 && b <= 1.0 {
        "training on bounce forms is at least as good in direct view and better on bounced light: these numbers support it as the default fit"
    } else if d > 1.0 && b < 1.0 {
        "training on bounce forms helps bounced light but costs direct view: these numbers support keeping the plain fit as the default and offering the bounce-trained fit for scenes of mostly bounced light"
    } else if d <= 1.0 {
        "training on bounce forms costs bounced light, the very case it is for, and gains in direct view: nothing here supports changing the default"
    } else {
        "training on bounce forms loses in direct view and on bounced light: these numbers support the plain fit as the default"
    };
    writeln!(o, "   So {verdict}.").ok();
}

impl Inputs<'_> {
    fn spp(&self) -> &'static [usize] {
        if self.quick {
            &QUICK_SPP
        } else {
            &SPP
        }
    }
}

fn tag(m: usize) -> &'static str {
    ["own", "grp", "bnc", "rad"][m]
}

fn short(c: &Config) -> &'static str {
    match c.sampler {
        Sampler::Visible => "pbrt×4",
        Sampler::Hero { .. } => "hero×4",
        Sampler::Uniform { .. } => "unif×4",
    }
}

fn csv(
    lights: &[String],
    sets: &[Sets],
    errors: &Errors,
    randoms: &[Random],
    random_groups: &[((usize, usize), Vec<usize>)],
) -> Table {
    let mut t = Table::new(
        "n,method,set,light,form,mean_de00,p95_de00,reach_spp_pbrt_v4_visible_x4,reach_spp_hero_x4",
    );
    let all = Form::all();
    for (s, set) in sets.iter().enumerate() {
        for (m, per_light) in set.methods.iter().enumerate() {
            for (l, es) in per_light.iter().enumerate() {
                let Some(es) = es else { continue };
                for (f, form) in all.iter().enumerate() {
                    let Some((mean, p95)) = errors[s][m][l][f] else {
                        continue;
                    };
                    let reaches: Vec<String> = randoms
                        .iter()
                        .map(|r| {
                            random_groups.iter().position(|g| g.0 == (l, f)).map_or(
                                String::new(),
                                |g| match reach(&r.curves[g], mean) {
                                    Reach::AtFirst => "1".into(),
                                    Reach::Between(v) => format!("{v:.1}"),
                                    Reach::Beyond(v) => format!("~{v:.0}"),
                                    Reach::Never => "never".into(),
                                },
                            )
                        })
                        .collect();
                    t.row([
                        set.n.to_string(),
                        METHODS[m].to_string(),
                        es.name.clone(),
                        lights[l].clone(),
                        form.label(),
                        format!("{mean:.4}"),
                        format!("{p95:.4}"),
                        reaches.first().cloned().unwrap_or_default(),
                        reaches.get(1).cloned().unwrap_or_default(),
                    ]);
                }
            }
        }
    }
    t
}

/// Mean ΔE00 against the number of bounces k (ρ^k), one panel per light, a line per method and
/// size (colour: method; solid N = 8, dashed 6, dotted 4).
fn plot(out: &Path, lights: &[String], sets: &[Sets], errors: &Errors) -> Result<PathBuf, Error> {
    let path = out.join("interreflection.svg");
    let colours = [
        RGBColor(200, 30, 30),
        RGBColor(30, 90, 200),
        RGBColor(40, 150, 60),
        RGBColor(90, 90, 90),
    ];
    let mut entries: Vec<(String, RGBColor)> = METHODS
        .iter()
        .zip(colours)
        .map(|(m, c)| (m.to_string(), c))
        .collect();
    entries.push(("solid N = 8, dashed 6, dotted 4".into(), RGBColor(0, 0, 0)));
    let rows = lights.len().div_ceil(2) as u32;
    let lh = legend_height(entries.len(), 3);
    let root = SVGBackend::new(&path, (1100, 340 * rows + lh)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let (top, bottom) = root.split_vertically(340 * rows);
    let panels = top.split_evenly((rows as usize, 2));
    let kmax = *POWERS.end() as f64;
    const FLOOR: f64 = 0.01;
    for (l, panel) in lights.iter().enumerate().map(|(l, _)| l).zip(&panels) {
        let values = errors.iter().flat_map(|e| {
            e.iter().flat_map(move |m| {
                POWERS.filter_map(move |k| m[l][form_index(Form::Power(k))].map(|c| c.0))
            })
        });
        let (lo, hi) = values.fold((f64::MAX, FLOOR), |(a, b), v| (a.min(v), b.max(v)));
        let lo = lo.max(FLOOR);
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!("under {}: mean ΔE00 of ρ^k against k", lights[l]),
                ("sans-serif", 15),
            )
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(0.8f64..kmax + 0.2, (lo * 0.7..hi * 1.4).log_scale())
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc("bounces k")
            .x_label_formatter(&crate::plot::whole)
            .y_desc("ΔE00 (log)")
            .draw()
            .map_err(plot_err)?;
        for (s, set) in sets.iter().enumerate() {
            for (m, colour) in colours.iter().enumerate() {
                if set.methods[m][l].is_none() {
                    continue;
                }
                let pts: Vec<(f64, f64)> = POWERS
                    .filter_map(|k| {
                        errors[s][m][l][form_index(Form::Power(k))]
                            .map(|c| (f64::from(k), c.0.max(FLOOR)))
                    })
                    .collect();
                let style = colour.stroke_width(2);
                match set.n {
                    8 => chart.draw_series(LineSeries::new(pts, style)),
                    6 => chart.draw_series(DashedLineSeries::new(pts, 8, 4, style)),
                    _ => chart.draw_series(DashedLineSeries::new(pts, 2, 4, style)),
                }
                .map_err(plot_err)?;
            }
        }
    }
    legend(&bottom, &entries, 3)?;
    root.present().map_err(plot_err)?;
    drop(panels);
    drop(top);
    drop(bottom);
    drop(root);
    Ok(path)
}
