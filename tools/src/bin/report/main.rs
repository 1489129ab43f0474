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
mod error_vs_time;
mod fig6_fig7;
mod inputs;
mod interreflection;
mod light_groups;
mod plot;
mod random_wavelengths;
mod stability;
mod table2;
mod timing;
mod upsampling;
mod user;

use spectral_quadrature_tools as tools;
use tools::Error;

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Parser;
use spectral_quadrature_spectra::{
    builtin_illuminant, surfaces_under_lights, Errors, EvalSet, Reference, Spectra, Stimulus,
};

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
    let inputs = inputs::load(&args.spectra, range)?;
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
        table2 = table2::rows(&d, &cc_under_c, &cc_reference);
        table2::header(&mut text, &stimuli);
        table2::text(&mut text, &table2);
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

    let radiance = tools::budget::shared_sets_sized(&d, None, work.shared_sizes.clone())?;
    let folded_user = user::folded_for_lights(
        &d,
        &inputs.user_lights,
        &inputs.surfaces,
        &work.shared_sizes,
    )?;
    let mut extras = user::light_extras(&folded_user, &inputs.surfaces_from);
    extras.extend(scene_extras);
    let rows = error_vs_time::rows(error_vs_time::Inputs {
        d: &d,
        stimuli: &stimuli,
        reference: &reference,
        spaces: &spaces,
        radiance: &radiance,
        extras,
        runs: work.runs,
    })?;

    if args.csv {
        error_vs_time::csv(&rows).print()?;
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
    files.push(error_vs_time::csv(&rows).write(out, "error_vs_time.csv")?);
    files.push(table2::csv(&table2).write(out, "table2.csv")?);
    let fig6 = fig6_fig7::fig6_data(&spaces, &space_errors);
    files.push(fig6_fig7::fig6_csv(&fig6).write(out, "fig6.csv")?);
    let fig7 = fig6_fig7::fig7_data(&spaces[0].1, &space_errors[0]);
    files.push(fig6_fig7::fig7_csv(&fig7).write(out, "fig7.csv")?);
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
    let (random_text, random_files) = random_wavelengths::section(
        &random_wavelengths::Inputs {
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
    let (groups_text, groups_files) = light_groups::section(
        &light_groups::Inputs {
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
    fig6_fig7::text(&mut rest, fig_stimuli, &fig6, &fig7);
    error_vs_time::text(&mut rest, &rows);
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

/// Errors of many sets, on every core.
fn par_errors(reference: &Reference, sets: &[EvalSet], stimuli: &[Stimulus]) -> Vec<Errors> {
    tools::par_map(sets, |set| reference.errors(set, stimuli))
}

fn write(dir: &Path, name: &str, text: &str) -> Result<PathBuf, Error> {
    let path = dir.join(name);
    std::fs::write(&path, text).map_err(|source| Error::Write {
        path: path.clone(),
        source,
    })?;
    Ok(path)
}
