//! The crate's main job: error against run time for every wavelength set it offers, and the
//! paper's Table 2 and Figs. 6-7, on the spectra you give it.
//!
//! ```text
//! cargo run --release -p spectral-quadrature-tools --bin report
//! cargo run --release -p spectral-quadrature-tools --bin report -- --reflectances my.csv --illuminants lamps.csv
//! cargo run --release -p spectral-quadrature-tools --bin report -- --emission leds.csv --out target/leds
//! cargo run --release -p spectral-quadrature-tools --bin report -- --csv > error_vs_time.csv   # section 4 alone
//! cargo run -p spectral-quadrature-tools --bin report -- --quick --out target/quick   # every file, less work
//! cargo run --release -p spectral-quadrature-tools --bin report -- --trials 256 --seed 7
//! ```
//!
//! Section 7 measures random wavelengths per sample (pbrt-v4's sampler, hero, uniform) against
//! the fixed sets; `--trials` and `--seed` set its trials (see `docs/random-wavelengths.md`).
//! Section 8 relights RGB materials upsampled to a set's nodes: the crate's map beside
//! Jakob-Hanika, Mallett-Yuksel and Smits (see `docs/upsampling.md`). Section 9 judges light
//! groups, one node set shared by several lights (see `docs/light-groups.md`). Section 10 judges
//! the sets on light that bounces off several surfaces (see `docs/interreflection.md`).
//!
//! Spectra files: CSV, first column wavelength in nm, one column per spectrum, any spacing;
//! they are interpolated linearly and must cover the observer's 380-770 nm. Errors name the file
//! and line and exit with code 2. Negative values within 1e-6 of a file's largest value are
//! rounding noise, read as 0 with one warning per file on standard error; a more negative value
//! is an error naming its line and column, unless `--clamp-negatives` reads it as 0 too.

mod budget;
mod groups;
mod interreflection;
mod plot;
mod random;
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
use spectral_quadrature::{tables, FoldedSet, WavelengthSet};
use spectral_quadrature_generator::Derivation;
use spectral_quadrature_spectra::{
    builtin_illuminant, emissions, surfaces_under_lights, Curve, Errors, EvalSet, Reference,
    Spectra, Stimulus,
};
use tools::csv_table::Table;

/// Error against run time for Meyer's wavelength sets and their alternatives.
#[derive(Parser)]
#[command(version)]
struct Args {
    #[command(flatten)]
    spectra: tools::cli::SpectraArgs,
    /// A scene file whose sets join section 4 (catalogue names, its lights' shared sets, fixed
    /// wavelengths and sensors). Paths in it are relative to it.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Folder for the CSV files and SVG plots, relative to the current folder.
    #[arg(long, value_name = "DIR", default_value = "target/report")]
    out: PathBuf,
    /// Run section 4 (error against run time) alone and print it as CSV on standard output,
    /// nothing else: no other section runs and no file is written (the same CSV as
    /// error_vs_time.csv).
    #[arg(long, conflicts_with_all = ["out", "trials", "seed", "quick"])]
    csv: bool,
    /// A quick run that checks the output, not the figures: every section and every file, on
    /// reduced work (orders up to 4, one timing run, 2 trials per random sampler, shared sets
    /// at 4 and 8 wavelengths only in sections 4 and 5). Its numbers are not the report's.
    #[arg(long, conflicts_with_all = ["runs", "max_order", "trials"])]
    quick: bool,
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
const STEPS: [&str; 12] = [
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
    "section 9: several lights in one scene (light groups, cross-validated)",
    "section 10: light that bounces (bounce forms, fixed sets, seeded trials)",
];

/// The steps of `--csv`: section 4 alone.
const CSV_STEPS: [&str; 3] = [
    "deriving the rules (CIE 1931 2°, 380-770 nm, 5 nm)",
    "reading spectra",
    "section 4: error against run time (every per-channel order combination, timing every set)",
];

/// Progress on standard error, one line per step of [`STEPS`] (or [`CSV_STEPS`]).
struct Progress {
    steps: &'static [&'static str],
    step: usize,
    start: Instant,
}

impl Progress {
    /// Announces the next step.
    fn next(&mut self) {
        let what = self.steps.get(self.step).copied().unwrap_or("finishing");
        self.step = (self.step + 1).min(self.steps.len());
        eprintln!(
            "[{}/{}] {what} ({:.1} s)",
            self.step,
            self.steps.len(),
            self.start.elapsed().as_secs_f64()
        );
    }
}

/// How much work each section does: the options', or `--quick`'s.
struct Work {
    runs: usize,
    max_order: usize,
    trials: Option<usize>,
    /// The sizes of the shared sets in sections 4 and 5 (for radiances, and folded for each
    /// light).
    shared_sizes: Vec<usize>,
    /// The sizes of section 9's light groups.
    group_sizes: Vec<usize>,
}

impl Work {
    fn of(args: &Args) -> Work {
        if args.quick {
            Work {
                runs: 1,
                max_order: 4,
                trials: Some(2),
                shared_sizes: vec![4, 8],
                group_sizes: vec![8],
            }
        } else {
            Work {
                runs: args.runs as usize,
                max_order: args.max_order as usize,
                trials: args.trials.map(|t| t as usize),
                shared_sizes: tools::budget::BUDGETS.collect(),
                group_sizes: vec![4, 6, 8],
            }
        }
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
    let work = Work::of(args);
    let mut progress = Progress {
        steps: if args.csv { &CSV_STEPS } else { &STEPS },
        step: 0,
        start: Instant::now(),
    };
    progress.next();
    let d = spectral_quadrature_generator::derive(&tools::settings())?;
    tools::warn_zeroed("report", &d.observer.zeroed);
    let range = d.settings.range_nm;
    let reference_set = d.observer.full_integration(range, 1.0)?;

    progress.next();
    let inputs = load_inputs(args, range)?;
    let stimuli = inputs.stimuli.clone();
    // The scene is read with the spectra, so that a mistake in it stops the report at once.
    let scene_extras = match &args.scene {
        Some(path) => user::scene_extras(
            &d,
            path,
            &inputs.surfaces,
            &inputs.surfaces_from,
            &inputs.user_lights,
            &args
                .spectra
                .illuminants
                .as_ref()
                .map_or(String::new(), |p| p.display().to_string()),
        )?,
        None => Vec::new(),
    };
    let reference = Reference::new(reference_set.clone(), &stimuli);
    let (cc_under_c, cc_reference) = {
        let cc = Spectra::builtin(
            &d.settings.data_dir,
            "data/reflectance_colorchecker_ohta.csv",
        )
        .and_then(|s| s.curves(range))?;
        let c = builtin_illuminant(&d.settings.data_dir, "C", range)?;
        let st = surfaces_under_lights(&cc, &[c]);
        let r = Reference::new(reference_set.clone(), &st);
        (st, r)
    };
    if !args.csv {
        std::fs::create_dir_all(&args.out).map_err(|source| Error::Write {
            path: args.out.clone(),
            source,
        })?;
    }

    // The first table goes out at once; the rest follows when it is measured.
    let mut text = String::new();
    let mut table2 = Vec::new();
    if !args.csv {
        progress.next();
        table2 = table2_rows(&d, &cc_under_c, &cc_reference);
        print_intro_and_table2(&mut text, &stimuli, &table2);
        print!("{text}");
        std::io::stdout().flush().ok();
    }

    progress.next();
    let spaces = tools::budget::rule_spaces(&d, work.max_order)?;
    // Figs. 6 and 7 reproduce the paper's setup (ColorChecker under C) unless spectra are given.
    let user_spectra = args.spectra.any();
    let (fig_stimuli, fig_reference) = if user_spectra {
        (&stimuli, &reference)
    } else {
        (&cc_under_c, &cc_reference)
    };
    let space_errors: Vec<Vec<Errors>> = if args.csv {
        Vec::new()
    } else {
        let e = spaces
            .iter()
            .map(|(_, sets)| par_errors(fig_reference, sets, fig_stimuli))
            .collect();
        progress.next();
        e
    };

    let mut sets: Vec<EvalSet> = spaces[0].1.clone();
    for set in &d.table2 {
        sets.push(EvalSet {
            name: table2_name(&set.name),
            ..d.eval_set(set, "Table 2")
        });
    }
    // Gauss rules in XYZ space: each number of distinct wavelengths' best is shown.
    sets.extend(spaces[1].1.iter().filter(|s| s.len() <= 16).cloned());
    for n in (3..=16).chain([24, 32]) {
        sets.push(d.observer.uniform_set(range, n));
    }
    // The shared sets for radiances (the lights here are many; section 5 folds each one in),
    // method (a) for comparison, and sampling every 10 and 20 nm with linear interpolation.
    let radiance = tools::budget::shared_sets_sized(&d, None, work.shared_sizes.clone())?;
    sets.extend(radiance.iter().cloned());
    for n in tools::budget::BUDGETS {
        if let Ok(a) = spectral_quadrature_generator::catalog::resolve(&d, &format!("INTERP_A_{n}"))
        {
            sets.push(d.eval_set(&a, "interp A"));
        }
    }
    let flat = Curve::constant("equal energy", 1.0, range);
    for step in [10.0, 20.0] {
        sets.push(tools::budget::interval_set(&d, &flat, step)?);
    }
    sets.push(d.observer.full_integration(range, 5.0)?);
    sets.push(reference_set.clone());
    let errs = par_errors(&reference, &sets, &stimuli);
    let total = sets.len();
    let mut rows = Vec::with_capacity(total);
    for (k, (set, errors)) in sets.into_iter().zip(errs).enumerate() {
        if (k + 1) % total.div_ceil(4).max(1) == 0 || k + 1 == total {
            eprintln!("      timed {}/{total} sets", k + 1);
        }
        let ns_per_pixel = time_set(&set, &stimuli, work.runs)?;
        rows.push(Row {
            samples: set.len(),
            set,
            errors,
            ns_per_pixel,
            judged_on: None,
        });
    }
    // The user's: shared sets folded for each light of --illuminants, and a scene's sets. A
    // set already measured (a scene naming a light of --illuminants, or a set of the
    // report's own) is measured once; a set judged on exactly the report's stimuli (the only
    // light's folded sets) is labelled as judged on all of them, as the report's own are.
    let folded_user = user::folded_for_lights(
        &d,
        &inputs.user_lights,
        &inputs.surfaces,
        &work.shared_sizes,
    )?;
    let mut extras = user::light_extras(&folded_user, &inputs.surfaces_from);
    extras.extend(scene_extras);
    for x in extras {
        if rows.iter().any(|r| r.set.name == x.set.name) {
            continue;
        }
        let (own, judged_on) = match x.judged_on {
            Some((s, what)) if !same_stimuli(&s, &stimuli, range) => (s, Some(what)),
            _ => (stimuli.clone(), None),
        };
        let errors = Reference::new(reference_set.clone(), &own).errors(&x.set, &own);
        let ns_per_pixel = time_set(&x.timing, &own, work.runs)?;
        rows.push(Row {
            set: x.set,
            samples: x.samples,
            errors,
            ns_per_pixel,
            judged_on,
        });
    }

    if args.csv {
        section4_csv(&rows).print()?;
        eprintln!(
            "done in {:.1} s: {} stimuli, {} sets timed (section 4 only, --csv)",
            progress.start.elapsed().as_secs_f64(),
            stimuli.len(),
            rows.len()
        );
        return Ok(());
    }

    progress.next();
    let out = &args.out;
    let mut files = Vec::new();
    files.push(section4_csv(&rows).write(out, "error_vs_time.csv")?);
    files.push(table2_csv(&table2).write(out, "table2.csv")?);
    let fig6 = fig6_data(&spaces, &space_errors);
    files.push(fig6_csv(&fig6).write(out, "fig6.csv")?);
    let fig7 = fig7_data(&spaces[0].1, &space_errors[0]);
    files.push(fig7_csv(&fig7).write(out, "fig7.csv")?);
    files.push(plot::fig6(out, &fig6)?);
    files.push(plot::fig7(out, &fig7)?);
    files.push(plot::error_vs_time(out, &rows)?);
    files.push(plot::swatches(out, &cc_under_c, &rows)?);

    progress.next();
    let (budget_text, budget_files) = budget::section(
        &d,
        &spaces,
        &radiance,
        &folded_user,
        args.spectra
            .reflectances
            .as_ref()
            .map(|_| inputs.surfaces.as_slice()),
        &inputs.surfaces_from,
        out,
        work.runs,
        &work.shared_sizes,
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
            trials: work.trials,
            seed: args.seed,
            runs: work.runs,
        },
        out,
    )?;
    files.extend(random_files);

    // What sections 8 to 10 judge instead of their defaults: the user's reflectances and lights,
    // where given.
    let users_reflectances = args
        .spectra
        .reflectances
        .as_ref()
        .map(|_| (inputs.surfaces.as_slice(), inputs.surfaces_from.as_str()));
    let users_lights = args
        .spectra
        .illuminants
        .as_ref()
        .map(|_| inputs.user_lights.as_slice());
    progress.next();
    let (upsampling_text, upsampling_files) = upsampling::section(
        &upsampling::Inputs {
            d: &d,
            reflectances: users_reflectances,
            lights: users_lights,
        },
        out,
    )?;
    files.extend(upsampling_files);

    progress.next();
    let (groups_text, groups_files) = groups::section(
        &groups::Inputs {
            d: &d,
            reflectances: users_reflectances,
            lights: users_lights,
            sizes: &work.group_sizes,
        },
        out,
    )?;
    files.extend(groups_files);

    progress.next();
    let (bounce_text, bounce_files) = interreflection::section(
        &interreflection::Inputs {
            d: &d,
            reflectances: users_reflectances,
            sizes: &work.group_sizes,
            trials: work.trials,
            seed: args.seed,
            quick: args.quick,
        },
        out,
    )?;
    files.extend(bounce_files);

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
    rest.push('\n');
    rest.push_str(&groups_text);
    rest.push('\n');
    rest.push_str(&bounce_text);
    print!("{rest}");
    text.push_str(&rest);
    files.push(write(out, "report.txt", &text)?);
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
        let spectra = Spectra::read_with(p, tools::negatives(args.spectra.clamp_negatives))?;
        tools::warn_zeroed("report", spectra.zeroed());
        spectra.curves(range)
    };
    let (surfaces, surfaces_from) = match &args.spectra.reflectances {
        Some(p) => (read(p)?, p.display().to_string()),
        None => (
            tools::prefilter::default_surfaces(range)?,
            "the ColorChecker and CIE TCS 1-14".to_string(),
        ),
    };
    let user_lights = match &args.spectra.illuminants {
        Some(p) => read(p)?,
        None => Vec::new(),
    };
    let (stimuli, lights) = if let Some(path) = &args.spectra.emission {
        (emissions(&read(path)?), Vec::new())
    } else if user_lights.is_empty() {
        let lights: Vec<Curve> = DEFAULT_ILLUMINANTS
            .iter()
            .map(|n| builtin_illuminant(std::path::Path::new(tools::DATA_DIR), n, range))
            .collect::<Result<_, _>>()?;
        (surfaces_under_lights(&surfaces, &lights), lights)
    } else {
        (
            surfaces_under_lights(&surfaces, &user_lights),
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

/// Whether `a` and `b` are the same stimuli: the same names, and the same radiance at every nm
/// of `range`.
fn same_stimuli(a: &[Stimulus], b: &[Stimulus], range: [f64; 2]) -> bool {
    let (lo, hi) = (range[0].ceil() as i64, range[1].floor() as i64);
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.name == y.name && (lo..=hi).all(|nm| x.radiance(nm as f64) == y.radiance(nm as f64))
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
        .zip(tools::paper::TABLE2_MEAN_DELTA_E)
        .map(|(set, paper)| {
            let es = d.eval_set(set, "Table 2");
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

fn table2_csv(rows: &[Table2Row]) -> Table {
    let mut t = Table::new("row,wavelengths_nm,mean_de76,paper_mean_de76,difference");
    for r in rows {
        let w: Vec<String> = r.wavelengths.iter().map(|l| format!("{l:.1}")).collect();
        t.row([
            r.name.clone(),
            w.join(" "),
            format!("{:.4}", r.mean_de76),
            r.paper.to_string(),
            format!("{:+.4}", r.mean_de76 - r.paper),
        ]);
    }
    t
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

fn fig6_csv(f: &Fig6) -> Table {
    let mut t = Table::new("space,total_wavelengths,combinations,mean_de76");
    for (space, total, n, e) in &f.points {
        t.row([
            space.clone(),
            total.to_string(),
            n.to_string(),
            format!("{e:.4}"),
        ]);
    }
    t
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

fn fig7_csv(f: &Fig7) -> Table {
    let mut t = Table::new("a_fraction_from,c1_fraction_from,orientation,combinations,mean_de76");
    for (i, j, up, n, e) in &f.cells {
        t.row([
            format!("{:.3}", *i as f64 / K as f64),
            format!("{:.3}", *j as f64 / K as f64),
            (if *up { "up" } else { "down" }).to_string(),
            n.to_string(),
            format!("{e:.4}"),
        ]);
    }
    t
}

// ---------------------------------------------------------------------------------------------
// Section 4 and the text report.

fn section4_csv(rows: &[Row]) -> Table {
    let mut t = Table::new(
        "set,distinct_wavelengths,mean_de76,max_de76,mean_de00,max_de00,ns_per_pixel,judged_on",
    );
    for r in rows {
        t.row([
            r.set.name.clone(),
            r.samples.to_string(),
            format!("{:.4}", r.errors.mean_de76()),
            format!("{:.4}", r.errors.max_de76()),
            format!("{:.4}", r.errors.mean_de00()),
            format!("{:.4}", r.errors.max_de00()),
            format!("{:.2}", r.ns_per_pixel),
            r.judged_on.clone().unwrap_or_else(|| "all stimuli".into()),
        ]);
    }
    t
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
