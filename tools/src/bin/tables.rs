//! Prints the baked tables beside the paper's printed values: Eq. 9, Eq. 10, Table 1a (orders
//! 1-8) with differences, Table 1b (orders 9-16, lost in the transcription) and Table 2's sets;
//! then the AC1C2 matrices, eigenvalues and rules of the other observers (CIE 1964 10°, CIE 2015
//! 2° and 10°), derived here.
//!
//! With `--rust`, `--wgsl` or `--glsl` it prints instead what the build bakes for a scene: the
//! `tables.rs` or the shader snippet the runtime's build script writes, byte for byte, for the
//! scene named by `SPECTRAL_QUADRATURE_SCENE` (a path relative to the runtime crate's root, or
//! absolute, as the build script reads it; the default scene without it). With `--c-header` it
//! prints the C header the build writes (`tables::c::HEADER`), for the scene of `--scene <file>`
//! (relative to the working directory) or else of `SPECTRAL_QUADRATURE_SCENE`, so that a C
//! project needs Rust only to make the file (docs/c-and-cpp.md). `--scene` applies to the other
//! printed forms too.
//!
//! ```text
//! cargo run --release -p spectral-quadrature-tools --bin tables          # side by side
//! cargo run --release -p spectral-quadrature-tools --bin tables -- --csv # every rule as CSV
//! cargo run --release -p spectral-quadrature-tools --bin tables -- --shared-cache > data/shared_nodes.csv
//! cargo run --release -p spectral-quadrature-tools --bin tables -- --upsampling-cache > data/upsampling_codes.csv
//! cargo run --release -p spectral-quadrature-tools --bin tables -- --report-cache > tools/data/report_nodes.csv
//! SPECTRAL_QUADRATURE_SCENE=examples/scenes/minimal.toml \
//!   cargo run -p spectral-quadrature-tools --bin tables -- --rust         # what the scene bakes
//! cargo run --release -p spectral-quadrature-tools --bin tables -- --c-header \
//!   --scene examples/scenes/sensor.toml > spectral_quadrature.h           # the C header
//! ```

use spectral_quadrature_spectra::DataError;
use spectral_quadrature_tools as tools;

use clap::Parser;
use spectral_quadrature::{tables, Channel, GaussRule, RuleStatus, WavelengthSet};
use tools::csv_table::Table;
use tools::paper::{self, Entry};

/// Prints the crate's derived tables beside the paper's.
#[derive(Parser)]
#[command(version)]
struct Args {
    /// Print every rule as CSV: observer,channel,order,status,index,wavelength_nm,weight
    #[arg(long)]
    csv: bool,
    /// Run the node search of every cached shared set and print the cache file
    /// (data/shared_nodes.csv), which the build reuses instead of searching
    #[arg(long, conflicts_with = "csv")]
    shared_cache: bool,
    /// Fit every upsampling of the default scene afresh and print the cache file
    /// (data/upsampling_codes.csv), which the build reuses instead of fitting
    #[arg(long, conflicts_with_all = ["csv", "shared_cache"])]
    upsampling_cache: bool,
    /// Run every node search of the report's default run afresh and print the report's node
    /// cache (tools/data/report_nodes.csv), which the report reuses instead of searching
    #[arg(long, conflicts_with_all = ["csv", "shared_cache", "upsampling_cache"])]
    report_cache: bool,
    /// Print the tables.rs the build bakes for the scene named by SPECTRAL_QUADRATURE_SCENE
    /// (relative to the runtime crate's root, or absolute), or the default scene
    #[arg(long, group = "baked", conflicts_with_all = ["csv", "shared_cache", "upsampling_cache", "report_cache"])]
    rust: bool,
    /// Print the WGSL snippet the build bakes for that scene
    #[arg(long, group = "baked", conflicts_with_all = ["csv", "shared_cache", "upsampling_cache", "report_cache"])]
    wgsl: bool,
    /// Print the GLSL snippet the build bakes for that scene
    #[arg(long, group = "baked", conflicts_with_all = ["csv", "shared_cache", "upsampling_cache", "report_cache"])]
    glsl: bool,
    /// Print the C header (C99 and C++11) the build bakes for that scene
    #[arg(long, group = "baked", conflicts_with_all = ["csv", "shared_cache", "upsampling_cache"])]
    c_header: bool,
    /// The scene file for --rust, --wgsl, --glsl and --c-header, relative to the working
    /// directory (instead of SPECTRAL_QUADRATURE_SCENE)
    #[arg(long, value_name = "FILE", requires = "baked")]
    scene: Option<std::path::PathBuf>,
}

fn main() {
    let args = Args::parse();
    if args.rust || args.wgsl || args.glsl || args.c_header {
        if let Err(e) = print_baked(&args) {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    } else if args.shared_cache {
        if let Err(e) = print_shared_cache() {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    } else if args.report_cache {
        if let Err(e) = print_report_cache() {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    } else if args.upsampling_cache {
        if let Err(e) = print_upsampling_cache() {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    } else if args.csv {
        if let Err(e) = print_csv() {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    } else {
        print_side_by_side();
    }
}

/// Prints what the runtime's build script writes for the scene of `SPECTRAL_QUADRATURE_SCENE`:
/// the same call ([`spectral_quadrature_generator::generate`]) on the same crate directory, so the same bytes.
fn print_baked(args: &Args) -> Result<(), spectral_quadrature_generator::Error> {
    let crate_dir = std::fs::canonicalize(tools::CRATE_DIR).map_err(|e| {
        spectral_quadrature_generator::Error::Data(DataError {
            file: tools::CRATE_DIR.into(),
            line: 0,
            message: format!("cannot find the runtime crate: {e}"),
        })
    })?;
    let scene = match &args.scene {
        // Relative to the working directory, as a command line's paths are: absolute, the
        // generator takes it as it is.
        Some(path) => Some(
            std::path::absolute(path)
                .map_err(|e| {
                    spectral_quadrature_generator::Error::Data(DataError {
                        file: path.display().to_string(),
                        line: 0,
                        message: format!("cannot resolve the scene's path: {e}"),
                    })
                })?
                .into_os_string(),
        ),
        None => std::env::var_os(spectral_quadrature_generator::SCENE_ENV),
    };
    let out = spectral_quadrature_generator::generate(&crate_dir, scene.as_deref())?;
    let text = if args.rust {
        out.tables_rs
    } else if args.wgsl {
        out.wgsl
    } else if args.c_header {
        out.c_header
    } else {
        out.glsl
    };
    // A reader that stops early (`| head`) is not an error.
    use std::io::Write as _;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            eprintln!("error: cannot write to stdout: {e}");
            std::process::exit(2);
        }
        _ => Ok(()),
    }
}

/// The other observers, derived here in f64 with their default settings.
fn other_observers() -> Vec<spectral_quadrature_generator::Derivation> {
    spectral_quadrature_generator::ObserverId::ALL
        .into_iter()
        .filter(|id| id.name() != tables::OBSERVER)
        .map(|id| {
            spectral_quadrature_generator::Settings::for_observer(id, tools::DATA_DIR)
                .and_then(|s| spectral_quadrature_generator::derive(&s))
                .unwrap_or_else(|e| panic!("deriving {}: {e}", id.name()))
        })
        .collect()
}

/// Searches every set of the node cache afresh and prints the cache file.
fn print_shared_cache() -> Result<(), spectral_quadrature_generator::Error> {
    let d = spectral_quadrature_generator::derive(&tools::settings())?;
    let text = spectral_quadrature_generator::shared::cache_file(&d, |name| {
        eprintln!("searching {name}")
    })?;
    print!("{text}");
    Ok(())
}

/// Runs every node search of the report's default run afresh and prints its node cache.
fn print_report_cache() -> Result<(), spectral_quadrature_generator::Error> {
    let d = spectral_quadrature_generator::derive(&tools::settings())?;
    let text = tools::node_cache::report_cache_file(&d, |what| eprintln!("searching {what}"))?;
    print!("{text}");
    Ok(())
}

/// Fits every upsampling of the default scene afresh and prints the cache file.
fn print_upsampling_cache() -> Result<(), spectral_quadrature_generator::Error> {
    let settings = tools::settings();
    let d = spectral_quadrature_generator::derive(&settings)?;
    let scene = spectral_quadrature_generator::scene::Scene::default_scene(&settings.data_dir);
    let resolved = scene.resolve_fitting(&d)?;
    print!("{}", resolved.upsampling_cache_file(&d)?);
    Ok(())
}

/// Every rule as CSV on standard output: the baked observer's (the crate's f32 consts), then
/// the other observers' (derived in f64).
fn print_csv() -> Result<(), tools::Error> {
    let mut t = Table::new("observer,channel,order,status,index,wavelength_nm,weight");
    for rules in tables::RULES {
        for rule in rules {
            let head = [
                tables::OBSERVER.to_string(),
                rule.channel().name().to_string(),
                rule.order().to_string(),
                rule.status().name().to_string(),
            ];
            if rule.status() == RuleStatus::Defined {
                for (i, (l, w)) in rule.wavelengths_nm().iter().zip(rule.weights()).enumerate() {
                    t.row(head.iter().cloned().chain([
                        i.to_string(),
                        l.to_string(),
                        w.to_string(),
                    ]));
                }
            } else {
                t.row(
                    head.iter()
                        .cloned()
                        .chain([String::new(), String::new(), String::new()]),
                );
            }
        }
    }
    for d in other_observers() {
        for (c, rules) in d.rules.iter().enumerate() {
            for rule in rules {
                let head = [
                    d.settings.observer.name().to_string(),
                    Channel::ALL[c].name().to_string(),
                    rule.order.to_string(),
                    rule.status.as_str().to_string(),
                ];
                if rule.is_defined() {
                    for (i, (l, w)) in rule.nodes_nm.iter().zip(&rule.weights).enumerate() {
                        t.row(head.iter().cloned().chain([
                            i.to_string(),
                            l.to_string(),
                            w.to_string(),
                        ]));
                    }
                } else {
                    t.row(head.iter().cloned().chain([
                        String::new(),
                        String::new(),
                        String::new(),
                    ]));
                }
            }
        }
    }
    t.print()
}

fn print_other_observers() {
    println!();
    println!("Other observers, derived with their default settings (cone matrices: see ObserverId::cone_matrix)");
    for d in other_observers() {
        let s = &d.settings;
        let e = d.opponent.eigenvalues;
        println!();
        println!(
            "  {} ({}-{} nm, every {} nm)",
            s.observer.name(),
            s.range_nm[0],
            s.range_nm[1],
            s.step_nm
        );
        for (r, name) in ["A ", "C1", "C2"].iter().enumerate() {
            let m = d.opponent.xyz_to_ac1c2[r];
            println!("    {name}  {:8.4} {:8.4} {:8.4}", m[0], m[1], m[2]);
        }
        println!(
            "    eigenvalues {:.4} : {:.4} : {:.6} (A/C1 {:.1}, C1/C2 {:.1})",
            e[0],
            e[1],
            e[2],
            e[0] / e[1],
            e[1] / e[2]
        );
        for (c, rules) in d.rules.iter().enumerate() {
            let cells: Vec<String> = rules
                .iter()
                .take(8)
                .map(|r| {
                    if r.is_defined() {
                        r.nodes_nm
                            .iter()
                            .map(|l| format!("{l:.1}"))
                            .collect::<Vec<_>>()
                            .join(" ")
                    } else {
                        format!("({})", r.status.as_str())
                    }
                })
                .collect();
            println!("    {} orders 1-8:", Channel::ALL[c].name());
            for (n, cell) in cells.iter().enumerate() {
                println!("      {:>2}  {cell}", n + 1);
            }
        }
    }
}

/// Each channel's total mass ∫ w dλ (weights for dλ in nm): the sum of any defined rule's
/// weights; the lowest defined order's is used.
fn total_mass(c: usize) -> f32 {
    tables::RULES[c]
        .iter()
        .find(|r| r.status() == RuleStatus::Defined)
        .map_or(f32::NAN, |r| r.weights().iter().sum())
}

fn suspect(c: usize, order: usize, i: usize, entry: Entry) -> Option<&'static paper::Suspect> {
    paper::TABLE_1A_SUSPECTS
        .iter()
        .find(|s| s.channel == c && s.order == order && s.index == i && s.entry == entry)
}

fn print_side_by_side() {
    println!("spectral-quadrature tables: {}", tables::SETTINGS);
    for (file, sha) in tables::INPUTS {
        println!("  input {file} sha256 {sha}");
    }
    println!();
    println!("Eq. 9  XYZ -> AC1C2 (rows A, C1, C2): derived | printed | difference");
    for (r, name) in ["A ", "C1", "C2"].iter().enumerate() {
        let ours = tables::XYZ_TO_AC1C2[r];
        let printed = paper::EQ9_XYZ_TO_AC1C2[r];
        let cells: Vec<String> = (0..3)
            .map(|c| {
                format!(
                    "{:8.4} {:8.4} {:+8.4}",
                    ours[c],
                    printed[c],
                    f64::from(ours[c]) - printed[c]
                )
            })
            .collect();
        println!("  {name}  {}", cells.join("   "));
    }
    println!();
    let e = tables::EIGENVALUES.map(f64::from);
    let p = paper::EQ10_EIGENVALUE_RATIO;
    println!(
        "Eq. 10  eigenvalues: {:.4} : {:.4} : {:.6}  (printed {} : {} : {})",
        e[0], e[1], e[2], p[0], p[1], p[2]
    );
    for (what, ours, printed) in [
        ("A/C1 ", e[0] / e[1], p[0] / p[1]),
        ("C1/C2", e[1] / e[2], p[1] / p[2]),
    ] {
        println!(
            "  {what} {ours:10.3}  printed {printed:10.3}  difference {:+.2} %",
            100.0 * (ours / printed - 1.0)
        );
    }
    println!();
    println!("Table 1a (orders 1-8). Weights on the paper's scale: ours x (printed total mass / our total mass).");
    println!(
        "  [s] marks an entry printed wrongly in the transcription; the reading used is shown."
    );
    for (c, channel) in Channel::ALL.iter().enumerate() {
        let scale = paper::TABLE_1A_TOTAL_MASS[c] / f64::from(total_mass(c));
        println!();
        println!("  {} ({:.5} per unit weight)", channel.name(), scale);
        println!("  order    node   printed     diff |    weight   printed      diff");
        for order in 1..=8 {
            let rule = &tables::RULES[c][order - 1];
            let printed = paper::TABLE_1A[c][order - 1];
            match (rule.status(), printed) {
                (RuleStatus::Defined, Some(p)) => {
                    for i in 0..order {
                        let (node, w) = (
                            f64::from(rule.wavelengths_nm()[i]),
                            f64::from(rule.weights()[i]) * scale,
                        );
                        let (mut pn, mut pw) = (p.wavelengths_nm[i], p.weights[i]);
                        let mut mark = "   ";
                        if let Some(s) = suspect(c, order, i, Entry::Node) {
                            pn = s.reading;
                            mark = "[s]";
                        }
                        if let Some(s) = suspect(c, order, i, Entry::Weight) {
                            pw = s.reading;
                            mark = "[s]";
                        }
                        println!(
                            "  {:>5} {:7.2} {:7.1} {:+8.2} | {:9.5} {:9.5} {:+9.5} {mark}",
                            if i == 0 {
                                order.to_string()
                            } else {
                                String::new()
                            },
                            node,
                            pn,
                            node - pn,
                            w,
                            pw,
                            w - pw
                        );
                    }
                }
                (status, None) if status != RuleStatus::Defined => {
                    println!(
                        "  {order:>5}  undefined ({}), printed undefined",
                        status.name()
                    )
                }
                (status, printed) => println!(
                    "  {order:>5}  MISMATCH: derived {}, printed {}",
                    status.name(),
                    if printed.is_some() {
                        "defined"
                    } else {
                        "undefined"
                    }
                ),
            }
        }
    }
    println!();
    for s in paper::TABLE_1A_SUSPECTS {
        println!(
            "  [s] {} order {} {:?} {}: printed {}, read {} ({})",
            Channel::ALL[s.channel].name(),
            s.order,
            s.entry,
            s.index,
            s.printed,
            s.reading,
            s.evidence
        );
    }
    println!(
        "  C2 order 7's printed weights sum to {} instead of {}: one entry is misprinted, and which is ambiguous.",
        paper::TABLE_1A_C2_7_SUM,
        paper::TABLE_1A_TOTAL_MASS[2]
    );
    println!();
    println!(
        "Table 1b (orders 9-{}), weights for dλ in nm:",
        tables::MAX_ORDER
    );
    for (c, channel) in Channel::ALL.iter().enumerate() {
        println!();
        println!("  {}", channel.name());
        for rule in &tables::RULES[c][8..] {
            print_rule(rule);
        }
    }
    println!();
    print_set("Table 2, row 1", &tables::TABLE2_ROW1);
    print_set("Table 2, row 2", &tables::TABLE2_ROW2);
    let a: Vec<f64> = tables::TABLE2_ROW2.weights()[0]
        .iter()
        .filter(|w| **w != 0.0)
        .map(|w| f64::from(*w) * paper::TABLE_1A_TOTAL_MASS[0] / f64::from(total_mass(0)))
        .collect();
    println!(
        "  row 2 A weights on the paper's scale: {:.5?}  printed {:?}",
        a,
        paper::TABLE2_ROW2_A.weights
    );
    print_other_observers();
}

fn print_rule(rule: &GaussRule) {
    if rule.status() != RuleStatus::Defined {
        println!(
            "  {:>5}  undefined ({})",
            rule.order(),
            rule.status().name()
        );
        return;
    }
    let nodes: Vec<String> = rule
        .wavelengths_nm()
        .iter()
        .map(|l| format!("{l:.1}"))
        .collect();
    let weights: Vec<String> = rule.weights().iter().map(|w| format!("{w:.5}")).collect();
    println!("  {:>5}  nm: {}", rule.order(), nodes.join(" "));
    println!("         w:  {}", weights.join(" "));
}

fn print_set<const N: usize>(name: &str, set: &WavelengthSet<N>) {
    println!("{name}: {N} wavelengths");
    println!(
        "  nm  {}",
        set.wavelengths_nm().map(|l| format!("{l:9.1}")).join("")
    );
    for (c, channel) in Channel::ALL.iter().enumerate() {
        println!(
            "  {:<3} {}",
            channel.name(),
            set.weights()[c].map(|w| format!("{w:9.4}")).join("")
        );
    }
}
