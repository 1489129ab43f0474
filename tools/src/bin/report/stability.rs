//! Section 6 of the report: numerical stability. Where the method and its numbers hold, where
//! they break, and how close each classification is to flipping.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use plotters::prelude::*;
use spectral_quadrature::tables;

use crate::tools::csv_table::Table;
use crate::tools::sensitivity::{shifts, standard_variants};
use crate::tools::stability;
use crate::Error;
use spectral_quadrature_generator::{derive, Settings, Status};

const CHANNELS: [&str; 3] = ["A", "C1", "C2"];

/// The sensitivity table: node shifts against the baseline for each variant, orders 1-8.
fn sensitivity(o: &mut String) -> Result<Table, Error> {
    let rows = shifts(&crate::tools::settings(), &standard_variants(), 8)?;
    writeln!(o, "   6c. sensitivity: how far each rule moves (largest node shift in nm; '-' where either is undefined)").ok();
    writeln!(
        o,
        "   {:<14} {:<3} {}",
        "variant",
        "ch",
        (1..=8).map(|n| format!("{n:>8}")).collect::<String>()
    )
    .ok();
    let mut csv = Table::new(
        "variant,channel,order,baseline_status,variant_status,max_node_shift_nm,max_weight_change",
    );
    for v in standard_variants() {
        for (c, ch) in CHANNELS.iter().enumerate() {
            let cells: String = rows
                .iter()
                .filter(|r| r.variant == v.name && r.channel == c)
                .map(|r| match r.max_node_shift_nm {
                    Some(s) => format!("{s:>8.2}"),
                    None if r.baseline != r.changed => format!(
                        "{:>8}",
                        format!(
                            "{}>{}",
                            short(r.baseline.as_str()),
                            short(r.changed.as_str())
                        )
                    ),
                    None => format!("{:>8}", "-"),
                })
                .collect();
            writeln!(o, "   {:<14} {:<3} {cells}", v.name, ch).ok();
        }
    }
    for r in &rows {
        csv.row([
            r.variant.to_string(),
            CHANNELS[r.channel].to_string(),
            r.order.to_string(),
            r.baseline.as_str().to_string(),
            r.changed.as_str().to_string(),
            r.max_node_shift_nm
                .map_or(String::new(), |v| format!("{v:.4}")),
            r.max_weight_change
                .map_or(String::new(), |v| format!("{v:.3e}")),
        ]);
    }
    writeln!(
        o,
        "   (d>o: defined in the baseline, outside in the variant; c = complex)\n"
    )
    .ok();
    Ok(csv)
}

fn short(status: &str) -> &'static str {
    match status {
        "defined" => "d",
        "outside" => "o",
        "complex" => "c",
        _ => "v",
    }
}

/// 6a: every order's margin from being undefined (orders 1-16).
fn margins(o: &mut String, out: &Path, files: &mut Vec<PathBuf>) -> Result<(), Error> {
    let d = derive(&crate::tools::settings())?;
    let m = stability::margins(&d);
    writeln!(o, "   6a. margins: how far each order is from changing class (clear: norm ratio > 1e3 x threshold,").ok();
    writeln!(o, "       |Im| > 1 nm for complex nodes, deciding node > 1 nm from 380/770 nm, nodes > 1 nm apart)").ok();
    for line in stability::margin_table(&m).lines() {
        writeln!(o, "   {line}").ok();
    }
    let unclear: Vec<String> = (0..3)
        .flat_map(|c| {
            m[c].iter()
                .filter(|r| !r.clear)
                .map(move |r| format!("{} {} ({})", CHANNELS[c], r.order, r.unclear))
        })
        .collect();
    writeln!(
        o,
        "   not clear: {}\n",
        if unclear.is_empty() {
            "none".to_string()
        } else {
            unclear.join("; ")
        }
    )
    .ok();
    let mut csv = Table::new("channel,order,status,norm_ratio,norm_margin,max_imaginary_nm,range_margin_nm,min_gap_nm,clear");
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.6e}"));
    for (c, rows) in m.iter().enumerate() {
        for r in rows {
            csv.row([
                CHANNELS[c].to_string(),
                r.order.to_string(),
                r.status.as_str().to_string(),
                format!("{:.6e}", r.norm_ratio),
                format!("{:.6e}", r.norm_margin),
                format!("{:.6e}", r.max_imaginary_nm),
                opt(r.range_margin_nm),
                opt(r.min_gap_nm),
                r.clear.to_string(),
            ]);
        }
    }
    files.push(csv.write(out, "margins.csv")?);
    // Plot: the norm margin of each order (log), one line per channel.
    let path = out.join("margins.svg");
    {
        let root = SVGBackend::new(&path, (720, 460)).into_drawing_area();
        root.fill(&WHITE).map_err(crate::plot::plot_err)?;
        let ymax = m
            .iter()
            .flatten()
            .map(|r| r.norm_margin)
            .fold(10.0, f64::max);
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "Margin of each order from a vanishing norm (ratio / threshold)",
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.5f64..16.5, (0.5f64..ymax * 3.0).log_scale())
            .map_err(crate::plot::plot_err)?;
        chart
            .configure_mesh()
            .x_desc("order")
            .x_label_formatter(&crate::plot::whole)
            .y_desc("norm margin (log; 1 = undefined)")
            .y_label_formatter(&crate::plot::power_of_ten)
            .draw()
            .map_err(crate::plot::plot_err)?;
        for (c, colour) in [(0usize, BLACK), (1, RED), (2, BLUE)] {
            let pts: Vec<(f64, f64)> = m[c]
                .iter()
                .map(|r| (r.order as f64, r.norm_margin.max(0.6)))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                .map_err(crate::plot::plot_err)?
                .label(CHANNELS[c])
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            // Hollow markers for orders that are not defined.
            chart
                .draw_series(m[c].iter().map(|r| {
                    let p = (r.order as f64, r.norm_margin.max(0.6));
                    if r.status == Status::Defined {
                        Circle::new(p, 4, colour.filled())
                    } else {
                        Circle::new(p, 4, colour.stroke_width(1))
                    }
                }))
                .map_err(crate::plot::plot_err)?;
        }
        chart
            .draw_series(LineSeries::new(
                vec![(0.5, 1.0), (16.5, 1.0)],
                BLACK.mix(0.4),
            ))
            .map_err(crate::plot::plot_err)?;
        chart
            .configure_series_labels()
            .border_style(BLACK)
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(crate::plot::plot_err)?;
        root.present().map_err(crate::plot::plot_err)?;
    }
    files.push(path);
    Ok(())
}

/// 6b: where the unstable alternatives lose accuracy (orders 1-30).
fn breakdown(o: &mut String, out: &Path, files: &mut Vec<PathBuf>) -> Result<(), Error> {
    let d = derive(&Settings {
        max_order: 30,
        ..crate::tools::settings()
    })?;
    let cmp = stability::compare(&d, 30, stability::BREAKDOWN_TOLERANCE);
    writeln!(o, "   6b. breakdown: the first order at which each way of computing the rules fails, orders 1-30").ok();
    for t in [
        stability::BREAKDOWN_TOLERANCE,
        stability::ACCURACY_TOLERANCE,
    ] {
        for line in cmp.breakdown_table(&t).lines() {
            writeln!(o, "   {line}").ok();
        }
    }
    writeln!(o, "   (chosen: Stieltjes in the scaled variable, balanced Jacobi matrix, Golub-Welsch/Christoffel weights)\n").ok();
    let mut csv = Table::new("method,channel,order,reference_status,method_status,node_error_nm,weight_error,moment_residual");
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.3e}"));
    for mc in &cmp.methods {
        for e in &mc.errors {
            csv.row([
                mc.method.name().to_string(),
                CHANNELS[mc.channel].to_string(),
                e.order.to_string(),
                e.reference.as_str().to_string(),
                e.alternative.as_str().to_string(),
                opt(e.node_error_nm),
                opt(e.weight_error),
                opt(e.alternative_residual),
            ]);
        }
    }
    files.push(csv.write(out, "breakdown.csv")?);
    // Plot: each method's moment residual (how far its rule is from integrating x^k exactly,
    // k < 2n), worst channel, against the order; it applies to every method alike.
    let path = out.join("breakdown.svg");
    {
        // The legend below the chart: inside, it covered the lines of the higher orders.
        const COLUMNS: usize = 3;
        let legend_h = crate::plot::legend_height(stability::Method::ALL.len(), COLUMNS);
        let root = SVGBackend::new(&path, (760, 480 + legend_h)).into_drawing_area();
        root.fill(&WHITE).map_err(crate::plot::plot_err)?;
        let (top, below) = root.split_vertically(480);
        const FLOOR: f64 = 1e-13;
        let mut chart = ChartBuilder::on(&top)
            .caption(
                "Moment residual of each method's rules (worst channel)",
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.5f64..30.5, (FLOOR..1e3).log_scale())
            .map_err(crate::plot::plot_err)?;
        chart
            .configure_mesh()
            .x_desc("order")
            .x_label_formatter(&crate::plot::whole)
            .y_desc("moment residual (log; failed rules drawn at 100)")
            .y_label_formatter(&crate::plot::power_of_ten)
            .draw()
            .map_err(crate::plot::plot_err)?;
        let colours = [BLACK, RED, MAGENTA, GREEN, BLUE, CYAN];
        for (method, colour) in stability::Method::ALL.iter().zip(colours) {
            let pts: Vec<(f64, f64)> = (1..=30)
                .filter_map(|n| {
                    let worst = (0..3)
                        .filter_map(|c| cmp.get(*method, c).and_then(|m| m.errors.get(n - 1)))
                        .map(|e| {
                            if e.reference != e.alternative || !e.finite {
                                100.0
                            } else {
                                e.alternative_residual.unwrap_or(0.0)
                            }
                        })
                        .fold(f64::NAN, f64::max);
                    worst.is_finite().then_some((n as f64, worst.max(FLOOR)))
                })
                .collect();
            chart
                .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
                .map_err(crate::plot::plot_err)?;
        }
        let entries: Vec<(String, RGBColor)> = stability::Method::ALL
            .iter()
            .zip(colours)
            .map(|(m, c)| (m.name().to_string(), c))
            .collect();
        crate::plot::legend(&below, &entries, COLUMNS)?;
        root.present().map_err(crate::plot::plot_err)?;
    }
    files.push(path);
    Ok(())
}

/// 6d: spiky spectra and the two pre-filters.
fn spiky(o: &mut String, out: &Path, files: &mut Vec<PathBuf>) -> Result<(), Error> {
    use crate::tools::prefilter::{self, Method};
    let d = derive(&crate::tools::settings())?;
    let sets = prefilter::default_sets(&d)?;
    let sum = prefilter::summary(&d, &sets)?;
    let methods = [
        Method::Plain,
        Method::BandAveraged,
        Method::ChannelBandAveraged,
        Method::LinesExact(prefilter::LineDetection::DEFAULT),
        Method::LinesExactBandAveraged(prefilter::LineDetection::DEFAULT),
        Method::LampAdapted,
    ];
    writeln!(
        o,
        "   6d. spiky spectra: mean ΔE00 of {} surfaces under F1-F12, by how the lamp is sampled",
        sum.surfaces
    )
    .ok();
    writeln!(o, "       plain: at the nodes; band: averaged over each node's band (all nodes); channel_band: each channel's own").ok();
    writeln!(o, "       bands; lines: lamp lines integrated exactly (+1 wavelength each), the rest at the nodes; lines_band: both").ok();
    writeln!(
        o,
        "   {:<16} {:>4} {}",
        "set",
        "N",
        methods
            .iter()
            .map(|m| format!("{:>13}", m.as_str()))
            .collect::<String>()
    )
    .ok();
    for s in &sum.sets {
        writeln!(
            o,
            "   {:<16} {:>4} {}",
            s.name,
            s.wavelengths,
            methods
                .iter()
                .map(|m| format!("{:>13.3}", s.f_series.get(*m).mean_de00))
                .collect::<String>()
        )
        .ok();
    }
    let lines: Vec<String> = sum
        .f_lamps
        .iter()
        .map(|l| {
            format!(
                "{} {}",
                l.name,
                l.lines
                    .iter()
                    .map(|x| format!("{:.0}", x.nm))
                    .collect::<Vec<_>>()
                    .join("/")
            )
        })
        .collect();
    writeln!(o, "   lines found: {}", lines.join(", ")).ok();
    writeln!(o, "\n   LED lamps (B1-B5, BH1, RGB1, V1, V2), monochromatic lines at every nm (seen directly) and narrow bands:").ok();
    writeln!(
        o,
        "   {:<16} {:>10} {:>10} {:>12} {:>12} {}",
        "set",
        "LED plain",
        "LED ch.band",
        "line median",
        "line ch.band",
        sum.band_widths_nm
            .iter()
            .map(|w| format!("{:>11}", format!("band {w:.0} nm")))
            .collect::<String>()
    )
    .ok();
    for s in &sum.sets {
        writeln!(
            o,
            "   {:<16} {:>10.3} {:>10.3} {:>12.3} {:>12.3} {}",
            s.name,
            s.leds.get(Method::Plain).mean_de00,
            s.leds.get(Method::ChannelBandAveraged).mean_de00,
            s.lines.get(Method::Plain).median_de00,
            s.lines.get(Method::ChannelBandAveraged).median_de00,
            s.bands
                .iter()
                .map(|b| format!("{:>11.3}", b.get(Method::Plain).mean_de00))
                .collect::<String>()
        )
        .ok();
    }
    writeln!(
        o,
        "   (a line between nodes is invisible to plain sampling: ΔE00 about 100 for most lines)\n"
    )
    .ok();
    let mut csv = Table::new(
        "set,distinct_wavelengths,group,method,mean_de00,median_de00,max_de00,mean_de76",
    );
    for s in &sum.sets {
        for (group, scores) in [
            ("f_series", &s.f_series),
            ("led", &s.leds),
            ("lines", &s.lines),
        ] {
            for m in Method::ALL {
                let sc = scores.get(m);
                csv.row([
                    s.name.clone(),
                    s.wavelengths.to_string(),
                    group.to_string(),
                    m.as_str().to_string(),
                    format!("{:.4}", sc.mean_de00),
                    format!("{:.4}", sc.median_de00),
                    format!("{:.4}", sc.max_de00),
                    format!("{:.4}", sc.mean_de76),
                ]);
            }
        }
    }
    files.push(csv.write(out, "spiky.csv")?);
    // Plot: mean ΔE00 on the F-series per set, one marker per method.
    let path = out.join("prefilter.svg");
    {
        let root = SVGBackend::new(&path, (820, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(crate::plot::plot_err)?;
        let ymax = sum
            .sets
            .iter()
            .map(|s| {
                s.f_series
                    .get(Method::BandAveraged)
                    .mean_de00
                    .max(s.f_series.get(Method::Plain).mean_de00)
            })
            .fold(1.0, f64::max);
        let n = sum.sets.len();
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "F-series: mean ΔE00 by pre-filter (each set left to right)",
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(70)
            .y_label_area_size(50)
            .build_cartesian_2d(-0.5f64..n as f64 - 0.5, (0.01f64..ymax * 2.0).log_scale())
            .map_err(crate::plot::plot_err)?;
        let names: Vec<String> = sum.sets.iter().map(|s| s.name.clone()).collect();
        chart
            .configure_mesh()
            .x_labels(n)
            .x_label_formatter(&|x| {
                let i = x.round();
                if (x - i).abs() < 1e-6 && i >= 0.0 {
                    names.get(i as usize).cloned().unwrap_or_default()
                } else {
                    String::new()
                }
            })
            .x_label_style(("sans-serif", 10))
            .y_desc("mean ΔE00 (log)")
            .y_label_formatter(&|v| format!("{v}"))
            .draw()
            .map_err(crate::plot::plot_err)?;
        let colours = [BLACK, MAGENTA, RED, BLUE, GREEN, CYAN];
        for (k, (m, colour)) in methods.iter().zip(colours).enumerate() {
            let dx = (k as f64 - 2.5) * 0.1;
            let pts: Vec<(f64, f64)> = sum
                .sets
                .iter()
                .enumerate()
                .map(|(i, s)| (i as f64 + dx, s.f_series.get(*m).mean_de00.max(0.011)))
                .collect();
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 4, colour.filled())))
                .map_err(crate::plot::plot_err)?
                .label(m.as_str())
                .legend(move |(x, y)| Circle::new((x, y), 4, colour.filled()));
        }
        chart
            .configure_series_labels()
            .border_style(BLACK)
            .background_style(WHITE.mix(0.8))
            .draw()
            .map_err(crate::plot::plot_err)?;
        root.present().map_err(crate::plot::plot_err)?;
    }
    files.push(path);
    Ok(())
}

/// 6e: the f32 runtime on extreme inputs (the same pool as tests/extremes.rs).
fn extremes(o: &mut String) -> Result<(), Error> {
    let d = derive(&crate::tools::settings())?;
    let w = &d.table2[1].weights;
    let pool = [
        0.0f32,
        -0.0,
        1.0,
        -1.0,
        f32::MAX,
        -f32::MAX,
        1e38,
        1e30,
        -1e20,
        1e-30,
        f32::MIN_POSITIVE,
        1e-40,
        -1e-45,
        123_456.79,
    ];
    let (mut worst, mut finite, mut overflow) = (0.0f64, 0usize, 0usize);
    for a in pool {
        for b in pool {
            for c in pool {
                for e in pool {
                    let s = [a, b, c, e];
                    let got = tables::TABLE2_ROW2.ac1c2(&s);
                    for ch in 0..3 {
                        let exact: f64 = (0..4).map(|i| w[ch][i] * f64::from(s[i])).sum();
                        let abs_sum: f64 = (0..4).map(|i| (w[ch][i] * f64::from(s[i])).abs()).sum();
                        if abs_sum * (1.0 + 5.0 * f64::from(f32::EPSILON)) < f64::from(f32::MAX) {
                            finite += 1;
                            let budget = spectral_quadrature::f32_budget(4, abs_sum);
                            if budget > 0.0 {
                                worst = worst.max((f64::from(got[ch]) - exact).abs() / budget);
                            }
                        } else {
                            overflow += 1;
                        }
                    }
                }
            }
        }
    }
    writeln!(o, "   6e. extreme f32 inputs (±MAX, subnormals, huge and tiny mixed), Table 2 row 2, {} channel values:", finite + overflow).ok();
    writeln!(o, "       {finite} within reach of f32: largest error / f32_budget = {worst:.3}; {overflow} may overflow (±Inf or NaN, as documented)").ok();
    Ok(())
}

/// Runs every part of the section; returns the text and the files written.
pub fn section(out: &Path) -> Result<(String, Vec<PathBuf>), Error> {
    let mut o = String::new();
    let mut files = Vec::new();
    writeln!(o, "6. Stability").ok();
    margins(&mut o, out, &mut files)?;
    breakdown(&mut o, out, &mut files)?;
    files.push(sensitivity(&mut o)?.write(out, "sensitivity.csv")?);
    spiky(&mut o, out, &mut files)?;
    extremes(&mut o)?;
    Ok((o, files))
}
