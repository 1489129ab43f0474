//! Section 5: every method at each wavelength budget, per light, judged on the ColorChecker (or
//! on the user's reflectances when given).
//! The shared sets were trained on the CIE test colour samples only.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use plotters::prelude::*;

use crate::plot::plot_err;
use crate::progress::Meter;
use crate::timing::time_set;
use crate::tools::budget::{self, Entry, LIGHTS, METHODS};
use crate::tools::csv_table::Table;
use crate::Error;
use spectral_quadrature_generator::{shared, Derivation};
use spectral_quadrature_spectra::{builtin_illuminant, surfaces_under_lights, Curve, EvalSet};

/// Text, and the files written (budget.csv, budget.svg). `shared_sizes`: the sizes of the
/// shared sets folded for each light (every budget, or fewer for `--quick`). `spaces` and `radiance`: the rule
/// combinations and the shared sets for radiances the report has built for sections 2-4.
/// `user`: the lights of `--illuminants`, with the shared sets folded for each and the
/// stimuli they are judged on (the user's reflectances, `surfaces_from`, under that light);
/// each gets a table after the built-in lights'. `surfaces`: the user's reflectances, which
/// replace the ColorChecker as what every table is judged on.
#[allow(clippy::too_many_arguments)]
pub fn section(
    d: &Derivation,
    spaces: &[(&'static str, Vec<EvalSet>); 3],
    radiance: &[EvalSet],
    user: &[crate::user::Folded],
    surfaces: Option<&[Curve]>,
    surfaces_from: &str,
    out: &Path,
    runs: usize,
    shared_sizes: &[usize],
) -> Result<(String, Vec<PathBuf>), Error> {
    let others = budget::other_sets(d, spaces);
    let folded = LIGHTS
        .iter()
        .map(|l| {
            let curve = builtin_illuminant(&d.settings.data_dir, l, d.settings.range_nm)?;
            budget::shared_sets_sized(d, Some(&curve), shared_sizes.iter().copied())
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let mut tables = Vec::new();
    // (heading, the light's name for the CSV)
    let mut names: Vec<(String, String)> = Vec::new();
    let meter = Meter::new("judging", LIGHTS.len() + user.len(), "lights");
    for (light, f) in LIGHTS.iter().zip(&folded) {
        tables.push(match surfaces {
            None => budget::compare(d, light, &others, radiance, f)?,
            Some(s) => {
                let l = builtin_illuminant(&d.settings.data_dir, light, d.settings.range_nm)?;
                let stimuli = surfaces_under_lights(s, std::slice::from_ref(&l));
                budget::compare_on(d, &l, &stimuli, &others, radiance, f)?
            }
        });
        names.push((light.to_string(), light.to_string()));
        meter.add(1);
    }
    for (light, f, stimuli) in user {
        tables.push(budget::compare_on(d, light, stimuli, &others, radiance, f)?);
        meter.add(1);
        names.push((
            format!("{} (yours; on {surfaces_from})", light.name),
            light.name.clone(),
        ));
    }
    let stimuli = budget::judge_stimuli(d, "C")?;
    // Run time depends only on N: time the folded shared set at each budget.
    let mut ns = Vec::new();
    for set in &folded[0] {
        ns.push((set.len(), time_set(set, &stimuli, runs)?));
    }

    let mut o = String::new();
    writeln!(
        o,
        "5. Shared sets at each wavelength budget: mean ΔE00 of each method's best set with N distinct wavelengths"
    )
    .ok();
    writeln!(
        o,
        "   judged on {}, white integrated by the same set; the KQ sets were trained on the",
        if surfaces.is_some() {
            surfaces_from
        } else {
            "the ColorChecker (Ohta)"
        }
    )
    .ok();
    writeln!(
        o,
        "   CIE test colour samples 1-14 only (Matérn 5/2, ℓ = {} nm, empirical weight {}, fitted by leave-one-out",
        shared::LENGTH_NM,
        shared::EMPIRICAL_WEIGHT
    )
    .ok();
    writeln!(
        o,
        "   likelihood on those samples). KQ folded: the light folded into the weights, samples are reflectances."
    )
    .ok();
    let mut csv =
        Table::new("light,n,method,set,wavelengths_nm,mean_de76,max_de76,mean_de00,max_de00");
    for ((light, csv_light), (table, intervals)) in names.iter().zip(&tables) {
        writeln!(o, "\n   under {light}:").ok();
        let mut header = format!("   {:>3}", "N");
        for m in METHODS {
            write!(header, " {m:>12}").ok();
        }
        writeln!(o, "{header} {:>10} {:>9}", "KQ ΔE*ab", "ns/pixel").ok();
        for (n, row) in table {
            let mut line = format!("   {n:>3}");
            for m in METHODS {
                let cell = row
                    .iter()
                    .find(|e| e.method == m)
                    .map_or("-".to_string(), |e| format!("{:.3}", e.errors.mean_de00()));
                write!(line, " {cell:>12}").ok();
            }
            let kq = row.iter().find(|e| e.method == "KQ folded");
            let best_other = row
                .iter()
                .filter(|e| e.method != "KQ folded")
                .min_by(|a, b| a.errors.mean_de00().total_cmp(&b.errors.mean_de00()));
            let t = ns.iter().find(|x| x.0 == *n).map_or(f64::NAN, |x| x.1);
            write!(
                line,
                " {:>10} {t:>9.1}",
                kq.map_or("-".into(), |e| format!("{:.3}", e.errors.mean_de76()))
            )
            .ok();
            if let (Some(k), Some(b)) = (kq, best_other) {
                if k.errors.mean_de00() >= b.errors.mean_de00() {
                    write!(line, "  (best: {})", b.set.name).ok();
                }
            }
            writeln!(o, "{line}").ok();
            for e in row {
                csv_row(&mut csv, csv_light, *n, e);
            }
        }
        for e in intervals {
            writeln!(
                o,
                "   {} ({} wavelengths, light folded): mean ΔE00 {:.3}, mean ΔE*ab {:.3}",
                e.method,
                e.set.len(),
                e.errors.mean_de00(),
                e.errors.mean_de76()
            )
            .ok();
            csv_row(&mut csv, csv_light, e.set.len(), e);
        }
    }
    let mut files = vec![csv.write(out, "budget.csv")?];
    files.push(plot(out, &tables)?);
    Ok((o, files))
}

fn csv_row(csv: &mut Table, light: &str, n: usize, e: &Entry) {
    let w: Vec<String> = e
        .set
        .wavelengths_nm
        .iter()
        .map(|l| format!("{l:.1}"))
        .collect();
    csv.row([
        light.to_string(),
        n.to_string(),
        e.method.to_string(),
        e.set.name.clone(),
        w.join(" "),
        format!("{:.4}", e.errors.mean_de76()),
        format!("{:.4}", e.errors.max_de76()),
        format!("{:.4}", e.errors.mean_de00()),
        format!("{:.4}", e.errors.max_de00()),
    ]);
}

use crate::tools::budget::Comparison;

fn plot(out: &Path, tables: &[Comparison]) -> Result<PathBuf, Error> {
    const FLOOR: f64 = 0.01;
    let path = out.join("budget.svg");
    // One legend for the four panels, below them: inside each it covered the lines.
    const COLUMNS: usize = 4;
    let legend_h = crate::plot::legend_height(METHODS.len(), COLUMNS);
    let root = SVGBackend::new(&path, (1100, 800 + legend_h)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let (top, below) = root.split_vertically(800);
    let panels = top.split_evenly((2, 2));
    let colours = [
        RGBColor(230, 120, 120),
        RGBColor(120, 120, 230),
        RGBColor(120, 190, 120),
        RGBColor(60, 60, 60),
        RGBColor(200, 140, 40),
        RGBColor(150, 60, 170),
        RGBColor(220, 0, 0),
    ];
    for ((panel, light), (table, _)) in panels.iter().zip(LIGHTS).zip(tables) {
        let emax = table
            .iter()
            .flat_map(|r| r.1.iter().map(|e| e.errors.mean_de00()))
            .fold(FLOOR, f64::max);
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!("under {light}: mean ΔE00 by distinct wavelengths"),
                ("sans-serif", 16),
            )
            .margin(8)
            .x_label_area_size(32)
            .y_label_area_size(50)
            .build_cartesian_2d(2.5f64..16.5, (FLOOR..emax * 1.5).log_scale())
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc("N")
            .x_label_formatter(&crate::plot::whole)
            .y_desc("mean ΔE00 (log)")
            .draw()
            .map_err(plot_err)?;
        for (m, colour) in METHODS.iter().zip(colours) {
            let pts: Vec<(f64, f64)> = table
                .iter()
                .filter_map(|(n, row)| {
                    row.iter()
                        .find(|e| e.method == *m)
                        .map(|e| (*n as f64, e.errors.mean_de00().max(FLOOR)))
                })
                .collect();
            let width = if *m == "KQ folded" { 3 } else { 1 };
            chart
                .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(width)))
                .map_err(plot_err)?;
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 2, colour.filled())))
                .map_err(plot_err)?;
        }
    }
    let entries: Vec<(String, RGBColor)> = METHODS
        .iter()
        .zip(colours)
        .map(|(m, c)| (m.to_string(), c))
        .collect();
    crate::plot::legend(&below, &entries, COLUMNS)?;
    root.present().map_err(plot_err)?;
    drop(panels);
    drop(top);
    drop(below);
    drop(root);
    Ok(path)
}
