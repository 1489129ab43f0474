//! Error against render time: the Cornell box path traced with every spectral method, each
//! image judged in CIEDE2000 against the 1 nm reference through the same paths
//! (`docs/render-time.md`).
//!
//! ```text
//! cargo run --release -p spectral-quadrature-render --bin render
//! cargo run --release -p spectral-quadrature-render --bin render -- --scene examples/render/a.toml --size 32 --max-spp 16
//! ```
//!
//! Writes `<out>/error_vs_render_time.csv` (every method at every level of samples per pixel),
//! `<out>/methods.csv` (each method's last level, frame conversion and error through the
//! reference's own paths), `<out>/cost_ratio.csv` (the 8-node set's render time over RGB's and
//! what the AVX2 loop gains, measured in turns), `<out>/equal_time.csv` (each method's error at
//! the time the 8-node set takes at 64 samples per pixel), `<out>/targets.csv` (the 8-node
//! set against RGB and pbrt-v4 ×4 at every point of the plot), `<out>/crossings.csv` (where
//! random wavelengths pass below each fixed set), `<out>/paints_at_nodes.csv` (each measured
//! paint at each fixed set's nodes), and per scene `<out>/<scene>.svg` (mean ΔE00 against wall
//! seconds, log-log) and `<out>/<scene>.png` (the images at 64 samples per pixel over their
//! ΔE00 maps, each method's name drawn in). The reference is cached in
//! `<reference-dir>/<scene>-<size>.txt`.
//!
//! **Where the curves stop.** Every method renders 1, 2, 4, … paths a pixel until the 8-node
//! set's curve has flattened (its mean ΔE00 fell by less than [`curves::FLAT`] over the last
//! doubling), or `--max-spp`. There RGB and the fixed sets stop; each random-wavelength method
//! goes on until it is below every fixed set's last error, or has flattened itself, or
//! `--max-spp`.
//!
//! **Time.** Each method's tables (sets searched, maps baked, texels converted) are made
//! before its render and not counted. A level's time is the wall-clock seconds of its passes
//! (one path a pixel each) and of its frames (the film converted once per level, as a renderer
//! displays it). The levels up to [`REPEATED_UP_TO`] paths a pixel last milliseconds, where
//! other processes' load decides single timings: each method renders them again and again
//! from its first path (`--repeats` times the step to 64, up to eight times as often the
//! shortest steps), the methods taking turns level by level, and a level's time is the sum of
//! the medians of the steps to it. Above, the methods take turns of at most [`CHUNK`]
//! passes, and a level's time is the time at
//! [`REPEATED_UP_TO`] plus the turns and frames since: load falls on every method alike.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::builder::TypedValueParser as _;
use clap::Parser;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use spectral_quadrature_render::cornell::picture::{self, Rgb8};
use spectral_quadrature_render::render::curves::{self, Point};
use spectral_quadrature_render::render::measure::{self, CachedReference};
use spectral_quadrature_render::render::methods::{Method, Setup};
use spectral_quadrature_render::render::scene::{self, Scene};
use spectral_quadrature_render::render::transport::{self, Geometry, Options};
use spectral_quadrature_tools as tools;
use tools::Error;

/// Renders the Cornell box scenes with every spectral method and plots error against time.
#[derive(Parser)]
#[command(version)]
struct Args {
    /// A scene file (repeatable). Default: every `examples/render/*.toml` of the crate.
    #[arg(long = "scene", value_name = "FILE")]
    scenes: Vec<PathBuf>,
    /// The folder the CSV files, plots and pictures go to.
    #[arg(long, value_name = "DIR", default_value = "docs/render-time")]
    out: PathBuf,
    /// Image width and height, pixels (8 to 512).
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u16).range(8..=512).map(usize::from))]
    size: usize,
    /// The most samples per pixel a curve goes to (powers of 2 from 1; 1 to 1048576): the cap
    /// on where the curves stop.
    #[arg(long, default_value_t = 32768, value_parser = clap::value_parser!(u32).range(1..=1_048_576).map(|v| v as usize))]
    max_spp: usize,
    /// How many times each method renders the step to 64 paths a pixel (the shorter steps up to
    /// eight times as often), whose time is the median (1 to 99).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u8).range(1..=99).map(usize::from))]
    repeats: usize,
    /// The level at which each method's image is judged against a 1 nm image through the same
    /// paths (the methods' seed): its spectral error alone, without the paths' noise.
    #[arg(long, default_value_t = 1024)]
    same_path_spp: usize,
    /// The seed of the methods' paths.
    #[arg(long, default_value_t = 1988)]
    seed: u64,
    /// Threads (default: every core).
    #[arg(long)]
    threads: Option<usize>,
    /// Paths a pixel in each of the reference's two images.
    #[arg(long, default_value_t = 32768, value_parser = clap::value_parser!(u32).range(1..=16_777_216).map(|v| v as usize))]
    reference_spp: usize,
    /// Where the references are cached (`<scene>-<size>.txt`).
    #[arg(long, value_name = "DIR", default_value = "docs/render-time/reference")]
    reference_dir: PathBuf,
    /// Render the references again even where a cached one fits.
    #[arg(long)]
    remake_reference: bool,
    /// The baseline loop only (no AVX2), to measure what the vector layout gains.
    #[arg(long)]
    no_simd: bool,
    /// Paths a pixel for the cost ratio: RGB, the 8-node set and the 8-node set's and the
    /// reference's baseline loops, in turns of 16.
    #[arg(long, default_value_t = 512)]
    cost_spp: usize,
    /// The `cornell` tool's radiosity reference at the same size (its `--reference-xyz`
    /// file): a cross-check of the 1 nm reference of every scene lit by the box's lamp alone
    /// with measured paints and no texture, printed as the mean and p95 ΔE00 between them.
    #[arg(long, value_name = "FILE")]
    radiosity: Option<PathBuf>,
    /// Only write the ColorChecker texture (16-bit sRGB PNG, the 24 patches' sRGB under D65)
    /// to FILE and print the box's paints' sRGB under D65, then stop.
    #[arg(long, value_name = "FILE")]
    write_colorchecker: Option<PathBuf>,
}

fn main() {
    let args = Args::parse();
    if let Err(e) = run(&args) {
        eprintln!("render: error: {e}");
        std::process::exit(2);
    }
}

/// The most passes a method renders before the next takes its turn.
const CHUNK: usize = 64;
/// The levels whose time is the median of `--repeats` renders.
const REPEATED_UP_TO: usize = 64;
/// How many times the step to `level` (a short level, at most [`REPEATED_UP_TO`]) is timed:
/// `repeats` at [`REPEATED_UP_TO`], twice as often for each halving below, at most eight times
/// `repeats` (levels 1 to 8: 40 times with the default 5), so that every short level's steps
/// add up to about the same number of passes.
fn repeats_at(level: usize, repeats: usize) -> usize {
    repeats.max(1) * (REPEATED_UP_TO / level.max(1)).clamp(1, 8)
}
/// The passes of one turn in the cost ratio's measurement.
const COST_CHUNK: usize = 16;
/// The level shown in the pictures and the equal-time comparison.
const SHOWN_SPP: usize = 64;

/// Texels a patch side in the ColorChecker texture.
const PATCH_TEXELS: usize = 16;

fn write_colorchecker(path: &Path) -> Result<(), Error> {
    let d = spectral_quadrature_generator::derive(&tools::settings())?;
    let cc = spectral_quadrature_spectra::Spectra::builtin(
        &d.settings.data_dir,
        "data/reflectance_colorchecker_ohta.csv",
    )?
    .curves(d.settings.range_nm)?;
    let lin = tools::upsampling::srgb_under_d65(&d, &cc)?;
    let (w, h) = (6 * PATCH_TEXELS, 4 * PATCH_TEXELS);
    let px: Vec<[f64; 3]> = (0..w * h)
        .map(|k| {
            let p = (k / w / PATCH_TEXELS) * 6 + (k % w) / PATCH_TEXELS;
            lin[p].map(scene::srgb_encode)
        })
        .collect();
    scene::write_png16(path, w, h, &px)?;
    println!(
        "Wrote {} ({w} × {h}, 16-bit sRGB): the 24 patches' white-balanced sRGB under D65 (1 nm, the derivation's range), row by row",
        path.display()
    );
    for (c, l) in cc.iter().zip(&lin) {
        if l.iter().any(|v| !(0.0..=1.0).contains(v)) {
            println!("  {} is outside sRGB (linear {l:.4?}): clipped", c.name);
        }
    }
    let data = spectral_quadrature_render::cornell::read_data(Path::new(tools::DATA_DIR))?;
    let paints = tools::upsampling::srgb_under_d65(&d, &data.paints)?;
    println!("The box's paints' sRGB under D65 (encoded), for a scene's [[paint]]:");
    for (name, l) in ["white", "red", "green"].iter().zip(&paints) {
        let e = l.map(scene::srgb_encode);
        println!(
            "[[paint]]\nname = \"{name}\"\nsrgb = [{:.6}, {:.6}, {:.6}]",
            e[0], e[1], e[2]
        );
    }
    Ok(())
}

fn default_scenes() -> Result<Vec<PathBuf>, Error> {
    let dir = Path::new(tools::CRATE_DIR).join("examples/render");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| Error::Write {
            path: dir.clone(),
            source: e,
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    v.sort();
    Ok(v)
}

/// The levels: 1, 2, 4, … up to `max`.
fn levels(max: usize) -> Vec<usize> {
    std::iter::successors(Some(1usize), |s| Some(s * 2))
        .take_while(|&s| s <= max.max(1))
        .collect()
}

/// The reference for `scene` at `size`: the cached one if it fits, else rendered from two
/// seeds and cached.
fn reference(
    args: &Args,
    scene: &Scene,
    setup: &Setup,
    g: &Geometry,
    seen: &[usize],
    threads: usize,
) -> Result<CachedReference, Error> {
    let stem = scene
        .file
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let path = args.reference_dir.join(format!("{stem}-{}.txt", args.size));
    let text = std::fs::read_to_string(&scene.file).unwrap_or_default();
    if !args.remake_reference && path.exists() {
        let r = CachedReference::read(&path)?;
        if r.size == args.size && r.scene_text == text && r.spp >= args.reference_spp {
            eprintln!(
                "render: {}: the cached reference ({} paths a pixel, own error {:.3} mean)",
                path.display(),
                r.spp,
                r.own_mean
            );
            return Ok(r);
        }
        eprintln!(
            "render: {}: does not fit (size, scene or paths); rendering the reference again",
            path.display()
        );
    }
    let seeds = [1_000_001u64, 1_000_002];
    let t = Instant::now();
    let mut images = Vec::new();
    for seed in seeds {
        let opts = Options {
            seed,
            threads,
            simd: !args.no_simd,
        };
        let r = setup.render(Method::Reference, g, &[args.reference_spp], opts)?;
        images.push(r.images.into_iter().next().unwrap_or_default());
    }
    let seconds = t.elapsed().as_secs_f64();
    let mean: Vec<[f64; 3]> = images[0]
        .iter()
        .zip(&images[1])
        .map(|(a, b)| [0, 1, 2].map(|c| 0.5 * (a[c] + b[c])))
        .collect();
    let white = measure::white(setup.d, scene, &mean, seen)?;
    let r = CachedReference::from_pair(
        &images[0],
        &images[1],
        seen,
        white,
        (args.size, args.reference_spp, seeds, seconds, text),
    );
    std::fs::create_dir_all(&args.reference_dir).map_err(|e| Error::Write {
        path: args.reference_dir.clone(),
        source: e,
    })?;
    let command = format!(
        "cargo run --release -p spectral-quadrature-render --bin render -- --scene {} --size {} --reference-spp {} --remake-reference",
        scene.file.strip_prefix(tools::CRATE_DIR).unwrap_or(&scene.file).display(),
        args.size,
        args.reference_spp
    );
    std::fs::write(&path, r.to_text(&command)).map_err(|e| Error::Write {
        path: path.clone(),
        source: e,
    })?;
    eprintln!(
        "render: wrote {} ({} paths a pixel × 2 seeds, {seconds:.0} s; own error {:.4} mean, {:.4} p95)",
        path.display(),
        args.reference_spp,
        r.own_mean,
        r.own_p95
    );
    Ok(r)
}

/// The radiosity file's per-pixel XYZ (`seen,x,y,z` rows after `#` lines).
fn read_radiosity(path: &Path) -> Result<Vec<[f64; 3]>, Error> {
    let file = path.display().to_string();
    let text =
        std::fs::read_to_string(path).map_err(|e| spectral_quadrature_spectra::DataError {
            file: file.clone(),
            line: 0,
            message: format!("cannot read: {e}"),
        })?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.starts_with('#') || line.starts_with("seen") || line.trim().is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split(',')
            .skip(1)
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .ok()
            .filter(|v: &Vec<f64>| v.len() == 3)
            .ok_or_else(|| spectral_quadrature_spectra::DataError {
                file: file.clone(),
                line: i as u64 + 1,
                message: "expected seen,x,y,z".into(),
            })?;
        out.push([v[0], v[1], v[2]]);
    }
    Ok(out)
}

/// How a method's curve is drawn: colour, line (dash length in pixels, 0 for solid), width and
/// marker. The fixed sets are cool hues with solid lines, the random samplers warm hues with
/// dashes, RGB black; no two share a colour and a marker.
struct Style {
    colour: RGBColor,
    dash: u32,
    width: u32,
    marker: Marker,
    filled: bool,
}

#[derive(Clone, Copy)]
enum Marker {
    Circle,
    Square,
    Triangle,
    Diamond,
    Cross,
}

fn style(method: &Method) -> Style {
    let s = |colour, dash, width, marker, filled| Style {
        colour,
        dash,
        width,
        marker,
        filled,
    };
    match method {
        Method::Reference => s(RGBColor(0, 0, 0), 0, 1, Marker::Cross, false),
        Method::Rgb => s(RGBColor(0, 0, 0), 0, 2, Marker::Cross, false),
        Method::Random { sampler, k } => {
            let visible = matches!(sampler, tools::random_wavelengths::Sampler::Visible);
            match (visible, *k <= 4) {
                (true, true) => s(RGBColor(230, 85, 13), 8, 2, Marker::Triangle, true),
                (false, true) => s(RGBColor(203, 24, 29), 8, 2, Marker::Diamond, true),
                (true, false) => s(RGBColor(191, 129, 45), 3, 2, Marker::Triangle, false),
                (false, false) => s(RGBColor(174, 1, 126), 3, 2, Marker::Diamond, false),
            }
        }
        Method::Fixed { n } => match n {
            4 => s(RGBColor(107, 174, 214), 0, 2, Marker::Circle, false),
            6 => s(RGBColor(33, 113, 181), 0, 2, Marker::Square, false),
            8 => s(RGBColor(8, 48, 107), 0, 3, Marker::Circle, true),
            _ => s(RGBColor(35, 139, 69), 0, 2, Marker::Square, true),
        },
    }
}

/// Runs `$body` with `$mk` a function from a point to `$st`'s marker there (each marker is its
/// own type, so the body is expanded once per marker).
macro_rules! with_marker {
    ($st:expr, $mk:ident => $body:expr) => {{
        let st: &Style = $st;
        let shape = if st.filled {
            st.colour.filled()
        } else {
            st.colour.stroke_width(2)
        };
        match st.marker {
            Marker::Circle => {
                let $mk = |p| EmptyElement::at(p) + Circle::new((0, 0), 4, shape);
                $body
            }
            Marker::Square => {
                let $mk = |p| EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], shape);
                $body
            }
            Marker::Triangle => {
                let $mk = |p| EmptyElement::at(p) + TriangleMarker::new((0, 0), 5, shape);
                $body
            }
            Marker::Diamond => {
                let $mk = |p| {
                    EmptyElement::at(p)
                        + Polygon::new(vec![(0, -5), (5, 0), (0, 5), (-5, 0)], shape)
                };
                $body
            }
            Marker::Cross => {
                let $mk =
                    |p| EmptyElement::at(p) + Cross::new((0, 0), 4, st.colour.stroke_width(2));
                $body
            }
        }
    }};
}

fn plot_err<E: std::fmt::Debug>(e: E) -> Error {
    Error::Plot(format!("{e:?}"))
}

/// A tick's label on a log axis: the 1, 2 and 5 of each decade as plain decimals (`0.01`,
/// `0.2`, `5`, `10`), the others unlabelled.
fn tick(v: f64) -> String {
    if v.is_nan() || v <= 0.0 {
        return String::new();
    }
    let e = v.log10().floor();
    let m = v / 10f64.powf(e);
    if ![1.0, 2.0, 5.0].iter().any(|k| (m - k).abs() < 1e-6 * k) {
        return String::new();
    }
    let decimals = (-e).max(0.0) as usize;
    format!("{v:.decimals$}")
}

/// Mean ΔE00 against wall seconds, log-log, one curve per method (each its colour, line and
/// marker), the reference's own error as a dashed and labelled floor.
fn plot(
    path: &Path,
    title: &str,
    curves: &[(Method, Vec<Point>)],
    floor: f64,
) -> Result<(), Error> {
    let root = SVGBackend::new(path, (900, 580)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let (chart_area, legend_area) = root.split_horizontally(680);
    let (mut t0, mut t1, mut e0, mut e1) = (f64::MAX, 0.0f64, f64::MAX, 0.0f64);
    for p in curves.iter().flat_map(|c| c.1.iter()) {
        t0 = t0.min(p.seconds);
        t1 = t1.max(p.seconds);
        e0 = e0.min(p.mean);
        e1 = e1.max(p.mean);
    }
    e0 = e0.min(floor).max(1e-4);
    let (t0, t1) = (t0.max(1e-4) / 1.5, t1.max(1e-3) * 1.5);
    let (e0, e1) = (e0 / 1.5, e1.max(e0 * 10.0) * 1.5);
    let mut chart = ChartBuilder::on(&chart_area)
        .caption(title, ("sans-serif", 15))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d((t0..t1).log_scale(), (e0..e1).log_scale())
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc("wall-clock seconds (render)")
        .y_desc("mean ΔE00 over the pixels that see the box")
        .x_labels(30)
        .y_labels(30)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .bold_line_style(RGBColor(225, 225, 225))
        .light_line_style(WHITE)
        .draw()
        .map_err(plot_err)?;
    // The floor: dashes along the time axis, and its label above them at the left.
    chart
        .draw_series(DashedLineSeries::new(
            [(t0, floor), (t1, floor)],
            6,
            5,
            BLACK.stroke_width(1),
        ))
        .map_err(plot_err)?;
    chart
        .draw_series(std::iter::once(Text::new(
            format!("reference's own error {floor:.3}: no claim below"),
            (t0 * 1.15, floor * 1.32),
            ("sans-serif", 13),
        )))
        .map_err(plot_err)?;
    for (k, (method, pts)) in curves.iter().enumerate() {
        let st = style(method);
        let line = st.colour.stroke_width(st.width);
        let xy: Vec<(f64, f64)> = pts.iter().map(|p| (p.seconds, p.mean)).collect();
        if st.dash == 0 {
            chart
                .draw_series(LineSeries::new(xy.iter().copied(), line))
                .map_err(plot_err)?;
        } else {
            chart
                .draw_series(DashedLineSeries::new(
                    xy.iter().copied(),
                    st.dash,
                    st.dash.div_ceil(2) + 2,
                    line,
                ))
                .map_err(plot_err)?;
        }
        with_marker!(&st, mk => chart.draw_series(xy.iter().map(|&p| mk(p))).map_err(plot_err)?);
        let y = 30 + 24 * k as i32;
        if st.dash == 0 {
            legend_area
                .draw(&PathElement::new(vec![(8, y), (44, y)], line))
                .map_err(plot_err)?;
        } else {
            legend_area
                .draw(&DashedPathElement::new(
                    vec![(8, y), (44, y)],
                    st.dash,
                    st.dash.div_ceil(2) + 2,
                    line,
                ))
                .map_err(plot_err)?;
        }
        with_marker!(&st, mk => legend_area.draw(&mk((26, y))).map_err(plot_err)?);
        legend_area
            .draw(&Text::new(method.name(), (52, y - 7), ("sans-serif", 13)))
            .map_err(plot_err)?;
    }
    let y = 30 + 24 * curves.len() as i32;
    legend_area
        .draw(&DashedPathElement::new(
            vec![(8, y), (44, y)],
            6,
            5,
            BLACK.stroke_width(1),
        ))
        .map_err(plot_err)?;
    legend_area
        .draw(&Text::new(
            format!("reference's own error ({floor:.3})"),
            (52, y - 7),
            ("sans-serif", 13),
        ))
        .map_err(plot_err)?;
    root.present().map_err(plot_err)?;
    Ok(())
}

/// Pixel-doubles an image (so that the names fit above a small one).
fn upscale(img: &Rgb8, f: usize) -> Rgb8 {
    let mut out = Rgb8::filled(img.width * f, img.height * f, [0, 0, 0]);
    for y in 0..out.height {
        for x in 0..out.width {
            let s = ((y / f) * img.width + x / f) * 3;
            let d = (y * out.width + x) * 3;
            out.data[d..d + 3].copy_from_slice(&img.data[s..s + 3]);
        }
    }
    out
}

/// One method's render in a scene.
struct Run<'g> {
    method: Method,
    p: Box<dyn transport::Progressive + 'g>,
    /// Its levels so far.
    points: Vec<Point>,
    /// Seconds of its frame conversions, each.
    frames: Vec<f64>,
    /// Seconds so far, on the curve.
    seconds: f64,
    /// Whether it renders on.
    active: bool,
    /// Seconds its tables took (not counted).
    tables: f64,
    /// Its image at [`SHOWN_SPP`] and at `--same-path-spp`.
    shown: Option<Vec<[f64; 3]>>,
    same_path: Option<Vec<[f64; 3]>>,
}

impl Run<'_> {
    fn random(&self) -> bool {
        matches!(self.method, Method::Random { .. })
    }
}

/// What images are judged against.
struct Judge<'a> {
    reference: &'a [[f64; 3]],
    seen: &'a [usize],
    white: [f64; 3],
    shown_spp: usize,
    same_path_spp: usize,
}

impl Judge<'_> {
    /// `img` at `spp` paths a pixel, `seconds` into the render: its point, and the images kept.
    fn record(&self, run: &mut Run, spp: usize, seconds: f64, img: Vec<[f64; 3]>) {
        let (mean, p95) = measure::stats(&img, self.reference, self.seen, self.white);
        run.points.push(Point {
            spp,
            seconds,
            mean,
            p95,
        });
        if spp == self.shown_spp {
            run.shown = Some(img.clone());
        }
        if spp == self.same_path_spp {
            run.same_path = Some(img);
        }
    }
}

/// The quartiles of `v`: first, median, third.
fn quartiles(v: &[f64]) -> [f64; 3] {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let q = |f: f64| {
        s.get(((s.len().max(1) - 1) as f64 * f).round() as usize)
            .copied()
    };
    [0.25, 0.5, 0.75].map(|f| q(f).unwrap_or(f64::NAN))
}

/// The curves of one scene: every method at every level until the curves stop (module doc).
fn curves_of<'g>(
    args: &Args,
    setup: &Setup,
    g: &'g Geometry,
    opts: Options,
    judge: &Judge,
) -> Result<Vec<Run<'g>>, Error> {
    let spp = levels(args.max_spp);
    // Every method's tables first (load time, not render time).
    let mut runs: Vec<Run<'g>> = Vec::new();
    for method in Method::all_for(setup.scene) {
        let t = Instant::now();
        let p = setup.progress(method, g, opts)?;
        runs.push(Run {
            method,
            p,
            points: Vec::new(),
            frames: Vec::new(),
            seconds: 0.0,
            active: true,
            tables: t.elapsed().as_secs_f64(),
            shown: None,
            same_path: None,
        });
    }
    // The short levels, rendered from the first path again and again, the methods taking turns
    // level by level (each level's order turned by one from the last), so that every method's
    // passes to a level fall within the same fraction of a second of load; a level's time is
    // the sum of the medians of each step's time (its passes and its frame). A step of one pass
    // lasts milliseconds, and on a loaded machine it either runs at once or waits for a turn of
    // the scheduler: the short steps are timed more often ([`repeats_at`]). Their images are
    // judged once.
    let short: Vec<usize> = spp
        .iter()
        .copied()
        .filter(|&s| s <= REPEATED_UP_TO)
        .collect();
    let reps: Vec<usize> = short.iter().map(|&l| repeats_at(l, args.repeats)).collect();
    let mut steps = vec![vec![Vec::new(); short.len()]; runs.len()];
    for rep in 0..reps.first().copied().unwrap_or(0) {
        for run in runs.iter_mut() {
            run.p.reset();
        }
        for (li, &level) in short.iter().enumerate() {
            if rep >= reps[li] {
                break;
            }
            for j in 0..runs.len() {
                let i = (j + rep + li) % runs.len();
                let run = &mut runs[i];
                let mut t = run.p.advance(level);
                let (img, frame) = run.p.image();
                t += frame;
                run.frames.push(frame);
                steps[i][li].push(t);
                if rep == 0 {
                    judge.record(run, level, 0.0, img);
                }
            }
        }
    }
    for (run, steps) in runs.iter_mut().zip(&steps) {
        let mut total = 0.0;
        for (p, t) in run.points.iter_mut().zip(steps) {
            total += curves::median(t);
            p.seconds = total;
        }
        run.seconds = total;
    }
    // Level by level: the long ones rendered in turns of CHUNK passes by the methods still
    // going; after each, where the curves stop.
    let fixed8 = runs
        .iter()
        .position(|r| r.method == Method::Fixed { n: 8 })
        .ok_or_else(|| Error::Sampling("no 8-node set".into()))?;
    let mut target: Option<f64> = None;
    for (li, &level) in spp.iter().enumerate() {
        if li >= short.len() {
            loop {
                let mut any = false;
                for run in runs.iter_mut().filter(|r| r.active) {
                    let done = run.p.spp();
                    if done < level {
                        run.seconds += run.p.advance((done + CHUNK).min(level));
                        any = true;
                    }
                }
                if !any {
                    break;
                }
            }
            for run in runs.iter_mut().filter(|r| r.active) {
                let (img, t) = run.p.image();
                run.seconds += t;
                run.frames.push(t);
                let seconds = run.seconds;
                judge.record(run, level, seconds, img);
            }
        }
        // Where the curves stop: RGB and the fixed sets where the 8-node set flattened;
        // each random method once below every fixed set's last error, or flat itself.
        if target.is_none() && curves::flattened(&runs[fixed8].points[..=li]) {
            for run in runs.iter_mut().filter(|r| !r.random()) {
                run.active = false;
                run.points.truncate(li + 1);
            }
            target = runs
                .iter()
                .filter(|r| matches!(r.method, Method::Fixed { .. }))
                .filter_map(|r| r.points.last().map(|p| p.mean))
                .reduce(f64::min);
        }
        if let Some(target) = target {
            for run in runs.iter_mut().filter(|r| r.active) {
                let pts = &run.points[..=li.min(run.points.len() - 1)];
                let below = pts.last().is_some_and(|p| p.mean < target);
                if below || curves::flattened(pts) {
                    run.active = false;
                    run.points.truncate(li + 1);
                }
            }
        }
        if !runs.iter().any(|r| r.active) {
            break;
        }
    }
    Ok(runs)
}

/// The cost ratio: RGB, the 8-node set, and the 8-node set's and the reference's baseline loops
/// against their AVX2 loops, in turns of COST_CHUNK passes over the same paths (the order
/// turning each round); each ratio is the median over the rounds of the two turns' times.
struct Cost {
    spp: usize,
    rgb_paths_per_second: f64,
    fixed8_paths_per_second: f64,
    fixed8_over_rgb: [f64; 3],
    fixed8_baseline_over_avx2: [f64; 3],
    reference_baseline_over_avx2: [f64; 3],
}

fn cost(args: &Args, setup: &Setup, g: &Geometry, opts: Options) -> Result<Cost, Error> {
    let base = Options {
        simd: false,
        ..opts
    };
    let mut ps = [
        setup.progress(Method::Rgb, g, opts)?,
        setup.progress(Method::Fixed { n: 8 }, g, opts)?,
        setup.progress(Method::Fixed { n: 8 }, g, base)?,
        setup.progress(Method::Reference, g, opts)?,
        setup.progress(Method::Reference, g, base)?,
    ];
    let spp = args.cost_spp.max(1);
    let mut rounds: Vec<[f64; 5]> = Vec::new();
    let mut done = 0;
    while done < spp {
        done = (done + COST_CHUNK).min(spp);
        let mut t = [0.0; 5];
        for j in 0..ps.len() {
            let i = (j + rounds.len()) % ps.len();
            t[i] = ps[i].advance(done);
        }
        rounds.push(t);
    }
    let ratio = |a: usize, b: usize| {
        quartiles(
            &rounds
                .iter()
                .map(|t| t[a] / t[b].max(1e-12))
                .collect::<Vec<_>>(),
        )
    };
    let total = |i: usize| rounds.iter().map(|t| t[i]).sum::<f64>();
    let paths = (spp * g.size * g.size) as f64;
    Ok(Cost {
        spp,
        rgb_paths_per_second: paths / total(0),
        fixed8_paths_per_second: paths / total(1),
        fixed8_over_rgb: ratio(1, 0),
        fixed8_baseline_over_avx2: ratio(2, 1),
        reference_baseline_over_avx2: ratio(4, 3),
    })
}

/// The CSV files, filled scene by scene.
struct Tables {
    main: tools::csv_table::Table,
    methods: tools::csv_table::Table,
    costs: tools::csv_table::Table,
    equal: tools::csv_table::Table,
    targets: tools::csv_table::Table,
    crossings: tools::csv_table::Table,
    paints: tools::csv_table::Table,
}

impl Tables {
    fn new() -> Tables {
        use tools::csv_table::Table;
        Tables {
            main: Table::new(
                "scene,light,method,n,spp,wall_seconds,paths_per_second,mean_de00,p95_de00",
            ),
            methods: Table::new(
                "scene,light,method,n,last_spp,wall_seconds,paths_per_second,frame_seconds_median,mean_de00,p95_de00,same_path_spp,same_path_mean_de00,same_path_p95_de00,tables_seconds",
            ),
            costs: Table::new(
                "scene,light,spp,rgb_paths_per_second,fixed8_paths_per_second,fixed8_over_rgb_time,fixed8_over_rgb_q1,fixed8_over_rgb_q3,fixed8_over_rgb_time_curves,fixed8_baseline_over_avx2_time,fixed8_baseline_over_avx2_q1,fixed8_baseline_over_avx2_q3,reference_baseline_over_avx2_time,reference_baseline_over_avx2_q1,reference_baseline_over_avx2_q3",
            ),
            equal: Table::new(
                "scene,light,method,seconds,mean_de00_at_equal_time,reference_own_mean_de00",
            ),
            targets: Table::new(
                "scene,light,against,seconds,fixed8_mean_de00,other_mean_de00,fixed8_below",
            ),
            crossings: Table::new(
                "scene,light,method,fixed,spp,seconds,mean_de00,fixed_mean_de00",
            ),
            paints: Table::new("scene,light,method,under,paint,bounces,de00,de00_smoothed"),
        }
    }
}

fn f4(v: f64) -> String {
    format!("{v:.4}")
}

fn run(args: &Args) -> Result<(), Error> {
    if let Some(p) = &args.write_colorchecker {
        return write_colorchecker(p);
    }
    let start = Instant::now();
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let scenes = if args.scenes.is_empty() {
        default_scenes()?
    } else {
        args.scenes.clone()
    };
    std::fs::create_dir_all(&args.out).map_err(|e| Error::Write {
        path: args.out.clone(),
        source: e,
    })?;
    let d = spectral_quadrature_generator::derive(&tools::settings())?;
    let spp = levels(args.max_spp);
    let opts = Options {
        seed: args.seed,
        threads,
        simd: !args.no_simd,
    };
    println!(
        "# Error against render time\n\n{} × {} pixels, 1 to at most {} paths a pixel, {threads} threads, vector loop: {}; the steps to the levels up to {REPEATED_UP_TO} paths a pixel timed {} to {} times (the median)\n",
        args.size,
        args.size,
        spp.last().copied().unwrap_or(1),
        if opts.simd && transport::has_avx2() { "AVX2" } else { "baseline" },
        repeats_at(REPEATED_UP_TO, args.repeats),
        repeats_at(1, args.repeats)
    );
    let mut tables = Tables::new();
    for file in &scenes {
        let scene = Scene::read(file, &d)?;
        scene_curves(args, &d, &scene, opts, &mut tables)?;
    }
    let mut written = Vec::new();
    let Tables {
        main,
        methods,
        costs,
        equal,
        targets,
        crossings,
        paints,
    } = tables;
    for (t, name) in [
        (main, "error_vs_render_time.csv"),
        (methods, "methods.csv"),
        (costs, "cost_ratio.csv"),
        (equal, "equal_time.csv"),
        (targets, "targets.csv"),
        (crossings, "crossings.csv"),
        (paints, "paints_at_nodes.csv"),
    ] {
        written.push(t.write(&args.out, name)?.display().to_string());
    }
    println!(
        "Wrote {}. Wall time {:.0} s.",
        written.join(", "),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// One scene: its reference, curves, cost, tables, plot and picture.
fn scene_curves(
    args: &Args,
    d: &spectral_quadrature_generator::Derivation,
    scene: &Scene,
    opts: Options,
    tables: &mut Tables,
) -> Result<(), Error> {
    let threads = opts.threads;
    let label = format!("{} ({})", scene.scene, scene.light);
    let stem = scene
        .file
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let g = Geometry::new(scene, args.size);
    let seen = measure::seen(&g);
    let setup = Setup::new(scene, d)?;
    let reference = reference(args, scene, &setup, &g, &seen, threads)?;
    let white = measure::white(d, scene, &reference.xyz, &seen)?;
    println!(
        "## Scene {label}: {}\n\n{} pixels see the box; the reference: {} paths a pixel × 2 seeds, own error {:.4} mean, {:.4} p95",
        scene.description,
        seen.len(),
        reference.spp,
        reference.own_mean,
        reference.own_p95
    );
    let box_alone = scene.lights.len() == 1
        && scene.lights[0].name == "box"
        && scene.paint_srgb.is_none()
        && scene.texture.is_none();
    if let (Some(path), true) = (&args.radiosity, box_alone) {
        let rad = read_radiosity(path)?;
        if rad.len() != reference.xyz.len() {
            return Err(Error::Sampling(format!(
                "{}: {} pixels, the render has {}",
                path.display(),
                rad.len(),
                reference.xyz.len()
            )));
        }
        // The radiosity file's units are the light's (Y = 1): scaled to the reference's by
        // the ratio of their summed luminance over the seen pixels.
        let sum = |v: &[[f64; 3]]| seen.iter().map(|&k| v[k][1]).sum::<f64>();
        let k = sum(&reference.xyz) / sum(&rad);
        let rad: Vec<[f64; 3]> = rad.iter().map(|v| v.map(|x| x * k)).collect();
        let (m, p) = measure::stats(&rad, &reference.xyz, &seen, white);
        println!(
            "Cross-check: the `cornell` tool's radiosity reference ({}) against this 1 nm reference: mean ΔE00 {m:.3}, p95 {p:.3} (the radiosity mesh's own error included)",
            path.display()
        );
    }
    tables.main.row([
        scene.scene.clone(),
        scene.light.clone(),
        Method::Reference.name(),
        Method::Reference.lanes().to_string(),
        (reference.spp * 2).to_string(),
        f4(reference.seconds),
        format!(
            "{:.4e}",
            (reference.spp * 2 * args.size * args.size) as f64 / reference.seconds.max(1e-9)
        ),
        f4(reference.own_mean),
        f4(reference.own_p95),
    ]);
    let max_level = levels(args.max_spp).last().copied().unwrap_or(1);
    let judge = Judge {
        reference: &reference.xyz,
        seen: &seen,
        white,
        shown_spp: SHOWN_SPP.min(max_level),
        same_path_spp: args.same_path_spp.clamp(1, max_level),
    };
    let runs = curves_of(args, &setup, &g, opts, &judge)?;
    let stop = runs
        .iter()
        .find(|r| r.method == Method::Fixed { n: 8 })
        .and_then(|r| r.points.last().map(|p| p.spp))
        .unwrap_or(1);
    let flat = runs
        .iter()
        .find(|r| r.method == Method::Fixed { n: 8 })
        .is_some_and(|r| curves::flattened(&r.points));
    println!(
        "\nThe 8-node set's curve {} at {stop} paths a pixel; RGB and the fixed sets stop there.",
        if flat {
            format!(
                "flattened (fell by less than {:.0} % over the last doubling)",
                100.0 * curves::FLAT
            )
        } else {
            "reached --max-spp".to_string()
        }
    );
    // The spectral error alone: each method's image at same_path_spp against the 1 nm image
    // through the same paths (the methods' seed).
    let same = setup.render(Method::Reference, &g, &[judge.same_path_spp], opts)?;
    let same_ref = &same.images[0];
    for run in &runs {
        for p in &run.points {
            tables.main.row([
                scene.scene.clone(),
                scene.light.clone(),
                run.method.name(),
                run.method.lanes().to_string(),
                p.spp.to_string(),
                f4(p.seconds),
                format!(
                    "{:.4e}",
                    (p.spp * args.size * args.size) as f64 / p.seconds.max(1e-9)
                ),
                f4(p.mean),
                f4(p.p95),
            ]);
        }
        let last = run.points.last().copied().unwrap_or(Point {
            spp: 0,
            seconds: f64::NAN,
            mean: f64::NAN,
            p95: f64::NAN,
        });
        let (sm, sp) = run.same_path.as_ref().map_or((f64::NAN, f64::NAN), |img| {
            measure::stats(img, same_ref, &seen, white)
        });
        let frame = curves::median(&run.frames);
        println!(
            "- {}: {} paths a pixel in {:.2} s ({:.2e} paths/s), mean ΔE00 {:.3}; through the reference's paths at {} paths a pixel {:.3}; frame {:.3} ms; tables made in {:.2} s",
            run.method.name(),
            last.spp,
            last.seconds,
            (last.spp * args.size * args.size) as f64 / last.seconds.max(1e-9),
            last.mean,
            judge.same_path_spp,
            sm,
            1e3 * frame,
            run.tables
        );
        tables.methods.row([
            scene.scene.clone(),
            scene.light.clone(),
            run.method.name(),
            run.method.lanes().to_string(),
            last.spp.to_string(),
            f4(last.seconds),
            format!(
                "{:.4e}",
                (last.spp * args.size * args.size) as f64 / last.seconds.max(1e-9)
            ),
            format!("{frame:.3e}"),
            f4(last.mean),
            f4(last.p95),
            judge.same_path_spp.to_string(),
            if sm.is_nan() { String::new() } else { f4(sm) },
            if sp.is_nan() { String::new() } else { f4(sp) },
            format!("{:.3}", run.tables),
        ]);
    }

    // The cost ratio, in turns, beside the same ratio from the curves' run.
    let c = cost(args, &setup, &g, opts)?;
    let last_seconds = |m: Method| {
        runs.iter()
            .find(|r| r.method == m)
            .and_then(|r| r.points.last().map(|p| p.seconds))
            .unwrap_or(f64::NAN)
    };
    let curves_ratio = last_seconds(Method::Fixed { n: 8 }) / last_seconds(Method::Rgb);
    println!(
        "\nCost: the 8-node set's render time over RGB's, the same paths, {} paths a pixel in turns of {COST_CHUNK} (median of the turns, quartiles): {:.3} ({:.3}-{:.3}); {:.3e} against {:.3e} paths/s; in the curves' run: {curves_ratio:.3}. Baseline loop over the AVX2 loop: the 8-node set {:.3} ({:.3}-{:.3}), the reference {:.3} ({:.3}-{:.3})",
        c.spp,
        c.fixed8_over_rgb[1],
        c.fixed8_over_rgb[0],
        c.fixed8_over_rgb[2],
        c.fixed8_paths_per_second,
        c.rgb_paths_per_second,
        c.fixed8_baseline_over_avx2[1],
        c.fixed8_baseline_over_avx2[0],
        c.fixed8_baseline_over_avx2[2],
        c.reference_baseline_over_avx2[1],
        c.reference_baseline_over_avx2[0],
        c.reference_baseline_over_avx2[2],
    );
    tables.costs.row([
        scene.scene.clone(),
        scene.light.clone(),
        c.spp.to_string(),
        format!("{:.4e}", c.rgb_paths_per_second),
        format!("{:.4e}", c.fixed8_paths_per_second),
        f4(c.fixed8_over_rgb[1]),
        f4(c.fixed8_over_rgb[0]),
        f4(c.fixed8_over_rgb[2]),
        f4(curves_ratio),
        f4(c.fixed8_baseline_over_avx2[1]),
        f4(c.fixed8_baseline_over_avx2[0]),
        f4(c.fixed8_baseline_over_avx2[2]),
        f4(c.reference_baseline_over_avx2[1]),
        f4(c.reference_baseline_over_avx2[0]),
        f4(c.reference_baseline_over_avx2[2]),
    ]);

    let curve = |m: Method| runs.iter().find(|r| r.method == m).map(|r| &r.points[..]);
    let fixed8 = curve(Method::Fixed { n: 8 }).unwrap_or(&[]);
    // Equal time: each method's error at the time the 8-node set takes at SHOWN_SPP.
    if let Some(at) = fixed8
        .iter()
        .find(|p| p.spp == judge.shown_spp)
        .map(|p| p.seconds)
    {
        println!(
            "\nAt equal time ({at:.3} s, the 8-node set at {} spp):",
            judge.shown_spp
        );
        for run in &runs {
            let e = curves::at_time(&run.points, at);
            println!(
                "- {}: {}",
                run.method.name(),
                e.map_or("—".into(), |v| format!("{v:.3}"))
            );
            tables.equal.row([
                scene.scene.clone(),
                scene.light.clone(),
                run.method.name(),
                f4(at),
                e.map_or(String::new(), f4),
                f4(reference.own_mean),
            ]);
        }
    }
    // The targets at every point of the plot: the 8-node set below RGB and pbrt-v4 ×4.
    println!();
    let pbrt4 = Method::Random {
        sampler: tools::random_wavelengths::Sampler::Visible,
        k: 4,
    };
    for other in [Method::Rgb, pbrt4] {
        let b = curve(other).unwrap_or(&[]);
        let all = curves::side_by_side(fixed8, b);
        let misses: Vec<String> = all
            .iter()
            .filter(|x| x.1 >= x.2)
            .map(|x| format!("{:.4} s: {:.2} against {:.2}", x.0, x.1, x.2))
            .collect();
        println!(
            "The 8-node set against {} at {} times: {}",
            other.name(),
            all.len(),
            if misses.is_empty() {
                "below at every one".to_string()
            } else {
                format!("not below at {}", misses.join("; "))
            }
        );
        for (t, a, b) in all {
            tables.targets.row([
                scene.scene.clone(),
                scene.light.clone(),
                other.name(),
                format!("{t:.5}"),
                f4(a),
                f4(b),
                (a < b).to_string(),
            ]);
        }
    }
    // Where random wavelengths pass below each fixed set for good.
    for r in runs.iter().filter(|r| r.random()) {
        for f in runs
            .iter()
            .filter(|f| matches!(f.method, Method::Fixed { .. }))
        {
            let at = curves::passes_below(&r.points, &f.points).map(|k| r.points[k]);
            let fixed_mean = at.and_then(|p| curves::at_time_held(&f.points, p.seconds));
            if let (Some(p), Some(e)) = (at, fixed_mean) {
                println!(
                    "{} passes below {} for good from {} paths a pixel ({:.2} s: {:.3} against {:.3})",
                    r.method.name(),
                    f.method.name(),
                    p.spp,
                    p.seconds,
                    p.mean,
                    e
                );
            } else {
                println!(
                    "{} is not below {} at its last level",
                    r.method.name(),
                    f.method.name()
                );
            }
            tables.crossings.row([
                scene.scene.clone(),
                scene.light.clone(),
                r.method.name(),
                f.method.name(),
                at.map_or(String::new(), |p| p.spp.to_string()),
                at.map_or(String::new(), |p| f4(p.seconds)),
                at.map_or(String::new(), |p| f4(p.mean)),
                fixed_mean.map_or(String::new(), f4),
            ]);
        }
    }
    // Each measured paint at each fixed set's nodes.
    for n in spectral_quadrature_render::render::methods::FIXED_SIZES {
        for e in setup.paint_errors(n)? {
            tables.paints.row([
                scene.scene.clone(),
                scene.light.clone(),
                Method::Fixed { n }.name(),
                e.light,
                e.paint,
                e.bounces.to_string(),
                f4(e.de00),
                f4(e.de00_smoothed),
            ]);
        }
    }

    // The plot and the picture.
    let svg = args.out.join(format!("{stem}.svg"));
    let drawn: Vec<(Method, Vec<Point>)> =
        runs.iter().map(|r| (r.method, r.points.clone())).collect();
    plot(
        &svg,
        &format!(
            "Scene {label}: mean ΔE00 against render time ({} px, {} threads)",
            args.size, threads
        ),
        &drawn,
        reference.own_mean,
    )?;
    let (_, srgb) = d.display("SRGB")?;
    let tone = |img: &[[f64; 3]]| picture::tone_map(img, args.size, white, &srgb.xyz_to_rgb);
    let factor = if args.size < 128 {
        128usize.div_ceil(args.size)
    } else {
        1
    };
    let mut top = vec![picture::labelled(
        &upscale(&tone(&reference.xyz), factor),
        "reference (1 nm)",
        3,
    )];
    let mut bottom = vec![picture::labelled(
        &Rgb8::filled(args.size * factor, args.size * factor, [24, 24, 24]),
        &format!("{} spp; dE00 maps below", judge.shown_spp),
        3,
    )];
    for run in &runs {
        if let Some(img) = &run.shown {
            let de = measure::de00(img, &reference.xyz, &seen, white);
            let mean = de.iter().sum::<f64>() / de.len().max(1) as f64;
            top.push(picture::labelled(
                &upscale(&tone(img), factor),
                &run.method.name(),
                3,
            ));
            bottom.push(picture::labelled(
                &upscale(&picture::de_map(&de, &seen, args.size), factor),
                &format!("mean {mean:.2}"),
                3,
            ));
        }
    }
    let png = args.out.join(format!("{stem}.png"));
    picture::grid(&[top, bottom], 8).write_png(&png)?;
    println!("\nWrote {} and {}.\n", svg.display(), png.display());
    Ok(())
}
