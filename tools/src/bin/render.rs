//! Error against render time: the Cornell box path traced with every spectral method, each
//! image judged in CIEDE2000 against the 1 nm reference through the same paths
//! (`docs/render-time.md`).
//!
//! ```text
//! cargo run --release -p spectral-quadrature-tools --bin render
//! cargo run --release -p spectral-quadrature-tools --bin render -- --scene examples/render/a.toml --size 32 --max-spp 16
//! ```
//!
//! Writes `<out>/error_vs_render_time.csv` (every method at every level of samples per pixel),
//! `<out>/cost_ratio.csv` (the 8-node set's render time over RGB's, measured in one run, and
//! what the AVX2 loop gains),
//! `<out>/equal_time.csv` (each method's error at the time the 8-node set takes at 64 samples
//! per pixel), and per scene `<out>/<scene>.svg` (mean ΔE00 against wall seconds, log-log) and
//! `<out>/<scene>.png` (the images at 64 samples per pixel over their ΔE00 maps, each method's
//! name drawn in). The reference is cached in `<reference-dir>/<scene>-<size>.txt`.
//!
//! **Time.** Each method's tables (sets searched, maps baked, texels converted) are made
//! before its render and not counted. The methods of a scene then take turns on the machine,
//! at most [`CHUNK`] passes (one path a pixel each) before the next method's turn, and each
//! method's time is the sum of its own turns' wall-clock seconds and of its conversions to
//! XYZ: load from other processes falls on every method alike.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::builder::TypedValueParser as _;
use clap::Parser;
use plotters::prelude::*;

use spectral_quadrature_tools as tools;
use tools::cornell::picture::{self, Rgb8};
use tools::render::measure::{self, CachedReference};
use tools::render::methods::{Method, Setup};
use tools::render::scene::{self, Scene};
use tools::render::transport::{self, Geometry, Options};
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
    /// Samples per pixel the curves go up to (powers of 2 from 1; 1 to 1048576).
    #[arg(long, default_value_t = 8192, value_parser = clap::value_parser!(u32).range(1..=1_048_576).map(|v| v as usize))]
    max_spp: usize,
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
    /// Paths a pixel for the cost ratio: RGB, the 8-node set and its baseline loop in turns.
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

/// One row of the CSV.
struct Row {
    scene: String,
    light: String,
    method: String,
    n: usize,
    spp: usize,
    seconds: f64,
    paths_per_second: f64,
    mean: f64,
    p95: f64,
}

/// The most passes a method renders before the next takes its turn.
const CHUNK: usize = 64;
/// The passes of one turn in the cost ratio's measurement.
const COST_CHUNK: usize = 8;

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
    let data = tools::cornell::read_data(Path::new(tools::DATA_DIR))?;
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
        "cargo run --release -p spectral-quadrature-tools --bin render -- --scene {} --size {} --reference-spp {} --remake-reference",
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

/// Each method's error at `time` seconds: log-log interpolation along its curve; `None`
/// outside the curve's times.
fn at_time(points: &[(f64, f64)], time: f64) -> Option<f64> {
    for w in points.windows(2) {
        let ((t0, e0), (t1, e1)) = (w[0], w[1]);
        if t0 <= time && time <= t1 && t0 > 0.0 && t1 > t0 {
            let f = (time.ln() - t0.ln()) / (t1.ln() - t0.ln());
            return Some((e0.ln() + f * (e1.ln() - e0.ln())).exp());
        }
    }
    points
        .iter()
        .find(|p| (p.0 - time).abs() <= 1e-12 * time)
        .map(|p| p.1)
}

const COLOURS: [RGBColor; 10] = [
    RGBColor(220, 50, 47),
    RGBColor(38, 139, 210),
    RGBColor(133, 153, 0),
    RGBColor(211, 54, 130),
    RGBColor(108, 113, 196),
    RGBColor(181, 137, 0),
    RGBColor(42, 161, 152),
    RGBColor(203, 75, 22),
    RGBColor(88, 110, 117),
    RGBColor(0, 0, 0),
];

fn plot_err<E: std::fmt::Debug>(e: E) -> Error {
    Error::Plot(format!("{e:?}"))
}

/// Mean ΔE00 against wall seconds, log-log, one curve per method, the reference's own error as
/// a dashed floor.
fn plot(
    path: &Path,
    title: &str,
    curves: &[(String, Vec<(f64, f64)>)],
    floor: f64,
) -> Result<(), Error> {
    let root = SVGBackend::new(path, (820, 560)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let (chart_area, legend_area) = root.split_horizontally(620);
    let pts = curves.iter().flat_map(|c| c.1.iter());
    let (mut t0, mut t1, mut e0, mut e1) = (f64::MAX, 0.0f64, f64::MAX, 0.0f64);
    for &(t, e) in pts {
        t0 = t0.min(t);
        t1 = t1.max(t);
        e0 = e0.min(e);
        e1 = e1.max(e);
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
        .x_label_formatter(&|v| format!("{v:.2e}"))
        .y_label_formatter(&|v| format!("{v:.2}"))
        .draw()
        .map_err(plot_err)?;
    for (k, (name, pts)) in curves.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        chart
            .draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(2)))
            .map_err(plot_err)?;
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled())))
            .map_err(plot_err)?;
        let y = 30 + 22 * k as i32;
        legend_area
            .draw(&PathElement::new(
                vec![(10, y), (40, y)],
                colour.stroke_width(2),
            ))
            .map_err(plot_err)?;
        legend_area
            .draw(&Text::new(name.clone(), (48, y - 7), ("sans-serif", 13)))
            .map_err(plot_err)?;
    }
    // The floor: dashes along the time axis.
    let steps = 40;
    let dash: Vec<((f64, f64), (f64, f64))> = (0..steps)
        .step_by(2)
        .map(|i| {
            let a = (t0.ln() + (t1.ln() - t0.ln()) * i as f64 / steps as f64).exp();
            let b = (t0.ln() + (t1.ln() - t0.ln()) * (i + 1) as f64 / steps as f64).exp();
            ((a, floor), (b, floor))
        })
        .collect();
    for (a, b) in dash {
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![a, b],
                BLACK.stroke_width(1),
            )))
            .map_err(plot_err)?;
    }
    let y = 30 + 22 * curves.len() as i32;
    legend_area
        .draw(&PathElement::new(
            vec![(10, y), (18, y)],
            BLACK.stroke_width(1),
        ))
        .map_err(plot_err)?;
    legend_area
        .draw(&PathElement::new(
            vec![(26, y), (34, y)],
            BLACK.stroke_width(1),
        ))
        .map_err(plot_err)?;
    legend_area
        .draw(&Text::new(
            format!("reference's own error ({floor:.3})"),
            (48, y - 7),
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
        "# Error against render time\n\n{} × {} pixels, 1 to {} paths a pixel, {threads} threads, vector loop: {}\n",
        args.size,
        args.size,
        spp.last().copied().unwrap_or(1),
        if opts.simd && transport::has_avx2() { "AVX2" } else { "baseline" }
    );
    let mut rows: Vec<Row> = Vec::new();
    let mut costs = tools::csv_table::Table::new(
        "scene,light,rgb_paths_per_second,fixed8_paths_per_second,fixed8_over_rgb_time,fixed8_over_rgb_time_curves,fixed8_baseline_paths_per_second,baseline_over_avx2_time,spp",
    );
    let mut equal = tools::csv_table::Table::new(
        "scene,light,method,seconds,mean_de00_at_equal_time,reference_own_mean_de00",
    );
    for file in &scenes {
        let scene = Scene::read(file, &d)?;
        let label = format!("{} ({})", scene.scene, scene.light);
        let stem = file
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        let g = Geometry::new(&scene, args.size);
        let seen = measure::seen(&g);
        let setup = Setup::new(&scene, &d)?;
        let reference = reference(args, &scene, &setup, &g, &seen, threads)?;
        let white = measure::white(&d, &scene, &reference.xyz, &seen)?;
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
        rows.push(Row {
            scene: scene.scene.clone(),
            light: scene.light.clone(),
            method: Method::Reference.name(),
            n: Method::Reference.lanes(),
            spp: reference.spp * 2,
            seconds: reference.seconds,
            paths_per_second: (reference.spp * 2 * args.size * args.size) as f64
                / reference.seconds.max(1e-9),
            mean: reference.own_mean,
            p95: reference.own_p95,
        });
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
            2,
        )];
        let mut bottom = vec![picture::labelled(
            &Rgb8::filled(args.size * factor, args.size * factor, [24, 24, 24]),
            "below: dE00 maps",
            2,
        )];
        let mut curves: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
        let shown_spp = 64.min(*spp.last().unwrap_or(&1));
        // Every method's tables first (load time, not render time), then the methods take
        // turns on the machine, at most CHUNK passes each, so that their times see the same
        // load from other processes.
        let methods = Method::all_for(&scene);
        let mut runs = Vec::new();
        for &method in &methods {
            let t = Instant::now();
            let p = setup.progress(method, &g, opts)?;
            runs.push((method, p, 0.0f64, Vec::new(), t.elapsed().as_secs_f64()));
        }
        for &level in &spp {
            loop {
                let mut any = false;
                for run in runs.iter_mut() {
                    let done = run.1.spp();
                    if done < level {
                        run.2 += run.1.advance((done + CHUNK).min(level));
                        any = true;
                    }
                }
                if !any {
                    break;
                }
            }
            for (method, p, seconds, pts, _) in runs.iter_mut() {
                let (img, t) = p.image();
                *seconds += t;
                let (mean, p95) = measure::stats(&img, &reference.xyz, &seen, white);
                let paths = level * args.size * args.size;
                rows.push(Row {
                    scene: scene.scene.clone(),
                    light: scene.light.clone(),
                    method: method.name(),
                    n: method.lanes(),
                    spp: level,
                    seconds: *seconds,
                    paths_per_second: paths as f64 / seconds.max(1e-9),
                    mean,
                    p95,
                });
                pts.push((*seconds, mean));
                if level == shown_spp {
                    let de = measure::de00(&img, &reference.xyz, &seen, white);
                    let name = format!("{}, {} spp", method.name(), shown_spp);
                    top.push(picture::labelled(&upscale(&tone(&img), factor), &name, 2));
                    bottom.push(picture::labelled(
                        &upscale(&picture::de_map(&de, &seen, args.size), factor),
                        &format!("mean {mean:.2}"),
                        2,
                    ));
                }
            }
        }
        for (method, _, seconds, pts, load) in runs {
            let last = pts.last().copied().unwrap_or((0.0, f64::NAN));
            let paths = spp.last().copied().unwrap_or(1) * args.size * args.size;
            println!(
                "- {}: {} paths a pixel in {seconds:.2} s ({:.2e} paths/s), mean ΔE00 {:.3} (tables made in {load:.2} s)",
                method.name(),
                spp.last().copied().unwrap_or(1),
                paths as f64 / seconds.max(1e-9),
                last.1,
            );
            curves.push((method.name(), pts));
        }

        // The cost ratio: RGB, the 8-node set and the 8-node set's baseline loop take turns
        // of COST_CHUNK passes over the same paths; each one's time is the sum of its turns.
        let mut cost: Vec<(Box<dyn transport::Progressive + '_>, f64)> = vec![
            (setup.progress(Method::Rgb, &g, opts)?, 0.0),
            (setup.progress(Method::Fixed { n: 8 }, &g, opts)?, 0.0),
            (
                setup.progress(
                    Method::Fixed { n: 8 },
                    &g,
                    Options {
                        simd: false,
                        ..opts
                    },
                )?,
                0.0,
            ),
        ];
        let cost_spp = args.cost_spp.max(1);
        let mut done = 0;
        while done < cost_spp {
            done = (done + COST_CHUNK).min(cost_spp);
            for (p, t) in cost.iter_mut() {
                *t += p.advance(done);
            }
        }
        let (mr, mf, mb) = (cost[0].1, cost[1].1, cost[2].1);
        let paths = (cost_spp * args.size * args.size) as f64;
        // The same ratio from the curves' run: the two methods' total times at the last level.
        let total = |name: &str| {
            rows.iter()
                .rev()
                .find(|r| r.scene == scene.scene && r.light == scene.light && r.method == name)
                .map_or(f64::NAN, |r| r.seconds)
        };
        let curves_ratio = total("fixed 8") / total("RGB");
        println!(
            "\nCost: the 8-node set's render time over RGB's, the same paths, {cost_spp} paths a pixel in turns of {COST_CHUNK}: {:.3} ({:.3e} against {:.3e} paths/s); in the curves' run: {curves_ratio:.3}. The 8-node set's baseline loop: {:.3e} paths/s, {:.3}× the time of {}",
            mf / mr,
            paths / mf,
            paths / mr,
            paths / mb,
            mb / mf,
            if opts.simd && transport::has_avx2() { "AVX2" } else { "the same loop" }
        );
        costs.row([
            scene.scene.clone(),
            scene.light.clone(),
            format!("{:.4e}", paths / mr),
            format!("{:.4e}", paths / mf),
            format!("{:.4}", mf / mr),
            format!("{curves_ratio:.4}"),
            format!("{:.4e}", paths / mb),
            format!("{:.4}", mb / mf),
            cost_spp.to_string(),
        ]);

        // Equal time: each method's error at the time the 8-node set takes at 64 spp.
        let fixed8 = curves.iter().find(|c| c.0 == "fixed 8");
        if let Some(at) = fixed8.and_then(|c| {
            let k = spp.iter().position(|&s| s == shown_spp)?;
            c.1.get(k).map(|p| p.0)
        }) {
            println!("\nAt equal time ({at:.3} s, the 8-node set at {shown_spp} spp):");
            for (name, pts) in &curves {
                let e = at_time(pts, at);
                println!("- {name}: {}", e.map_or("—".into(), |v| format!("{v:.3}")));
                equal.row([
                    scene.scene.clone(),
                    scene.light.clone(),
                    name.clone(),
                    format!("{at:.4}"),
                    e.map_or(String::new(), |v| format!("{v:.4}")),
                    format!("{:.4}", reference.own_mean),
                ]);
            }
        }
        let svg = args.out.join(format!("{stem}.svg"));
        plot(
            &svg,
            &format!(
                "Scene {label}: mean ΔE00 against render time ({} px, {} threads)",
                args.size, threads
            ),
            &curves,
            reference.own_mean,
        )?;
        let png = args.out.join(format!("{stem}.png"));
        picture::grid(&[top, bottom], 4).write_png(&png)?;
        println!("\nWrote {} and {}.\n", svg.display(), png.display());
    }
    let mut csv = tools::csv_table::Table::new(
        "scene,light,method,n,spp,wall_seconds,paths_per_second,mean_de00,p95_de00",
    );
    for r in &rows {
        csv.row([
            r.scene.clone(),
            r.light.clone(),
            r.method.clone(),
            r.n.to_string(),
            r.spp.to_string(),
            format!("{:.4}", r.seconds),
            format!("{:.4e}", r.paths_per_second),
            format!("{:.4}", r.mean),
            format!("{:.4}", r.p95),
        ]);
    }
    let csv_path = csv.write(&args.out, "error_vs_render_time.csv")?;
    let cost_path = costs.write(&args.out, "cost_ratio.csv")?;
    let equal_path = equal.write(&args.out, "equal_time.csv")?;
    println!(
        "Wrote {}, {} and {}. Wall time {:.0} s.",
        csv_path.display(),
        cost_path.display(),
        equal_path.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
