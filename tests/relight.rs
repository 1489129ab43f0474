//! Relighting a material through a set for radiances with a light's baked samples
//! (`tables::lights`, `FoldedSet::linear_rgb_under`), against CIE 015's plain sums of the data
//! files (tests/common/cie015.rs): the white is the light's own, and the ColorChecker, which the
//! fit never saw (it is fitted on the CIE test colours), comes out closer than with the light's
//! values at the nodes, the route a renderer without baked samples takes.

mod common;

use common::cie015::{plain_xyz_over, read_rows};
use spectral_quadrature::tables::{folded, lights};
use spectral_quadrature::{delta_e2000, lab_from_xyz, FoldedSet};

/// The scene's range of integration (the default scene's), nm: the sets integrate over it.
const RANGE: [u32; 2] = [380, 770];

/// Column `k` of a data file's rows, linearly interpolated at `nm` (the end values outside).
fn at(rows: &[Vec<f64>], k: usize, nm: f64) -> f64 {
    let i = rows.partition_point(|r| r[0] < nm);
    if i == 0 {
        return rows[0][k];
    }
    if i >= rows.len() {
        return rows[rows.len() - 1][k];
    }
    let (a, b) = (&rows[i - 1], &rows[i]);
    a[k] + (nm - a[0]) / (b[0] - a[0]) * (b[k] - a[k])
}

fn chromaticity(xyz: [f64; 3]) -> [f64; 2] {
    let s = xyz[0] + xyz[1] + xyz[2];
    [xyz[0] / s, xyz[1] / s]
}

/// Mean CIEDE2000 of the ColorChecker under `light_file` relit through `set` with `samples`,
/// against the plain 1 nm sums (white: the light's own).
fn mean_de00<const N: usize>(set: &FoldedSet<N>, light_file: &str, samples: &[f32; N]) -> f64 {
    let light = read_rows(light_file);
    let chart = read_rows("reflectance_colorchecker_ohta.csv");
    let white = plain_xyz_over(RANGE, |nm| at(&light, 1, nm));
    let nodes = set.wavelengths_nm();
    let patches = chart[0].len() - 1;
    let mut total = 0.0;
    for k in 1..=patches {
        let exact = plain_xyz_over(RANGE, |nm| at(&light, 1, nm) * at(&chart, k, nm));
        let r: [f32; N] = core::array::from_fn(|i| at(&chart, k, f64::from(nodes[i])) as f32);
        let xyz = set
            .display()
            .xyz_from_linear(set.linear_rgb_under(samples, &r))
            .map(f64::from);
        // The relit white has Y = 1: compare in the light's own white's scale.
        let exact = exact.map(|v| v / white[1]);
        let white = white.map(|v| v / white[1]);
        total += delta_e2000(lab_from_xyz(exact, white), lab_from_xyz(xyz, white));
    }
    total / patches as f64
}

#[test]
fn a_reflectance_of_1_relit_gives_the_lights_own_white() {
    // The fit pins it: Y = 1 and the light's chromaticity, to f32 rounding of a 4- or 6-term
    // product and the display matrix (1e-5 in x and y is about 60 f32 ulps at 0.4).
    for (set, samples, file) in [
        (
            folded::TABLE2_ROW2_SRGB,
            lights::F11_AT_TABLE2_ROW2,
            "illuminant_F11.csv",
        ),
        (
            folded::TABLE2_ROW2_SRGB,
            lights::A_AT_TABLE2_ROW2,
            "illuminant_A.csv",
        ),
        (
            folded::TABLE2_ROW2_SRGB,
            lights::LED_B2_AT_TABLE2_ROW2,
            "illuminant_LED_B2.csv",
        ),
    ] {
        let light = read_rows(file);
        let white = plain_xyz_over(RANGE, |nm| at(&light, 1, nm));
        let xyz = set
            .display()
            .xyz_from_linear(set.linear_rgb_under(&samples, &[1.0; 4]))
            .map(f64::from);
        assert!((xyz[1] - 1.0).abs() < 1e-5, "{file}: Y {}", xyz[1]);
        let (got, want) = (chromaticity(xyz), chromaticity(white));
        for c in 0..2 {
            assert!(
                (got[c] - want[c]).abs() < 1e-5,
                "{file}: {got:?} against {want:?}"
            );
        }
    }
    let set = folded::TABLE2_ROW1_SRGB;
    let light = read_rows("illuminant_F11.csv");
    let white = plain_xyz_over(RANGE, |nm| at(&light, 1, nm));
    let xyz = set
        .display()
        .xyz_from_linear(set.linear_rgb_under(&lights::F11_AT_TABLE2_ROW1, &[1.0; 6]))
        .map(f64::from);
    let (got, want) = (chromaticity(xyz), chromaticity(white));
    assert!((got[0] - want[0]).abs() < 1e-5 && (got[1] - want[1]).abs() < 1e-5);
}

#[test]
fn the_fitted_samples_relight_the_colorchecker_better_than_the_lights_values_at_the_nodes() {
    // The light's values at the nodes, scaled to Y = 1 through the set: what a renderer takes
    // from the light's file by hand.
    fn point<const N: usize>(set: &FoldedSet<N>, file: &str) -> [f32; N] {
        let light = read_rows(file);
        let nodes = set.wavelengths_nm();
        let raw: [f32; N] = core::array::from_fn(|i| at(&light, 1, f64::from(nodes[i])) as f32);
        let y = set.display().xyz_from_linear(set.linear_rgb(&raw))[1];
        raw.map(|v| v / y)
    }
    let set = folded::TABLE2_ROW2_SRGB;
    let cases = [
        ("illuminant_F11.csv", lights::F11_AT_TABLE2_ROW2),
        ("illuminant_LED_B2.csv", lights::LED_B2_AT_TABLE2_ROW2),
        ("illuminant_A.csv", lights::A_AT_TABLE2_ROW2),
    ];
    for (file, fitted) in cases {
        let (f, p) = (
            mean_de00(&set, file, &fitted),
            mean_de00(&set, file, &point(&set, file)),
        );
        println!("{file}: TABLE2_ROW2 relit, mean ΔE00 {f:.2} fitted, {p:.2} point samples");
        assert!(f < p, "{file}: fitted {f} against point samples {p}");
    }
    // Under F11 the point samples miss the lamp's lines; the fitted ones take them in. Measured:
    // 4.66 against 13.11 ΔE00 at 4 nodes; the bound leaves room for the tables' f32 rounding.
    let f = mean_de00(&set, "illuminant_F11.csv", &lights::F11_AT_TABLE2_ROW2);
    let p = mean_de00(
        &set,
        "illuminant_F11.csv",
        &point(&set, "illuminant_F11.csv"),
    );
    assert!(f < 0.6 * p, "F11: fitted {f} against point samples {p}");
}
