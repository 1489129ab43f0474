//! Section 8: RGB materials under another light. The crate's upsampling (a least-squares map
//! projected onto the node values that round-trip, baked on a grid) beside Jakob-Hanika,
//! Mallett-Yuksel and Smits, each evaluated at the nodes of the radiance sets `KQ_4`, `KQ_6` and
//! `KQ_8`, by the relighting test of `spectral_quadrature_tools::upsampling`.
//!
//! Judged on reflectances no map was fitted on: by default, five-fold cross-validation over the
//! CIE test colours, the ColorChecker and the 190 rawtoaces patches (each fold's map fitted on
//! the other four fifths), plus the shipped map (fitted on the test colours and rawtoaces) on
//! the ColorChecker alone; with `--reflectances`, the shipped map on the user's file.
//!
//! Then light groups whose first light is D65 (`tools::upsampling::groups`): the group's map,
//! fitted for every light of the group, beside the first light's map alone, a `[fixed]` set's
//! map at the group's nodes and Jakob-Hanika, relit through each light's member; the group and
//! every map refitted in each fold (the groups' nodes from the report's node cache on the
//! default inputs, `tools::node_cache`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::plot::{self, plot_err};
use plotters::prelude::*;
use spectral_quadrature_generator::upsampling::{self as up, Baked};
use spectral_quadrature_generator::Derivation;
use spectral_quadrature_spectra::{builtin_illuminant, Curve, Spectra};
use spectral_quadrature_tools as tools;
use tools::csv_table::Table;
use tools::node_cache::NodeCache;
use tools::upsampling::{
    groups::{self, GroupMaps, DEFAULT_GROUPS, FOLDS, GROUP_SIZE, METHODS as GROUP_METHODS},
    jakob_hanika::JakobHanika,
    mean_p95, relit_de00,
    smooth::{MallettYuksel, Smits},
    srgb_under_d65,
};
use tools::Error;

/// The lights the report relights under unless `--illuminants` names others.
pub const DEFAULT_LIGHTS: [&str; 3] = ["A", "F11", "LED_B2"];

/// The set sizes compared.
const SIZES: [usize; 3] = [4, 6, 8];

/// The methods, in the order the table prints them.
const METHODS: [&str; 6] = [
    "true reflectance at the nodes (floor)",
    "this crate: baked upsampling",
    "this crate's least-squares map alone (unbounded)",
    "Jakob-Hanika 2019 (pbrt-v4, Mitsuba 3)",
    "Mallett-Yuksel 2019",
    "Smits 1999",
];

/// What section 8 measures on.
pub struct Inputs<'a> {
    /// The derivation.
    pub d: &'a Derivation,
    /// The user's reflectances, if `--reflectances` was given.
    pub reflectances: Option<(&'a [Curve], &'a str)>,
    /// The user's lights, if `--illuminants` was given (else [`DEFAULT_LIGHTS`]).
    pub lights: Option<&'a [Curve]>,
    /// `--quick`: the first light group alone, in the first fold alone.
    pub quick: bool,
    /// Called with 1 as each fold of each light group is judged.
    pub done: &'a (dyn Fn(usize) + Sync),
}

/// The number of folds the light groups' part runs, for a progress line: one per fold of each
/// group judged.
pub fn group_folds(user_reflectances: bool, quick: bool) -> usize {
    if quick {
        return 1;
    }
    let folds = if user_reflectances { 1 } else { FOLDS };
    folds * DEFAULT_GROUPS.len()
}

/// One result: a method at a set size under a light.
struct Cell {
    method: usize,
    n: usize,
    light: String,
    de: Vec<f64>,
}

/// The node values of the runtime's f32 path for `rgb`, on a fresh bake's codes
/// ([`tools::upsampling::runtime_values`]).
fn runtime_values(b: &Baked, rgb: &[[f64; 3]]) -> Result<Vec<Vec<f64>>, Error> {
    Ok(match tools::upsampling::runtime_values(b, rgb)? {
        Some(values) => values,
        // The section compares 4, 6 and 8 only; anything else is the f64 interpolation (a fresh
        // bake has its fit).
        None => rgb
            .iter()
            .map(|p| b.interpolate(*p).expect("a fresh bake has its fit"))
            .collect(),
    })
}

/// Runs section 8: the text, and the files written to `out`.
pub fn section(i: &Inputs, out: &Path) -> Result<(String, Vec<PathBuf>), Error> {
    let d = i.d;
    let range = d.settings.range_nm;
    let dir = &d.settings.data_dir;
    let lights: Vec<Curve> = match i.lights {
        Some(l) => l.to_vec(),
        None => DEFAULT_LIGHTS
            .iter()
            .map(|n| builtin_illuminant(dir, n, range))
            .collect::<Result<_, _>>()?,
    };
    let d65 = tools::upsampling::d65(d)?;
    let (_, srgb) = d.display("SRGB")?;
    let reference = d.observer.full_integration(range, 1.0)?;
    let jh = JakobHanika::srgb(d)?;
    let my = MallettYuksel::srgb(d)?;
    let smits = Smits::srgb(d)?;
    let shipped_training = up::training(dir, range)?;
    let cc = Spectra::builtin(dir, "data/reflectance_colorchecker_ohta.csv")?.curves(range)?;

    // The judged reflectances and the folds: each fold's training (the maps', and the light
    // groups' fits) and the indices it judges. Fold k of the cross-validation judges every
    // FOLDS-th reflectance from k.
    let (judged, all_folds, judged_from): (Vec<Curve>, Vec<groups::Fold>, String) =
        match i.reflectances {
            Some((r, from)) => (
                r.to_vec(),
                vec![(shipped_training.clone(), (0..r.len()).collect())],
                from.to_string(),
            ),
            None => {
                let all = groups::default_judged(d)?;
                let folds = (0..FOLDS).map(|f| groups::fold(&all, FOLDS, f)).collect();
                let from = "the ColorChecker, the CIE test colours and the 190 rawtoaces patches";
                (
                    all,
                    folds,
                    std::format!("{from}, by {FOLDS}-fold cross-validation"),
                )
            }
        };
    let fold_count = all_folds.len();
    let rgb = srgb_under_d65(d, &judged)?;
    let jh_coeffs: Vec<[f64; 3]> = rgb.iter().map(|p| jh.fit(*p)).collect();

    let mut cells: Vec<Cell> = Vec::new();
    let mut props = String::new();
    let mut shipped_cc: Vec<(usize, f64, f64)> = Vec::new();
    for n in SIZES {
        let set = spectral_quadrature_generator::catalog::resolve(d, &std::format!("KQ_{n}"))?;
        let eval = d.eval_set(&set, "KQ radiance");
        let nodes = &set.wavelengths_nm;
        // The crate's maps, fold by fold.
        let mut crate_values = vec![Vec::new(); judged.len()];
        let mut lsq_values = vec![Vec::new(); judged.len()];
        for (training, idx) in &all_folds {
            let b = up::bake(
                d,
                &set,
                ("SRGB", srgb),
                &d65,
                false,
                training,
                up::DEFAULT_GRID,
            )?;
            let pts: Vec<[f64; 3]> = idx.iter().map(|&k| rgb[k]).collect();
            let map = &b.fit.as_ref().expect("a fresh bake has its fit").map;
            for (&k, v) in idx.iter().zip(runtime_values(&b, &pts)?) {
                crate_values[k] = v;
                lsq_values[k] = map
                    .iter()
                    .map(|m| m[0] * rgb[k][0] + m[1] * rgb[k][1] + m[2] * rgb[k][2])
                    .collect();
            }
        }
        let floor: Vec<Vec<f64>> = judged
            .iter()
            .map(|r| nodes.iter().map(|&l| r.at(l)).collect())
            .collect();
        let jh_values: Vec<Vec<f64>> = jh_coeffs
            .iter()
            .map(|c| {
                nodes
                    .iter()
                    .map(|&l| tools::upsampling::jakob_hanika::spectrum(*c, l))
                    .collect()
            })
            .collect();
        let my_values: Vec<Vec<f64>> = rgb.iter().map(|p| my.at(*p, nodes)).collect();
        let smits_values: Vec<Vec<f64>> = rgb.iter().map(|p| smits.at(*p, nodes)).collect();
        let all = [
            &floor,
            &crate_values,
            &lsq_values,
            &jh_values,
            &my_values,
            &smits_values,
        ];
        for light in &lights {
            for (method, values) in all.iter().enumerate() {
                cells.push(Cell {
                    method,
                    n,
                    light: light.name.clone(),
                    de: relit_de00(&eval, &reference, &judged, values, light),
                });
            }
        }
        // The shipped map's properties, and its errors on the ColorChecker (held out).
        let b = up::bake(
            d,
            &set,
            ("SRGB", srgb),
            &d65,
            false,
            &shipped_training,
            up::DEFAULT_GRID,
        )?;
        let residual = tools::upsampling::bounded_exact_linear_residual(&b.encoding)?;
        let cc_rgb = srgb_under_d65(d, &cc)?;
        let cc_values = runtime_values(&b, &cc_rgb)?;
        let cc_de: Vec<f64> = lights
            .iter()
            .flat_map(|l| relit_de00(&eval, &reference, &cc, &cc_values, l))
            .collect();
        let (m, p) = mean_p95(&cc_de);
        shipped_cc.push((n, m, p));
        writeln!(
            props,
            "| `KQ_{n}` | {:.1} % | {} (residual {:.1e}) | {:.2} | {:.4} | {} |",
            100.0 * b.reachable_share(),
            if residual < 1e-6 { "yes" } else { "no" },
            residual,
            b.lipschitz,
            b.max_round_trip_de00,
            2 * n * b.codes.len()
        )
        .ok();
    }

    // Light groups: the group of D65 and each light relit under, or the default groups.
    let group_lights: Vec<Vec<Curve>> = match i.lights {
        Some(user) => {
            let mut g = vec![d65.clone()];
            g.extend(user.iter().filter(|l| l.name != "D65").cloned());
            vec![g]
        }
        None => DEFAULT_GROUPS
            .iter()
            .map(|names| {
                names
                    .iter()
                    .map(|n| builtin_illuminant(dir, n, range))
                    .collect::<Result<Vec<_>, _>>()
            })
            .collect::<Result<_, _>>()?,
    };
    let group_lights = &group_lights[..if i.quick { 1 } else { group_lights.len() }];
    let group_folds = &all_folds[..if i.quick { 1 } else { fold_count }];
    let mut group_maps = Vec::new();
    for lights in group_lights {
        let own = tools::light_groups::own_sets(d, lights, GROUP_SIZE)?;
        group_maps.push(groups::judge(
            d,
            NodeCache::report()?,
            lights,
            GROUP_SIZE,
            &own,
            &judged,
            &rgb,
            group_folds,
            i.done,
        )?);
    }
    // The texels that hold their reflectance's colour: inside the sRGB cube.
    let in_gamut: Vec<usize> = (0..judged.len())
        .filter(|&k| rgb[k].iter().all(|v| (0.0..=1.0).contains(v)))
        .collect();
    // The ColorChecker's patches among the judged (the first 24 by default).
    let cc_judged: Vec<usize> = match i.reflectances {
        Some(_) => Vec::new(),
        None => (0..cc.len()).collect(),
    };

    let mut o = String::new();
    writeln!(o, "8. RGB materials under another light").ok();
    writeln!(
        o,
        "   Linear sRGB under D65 (white-balanced) upsampled to the N nodes of KQ_N, relit under {} through KQ_N's radiance weights, against the reflectance under that light at 1 nm. Judged on {} ({} reflectances); mean ΔE00 (95th percentile) over reflectances and lights.",
        lights.iter().map(|l| l.name.as_str()).collect::<Vec<_>>().join(", "),
        judged_from,
        judged.len()
    )
    .ok();
    writeln!(o).ok();
    writeln!(o, "| method | KQ_4 | KQ_6 | KQ_8 |").ok();
    writeln!(o, "|---|---|---|---|").ok();
    for (method, name) in METHODS.iter().enumerate() {
        let mut line = std::format!("| {name} |");
        for n in SIZES {
            let de: Vec<f64> = cells
                .iter()
                .filter(|c| c.method == method && c.n == n)
                .flat_map(|c| c.de.iter().copied())
                .collect();
            let (m, p) = mean_p95(&de);
            line.push_str(&std::format!(" {m:.2} ({p:.2}) |"));
        }
        writeln!(o, "{line}").ok();
    }
    writeln!(o).ok();
    writeln!(o, "   At 8 nodes, per light (mean ΔE00):").ok();
    writeln!(o).ok();
    let names: Vec<String> = lights.iter().map(|l| l.name.clone()).collect();
    writeln!(o, "| method | {} |", names.join(" | ")).ok();
    writeln!(o, "|---|{}", "---|".repeat(names.len())).ok();
    for (method, name) in METHODS.iter().enumerate() {
        let mut line = std::format!("| {name} |");
        for l in &names {
            let de: Vec<f64> = cells
                .iter()
                .filter(|c| c.method == method && c.n == 8 && &c.light == l)
                .flat_map(|c| c.de.iter().copied())
                .collect();
            line.push_str(&std::format!(" {:.2} |", mean_p95(&de).0));
        }
        writeln!(o, "{line}").ok();
    }
    writeln!(o).ok();
    if i.reflectances.is_none() {
        writeln!(
            o,
            "   The shipped map (fitted on the CIE test colours and rawtoaces) on the ColorChecker alone: {}.",
            shipped_cc
                .iter()
                .map(|(n, m, p)| std::format!("KQ_{n} {m:.2} ({p:.2})"))
                .collect::<Vec<_>>()
                .join(", ")
        )
        .ok();
        writeln!(o).ok();
    }
    writeln!(
        o,
        "   The shipped maps ({g}×{g}×{g} grid, sRGB, D65): reachable share of the grid, whether a linear map bounded and exact at once exists (a feasibility programme; the largest residual of the nearest bounded map), Lipschitz constant, round trip at the reachable grid points (ΔE00), table bytes.",
        g = up::DEFAULT_GRID
    )
    .ok();
    writeln!(o).ok();
    writeln!(
        o,
        "| set | reachable | bounded exact linear map | Lipschitz | round trip | bytes |"
    )
    .ok();
    writeln!(o, "|---|---|---|---|---|---|").ok();
    o.push_str(&props);
    writeln!(o).ok();
    o.push_str(&default_scene_maps(d)?);
    writeln!(o).ok();
    let mut group_csv =
        Table::new("group,method,light,mean_de00,p95_de00,reflectances,judged_on,nodes_nm_fold1");
    for g in &group_maps {
        o.push_str(&group_text(
            g,
            &judged_from,
            &cc_judged,
            &in_gamut,
            fold_count,
        ));
        group_rows(&mut group_csv, g, &cc_judged);
    }
    let group_path = group_csv.write(out, "upsampling_groups.csv")?;

    let mut csv = Table::new("method,n,light,mean_de00,p95_de00,reflectances");
    for c in &cells {
        let (m, p) = mean_p95(&c.de);
        csv.row([
            METHODS[c.method].to_string(),
            c.n.to_string(),
            c.light.clone(),
            format!("{m:.6}"),
            format!("{p:.6}"),
            c.de.len().to_string(),
        ]);
    }
    let csv_path = csv.write(out, "upsampling.csv")?;
    let svg = plot(out, &cells)?;
    Ok((o, vec![csv_path, svg, group_path]))
}

/// The errors of `de` on the reflectances `of` (every one when `None`) that were judged: a
/// `--quick` run judges the light groups' maps in one fold, and leaves the others' NaN.
fn judged_of(de: &[f64], of: Option<&[usize]>) -> Vec<f64> {
    let all: Vec<f64> = match of {
        None => de.to_vec(),
        Some(idx) => idx.iter().map(|&k| de[k]).collect(),
    };
    all.into_iter().filter(|v| !v.is_nan()).collect()
}

/// Mean and 95th percentile of `de` over the reflectances `of` (every one when `None`) that
/// were judged.
fn stats(de: &[f64], of: Option<&[usize]>) -> (f64, f64) {
    mean_p95(&judged_of(de, of))
}

/// A light group's table: each method's mean (95th percentile) ΔE00 under each light, and the
/// mean over the lights other than the texels'; the round trip of the texels inside the sRGB
/// cube (`in_gamut`); the same table on the ColorChecker alone (`cc`).
fn group_text(
    g: &GroupMaps,
    judged_from: &str,
    cc: &[usize],
    in_gamut: &[usize],
    folds: usize,
) -> String {
    let mut o = String::new();
    let first = &g.lights[0];
    writeln!(
        o,
        "   A light group's map: linear sRGB under {first} upsampled to the {GROUP_SIZE} nodes of the light group {} (nodes searched for the mean ratio to each light's own folded set), each light's accumulator of those node values integrated through its member of the group, against the reflectance under that light at 1 nm. Under {first} this is the round trip (the texel's own colour); under the others, relighting. {}; mean ΔE00 (95th percentile).",
        g.lights.join(", "),
        if folds > 1 {
            format!("Judged on {judged_from}: each fold's group and maps fitted on the other four fifths")
        } else {
            format!("Judged on {judged_from}: the group and maps fitted on the CIE test colours and rawtoaces")
        }
    )
    .ok();
    writeln!(o).ok();
    let table = |o: &mut String, of: Option<&[usize]>| {
        writeln!(
            o,
            "| method | {} | the other lights |",
            g.lights.join(" | ")
        )
        .ok();
        writeln!(o, "|---|{}---|", "---|".repeat(g.lights.len())).ok();
        for (m, name) in GROUP_METHODS.iter().enumerate() {
            let mut line = format!("| {name} |");
            for de in &g.errors[m] {
                let (mean, p95) = stats(de, of);
                line.push_str(&format!(" {mean:.3} ({p95:.2}) |"));
            }
            let others: Vec<f64> = g.errors[m][1..]
                .iter()
                .flat_map(|de| judged_of(de, of))
                .collect();
            let (mean, p95) = mean_p95(&others);
            line.push_str(&format!(" {mean:.3} ({p95:.2}) |"));
            writeln!(o, "{line}").ok();
        }
        writeln!(o).ok();
    };
    table(&mut o, None);
    let judged_in_gamut = judged_of(&g.errors[1][0], Some(in_gamut)).len();
    let round_trip = |m: usize| {
        let de = judged_of(&g.errors[m][0], Some(in_gamut));
        let max = de.iter().fold(0.0f64, |a, &b| a.max(b));
        (mean_p95(&de).0, max)
    };
    let ((gm, gx), (am, ax), (fm, fx)) = (round_trip(1), round_trip(2), round_trip(3));
    writeln!(
        o,
        "   The round trip: of the {} judged reflectances whose colour under {first} lies inside the sRGB cube (the others' texels clip), the group's map gives each texel its own colour back under {first} within {gx:.4} ΔE00 (mean {gm:.4}), the first light's map alone within {ax:.4} (mean {am:.4}); the [fixed] set's map, fitted for its own weights, leaves them {fm:.3} ΔE00 off on average (at most {fx:.2}) through the group's {first} member.",
        judged_in_gamut
    )
    .ok();
    writeln!(o).ok();
    if !cc.is_empty() {
        writeln!(
            o,
            "   The same on the ColorChecker's {} patches alone (judged in their folds):",
            judged_of(&g.errors[1][0], Some(cc)).len()
        )
        .ok();
        writeln!(o).ok();
        table(&mut o, Some(cc));
    }
    o
}

/// The light group's rows of `upsampling_groups.csv`: every method under every light, on every
/// judged reflectance and on the ColorChecker's patches (`cc`).
fn group_rows(t: &mut Table, g: &GroupMaps, cc: &[usize]) {
    let nodes: Vec<String> = g
        .nodes_nm
        .first()
        .map_or(Vec::new(), |n| n.iter().map(|v| v.to_string()).collect());
    let name = g.lights.join("+");
    let subsets: Vec<(&str, Option<&[usize]>)> = if cc.is_empty() {
        vec![("all", None)]
    } else {
        vec![("all", None), ("ColorChecker", Some(cc))]
    };
    for (m, method) in GROUP_METHODS.iter().enumerate() {
        for (l, light) in g.lights.iter().enumerate() {
            for (label, of) in &subsets {
                let (mean, p95) = stats(&g.errors[m][l], *of);
                t.row([
                    name.clone(),
                    method.to_string(),
                    light.clone(),
                    format!("{mean:.6}"),
                    format!("{p95:.6}"),
                    judged_of(&g.errors[m][l], *of).len().to_string(),
                    label.to_string(),
                    nodes.join(" "),
                ]);
            }
        }
    }
}

/// The table of the default scene's maps (every set it upsamples and its light group, on every
/// display, as the build bakes them): the reference light, the share of the grid node values in [0, 1] reach, whether a
/// linear map bounded and exact at once exists, the Lipschitz constant, the round trip at the
/// reachable grid points and the table's bytes.
fn default_scene_maps(d: &Derivation) -> Result<String, Error> {
    let scene = spectral_quadrature_generator::scene::Scene::default_scene(&d.settings.data_dir);
    let resolved = scene.resolve(d)?;
    let mut o = String::new();
    writeln!(
        o,
        "   The default scene's maps ({} of them: its shared sets, Table 2's rows and its light group on every display, as the build bakes them; a group's map under its first light): the reference light, the share of the grid whose colour node values in [0, 1] reach (the others get the nearest reachable colour), whether a linear map bounded and exact at once exists (residual as above), Lipschitz constant, round trip at the reachable grid points (ΔE00), table bytes.",
        resolved.upsamplings.len()
    )
    .ok();
    writeln!(o).ok();
    writeln!(
        o,
        "| set | display | light | reachable | bounded exact linear map | Lipschitz | round trip | bytes |"
    )
    .ok();
    writeln!(o, "|---|---|---|---|---|---|---|---|").ok();
    for b in &resolved.upsamplings {
        let residual = tools::upsampling::bounded_exact_linear_residual(&b.encoding)?;
        writeln!(
            o,
            "| `{}` | {} | {} | {:.1} % | {} (residual {:.1e}) | {:.2} | {:.4} | {} |",
            b.set,
            b.display,
            b.light,
            100.0 * b.reachable_share(),
            if residual < 1e-6 { "yes" } else { "no" },
            residual,
            b.lipschitz,
            b.max_round_trip_de00,
            2 * b.wavelengths_nm.len() * b.codes.len()
        )
        .ok();
    }
    Ok(o)
}

fn plot(out: &Path, cells: &[Cell]) -> Result<PathBuf, Error> {
    let path = out.join("upsampling.svg");
    let colours = [
        BLACK,
        RGBColor(200, 40, 40),
        RGBColor(230, 150, 150),
        RGBColor(40, 90, 200),
        RGBColor(40, 150, 60),
        RGBColor(170, 110, 30),
    ];
    // The legend below the chart: the six names are long, and inside the plotting area they
    // covered the lines.
    const COLUMNS: usize = 2;
    let legend_h = plot::legend_height(METHODS.len(), COLUMNS);
    let root = SVGBackend::new(&path, (760, 480 + legend_h)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let (top, below) = root.split_vertically(480);
    let mean = |method: usize, n: usize| {
        let de: Vec<f64> = cells
            .iter()
            .filter(|c| c.method == method && c.n == n)
            .flat_map(|c| c.de.iter().copied())
            .collect();
        mean_p95(&de).0
    };
    let ymax = (0..METHODS.len())
        .flat_map(|m| SIZES.map(|n| mean(m, n)))
        .fold(0.0f64, f64::max)
        * 1.15;
    let mut chart = ChartBuilder::on(&top)
        .caption(
            "RGB materials relit: mean ΔE00 at the nodes of KQ_N",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(3.5f64..8.5, 0.0..ymax)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc("wavelengths (N)")
        .y_desc("mean ΔE00")
        .x_labels(SIZES.len() + 2)
        .x_label_formatter(&plot::whole)
        .draw()
        .map_err(plot_err)?;
    for (m, c) in colours.iter().enumerate() {
        let pts: Vec<(f64, f64)> = SIZES.iter().map(|&n| (n as f64, mean(m, n))).collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
            .map_err(plot_err)?;
        chart
            .draw_series(pts.iter().map(|p| Circle::new(*p, 4, c.filled())))
            .map_err(plot_err)?;
    }
    let entries: Vec<(String, RGBColor)> = METHODS
        .iter()
        .zip(colours)
        .map(|(m, c)| (m.to_string(), c))
        .collect();
    plot::legend(&below, &entries, COLUMNS)?;
    root.present().map_err(plot_err)?;
    drop(chart);
    drop(top);
    drop(below);
    drop(root);
    Ok(path)
}
