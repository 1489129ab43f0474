//! The Cornell box, rendered by radiosity once per spectral method, compared in CIEDE2000
//! against the 1 nm reference, and drawn side by side (`docs/cornell-box.md`).
//!
//! ```text
//! cargo run --release -p spectral-quadrature-render --bin cornell
//! cargo run --release -p spectral-quadrature-render --bin cornell -- --light F11 --size 192 --patches 16
//! ```
//!
//! Writes `<out>/<light>.png` (the images over their ΔE00 maps), `<out>/scale.png` (the maps'
//! colour scale), `<out>/cornell.csv` (every method's errors and time) and
//! `<out>/cornell_spp.csv` (the samples per pixel at which random wavelengths reach each fixed
//! set), and prints the tables. `--reference-xyz FILE` writes only the 1 nm reference under the
//! box's light, per-pixel XYZ, the reference the path tracer `examples/renderer` checks itself
//! against.

use spectral_quadrature_render::cornell::methods::{self as m, Albedo, Spectral, Upsampler};
use spectral_quadrature_render::cornell::picture::{self, Rgb8};
use spectral_quadrature_render::cornell::radiosity::Bounces;
use spectral_quadrature_render::cornell::{self as cb, Light};
use spectral_quadrature_tools as tools;
use tools::random_wavelengths::{stream_seed, Sampler};
use tools::upsampling::mean_p95;
use tools::Error;

use std::path::PathBuf;
use std::time::Instant;

use clap::builder::TypedValueParser as _;
use clap::Parser;

/// Renders the Cornell box by radiosity with each spectral method and compares them.
#[derive(Parser)]
#[command(version)]
struct Args {
    /// The folder the pictures and CSV files go to.
    #[arg(long, value_name = "DIR", default_value = "docs/cornell")]
    out: PathBuf,
    /// Image width and height, pixels (8 to 1024).
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u16).range(8..=1024).map(usize::from))]
    size: usize,
    /// Mesh resolution: patches along the back wall's width (556 mm); every quad is cut into
    /// patches no longer than 556 mm / this along either edge (1 to 64).
    #[arg(long, default_value_t = 12, value_parser = clap::value_parser!(u16).range(1..=64).map(usize::from))]
    patches: usize,
    /// The light (repeatable): `box` (the box's own), `F11`, `LED_B2`. Default: all three.
    #[arg(long = "light", value_enum)]
    lights: Vec<LightArg>,
    /// Samples per pixel the random-wavelength curves go up to (powers of 2 from 1; 1 to 65536).
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(1..=65536).map(|v| v as usize))]
    max_spp: usize,
    /// The seed of the random wavelengths.
    #[arg(long, default_value_t = 1988)]
    seed: u64,
    /// Only write the 1 nm reference image under the box's light to FILE, per-pixel XYZ as text
    /// (for the path tracer's check, `examples/renderer`), and nothing else.
    #[arg(long, value_name = "FILE")]
    reference_xyz: Option<PathBuf>,
}

/// The lights on the command line: clap's names for [`Light`], which the library keeps free of
/// the command line's parser.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum LightArg {
    /// The box's own light (`cornell_box_light.csv`).
    #[value(name = "box")]
    Box,
    /// CIE F11, three narrow lines.
    #[value(name = "F11")]
    F11,
    /// CIE LED-B2, a narrow blue pump beside a phosphor.
    #[value(name = "LED_B2")]
    LedB2,
}

impl From<LightArg> for Light {
    fn from(a: LightArg) -> Light {
        match a {
            LightArg::Box => Light::Box,
            LightArg::F11 => Light::F11,
            LightArg::LedB2 => Light::LedB2,
        }
    }
}

const SIZES: [usize; 3] = [4, 6, 8];

fn main() {
    let args = Args::parse();
    if let Err(e) = run(&args) {
        eprintln!("cornell: error: {e}");
        std::process::exit(2);
    }
}

/// One row of the error table.
struct Row {
    light: &'static str,
    method: String,
    cost: usize,
    bounces: &'static str,
    mean: f64,
    p95: f64,
    seconds: f64,
}

/// The samples per pixel at which a sampler's mean reaches `target`: interpolated in log-log
/// between the levels around it; past the last level extended along the −1/2 slope of unbiased
/// noise (marked `~`).
fn spp_to_reach(spp: &[usize], means: &[f64], target: f64) -> String {
    if means[0] <= target {
        return "≤1".into();
    }
    for k in 1..spp.len() {
        if means[k] <= target {
            let (x0, x1) = ((spp[k - 1] as f64).ln(), (spp[k] as f64).ln());
            let (y0, y1) = (means[k - 1].ln(), means[k].ln());
            let x = x0 + (target.ln() - y0) / (y1 - y0) * (x1 - x0);
            return format!("{:.0}", x.exp());
        }
    }
    let last = spp.len() - 1;
    let s = spp[last] as f64 * (means[last] / target).powi(2);
    format!("~{}", round_sig(s))
}

fn round_sig(x: f64) -> String {
    if x < 1000.0 {
        return format!("{x:.0}");
    }
    let p = 10f64.powf(x.log10().floor() - 1.0);
    format!("{:.0}", (x / p).round() * p)
}

/// The reference under the box's light as text: a header of `#` lines (the size; the white
/// every image is judged against, [`m::white`]; the paints' white-balanced linear sRGB under the
/// light, the input of the crate's upsampling map), then `seen,x,y,z` for each pixel row by row
/// from the top, `seen` one of `paint`, `light`, `miss`. XYZ in units where the light's own XYZ
/// (1 nm, 400-700 nm) has Y = 1: a folded set's units, where a reflectance of 1 at every node
/// under the light has Y = 1.
fn write_reference(args: &Args, path: &std::path::Path) -> Result<(), Error> {
    use std::fmt::Write as _;
    let d = spectral_quadrature_generator::derive(&tools::settings())?;
    let data = cb::read_data(std::path::Path::new(tools::DATA_DIR))?;
    let scene = m::Scene::new(&data.quads, 556.0 / args.patches.max(1) as f64, args.size);
    let curve = cb::light_curve(&data, &d, Light::Box)?;
    let reference = m::reference(&d, &curve, &data.paints)?;
    let b = reference.solve(&scene, Bounces::All);
    let image = scene.view.shade(&reference.patch_xyz(&b));
    let painted = scene.view.painted();
    let white = m::white(&d, &curve, &image, &painted)?;
    let light_y = m::xyz_1nm(&d, |l| curve.at(l))?[1];
    let (_, srgb) = d.display("SRGB")?;
    let rgb = spectral_quadrature_generator::upsampling::exact_rgb(&d, srgb, &curve, &data.paints)?;
    let mut text = format!(
        "# The cornell tool's 1 nm reference under the box's light (--patches {}), XYZ with the light's Y = 1\n# size {}\n# white {:.9} {:.9} {:.9}\n",
        args.patches,
        args.size,
        white[0] / light_y,
        white[1] / light_y,
        white[2] / light_y
    );
    for (name, c) in ["white", "red", "green"].iter().zip(&rgb) {
        let _ = writeln!(text, "# paint {name} {:.6} {:.6} {:.6}", c[0], c[1], c[2]);
    }
    text.push_str("seen,x,y,z\n");
    for (p, v) in scene.view.pixels.iter().zip(&image) {
        let seen = match p.seen {
            cb::camera::Seen::Paint => "paint",
            cb::camera::Seen::Light => "light",
            cb::camera::Seen::Miss => "miss",
        };
        let _ = writeln!(
            text,
            "{seen},{:.7e},{:.7e},{:.7e}",
            v[0] / light_y,
            v[1] / light_y,
            v[2] / light_y
        );
    }
    std::fs::write(path, text).map_err(|e| Error::Write {
        path: path.to_path_buf(),
        source: e,
    })?;
    println!(
        "Wrote {}: {} × {} pixels, {} painted; the brightest painted pixel has Y = {:.6} of the light's.",
        path.display(),
        args.size,
        args.size,
        painted.len(),
        white[1] / light_y
    );
    Ok(())
}

fn run(args: &Args) -> Result<(), Error> {
    if let Some(path) = &args.reference_xyz {
        return write_reference(args, path);
    }
    let start = Instant::now();
    let lights = if args.lights.is_empty() {
        Light::ALL.to_vec()
    } else {
        args.lights.iter().map(|&l| Light::from(l)).collect()
    };
    std::fs::create_dir_all(&args.out).map_err(|e| Error::Write {
        path: args.out.clone(),
        source: e,
    })?;
    let d = spectral_quadrature_generator::derive(&tools::settings())?;
    let data = cb::read_data(std::path::Path::new(tools::DATA_DIR))?;
    let patch_mm = 556.0 / args.patches.max(1) as f64;
    let scene = m::Scene::new(&data.quads, patch_mm, args.size);
    println!(
        "# The Cornell box by radiosity\n\n{} patches ({:.0} mm at most), form factors {:.2} s; {} × {} pixels, {} painted",
        scene.mesh.patches.len(),
        patch_mm,
        scene.form_factor_seconds,
        args.size,
        args.size,
        scene.view.painted().len()
    );
    let (_, srgb) = d.display("SRGB")?;
    let painted = scene.view.painted();
    let mut rows: Vec<Row> = Vec::new();
    let mut spp_rows: Vec<Vec<String>> = Vec::new();
    let mut legends: Vec<String> = Vec::new();
    let levels: Vec<usize> = std::iter::successors(Some(1usize), |s| Some(s * 2))
        .take_while(|&s| s <= args.max_spp.max(1))
        .collect();
    for (li, &light) in lights.iter().enumerate() {
        let name = light.name();
        let curve = cb::light_curve(&data, &d, light)?;
        let paints = &data.paints;
        let reference = m::reference(&d, &curve, paints)?;
        let t = Instant::now();
        let b_all = reference.solve(&scene, Bounces::All);
        let ref_all = scene.view.shade(&reference.patch_xyz(&b_all));
        let ref_seconds = t.elapsed().as_secs_f64();
        let b_direct = reference.solve(&scene, Bounces::Direct);
        let ref_direct = scene.view.shade(&reference.patch_xyz(&b_direct));
        let white_all = m::white(&d, &curve, &ref_all, &painted)?;
        let white_direct = m::white(&d, &curve, &ref_direct, &painted)?;
        rows.push(Row {
            light: name,
            method: reference.name.clone(),
            cost: reference.cost,
            bounces: "all",
            mean: 0.0,
            p95: 0.0,
            seconds: ref_seconds,
        });

        // The fixed methods.
        let t = Instant::now();
        let folded = m::folded_sets(&d, &curve, &SIZES)?;
        eprintln!(
            "cornell: {name}: KQ_{name}_4/6/8 searched in {:.2} s",
            t.elapsed().as_secs_f64()
        );
        let mut methods: Vec<Spectral> = Vec::new();
        for f in &folded {
            methods.push(m::folded(f, paints));
        }
        for n in SIZES {
            methods.push(m::radiance(&d, n, &curve, paints)?);
        }
        methods.push(m::rgb(&d, &curve, paints, Albedo::D65)?);
        methods.push(m::rgb(&d, &curve, paints, Albedo::UnderLight)?);
        for f in &folded {
            methods.push(m::upsampled(&d, f, &curve, paints, Upsampler::CrateMap)?);
        }
        for f in &folded {
            methods.push(m::upsampled(&d, f, &curve, paints, Upsampler::JakobHanika)?);
        }
        let mut shown: Vec<(String, Vec<[f64; 3]>, Vec<f64>)> = Vec::new();
        let mut fixed_means: Vec<(String, f64)> = Vec::new();
        for meth in &methods {
            let (img, secs) = meth.render(&scene, Bounces::All);
            let de = m::de00(&img, &ref_all, &painted, white_all);
            let (mean, p95) = mean_p95(&de);
            let (img_d, secs_d) = meth.render(&scene, Bounces::Direct);
            let de_d = m::de00(&img_d, &ref_direct, &painted, white_direct);
            let (mean_d, p95_d) = mean_p95(&de_d);
            rows.push(Row {
                light: name,
                method: meth.name.clone(),
                cost: meth.cost,
                bounces: "all",
                mean,
                p95,
                seconds: secs,
            });
            rows.push(Row {
                light: name,
                method: meth.name.clone(),
                cost: meth.cost,
                bounces: "direct",
                mean: mean_d,
                p95: p95_d,
                seconds: secs_d,
            });
            if meth.name.starts_with("KQ_") && !meth.name.contains('+') {
                fixed_means.push((meth.name.clone(), mean));
            }
            let show = [
                format!("KQ_{name}_4"),
                format!("KQ_{name}_8"),
                "KQ_4".into(),
                "KQ_8".into(),
                "RGB (paints' sRGB under D65)".into(),
                "RGB (paints' sRGB under the light)".into(),
                format!("KQ_{name}_8 + crate's map"),
                format!("KQ_{name}_8 + Jakob-Hanika"),
            ];
            if show.contains(&meth.name) {
                shown.push((meth.name.clone(), img, de));
            }
        }

        // Random wavelengths from the reference's per-nm solution.
        let cells_all = m::cells(&reference, &b_all);
        let cells_direct = m::cells(&reference, &b_direct);
        let samplers = [
            Sampler::Visible,
            Sampler::Hero {
                range_nm: m::CELL_SPAN_NM,
            },
        ];
        let mut curves: Vec<(String, Vec<f64>)> = Vec::new();
        for (si, sampler) in samplers.iter().enumerate() {
            for n in SIZES {
                let stream = stream_seed(0, &[li as u64, si as u64, n as u64]);
                for (bounces, cells, refimg, white) in [
                    ("all", &cells_all, &ref_all, white_all),
                    ("direct", &cells_direct, &ref_direct, white_direct),
                ] {
                    let (imgs, secs) =
                        m::random_image(&scene, cells, *sampler, n, &[1], args.seed, stream);
                    let de = m::de00(&imgs[0], refimg, &painted, white);
                    let (mean, p95) = mean_p95(&de);
                    let label = format!("{} ×{n}, 1 spp", sampler.name());
                    rows.push(Row {
                        light: name,
                        method: label.clone(),
                        cost: n,
                        bounces,
                        mean,
                        p95,
                        seconds: secs,
                    });
                    if bounces == "all" && n == 4 {
                        shown.push((label, imgs[0].clone(), de));
                    }
                }
            }
            // 4 and 8 a sample, up to max_spp: the spp at which each reaches each fixed set.
            for per_sample in [4usize, 8] {
                let stream = if per_sample == 4 {
                    stream_seed(1, &[li as u64, si as u64])
                } else {
                    stream_seed(1, &[li as u64, si as u64, per_sample as u64])
                };
                let (imgs, _) = m::random_image(
                    &scene, &cells_all, *sampler, per_sample, &levels, args.seed, stream,
                );
                curves.push((
                    format!("{} ×{per_sample}", sampler.name()),
                    imgs.iter()
                        .map(|img| mean_p95(&m::de00(img, &ref_all, &painted, white_all)).0)
                        .collect(),
                ));
            }
        }
        for (set, mean) in &fixed_means {
            let mut row = vec![name.to_string(), set.clone(), format!("{mean:.3}")];
            row.extend(curves.iter().map(|c| spp_to_reach(&levels, &c.1, *mean)));
            spp_rows.push(row);
        }
        for (label, c) in &curves {
            let text: Vec<String> = levels
                .iter()
                .zip(c)
                .map(|(s, v)| format!("{s}: {v:.3}"))
                .collect();
            println!("{name}: {label} mean ΔE00 by spp: {}", text.join(", "));
        }

        // The picture: the reference and the shown methods, their ΔE00 maps below.
        let order = [
            format!("KQ_{name}_4"),
            format!("KQ_{name}_8"),
            "KQ_4".into(),
            "KQ_8".into(),
            "pbrt-v4 visible ×4, 1 spp".into(),
            "RGB (paints' sRGB under D65)".into(),
            "RGB (paints' sRGB under the light)".into(),
            format!("KQ_{name}_8 + crate's map"),
            format!("KQ_{name}_8 + Jakob-Hanika"),
        ];
        let tone =
            |img: &[[f64; 3]]| picture::tone_map(img, args.size, white_all, &srgb.xyz_to_rgb);
        let mut top: Vec<Rgb8> = vec![tone(&ref_all)];
        let mut bottom: Vec<Rgb8> = vec![Rgb8::filled(args.size, args.size, [24, 24, 24])];
        let mut legend = vec!["reference (1 nm)".to_string()];
        for o in &order {
            if let Some((label, img, de)) = shown.iter().find(|s| &s.0 == o) {
                top.push(tone(img));
                bottom.push(picture::de_map(de, &painted, args.size));
                legend.push(label.clone());
            }
        }
        // Each method's name drawn above its image, and what the map below shows.
        let top: Vec<Rgb8> = top
            .iter()
            .zip(&legend)
            .map(|(t, l)| picture::labelled(t, l, 3))
            .collect();
        let bottom: Vec<Rgb8> = bottom
            .iter()
            .enumerate()
            .map(|(k, t)| picture::labelled(t, if k == 0 { "" } else { "dE00 map" }, 3))
            .collect();
        let path = args.out.join(format!("{name}.png"));
        picture::grid(&[top, bottom], 4).write_png(&path)?;
        legends.push(format!("{}: {}", path.display(), legend.join(" | ")));
    }
    let scale_path = args.out.join("scale.png");
    picture::scale_strip(300, 16).write_png(&scale_path)?;

    // The tables.
    let mut csv = tools::csv_table::Table::new(
        "light,method,wavelengths_per_pixel,bounces,mean_de00,p95_de00,seconds_per_image",
    );
    println!("\n| light | method | wavelengths per pixel | mean ΔE00 | p95 | mean, direct only | p95, direct only | s per image |\n|---|---|---|---|---|---|---|---|");
    for r in &rows {
        csv.row([
            r.light.to_string(),
            r.method.clone(),
            r.cost.to_string(),
            r.bounces.to_string(),
            format!("{:.4}", r.mean),
            format!("{:.4}", r.p95),
            format!("{:.4}", r.seconds),
        ]);
        if r.bounces == "all" {
            let direct = rows
                .iter()
                .find(|x| x.light == r.light && x.method == r.method && x.bounces == "direct");
            let (dm, dp) = direct.map_or(("—".into(), "—".into()), |x| {
                (format!("{:.2}", x.mean), format!("{:.2}", x.p95))
            });
            println!(
                "| {} | {} | {} | {:.2} | {:.2} | {} | {} | {:.3} |",
                r.light, r.method, r.cost, r.mean, r.p95, dm, dp, r.seconds
            );
        }
    }
    let csv_path = csv.write(&args.out, "cornell.csv")?;
    let mut spp_csv = tools::csv_table::Table::new(
        "light,fixed_set,mean_de00,pbrt_v4_x4_spp,pbrt_v4_x8_spp,hero_x4_spp,hero_x8_spp",
    );
    println!("\nSamples per pixel at which random wavelengths (4 or 8 a sample) reach each fixed set's mean ΔE00 on the box (~: extended along the −1/2 slope past {} spp):\n\n| light | fixed set | mean ΔE00 | pbrt-v4 ×4 | pbrt-v4 ×8 | hero ×4 | hero ×8 |\n|---|---|---|---|---|---|---|", levels.last().copied().unwrap_or(1));
    for r in &spp_rows {
        spp_csv.row(r.iter());
        println!("| {} |", r.join(" | "));
    }
    let spp_path = spp_csv.write(&args.out, "cornell_spp.csv")?;
    println!("\nColumns of the pictures (top: display images; bottom: ΔE00 maps, 0 black to {} yellow, white beyond {}; scale in {}):", picture::DE_SCALE_MAX, 1.5 * picture::DE_SCALE_MAX, scale_path.display());
    for l in &legends {
        println!("- {l}");
    }
    println!(
        "\nWrote {} and {}. Wall time {:.1} s.",
        csv_path.display(),
        spp_path.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
