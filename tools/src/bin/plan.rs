//! The planner: the wavelength set with the fewest distinct wavelengths whose CIEDE2000 error on
//! your spectra meets a budget, among every set the crate can build, written as a scene file.
//!
//! ```text
//! cargo run --release -p spectral-quadrature-tools --bin plan -- --max-delta-e 1.0
//! cargo run --release -p spectral-quadrature-tools --bin plan -- --reflectances my.csv --illuminants lamps.csv --max-delta-e 0.5
//! cargo run --release -p spectral-quadrature-tools --bin plan -- --emission leds.csv --max-delta-e 2 --metric max --out -
//! cargo run --release -p spectral-quadrature-tools --bin plan -- --max-delta-e 1 --display SRGB --display DISPLAY_P3 --out app.toml
//! ```
//!
//! Spectra files: CSV, first column wavelength in nm, one column per spectrum, any spacing;
//! they must cover the observer's 380-770 nm. Defaults: the ColorChecker (Ohta) and the CIE
//! test colour samples 1-14 under CIE illuminant C. Errors name the file and line and exit with
//! code 2. Negative values within 1e-6 of a file's largest value are rounding noise, read as 0
//! with one warning per file on standard error; a more negative value is an error naming its
//! line and column, unless `--clamp-negatives` reads it as 0 too. With `--out -` the scene goes to standard output and the summary to standard error.

use spectral_quadrature_tools as tools;
use tools::Error;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use clap::{Parser, ValueEnum};
use spectral_quadrature_generator::plan::{self, fmt_de, Candidate, Metric, Plan};
use spectral_quadrature_spectra::{
    builtin_illuminant, surfaces_under_lights, Curve, Spectra, Stimulus,
};

/// Finds the set with the fewest wavelengths that meets a ΔE00 budget and writes a scene file.
#[derive(Parser)]
#[command(version)]
struct Args {
    #[command(flatten)]
    spectra: tools::cli::SpectraArgs,
    /// The budget: the largest acceptable ΔE00 (mean or max over the spectra, see --metric).
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    max_delta_e: f64,
    /// Which statistic of ΔE00 over the spectra must meet the budget.
    #[arg(long, value_enum, default_value_t = MetricArg::Mean)]
    metric: MetricArg,
    /// A display the scene bakes (repeatable): SRGB, DISPLAY_P3, REC2020, MEYER_1987.
    #[arg(long = "display", value_name = "NAME", default_values_t = ["SRGB".to_string()])]
    displays: Vec<String>,
    /// The scene file to write; `-` for standard output.
    #[arg(long, value_name = "FILE", default_value = "scene.toml")]
    out: PathBuf,
}

#[derive(Clone, Copy, ValueEnum)]
enum MetricArg {
    Mean,
    Max,
}

impl From<MetricArg> for Metric {
    fn from(m: MetricArg) -> Metric {
        match m {
            MetricArg::Mean => Metric::Mean,
            MetricArg::Max => Metric::Max,
        }
    }
}

/// The catalogue's families, by name prefix, for the summary.
const FAMILIES: [&str; 4] = ["TABLE2", "AC1C2", "UNIFORM", "KQ"];

/// Count rows shown on each side of the chosen set's in the summary.
const AROUND: usize = 3;

fn main() {
    let args = Args::parse();
    if let Err(e) = run(&args) {
        eprintln!("plan: error: {e}");
        std::process::exit(2);
    }
}

fn run(args: &Args) -> Result<(), Error> {
    let start = Instant::now();
    let budget = args.max_delta_e;
    let metric = Metric::from(args.metric);
    let d = spectral_quadrature_generator::derive(&tools::settings())?;
    tools::warn_zeroed("plan", &d.observer.zeroed);
    let displays = check_displays(&d, &args.displays)?;
    let range = d.settings.range_nm;
    let (stimuli, described) = load_stimuli(args, range)?;
    // Beside the catalogue's sets, the shared sets: for radiances, and folded for the stimuli's
    // light when they share a built-in one.
    let shared = plan::shared_sets(&d, &stimuli, &[])?;
    let p = plan::plan(&d, &stimuli, &shared, budget, metric)?;
    let elapsed = start.elapsed().as_secs_f64();

    let note = format!(
        "`cargo run --release -p spectral-quadrature-tools --bin plan -- {}` ({described})",
        command_args()
    );
    let display_refs: Vec<&str> = displays.iter().map(String::as_str).collect();
    let scene = tools::scene_file::scene_toml(&p, d.settings.observer.name(), &display_refs, &note);
    let chosen_set = spectral_quadrature_generator::catalog::resolve(&d, &p.chosen.name)?;
    let summary = summary(&p, &described, &chosen_set.wavelengths_nm, elapsed);
    if args.out.as_os_str() == "-" {
        eprint!("{summary}");
        print!("{scene}");
        eprintln!("scene written to standard output");
    } else {
        std::fs::write(&args.out, &scene).map_err(|source| Error::Write {
            path: args.out.clone(),
            source,
        })?;
        print!("{summary}");
        println!("scene written to {}", args.out.display());
    }
    Ok(())
}

/// The displays, by the names the scene uses (any case); an unknown name is
/// [`spectral_quadrature_generator::Error::UnknownDisplay`], listing the valid ones.
fn check_displays(
    d: &spectral_quadrature_generator::Derivation,
    names: &[String],
) -> Result<Vec<String>, Error> {
    let mut out: Vec<String> = Vec::new();
    for n in names {
        let (spec, _) = d.display(&n.to_ascii_uppercase()).map_err(|e| match e {
            spectral_quadrature_generator::Error::UnknownDisplay { valid, .. } => {
                spectral_quadrature_generator::Error::UnknownDisplay {
                    name: n.clone(),
                    valid,
                }
            }
            other => other,
        })?;
        if !out.contains(&spec.name) {
            out.push(spec.name.clone());
        }
    }
    Ok(out)
}

/// The stimuli and a few words saying what they are.
fn load_stimuli(args: &Args, range: [f64; 2]) -> Result<(Vec<Stimulus>, String), Error> {
    let negatives = tools::negatives(args.spectra.clamp_negatives);
    if let Some(path) = &args.spectra.emission {
        let (s, zeroed) = plan::stimuli_from_files(range, None, None, Some(path), negatives)?;
        tools::warn_zeroed("plan", &zeroed);
        let described = format!("{} in {}", plural(s.len(), "light"), path.display());
        return Ok((s, described));
    }
    let read = |p: &std::path::Path| {
        let spectra = Spectra::read_with(p, negatives)?;
        tools::warn_zeroed("plan", spectra.zeroed());
        spectra.curves(range)
    };
    let (surfaces, surfaces_from) = match &args.spectra.reflectances {
        Some(p) => (read(p)?, p.display().to_string()),
        None => (
            tools::prefilter::default_surfaces(range)?,
            "the ColorChecker and CIE TCS 1-14".to_string(),
        ),
    };
    let (lights, lights_from): (Vec<Curve>, String) = match &args.spectra.illuminants {
        Some(p) => (read(p)?, p.display().to_string()),
        None => (
            vec![builtin_illuminant(
                std::path::Path::new(tools::DATA_DIR),
                "C",
                range,
            )?],
            "illuminant C".to_string(),
        ),
    };
    let described = format!(
        "{} from {surfaces_from} under {} from {lights_from}",
        plural(surfaces.len(), "surface"),
        plural(lights.len(), "light")
    );
    Ok((surfaces_under_lights(&surfaces, &lights), described))
}

/// `1 light`, `6 lights`.
fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

/// The command line's arguments, for the scene's comment.
fn command_args() -> String {
    std::env::args()
        .skip(1)
        .map(|a| {
            if a.is_empty() || a.contains(char::is_whitespace) {
                format!("'{a}'")
            } else {
                a
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The chosen set, and the best set at each wavelength count around it.
fn summary(p: &Plan, described: &str, wavelengths_nm: &[f64], elapsed_s: f64) -> String {
    let m = p.metric;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{} sets measured on {} stimuli ({described}) in {elapsed_s:.2} s; budget: {m} ΔE00 <= {}",
        p.candidates.len(),
        p.stimuli,
        p.budget
    );
    let _ = writeln!(
        s,
        "\nbest set at each wavelength count (* chosen: fewest wavelengths meeting the budget)"
    );
    let _ = writeln!(
        s,
        "  {:>3}  {:<16} {:>10} {:>10} {:>10} {:>10}  meets",
        "n", "set", "mean ΔE00", "max ΔE00", "mean ΔE76", "max ΔE76"
    );
    let best = plan::best_per_count(&p.candidates, m);
    let at = best
        .iter()
        .position(|c| c.wavelengths == p.chosen.wavelengths)
        .unwrap_or(0);
    let lo = at.saturating_sub(AROUND);
    let hi = (at + AROUND + 1).min(best.len());
    for (i, c) in best.iter().enumerate().take(hi).skip(lo) {
        let _ = writeln!(
            s,
            "{} {:>3}  {:<16} {:>10} {:>10} {:>10} {:>10}  {}",
            if i == at { '*' } else { ' ' },
            c.wavelengths,
            c.name,
            fmt_de(c.mean_de00),
            fmt_de(c.max_de00),
            fmt_de(c.mean_de76),
            fmt_de(c.max_de76),
            if c.meets(p.budget, m) { "yes" } else { "no" }
        );
    }
    let _ = write!(s, "\nfewest wavelengths meeting the budget, by family:");
    for family in FAMILIES {
        let members: Vec<Candidate> = p
            .candidates
            .iter()
            .filter(|c| c.name.starts_with(family))
            .cloned()
            .collect();
        let _ = match plan::choose(&members, p.budget, m) {
            Ok(c) => write!(
                s,
                " {family}: {} ({}, {});",
                c.name,
                c.wavelengths,
                fmt_de(c.error(m))
            ),
            Err(_) => write!(s, " {family}: none;"),
        };
    }
    s.pop();
    s.push('\n');
    let nm: Vec<String> = wavelengths_nm.iter().map(|l| format!("{l:.1}")).collect();
    let _ = writeln!(
        s,
        "\nchosen: {} ({} wavelengths: {} nm), {m} ΔE00 {}",
        p.chosen.name,
        p.chosen.wavelengths,
        nm.join(", "),
        fmt_de(p.chosen.error(m))
    );
    match &p.runner_up_with_fewer {
        Some(r) => {
            let _ = writeln!(
                s,
                "best with fewer wavelengths: {} ({} wavelengths), {m} ΔE00 {} > {}",
                r.name,
                r.wavelengths,
                fmt_de(r.error(m)),
                p.budget
            );
        }
        None => {
            let _ = writeln!(s, "no set has fewer wavelengths");
        }
    }
    s
}
