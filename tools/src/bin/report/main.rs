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
//! cargo run --release -p spectral-quadrature-tools --bin report -- --reflectances my.csv --sections 4,7
//! ```
//!
//! `--sections` runs only the sections named (1-10, any order, comma-separated); every section
//! runs by default. Each section is a file of this folder (`table2.rs` section 1,
//! `fig6_fig7.rs` sections 2-3, `error_vs_time.rs` 4, `budget.rs` 5, `stability.rs` 6,
//! `random_wavelengths.rs` 7, `upsampling.rs` 8, `light_groups.rs` 9, `interreflection.rs` 10);
//! this one holds the options and runs them in order.
//!
//! Section 7 measures random wavelengths per sample (pbrt-v4's sampler, hero, uniform) against
//! the fixed sets; `--trials` and `--seed` set its trials (see `docs/random-wavelengths.md`).
//! Section 8 relights RGB materials upsampled to a set's nodes: the crate's map beside
//! Jakob-Hanika, Mallett-Yuksel and Smits (see `docs/upsampling.md`). Section 9 judges light
//! groups, one node set shared by several lights (see `docs/light-groups.md`). Section 10 judges
//! the sets on light that bounces off several surfaces (see `docs/interreflection.md`). Sections
//! 7, 9 and 10 run seeded trials of every stimulus or refit on the reflectances they judge,
//! which costs time in proportion to their number: a file of more than `--sample` (256) is
//! judged there on a seeded sample of that many, and the sections say so with the standard
//! error the sample adds.
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
mod progress;
mod random_wavelengths;
mod stability;
mod table2;
mod timing;
mod upsampling;
mod user;

use spectral_quadrature_tools as tools;
use tools::Error;

use std::collections::BTreeSet;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use clap::Parser;
use spectral_quadrature_spectra::{
    builtin_illuminant, surfaces_under_lights, Errors, EvalSet, Reference, Spectra,
};

use progress::{Meter, Progress};

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
    /// Run only these sections (1-10, comma-separated, e.g. `4,7`): their text, files and
    /// plots, and what they need. Default: every section.
    #[arg(long, value_name = "LIST", value_delimiter = ',', num_args = 1.., value_parser = clap::value_parser!(u8).range(1..=10))]
    sections: Option<Vec<u8>>,
    /// Run section 4 (error against run time) alone and print it as CSV on standard output,
    /// nothing else: no other section runs and no file is written (the same CSV as
    /// error_vs_time.csv).
    #[arg(long, conflicts_with_all = ["out", "trials", "seed", "quick", "sections", "sample"])]
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
    /// The seed of the random numbers: section 7's and 10's trials, section 10's products of
    /// reflectances, and the sample of `--sample`.
    #[arg(long, default_value_t = 1988)]
    seed: u64,
    /// The most reflectances sections 7, 9 and 10 judge (at least 15: three per fold of
    /// section 9): a larger --reflectances file is judged there on a seeded sample of this many
    /// (the same in the three), which they state with the standard error it adds to their
    /// means. `all`: every reflectance.
    #[arg(long, value_name = "N|all", default_value = "256", value_parser = parse_sample)]
    sample: Sample,
}

/// How many reflectances sections 7, 9 and 10 judge at most.
#[derive(Clone, Copy, Debug)]
enum Sample {
    /// At most this many.
    Most(usize),
    /// Every one.
    All,
}

/// `--sample`: a number of at least 15, or `all`.
fn parse_sample(s: &str) -> Result<Sample, String> {
    if s == "all" {
        return Ok(Sample::All);
    }
    match s.parse::<usize>() {
        Ok(n) if n >= 3 * tools::light_groups::FOLDS => Ok(Sample::Most(n)),
        _ => Err(format!(
            "expected a number of at least {} or `all`",
            3 * tools::light_groups::FOLDS
        )),
    }
}

fn main() {
    let args = Args::parse();
    if let Err(e) = run(&args) {
        eprintln!("report: error: {e}");
        std::process::exit(2);
    }
}

/// The sections' steps, in order: the progress lines count those that run.
const SECTION_STEPS: [(&[u8], &str); 9] = [
    (&[1], "section 1: Table 2 (ColorChecker under C)"),
    (
        &[2, 3],
        "sections 2-3: Figs. 6 and 7 (every per-channel order combination)",
    ),
    (
        &[4],
        "section 4: error against run time (timing every set, writing its tables and plots)",
    ),
    (
        &[5],
        "section 5: shared sets at each wavelength budget (fitting and judging)",
    ),
    (&[6], "section 6: stability"),
    (
        &[7],
        "section 7: against random wavelengths (seeded trials, timing)",
    ),
    (
        &[8],
        "section 8: RGB materials under another light (fitting and relighting)",
    ),
    (
        &[9],
        "section 9: several lights in one scene (light groups, cross-validated)",
    ),
    (
        &[10],
        "section 10: light that bounces (bounce forms, fixed sets, seeded trials)",
    ),
];

/// The progress lines of a run of `sections`: deriving, reading, then each section's step.
fn steps(sections: &BTreeSet<u8>) -> Vec<String> {
    let mut steps = vec![
        "deriving the rules (CIE 1931 2°, 380-770 nm, 5 nm)".to_string(),
        "reading spectra".to_string(),
    ];
    for (which, what) in SECTION_STEPS {
        match which.iter().filter(|s| sections.contains(s)).count() {
            0 => {}
            n if n == which.len() => steps.push(what.to_string()),
            // Section 2 or 3 alone.
            _ if sections.contains(&2) => {
                steps.push("section 2: Fig. 6 (every per-channel order combination)".into())
            }
            _ => steps.push("section 3: Fig. 7 (every per-channel order combination)".into()),
        }
    }
    steps
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

/// Prints a section's text at once, a blank line after it, and keeps it for report.txt.
fn print_section(text: &mut String, section: &str) {
    let section = format!("{}\n\n", section.trim_end_matches('\n'));
    print!("{section}");
    std::io::stdout().flush().ok();
    text.push_str(&section);
}

fn run(args: &Args) -> Result<(), Error> {
    let work = Work::of(args);
    let sections: BTreeSet<u8> = if args.csv {
        [4].into()
    } else {
        match &args.sections {
            Some(s) => s.iter().copied().collect(),
            None => (1..=10).collect(),
        }
    };
    let runs = |s: u8| sections.contains(&s);
    if args.scene.is_some() && !runs(4) {
        return Err(Error::Derive(
            spectral_quadrature_generator::Error::Settings(
                "--scene adds sets to section 4, which --sections leaves out".into(),
            ),
        ));
    }
    let mut steps = steps(&sections);
    if args.csv {
        steps[2] = "section 4: error against run time (every per-channel order combination, timing every set)".into();
    }
    let mut progress = Progress::new(steps);
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
    let out = &args.out;
    if !args.csv {
        std::fs::create_dir_all(out).map_err(|source| Error::Write {
            path: out.clone(),
            source,
        })?;
    }
    let mut text = String::new();
    let mut files = Vec::new();
    if !args.csv {
        let mut header = String::new();
        table2::header(&mut header, &stimuli);
        print_section(&mut text, &header);
    }

    if runs(1) {
        progress.next();
        let table2 = table2::rows(&d, &cc_under_c, &cc_reference);
        let mut o = String::new();
        table2::text(&mut o, &table2);
        files.push(table2::csv(&table2).write(out, "table2.csv")?);
        print_section(&mut text, &o);
    }

    // Sections 2 to 5 build on every combination of per-channel rules.
    let spaces = if runs(2) || runs(3) || runs(4) || runs(5) {
        Some(tools::budget::rule_spaces(&d, work.max_order)?)
    } else {
        None
    };
    // Figs. 6 and 7 reproduce the paper's setup (ColorChecker under C) unless spectra are given.
    let user_spectra = args.spectra.any();
    let mut space_errors: Option<Vec<Vec<Errors>>> = None;
    if let (Some(spaces), true) = (&spaces, runs(2) || runs(3)) {
        progress.next();
        let (fig_stimuli, fig_reference) = if user_spectra {
            (&stimuli, &reference)
        } else {
            (&cc_under_c, &cc_reference)
        };
        let meter = Meter::new("judging", spaces.iter().map(|s| s.1.len()).sum(), "sets");
        let all: Vec<EvalSet> = spaces.iter().flat_map(|s| s.1.iter().cloned()).collect();
        // Figs. 6 and 7 are in ΔE*ab. Section 4 shows CIEDE2000 too, of every AC1C2 combination
        // and of the XYZ ones up to 16 wavelengths: on the user's spectra, section 4 judges the
        // same sets on the same stimuli and takes these.
        let share = user_spectra && runs(4);
        let ac1c2 = spaces[0].1.len();
        let xyz = ac1c2 + spaces[1].1.len();
        let de00 = |k: usize| share && (k < ac1c2 || (k < xyz && all[k].len() <= 16));
        let mut errors = tools::evaluate::errors_of_sets(
            fig_reference,
            fig_stimuli,
            &all,
            &de00,
            &meter.counter(),
        )
        .into_iter();
        let e: Vec<Vec<Errors>> = spaces
            .iter()
            .map(|(_, sets)| errors.by_ref().take(sets.len()).collect())
            .collect();
        let mut o = String::new();
        let fig6 = fig6_fig7::fig6_data(spaces, &e);
        let fig7 = fig6_fig7::fig7_data(&spaces[0].1, &e[0]);
        if runs(2) {
            files.push(fig6_fig7::fig6_csv(&fig6).write(out, "fig6.csv")?);
            files.push(plot::fig6(out, &fig6)?);
            fig6_fig7::fig6_text(&mut o, fig_stimuli, &fig6);
        }
        if runs(3) {
            files.push(fig6_fig7::fig7_csv(&fig7).write(out, "fig7.csv")?);
            files.push(plot::fig7(out, &fig7)?);
            fig6_fig7::fig7_text(&mut o, &fig7);
        }
        print_section(&mut text, &o);
        if share {
            space_errors = Some(e);
        }
    }

    // The shared sets for radiances, and folded for each of the user's lights (sections 4, 5):
    // fitted in the first of the two that runs.
    let shared = || -> Result<_, Error> {
        Ok((
            tools::budget::shared_sets_sized(&d, None, work.shared_sizes.clone())?,
            user::folded_for_lights(
                &d,
                &inputs.user_lights,
                &inputs.surfaces,
                &work.shared_sizes,
            )?,
        ))
    };
    let mut shared_sets = None;
    if let (Some(spaces), true) = (&spaces, runs(4)) {
        progress.next();
        let (radiance, folded_user) = shared_sets.insert(shared()?);
        let mut extras = user::light_extras(folded_user, &inputs.surfaces_from);
        extras.extend(scene_extras);
        let rows = error_vs_time::rows(error_vs_time::Inputs {
            d: &d,
            stimuli: &stimuli,
            reference: &reference,
            spaces,
            space_errors: space_errors.as_deref(),
            radiance,
            extras,
            runs: work.runs,
        })?;
        if args.csv {
            error_vs_time::csv(&rows).print()?;
            eprintln!(
                "done in {:.1} s: {} stimuli, {} sets timed (section 4 only, --csv)",
                progress.elapsed(),
                stimuli.len(),
                rows.len()
            );
            return Ok(());
        }
        files.push(error_vs_time::csv(&rows).write(out, "error_vs_time.csv")?);
        files.push(plot::error_vs_time(out, &rows)?);
        files.push(plot::swatches(out, &cc_under_c, &rows)?);
        let mut o = String::new();
        error_vs_time::text(&mut o, &rows);
        print_section(&mut text, &o);
    }

    if let (Some(spaces), true) = (&spaces, runs(5)) {
        progress.next();
        let (radiance, folded_user) = match &shared_sets {
            Some(s) => s,
            None => shared_sets.insert(shared()?),
        };
        let (budget_text, budget_files) = budget::section(
            &d,
            spaces,
            radiance,
            folded_user,
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
        print_section(&mut text, &budget_text);
    }

    if runs(6) {
        progress.next();
        let (stability_text, stability_files) = stability::section(out)?;
        files.extend(stability_files);
        print_section(&mut text, &stability_text);
    }

    if runs(7) {
        progress.next();
        let table2_row2 = d
            .table2
            .get(1)
            .map(|set| EvalSet {
                name: table2::name(&set.name),
                ..d.eval_set(set, "Table 2")
            })
            .ok_or_else(|| Error::Plot("the derivation has no Table 2 row 2".into()))?;
        // Surfaces under lights: at most --sample of the reflectances, under every light.
        let sample = (!inputs.lights.is_empty()).then(|| {
            inputs::Reflectances::new(
                inputs.surfaces.clone(),
                inputs.surfaces_from.clone(),
                args.sample,
                args.seed,
            )
        });
        let sampled = sample.as_ref().filter(|r| r.sampled()).map(|r| {
            let st = surfaces_under_lights(&r.curves, &inputs.lights);
            let re = Reference::new(reference_set.clone(), &st);
            (st, re)
        });
        let (stimuli7, reference7) = match &sampled {
            Some((st, re)) => (st.as_slice(), re),
            None => (stimuli.as_slice(), &reference),
        };
        let (random_text, random_files) = random_wavelengths::section(
            &random_wavelengths::Inputs {
                d: &d,
                stimuli: stimuli7,
                reference: reference7,
                surfaces_from: &inputs.surfaces_from,
                lights: &inputs.lights,
                users_lights: !inputs.user_lights.is_empty(),
                table2_row2: &table2_row2,
                trials: work.trials,
                seed: args.seed,
                runs: work.runs,
                sample: sample.as_ref(),
            },
            out,
        )?;
        files.extend(random_files);
        print_section(&mut text, &random_text);
    }

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
    if runs(8) {
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
        print_section(&mut text, &upsampling_text);
    }

    // Sections 9 and 10 judge at most --sample reflectances (the same sample as section 7's
    // when the reflectances are the user's).
    let judged = if runs(9) || runs(10) {
        let (all, from) = tools::light_groups::judged_reflectances(&d, users_reflectances)?;
        Some(inputs::Reflectances::new(all, from, args.sample, args.seed))
    } else {
        None
    };
    if let (Some(judged), true) = (&judged, runs(9)) {
        progress.next();
        let (groups_text, groups_files) = light_groups::section(
            &light_groups::Inputs {
                d: &d,
                judged,
                lights: users_lights,
                sizes: &work.group_sizes,
            },
            out,
        )?;
        files.extend(groups_files);
        print_section(&mut text, &groups_text);
    }

    if let (Some(judged), true) = (&judged, runs(10)) {
        progress.next();
        let (bounce_text, bounce_files) = interreflection::section(
            &interreflection::Inputs {
                d: &d,
                judged,
                sizes: &work.group_sizes,
                trials: work.trials,
                seed: args.seed,
                quick: args.quick,
            },
            out,
        )?;
        files.extend(bounce_files);
        print_section(&mut text, &bounce_text);
    }

    files.push(write(out, "report.txt", &text)?);
    eprintln!(
        "done in {:.1} s: {} stimuli, sections {}. Files in {}:",
        progress.elapsed(),
        stimuli.len(),
        sections
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        out.display()
    );
    for f in files {
        eprintln!("  {}", f.display());
    }
    Ok(())
}

fn write(dir: &Path, name: &str, text: &str) -> Result<PathBuf, Error> {
    let path = dir.join(name);
    std::fs::write(&path, text).map_err(|source| Error::Write {
        path: path.clone(),
        source,
    })?;
    Ok(path)
}
