//! The crate's main job: error against run time for every wavelength set it offers, and the
//! paper's Table 2 and Figs. 6-7, on the spectra you give it.
//!
//! ```text
//! cargo run --release -p spectral-quadrature-tools --bin report
//! cargo run --release -p spectral-quadrature-tools --bin report -- --reflectances my.csv --illuminants lamps.csv
//! cargo run --release -p spectral-quadrature-tools --bin report -- --emission leds.csv --out target/leds
//! cargo run --release -p spectral-quadrature-tools --bin report -- --csv > error_vs_time.csv
//! cargo run --release -p spectral-quadrature-tools --bin report -- --trials 256 --seed 7
//! ```
//!
//! Section 7 measures random wavelengths per sample (pbrt-v4's sampler, hero, uniform) against
//! the fixed sets; `--trials` and `--seed` set its trials (see `docs/random-wavelengths.md`).
//! Section 8 relights RGB materials upsampled to a set's nodes: the crate's map beside
//! Jakob-Hanika, Mallett-Yuksel and Smits (see `docs/upsampling.md`).
//!
//! Spectra files: CSV, first column wavelength in nm, one column per spectrum, any spacing;
//! they are interpolated linearly and must cover the observer's 380-770 nm. Errors name the file
//! and line and exit with code 2. Negative values within 1e-6 of a file's largest value are
//! rounding noise, read as 0 with one warning per file on standard error; a more negative value
//! is an error naming its line and column, unless `--clamp-negatives` reads it as 0 too.

mod budget;
mod random;
use spectral_quadrature_build as sqd;
use spectral_quadrature_tools as tools;
use tools::Error;
mod stability;
mod upsampling;
mod user;

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Parser;
use plotters::prelude::*;
use spectral_quadrature::{tables, FoldedSet, GamutMapping, WavelengthSet};
use sqd::evaluate::{self, Curve, Errors, EvalSet, Reference, Spectra, Stimulus};
use sqd::Derivation;

/// Error against run time for Meyer's wavelength sets and their alternatives.
#[derive(Parser)]
#[command(about)]
struct Args {
    /// Reflectances (CSV: wavelength_nm, one column per surface). Default: the ColorChecker
    /// (Ohta) and the CIE test colour samples 1-14.
    #[arg(long, value_name = "FILE")]
    reflectances: Option<PathBuf>,
    /// Illuminants (CSV: wavelength_nm, one column per light). Default: CIE C, D65, A, F2, F11
    /// and LED-B2.
    #[arg(long, value_name = "FILE")]
    illuminants: Option<PathBuf>,
    /// A scene file whose sets join section 4 (catalogue names, its lights' shared sets, fixed
    /// wavelengths and sensors). Paths in it are relative to it.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Light spectra seen directly (CSV), instead of surfaces under illuminants.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["reflectances", "illuminants"])]
    emission: Option<PathBuf>,
    /// Read every negative value of the spectra files given here as 0 (each file's count is
    /// printed as a warning), for measured data whose noise exceeds the tolerance (1e-6 of the
    /// file's largest value; within it, values are read as 0 without this flag). A scene sets
    /// its own files' rule with `clamp_negatives = true`.
    #[arg(long)]
    clamp_negatives: bool,
    /// Folder for the CSV files and SVG plots.
    #[arg(long, value_name = "DIR", default_value = "target/report")]
    out: PathBuf,
    /// Print only section 4 (error against run time) as CSV on standard output.
    #[arg(long)]
    csv: bool,
    /// Timing runs per set; the median is reported.
    #[arg(long, default_value_t = 7, value_parser = clap::value_parser!(u32).range(1..=101))]
    runs: u32,
    /// Highest per-channel order combined (1-16).
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=16))]
    max_order: u32,
    /// Seeded trials per random-wavelength sampler in section 7 (each: one pixel per stimulus
    /// at every number of samples per pixel). Default: rounds of 16 until every mean has a
    /// standard error within 2 % of itself (at most 512).
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=100_000))]
    trials: Option<u32>,
    /// The seed of section 7's random numbers.
    #[arg(long, default_value_t = 1988)]
    seed: u64,
}

const DEFAULT_ILLUMINANTS: [&str; 6] = ["C", "D65", "A", "F2", "F11", "LED_B2"];

fn main() {
    let args = Args::parse();
    if let Err(e) = run(&args) {
        eprintln!("report: error: {e}");
        std::process::exit(2);
    }
}

/// The report's steps, in order: the progress line counts these.
const STEPS: [&str; 10] = [
    "deriving the rules (CIE 1931 2°, 380-770 nm, 5 nm)",
    "reading spectra",
    "section 1: Table 2 (ColorChecker under C)",
    "sections 2-3: Figs. 6 and 7 (every per-channel order combination)",
    "section 4: error against run time (timing every set)",
    "writing tables and plots",
    "section 5: shared sets at each wavelength budget (fitting and judging)",
    "section 6: stability",
    "section 7: against random wavelengths (seeded trials, timing)",
    "section 8: RGB materials under another light (fitting and relighting)",
];

/// Progress on standard error, one line per step of [`STEPS`].
struct Progress {
    step: usize,
    start: Instant,
}

impl Progress {
    /// Announces the next step of [`STEPS`].
    fn next(&mut self) {
        let what = STEPS.get(self.step).copied().unwrap_or("finishing");
        self.step = (self.step + 1).min(STEPS.len());
        eprintln!(
            "[{}/{}] {what} ({:.1} s)",
            self.step,
            STEPS.len(),
            self.start.elapsed().as_secs_f64()
        );
    }
}

/// One row of section 4.
struct Row {
    set: EvalSet,
    /// Samples per pixel: the set's wavelengths, or a sensor's channels.
    samples: usize,
    errors: Errors,
    ns_per_pixel: f64,
    /// What the set is judged on, when not every stimulus (a set with a light folded in is
    /// judged under that light only).
    judged_on: Option<String>,
}

fn run(args: &Args) -> Result<(), Error> {
    let mut progress = Progress {
        step: 0,
        start: Instant::now(),
    };
    progress.next();
    let d = sqd::derive(&tools::settings())?;
    tools::warn_zeroed("report", &d.observer.zeroed);
    let range = d.settings.range_nm;
    let reference_set = evaluate::full_integration(&d.observer, range, 1.0)?;

    progress.next();
    let inputs = load_inputs(args, range)?;
    let stimuli = inputs.stimuli.clone();
    let reference = Reference::new(reference_set.clone(), &stimuli);
    let (cc_under_c, cc_reference) = {
        let cc = Spectra::builtin(
            &d.settings.data_dir,
            "data/reflectance_colorchecker_ohta.csv",
        )
        .and_then(|s| s.curves(range))?;
        let c = evaluate::builtin_illuminant(&d.settings.data_dir, "C", range)?;
        let st = evaluate::surfaces_under_lights(&cc, &[c]);
        let r = Reference::new(reference_set.clone(), &st);
        (st, r)
    };
    std::fs::create_dir_all(&args.out).map_err(|source| Error::Write {
        path: args.out.clone(),
        source,
    })?;

    progress.next();
    let table2 = table2_rows(&d, &cc_under_c, &cc_reference);
    // The first table goes out at once; the rest follows when it is measured.
    let mut text = String::new();
    if !args.csv {
        print_intro_and_table2(&mut text, &stimuli, &table2);
        print!("{text}");
        std::io::stdout().flush().ok();
    }

    progress.next();
    let max = args.max_order as usize;
    let spaces = tools::budget::rule_spaces(&d, max)?;
    // Figs. 6 and 7 reproduce the paper's setup (ColorChecker under C) unless spectra are given.
    let user_spectra =
        args.reflectances.is_some() || args.illuminants.is_some() || args.emission.is_some();
    let (fig_stimuli, fig_reference) = if user_spectra {
        (&stimuli, &reference)
    } else {
        (&cc_under_c, &cc_reference)
    };
    let space_errors: Vec<Vec<Errors>> = spaces
        .iter()
        .map(|(_, sets)| par_errors(fig_reference, sets, fig_stimuli))
        .collect();

    progress.next();
    let mut sets: Vec<EvalSet> = spaces[0].1.clone();
    for set in &d.table2 {
        sets.push(EvalSet {
            name: table2_name(&set.name),
            ..EvalSet::from_set(set, "Table 2", &d.opponent.ac1c2_to_xyz)
        });
    }
    // Gauss rules in XYZ space: each number of distinct wavelengths' best is shown.
    sets.extend(spaces[1].1.iter().filter(|s| s.len() <= 16).cloned());
    for n in (3..=16).chain([24, 32]) {
        sets.push(evaluate::uniform(&d.observer, range, n));
    }
    // The shared sets for radiances (the lights here are many; section 5 folds each one in),
    // method (a) for comparison, and sampling every 10 and 20 nm with linear interpolation.
    let radiance = tools::budget::shared_sets(&d, None)?;
    sets.extend(radiance.iter().cloned());
    for n in tools::budget::BUDGETS {
        if let Ok(a) = sqd::shared::interpolatory_a(&d, n, &format!("INTERP_A_{n}")) {
            sets.push(EvalSet::from_set(&a, "interp A", &d.opponent.ac1c2_to_xyz));
        }
    }
    let flat = Curve::constant("equal energy", 1.0, range);
    for step in [10.0, 20.0] {
        sets.push(tools::budget::interval_set(&d, &flat, step)?);
    }
    sets.push(evaluate::full_integration(&d.observer, range, 5.0)?);
    sets.push(reference_set.clone());
    let errs = par_errors(&reference, &sets, &stimuli);
    let total = sets.len();
    let mut rows = Vec::with_capacity(total);
    for (k, (set, errors)) in sets.into_iter().zip(errs).enumerate() {
        if (k + 1) % total.div_ceil(4).max(1) == 0 || k + 1 == total {
            eprintln!("      timed {}/{total} sets", k + 1);
        }
        let ns_per_pixel = time_set(&set, &stimuli, args.runs as usize)?;
        rows.push(Row {
            samples: set.len(),
            set,
            errors,
            ns_per_pixel,
            judged_on: None,
        });
    }
    // The user's: shared sets folded for each light of --illuminants, and a scene's sets.
    let folded_user = user::folded_for_lights(&d, &inputs.user_lights, &inputs.surfaces)?;
    let mut extras = user::light_extras(&folded_user, &inputs.surfaces_from);
    if let Some(path) = &args.scene {
        extras.extend(user::scene_extras(
            &d,
            path,
            &inputs.surfaces,
            &inputs.surfaces_from,
        )?);
    }
    for x in extras {
        let (own, judged_on) = match x.judged_on {
            Some((s, what)) => (s, Some(what)),
            None => (stimuli.clone(), None),
        };
        let errors = Reference::new(reference_set.clone(), &own).errors(&x.set, &own);
        let ns_per_pixel = time_set(&x.timing, &own, args.runs as usize)?;
        rows.push(Row {
            set: x.set,
            samples: x.samples,
            errors,
            ns_per_pixel,
            judged_on,
        });
    }

    progress.next();
    let out = &args.out;
    let mut files = Vec::new();
    let section4_csv = section4_csv(&rows);
    files.push(write(out, "error_vs_time.csv", &section4_csv)?);
    files.push(write(out, "table2.csv", &table2_csv(&table2))?);
    let fig6 = fig6_data(&spaces, &space_errors);
    files.push(write(out, "fig6.csv", &fig6_csv(&fig6))?);
    let fig7 = fig7_data(&spaces[0].1, &space_errors[0]);
    files.push(write(out, "fig7.csv", &fig7_csv(&fig7))?);
    files.push(plot_fig6(out, &fig6)?);
    files.push(plot_fig7(out, &fig7)?);
    files.push(plot_error_vs_time(out, &rows)?);
    files.push(draw_swatches(out, &d, &cc_under_c, &rows)?);

    progress.next();
    let (budget_text, budget_files) = budget::section(
        &d,
        &spaces,
        &radiance,
        &folded_user,
        args.reflectances
            .as_ref()
            .map(|_| inputs.surfaces.as_slice()),
        &inputs.surfaces_from,
        out,
        args.runs as usize,
    )?;
    files.extend(budget_files);

    progress.next();
    let (stability_text, stability_files) = stability::section(out)?;
    files.extend(stability_files);

    progress.next();
    let table2_row2 = rows
        .iter()
        .find(|r| r.set.name == "table2 row2")
        .map(|r| r.set.clone())
        .ok_or_else(|| Error::Plot("Table 2 row 2 is missing from section 4".into()))?;
    let (random_text, random_files) = random::section(
        &random::Inputs {
            d: &d,
            stimuli: &stimuli,
            reference: &reference,
            surfaces_from: &inputs.surfaces_from,
            lights: &inputs.lights,
            users_lights: !inputs.user_lights.is_empty(),
            table2_row2: &table2_row2,
            trials: args.trials.map(|t| t as usize),
            seed: args.seed,
            runs: args.runs as usize,
        },
        out,
    )?;
    files.extend(random_files);

    progress.next();
    let (upsampling_text, upsampling_files) = upsampling::section(
        &upsampling::Inputs {
            d: &d,
            reflectances: args
                .reflectances
                .as_ref()
                .map(|_| (inputs.surfaces.as_slice(), inputs.surfaces_from.as_str())),
            lights: args
                .illuminants
                .as_ref()
                .map(|_| inputs.user_lights.as_slice()),
        },
        out,
    )?;
    files.extend(upsampling_files);

    if args.csv {
        print!("{section4_csv}");
    } else {
        let mut rest = String::new();
        print_sections_2_to_4(&mut rest, fig_stimuli, &fig6, &fig7, &rows);
        rest.push('\n');
        rest.push_str(&budget_text);
        rest.push('\n');
        rest.push_str(&stability_text);
        rest.push('\n');
        rest.push_str(&random_text);
        rest.push('\n');
        rest.push_str(&upsampling_text);
        print!("{rest}");
        text.push_str(&rest);
        files.push(write(out, "report.txt", &text)?);
    }
    std::io::stdout().flush().ok();
    eprintln!(
        "done in {:.1} s: {} stimuli, {} sets timed. Files in {}:",
        progress.start.elapsed().as_secs_f64(),
        stimuli.len(),
        rows.len(),
        out.display()
    );
    for f in files {
        eprintln!("  {}", f.display());
    }
    Ok(())
}

/// What the report measures on.
struct Inputs {
    /// Every stimulus: surfaces under lights, or lights seen directly.
    stimuli: Vec<Stimulus>,
    /// The surfaces (the user's, or the ColorChecker and the CIE test colours).
    surfaces: Vec<Curve>,
    /// Where the surfaces come from, in words.
    surfaces_from: String,
    /// The lights of --illuminants (empty without it).
    user_lights: Vec<Curve>,
    /// The lights the surfaces are under: the user's or the default ones (empty for
    /// --emission).
    lights: Vec<Curve>,
}

fn load_inputs(args: &Args, range: [f64; 2]) -> Result<Inputs, Error> {
    let read = |p: &Path| {
        let spectra = Spectra::read_with(p, tools::negatives(args.clamp_negatives))?;
        tools::warn_zeroed("report", spectra.zeroed());
        spectra.curves(range)
    };
    let (surfaces, surfaces_from) = match &args.reflectances {
        Some(p) => (read(p)?, p.display().to_string()),
        None => (
            tools::prefilter::default_surfaces(range)?,
            "the ColorChecker and CIE TCS 1-14".to_string(),
        ),
    };
    let user_lights = match &args.illuminants {
        Some(p) => read(p)?,
        None => Vec::new(),
    };
    let (stimuli, lights) = if let Some(path) = &args.emission {
        (evaluate::emissions(&read(path)?), Vec::new())
    } else if user_lights.is_empty() {
        let lights: Vec<Curve> = DEFAULT_ILLUMINANTS
            .iter()
            .map(|n| evaluate::builtin_illuminant(std::path::Path::new(tools::DATA_DIR), n, range))
            .collect::<Result<_, _>>()?;
        (evaluate::surfaces_under_lights(&surfaces, &lights), lights)
    } else {
        (
            evaluate::surfaces_under_lights(&surfaces, &user_lights),
            user_lights.clone(),
        )
    };
    Ok(Inputs {
        stimuli,
        surfaces,
        surfaces_from,
        user_lights,
        lights,
    })
}

/// Errors of many sets, on every core.
fn par_errors(reference: &Reference, sets: &[EvalSet], stimuli: &[Stimulus]) -> Vec<Errors> {
    tools::par_map(sets, |set| reference.errors(set, stimuli))
}

// ---------------------------------------------------------------------------------------------
// Timing: the runtime path (f32, samples -> linear sRGB in one 3xN product) for each set.

macro_rules! dispatch {
    ($n:expr, $set:expr, $stimuli:expr, $runs:expr; $($k:literal)*) => {
        match $n {
            $($k => Some(time_n::<$k>($set, $stimuli, $runs)),)*
            _ => None,
        }
    };
}

fn time_set(set: &EvalSet, stimuli: &[Stimulus], runs: usize) -> Result<f64, Error> {
    dispatch!(set.len(), set, stimuli, runs;
        1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32
        33 34 35 36 37 38 39 40 41 42 43 44 45 46 47 48 79 391)
    .ok_or(Error::NoTimingPath(set.len()))
}

/// Median ns per pixel of `FoldedSet::<N>::linear_rgb_batch` over pixels cycling through the
/// stimuli, sampled at the set's wavelengths.
fn time_n<const N: usize>(set: &EvalSet, stimuli: &[Stimulus], runs: usize) -> f64 {
    let m = tables::XYZ_TO_AC1C2;
    // The report times sets on radiances: the light (if any) is already in the stimuli.
    let wavelengths_nm = core::array::from_fn(|i| set.wavelengths_nm[i] as f32);
    let weights = core::array::from_fn(|c| {
        core::array::from_fn(|i| {
            (0..3)
                .map(|k| f64::from(m[c][k]) * set.xyz_weights[k][i])
                .sum::<f64>() as f32
        })
    });
    let radiance = spectral_quadrature::Samples::Radiance;
    let ws = WavelengthSet::<N>::new(wavelengths_nm, weights, radiance).expect("a valid set");
    let folded: FoldedSet<N> = ws.fold(&tables::displays::SRGB, 1.0 / tables::UNIT_SPECTRUM_Y);
    const PIXELS: usize = 2048;
    let samples: Vec<[f32; N]> = (0..PIXELS)
        .map(|p| {
            let s = &stimuli[p % stimuli.len()];
            std::array::from_fn(|i| s.radiance(set.wavelengths_nm[i]) as f32)
        })
        .collect();
    let mut out = vec![[0.0f32; 3]; PIXELS];
    // Repeat each run until it lasts about half a millisecond, so the clock's resolution does
    // not matter.
    let reps = (500_000 / (PIXELS * (N + 4))).max(1);
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..reps {
                folded
                    .linear_rgb_batch(std::hint::black_box(&samples), &mut out)
                    .expect("lengths agree");
                std::hint::black_box(&mut out);
            }
            t.elapsed().as_nanos() as f64 / (reps * PIXELS) as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

// ---------------------------------------------------------------------------------------------
// Section 1: Table 2.

struct Table2Row {
    name: String,
    wavelengths: Vec<f64>,
    mean_de76: f64,
    paper: f64,
}

fn table2_rows(d: &Derivation, stimuli: &[Stimulus], reference: &Reference) -> Vec<Table2Row> {
    d.table2
        .iter()
        .zip(spectral_quadrature_build::paper::TABLE2_MEAN_DELTA_E)
        .map(|(set, paper)| {
            let es = EvalSet::from_set(set, "Table 2", &d.opponent.ac1c2_to_xyz);
            Table2Row {
                name: table2_name(&set.name),
                wavelengths: set.wavelengths_nm.clone(),
                mean_de76: reference.errors(&es, stimuli).mean_de76(),
                paper,
            }
        })
        .collect()
}

/// `TABLE2_ROW1` → `table2 row1`.
fn table2_name(const_name: &str) -> String {
    const_name.to_lowercase().replace('_', " ")
}

fn table2_csv(rows: &[Table2Row]) -> String {
    let mut s = String::from("row,wavelengths_nm,mean_de76,paper_mean_de76,difference\n");
    for r in rows {
        let w: Vec<String> = r.wavelengths.iter().map(|l| format!("{l:.1}")).collect();
        writeln!(
            s,
            "{},{},{:.4},{},{:+.4}",
            r.name,
            w.join(" "),
            r.mean_de76,
            r.paper,
            r.mean_de76 - r.paper
        )
        .ok();
    }
    s
}

// ---------------------------------------------------------------------------------------------
// Section 2: Fig. 6, mean error against the total number of wavelengths (n_A + n_C1 + n_C2).

struct Fig6 {
    /// (space, total, number of combinations, mean ΔE*ab averaged over them)
    points: Vec<(String, usize, usize, f64)>,
}

fn fig6_data(spaces: &[(&str, Vec<EvalSet>)], errors: &[Vec<Errors>]) -> Fig6 {
    let mut points = Vec::new();
    for ((name, sets), errs) in spaces.iter().zip(errors) {
        let mut by_total: std::collections::BTreeMap<usize, Vec<f64>> = Default::default();
        for (set, e) in sets.iter().zip(errs) {
            let o = set.orders.expect("combinations have orders");
            by_total
                .entry(o.iter().sum())
                .or_default()
                .push(e.mean_de76());
        }
        for (total, v) in by_total {
            points.push((
                name.to_string(),
                total,
                v.len(),
                v.iter().sum::<f64>() / v.len() as f64,
            ));
        }
    }
    Fig6 { points }
}

fn fig6_csv(f: &Fig6) -> String {
    let mut s = String::from("space,total_wavelengths,combinations,mean_de76\n");
    for (space, total, n, e) in &f.points {
        writeln!(s, "{space},{total},{n},{e:.4}").ok();
    }
    s
}

// ---------------------------------------------------------------------------------------------
// Section 3: Fig. 7, the allocation triangle.

/// Subdivisions of each side of the triangle (K² sub-triangles).
const K: usize = 6;

struct Fig7 {
    /// Per sub-triangle: (row i, column j, upward, number of combinations, mean ΔE*ab).
    cells: Vec<(usize, usize, bool, usize, f64)>,
}

/// The sub-triangle of barycentric fractions (fa, fc1, fc2): i = ⌊fa·K⌋, j = ⌊fc1·K⌋, upward
/// when the remainders sum below 1.
fn cell_of(fa: f64, fc1: f64) -> (usize, usize, bool) {
    let (x, y) = (fa * K as f64, fc1 * K as f64);
    let i = (x.floor() as usize).min(K - 1);
    let j = (y.floor() as usize).min(K - 1 - i);
    let up = (x - i as f64) + (y - j as f64) < 1.0 || i + j == K - 1;
    (i, j, up)
}

/// The fractions (A, C1, C2) at the centroid of sub-triangle (i, j, up).
fn centroid(i: usize, j: usize, up: bool) -> [f64; 3] {
    let off = if up { 1.0 / 3.0 } else { 2.0 / 3.0 };
    let (fa, fc1) = ((i as f64 + off) / K as f64, (j as f64 + off) / K as f64);
    [fa, fc1, 1.0 - fa - fc1]
}

fn fig7_data(sets: &[EvalSet], errors: &[Errors]) -> Fig7 {
    let mut acc: std::collections::BTreeMap<(usize, usize, bool), Vec<f64>> = Default::default();
    for (set, e) in sets.iter().zip(errors) {
        let o = set.orders.expect("combinations have orders");
        let t = (o[0] + o[1] + o[2]) as f64;
        acc.entry(cell_of(o[0] as f64 / t, o[1] as f64 / t))
            .or_default()
            .push(e.mean_de76());
    }
    Fig7 {
        cells: acc
            .into_iter()
            .map(|((i, j, up), v)| (i, j, up, v.len(), v.iter().sum::<f64>() / v.len() as f64))
            .collect(),
    }
}

fn fig7_csv(f: &Fig7) -> String {
    let mut s =
        String::from("a_fraction_from,c1_fraction_from,orientation,combinations,mean_de76\n");
    for (i, j, up, n, e) in &f.cells {
        writeln!(
            s,
            "{:.3},{:.3},{},{n},{e:.4}",
            *i as f64 / K as f64,
            *j as f64 / K as f64,
            if *up { "up" } else { "down" }
        )
        .ok();
    }
    s
}

// ---------------------------------------------------------------------------------------------
// Section 4 and the text report.

fn section4_csv(rows: &[Row]) -> String {
    let mut s = String::from(
        "set,distinct_wavelengths,mean_de76,max_de76,mean_de00,max_de00,ns_per_pixel,judged_on\n",
    );
    for r in rows {
        writeln!(
            s,
            "{},{},{:.4},{:.4},{:.4},{:.4},{:.2},{}",
            r.set.name,
            r.samples,
            r.errors.mean_de76(),
            r.errors.max_de76(),
            r.errors.mean_de00(),
            r.errors.max_de00(),
            r.ns_per_pixel,
            r.judged_on.as_deref().unwrap_or("all stimuli")
        )
        .ok();
    }
    s
}

/// The report's header and section 1 (Table 2): printed as soon as they are known.
fn print_intro_and_table2(o: &mut String, stimuli: &[Stimulus], table2: &[Table2Row]) {
    writeln!(o, "spectral-quadrature report: error against run time").ok();
    writeln!(o, "reference: full integration at 1 nm, 380-770 nm, CIE 1931 2°; CIELAB white integrated by the same rule as each colour").ok();
    writeln!(
        o,
        "{} stimuli (first: {}; last: {})\n",
        stimuli.len(),
        stimuli[0].name,
        stimuli[stimuli.len() - 1].name
    )
    .ok();

    writeln!(
        o,
        "1. Table 2: ColorChecker (Ohta) under illuminant C, mean ΔE*ab"
    )
    .ok();
    writeln!(
        o,
        "   {:<12} {:<40} {:>8} {:>8} {:>8}",
        "row", "wavelengths (nm)", "derived", "paper", "diff"
    )
    .ok();
    for r in table2 {
        let w: Vec<String> = r.wavelengths.iter().map(|l| format!("{l:.1}")).collect();
        writeln!(
            o,
            "   {:<12} {:<40} {:>8.3} {:>8.3} {:>+8.3}",
            r.name,
            w.join(" "),
            r.mean_de76,
            r.paper,
            r.mean_de76 - r.paper
        )
        .ok();
    }
    writeln!(
        o,
        "   (the paper used McCamy's reflectances of the chart; these are Ohta's)\n"
    )
    .ok();
}

/// Sections 2-4: Figs. 6 and 7, and error against run time.
fn print_sections_2_to_4(
    o: &mut String,
    fig_stimuli: &[Stimulus],
    fig6: &Fig6,
    fig7: &Fig7,
    rows: &[Row],
) {
    writeln!(
        o,
        "2. Fig. 6: mean ΔE*ab against the total number of wavelengths (n_A + n_C1 + n_C2),"
    )
    .ok();
    writeln!(
        o,
        "   averaged over every order combination with that total; {} stimuli ({} ... {})",
        fig_stimuli.len(),
        fig_stimuli[0].name,
        fig_stimuli[fig_stimuli.len() - 1].name
    )
    .ok();
    writeln!(
        o,
        "   {:>5} {:>9} {:>9} {:>9}",
        "total", "AC1C2", "XYZ", "SML"
    )
    .ok();
    let totals: std::collections::BTreeSet<usize> = fig6.points.iter().map(|p| p.1).collect();
    for t in totals.iter().filter(|t| **t <= 24) {
        let cell = |space: &str| {
            fig6.points
                .iter()
                .find(|p| p.0 == space && p.1 == *t)
                .map_or("-".to_string(), |p| format!("{:.3}", p.3))
        };
        writeln!(
            o,
            "   {t:>5} {:>9} {:>9} {:>9}",
            cell("AC1C2"),
            cell("XYZ"),
            cell("SML")
        )
        .ok();
    }
    writeln!(o, "   (totals up to 24 shown; all in fig6.csv)\n").ok();

    writeln!(o, "3. Fig. 7: mean ΔE*ab by the fraction of wavelengths given to A, C1, C2 ({K}x{K} sub-triangles)").ok();
    for (what, pred) in [
        (
            "mostly A   (A ≥ 2/3 of the wavelengths)",
            &(|f: [f64; 3]| f[0] >= 2.0 / 3.0) as &dyn Fn([f64; 3]) -> bool,
        ),
        ("mostly C1  (C1 ≥ 2/3)", &|f: [f64; 3]| f[1] >= 2.0 / 3.0),
        ("mostly C2  (C2 ≥ 2/3)", &|f: [f64; 3]| f[2] >= 2.0 / 3.0),
        ("balanced   (each ≥ 1/6)", &|f: [f64; 3]| {
            f.iter().all(|x| *x >= 1.0 / 6.0)
        }),
    ] {
        let v: Vec<f64> = fig7
            .cells
            .iter()
            .filter(|c| pred(centroid(c.0, c.1, c.2)))
            .map(|c| c.4)
            .collect();
        let mean = v.iter().sum::<f64>() / v.len().max(1) as f64;
        writeln!(
            o,
            "   {what}: {mean:.3} (mean of {} sub-triangles)",
            v.len()
        )
        .ok();
    }
    writeln!(o).ok();

    writeln!(
        o,
        "4. Error against run time ({} sets; all in error_vs_time.csv)",
        rows.len()
    )
    .ok();
    writeln!(o, "   the best per-channel Gauss combination (AC1C2 and XYZ) at each number of distinct wavelengths, Table 2's").ok();
    writeln!(o, "   sets, uniform sets, shared sets for radiances (KQ_N; trained on the CIE test colour samples, which these").ok();
    writeln!(o, "   stimuli include by default: section 5 judges on the ColorChecker alone), method (a) INTERP_A_N, sampling").ok();
    writeln!(o, "   every 10 and 20 nm, full integration:").ok();
    writeln!(
        o,
        "   {:<22} {:>5} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "set", "N", "mean76", "max76", "mean00", "max00", "ns/pixel"
    )
    .ok();
    let mut best: std::collections::BTreeMap<(&str, usize), &Row> = Default::default();
    for r in rows
        .iter()
        .filter(|r| r.set.family == "AC1C2" || r.set.family == "XYZ")
    {
        let e = best.entry((&r.set.family, r.set.len())).or_insert(r);
        if r.errors.mean_de00() < e.errors.mean_de00() {
            *e = r;
        }
    }
    let shown = best.values().copied().filter(|r| r.set.len() <= 16).chain(
        rows.iter()
            .filter(|r| r.set.family != "AC1C2" && r.set.family != "XYZ"),
    );
    for r in shown.clone().filter(|r| r.judged_on.is_none()) {
        section4_line(o, r);
    }
    let mut own: Vec<&Row> = shown.filter(|r| r.judged_on.is_some()).collect();
    own.sort_by_key(|r| r.judged_on.clone());
    let mut last: Option<&str> = None;
    for r in own {
        let on = r.judged_on.as_deref().unwrap_or_default();
        if last != Some(on) {
            writeln!(
                o,
                "   judged on {on} only (a light folded in, or a sensor fitted under it):"
            )
            .ok();
            last = Some(on);
        }
        section4_line(o, r);
    }
    let full = rows.iter().find(|r| r.set.name == "full 1 nm");
    let row2 = rows.iter().find(|r| r.set.name == "table2 row2");
    if let (Some(f), Some(r)) = (full, row2) {
        writeln!(o, "   table 2 row 2 is {:.0}x faster than the full 1 nm integration (medians of this run)", f.ns_per_pixel / r.ns_per_pixel).ok();
    }
}

/// One row of section 4's text table.
fn section4_line(o: &mut String, r: &Row) {
    writeln!(
        o,
        "   {:<22} {:>5} {:>9.3} {:>9.3} {:>9.3} {:>9.3} {:>9.1}",
        r.set.name,
        r.samples,
        r.errors.mean_de76(),
        r.errors.max_de76(),
        r.errors.mean_de00(),
        r.errors.max_de00(),
        r.ns_per_pixel
    )
    .ok();
}

fn write(dir: &Path, name: &str, text: &str) -> Result<PathBuf, Error> {
    let path = dir.join(name);
    std::fs::write(&path, text).map_err(|source| Error::Write {
        path: path.clone(),
        source,
    })?;
    Ok(path)
}

// ---------------------------------------------------------------------------------------------
// Plots (SVG).

fn plot_err<E: std::fmt::Debug>(e: E) -> Error {
    Error::Plot(format!("{e:?}"))
}

fn plot_fig6(out: &Path, f: &Fig6) -> Result<PathBuf, Error> {
    let path = out.join("fig6.svg");
    let root = SVGBackend::new(&path, (720, 480)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let max_t = f.points.iter().map(|p| p.1).max().unwrap_or(3).min(24) as f64;
    let max_e = f
        .points
        .iter()
        .filter(|p| p.1 as f64 <= max_t)
        .map(|p| p.3)
        .fold(0.0, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Fig. 6: mean ΔE*ab against total wavelengths",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(2.5f64..max_t + 0.5, (0.01f64..max_e * 1.2).log_scale())
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc("total number of wavelengths (n_A + n_C1 + n_C2)")
        .y_desc("mean ΔE*ab (log)")
        .draw()
        .map_err(plot_err)?;
    for (space, colour) in [("AC1C2", RED), ("XYZ", BLUE), ("SML", GREEN)] {
        let pts: Vec<(f64, f64)> = f
            .points
            .iter()
            .filter(|p| p.0 == space && p.1 as f64 <= max_t && p.3 > 0.0)
            .map(|p| (p.1 as f64, p.3))
            .collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
            .map_err(plot_err)?
            .label(space)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        chart
            .draw_series(pts.iter().map(|p| Circle::new(*p, 3, colour.filled())))
            .map_err(plot_err)?;
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(plot_err)?;
    root.present().map_err(plot_err)?;
    drop(chart);
    drop(root);
    Ok(path)
}

fn heat(t: f64) -> RGBColor {
    // Blue (low) → yellow → red (high).
    let t = t.clamp(0.0, 1.0);
    let (r, g, b) = if t < 0.5 {
        let u = t * 2.0;
        (u, u, 1.0 - u)
    } else {
        let u = (t - 0.5) * 2.0;
        (1.0, 1.0 - u, 0.0)
    };
    RGBColor((r * 255.0) as u8, (g * 255.0) as u8, (b * 255.0) as u8)
}

fn plot_fig7(out: &Path, f: &Fig7) -> Result<PathBuf, Error> {
    let path = out.join("fig7.svg");
    let (w, h) = (640i32, 600i32);
    let root = SVGBackend::new(&path, (w as u32, h as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    root.draw(&Text::new(
        "Fig. 7: mean ΔE*ab by wavelength allocation (log colour scale)",
        (20, 12),
        ("sans-serif", 18),
    ))
    .map_err(plot_err)?;
    // Corners: A at the top, C1 bottom left, C2 bottom right.
    let side = 520.0;
    let top = (w as f64 / 2.0, 70.0);
    let left = (top.0 - side / 2.0, top.1 + side * 3f64.sqrt() / 2.0);
    let right = (top.0 + side / 2.0, left.1);
    let point = |fa: f64, fc1: f64| {
        let fc2 = 1.0 - fa - fc1;
        (
            (fa * top.0 + fc1 * left.0 + fc2 * right.0) as i32,
            (fa * top.1 + fc1 * left.1 + fc2 * right.1) as i32,
        )
    };
    let (lo, hi) = f.cells.iter().fold((f64::MAX, f64::MIN), |(lo, hi), c| {
        (lo.min(c.4), hi.max(c.4))
    });
    let k = K as f64;
    for (i, j, up, n, e) in &f.cells {
        let (a, b) = (*i as f64 / k, *j as f64 / k);
        let corners = if *up {
            [point(a, b), point(a + 1.0 / k, b), point(a, b + 1.0 / k)]
        } else {
            [
                point(a + 1.0 / k, b),
                point(a + 1.0 / k, b + 1.0 / k),
                point(a, b + 1.0 / k),
            ]
        };
        let t = if hi > lo {
            (e.ln() - lo.ln()) / (hi.ln() - lo.ln())
        } else {
            0.5
        };
        root.draw(&Polygon::new(corners.to_vec(), heat(t).filled()))
            .map_err(plot_err)?;
        root.draw(&PathElement::new(
            vec![corners[0], corners[1], corners[2], corners[0]],
            BLACK.mix(0.4),
        ))
        .map_err(plot_err)?;
        let cx = (corners[0].0 + corners[1].0 + corners[2].0) / 3;
        let cy = (corners[0].1 + corners[1].1 + corners[2].1) / 3;
        let label = if *n > 0 {
            format!("{e:.2}")
        } else {
            String::new()
        };
        root.draw(&Text::new(label, (cx - 12, cy - 5), ("sans-serif", 10)))
            .map_err(plot_err)?;
    }
    let lab = |s: &str, p: (f64, f64), dx: i32, dy: i32| {
        Text::new(
            s.to_string(),
            (p.0 as i32 + dx, p.1 as i32 + dy),
            ("sans-serif", 16),
        )
    };
    root.draw(&lab("all A", top, -18, -24)).map_err(plot_err)?;
    root.draw(&lab("all C1", left, -30, 8)).map_err(plot_err)?;
    root.draw(&lab("all C2", right, -10, 8)).map_err(plot_err)?;
    root.draw(&Text::new(
        format!("blue {lo:.2} … red {hi:.2} ΔE*ab"),
        (20, h - 24),
        ("sans-serif", 14),
    ))
    .map_err(plot_err)?;
    root.present().map_err(plot_err)?;
    drop(root);
    Ok(path)
}

fn plot_error_vs_time(out: &Path, rows: &[Row]) -> Result<PathBuf, Error> {
    let path = out.join("error_vs_time.svg");
    let root = SVGBackend::new(&path, (800, 540)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let tmin = rows
        .iter()
        .map(|r| r.ns_per_pixel)
        .fold(f64::MAX, f64::min)
        .max(0.01);
    let tmax = rows.iter().map(|r| r.ns_per_pixel).fold(0.0, f64::max);
    // The reference has zero error: plot errors with a floor so the log axis can show it.
    const FLOOR: f64 = 1e-3;
    let emax = rows
        .iter()
        .map(|r| r.errors.mean_de00())
        .fold(0.0, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Error against run time (mean ΔE00, runtime f32 path)",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(
            (tmin * 0.7..tmax * 1.5).log_scale(),
            (FLOOR * 0.7..emax * 1.5).log_scale(),
        )
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc("ns per pixel (median, log)")
        .y_desc("mean ΔE00 (log; 0 drawn at 0.001)")
        .draw()
        .map_err(plot_err)?;
    for (family, colour, size) in [
        ("AC1C2", RGBColor(230, 120, 120), 2),
        ("XYZ", RGBColor(150, 150, 230), 2),
        ("uniform", BLUE, 4),
        ("interp A", RGBColor(200, 140, 40), 4),
        ("KQ radiance", RGBColor(150, 60, 170), 5),
        ("interval", RGBColor(60, 160, 60), 5),
        ("Table 2", RED, 6),
        ("full", BLACK, 5),
    ] {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.set.family == family)
            .map(|r| (r.ns_per_pixel, r.errors.mean_de00().max(FLOOR)))
            .collect();
        let label = match family {
            "AC1C2" => "per-channel Gauss combinations",
            "XYZ" => "Gauss combinations in XYZ",
            "uniform" => "uniform sets",
            "interp A" => "A's nodes, interpolatory C1, C2",
            "KQ radiance" => "shared sets (kernel quadrature)",
            "interval" => "every 10 / 20 nm, linear interpolation",
            "Table 2" => "Table 2 sets",
            _ => "full integration (5 nm, 1 nm)",
        };
        chart
            .draw_series(pts.iter().map(|p| Circle::new(*p, size, colour.filled())))
            .map_err(plot_err)?
            .label(label)
            .legend(move |(x, y)| Circle::new((x, y), 4, colour.filled()));
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(plot_err)?;
    root.present().map_err(plot_err)?;
    drop(chart);
    drop(root);
    Ok(path)
}

fn draw_swatches(
    out: &Path,
    d: &Derivation,
    cc_under_c: &[Stimulus],
    rows: &[Row],
) -> Result<PathBuf, Error> {
    let path = out.join("swatches.svg");
    let chosen: Vec<&Row> = [
        "table2 row1",
        "table2 row2",
        "uniform 4",
        "uniform 8",
        "uniform 16",
        "full 5 nm",
    ]
    .iter()
    .filter_map(|n| rows.iter().find(|r| r.set.name == *n))
    .collect();
    let reference = rows
        .iter()
        .find(|r| r.set.name == "full 1 nm")
        .ok_or_else(|| Error::Plot("the swatches' reference set is missing".into()))?;
    let cell = 36i32;
    let (cols, rows_n) = (6i32, 4i32);
    let panel_w = cols * cell + 20;
    let width = (panel_w * chosen.len() as i32 + 20) as u32;
    let height = (rows_n * cell + 70) as u32;
    let root = SVGBackend::new(&path, (width, height)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    root.draw(&Text::new(
        "ColorChecker under C: exact colour (upper left of each patch) beside each set's (lower right), sRGB",
        (10, 8),
        ("sans-serif", 13),
    ))
    .map_err(plot_err)?;
    let srgb = tables::displays::SRGB;
    let colour = |set: &EvalSet, s: &Stimulus| {
        let xyz = set.xyz(|l| s.radiance(l));
        let white = set.xyz(|l| s.white(l, 1.0));
        let rgb = srgb.linear_from_xyz(xyz.map(|v| (v / white[1]) as f32));
        let px = srgb.encode_u8(GamutMapping::Clip, rgb);
        RGBColor(px[0], px[1], px[2])
    };
    let _ = d;
    for (p, row) in chosen.iter().enumerate() {
        let x0 = 10 + p as i32 * panel_w;
        root.draw(&Text::new(
            row.set.name.clone(),
            (x0, 28),
            ("sans-serif", 12),
        ))
        .map_err(plot_err)?;
        for (k, s) in cc_under_c.iter().enumerate().take(24) {
            let (cx, cy) = (x0 + (k as i32 % cols) * cell, 46 + (k as i32 / cols) * cell);
            let exact = colour(&reference.set, s);
            let approx = colour(&row.set, s);
            root.draw(&Polygon::new(
                vec![(cx, cy), (cx + cell - 2, cy), (cx, cy + cell - 2)],
                exact.filled(),
            ))
            .map_err(plot_err)?;
            root.draw(&Polygon::new(
                vec![
                    (cx + cell - 2, cy),
                    (cx + cell - 2, cy + cell - 2),
                    (cx, cy + cell - 2),
                ],
                approx.filled(),
            ))
            .map_err(plot_err)?;
        }
    }
    root.present().map_err(plot_err)?;
    drop(root);
    Ok(path)
}
