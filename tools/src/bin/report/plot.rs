//! The report's plots (SVG, with plotters): the helpers every section's plots share (errors,
//! tick labels, a legend outside the plotting area), and the plots of sections 2-4.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use spectral_quadrature::{tables, GamutMapping};

use crate::error_vs_time::Row;
use crate::fig6_fig7::{Fig6, Fig7, K};
use crate::Error;
use spectral_quadrature_spectra::{EvalSet, Stimulus};

/// A plotting library's error, as the report's.
pub fn plot_err<E: std::fmt::Debug>(e: E) -> Error {
    Error::Plot(format!("{e:?}"))
}

/// The tick label of an axis of whole numbers (wavelengths, orders, samples per pixel): `4`,
/// not `4.0`; a tick between whole numbers gets no label.
pub fn whole(v: &f64) -> String {
    let r = v.round();
    if (v - r).abs() < 1e-9 {
        format!("{r:.0}")
    } else {
        String::new()
    }
}

/// The tick label of a log axis spanning many decades: `1e6`, not `1000000.0`.
pub fn power_of_ten(v: &f64) -> String {
    format!("{v:.0e}")
}

/// The height of a [`legend`] area with `entries` entries in `columns` columns.
pub fn legend_height(entries: usize, columns: usize) -> u32 {
    (entries.div_ceil(columns.max(1)) as u32) * 22 + 12
}

/// A legend drawn in an area of its own (below or beside the chart, never over its data):
/// for each entry a short line in its colour and its label, in `columns` columns.
pub fn legend(
    area: &DrawingArea<SVGBackend, Shift>,
    entries: &[(String, RGBColor)],
    columns: usize,
) -> Result<(), Error> {
    let width = area.dim_in_pixel().0 as i32;
    let column_w = (width - 20) / columns.max(1) as i32;
    for (k, (label, colour)) in entries.iter().enumerate() {
        let x = 20 + (k % columns.max(1)) as i32 * column_w;
        let y = 14 + (k / columns.max(1)) as i32 * 22;
        area.draw(&PathElement::new(
            vec![(x, y), (x + 28, y)],
            colour.stroke_width(2),
        ))
        .map_err(plot_err)?;
        area.draw(&Text::new(
            label.clone(),
            (x + 36, y),
            TextStyle::from(("sans-serif", 12).into_font()).pos(Pos::new(HPos::Left, VPos::Center)),
        ))
        .map_err(plot_err)?;
    }
    Ok(())
}

pub fn fig6(out: &Path, f: &Fig6) -> Result<PathBuf, Error> {
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
        .x_label_formatter(&whole)
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

pub fn fig7(out: &Path, f: &Fig7) -> Result<PathBuf, Error> {
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

pub fn error_vs_time(out: &Path, rows: &[Row]) -> Result<PathBuf, Error> {
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

pub fn swatches(out: &Path, cc_under_c: &[Stimulus], rows: &[Row]) -> Result<PathBuf, Error> {
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
