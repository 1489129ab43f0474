//! The baked RGB upsamplings (`tables::upsampling`), the sets' maps and the light groups' maps
//! alike: their tables equal a fresh bake, and the per-pixel function keeps every promise its
//! docs make: bounded for any input, white, black and greys exact, the round trip through the
//! set's own weights (a light group's first member's), and its Lipschitz bound.

mod common;

use spectral_quadrature_spectra::builtin_illuminant;
use std::sync::OnceLock;

use spectral_quadrature::tables::{displays, folded, groups, upsampling};
use spectral_quadrature::{
    delta_e2000, lab_from_xyz, Error, FoldedSet, LengthOf, Samples, Upsampling,
};
use spectral_quadrature_generator::scene::{Resolved, Scene};
use spectral_quadrature_generator::upsampling::Baked;

use common::check_property;
use proptest::prelude::*;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

/// The default scene, resolved afresh with every upsampling fitted (the cache ignored): the same
/// bakes as the tables, in f64.
fn fresh() -> &'static (spectral_quadrature_generator::Derivation, Resolved) {
    static R: OnceLock<(spectral_quadrature_generator::Derivation, Resolved)> = OnceLock::new();
    R.get_or_init(|| {
        let d = spectral_quadrature_generator::derive(
            &spectral_quadrature_generator::Settings::new(DATA_DIR),
        )
        .unwrap();
        let r = Scene::default_scene(std::path::Path::new(DATA_DIR))
            .resolve_fitting(&d)
            .unwrap();
        (d, r)
    })
}

/// One baked upsampling's fresh bake and what the tests judge it with.
struct Fresh {
    /// The const's name, `<SET>_<DISPLAY>`.
    name: &'static str,
    baked: &'static Baked,
    /// The display's matrices (f64), for the generator's functions.
    matrices: &'static spectral_quadrature_generator::display::DisplayMatrices,
    /// The reference light at the nodes for a set for radiances (D65); `None` where the set's
    /// light is folded into its weights.
    light_at_nodes: Option<Vec<f64>>,
}

/// The named upsamplings, by const name.
macro_rules! maps {
    ($($name:ident,)*) => {
        [$((stringify!($name), &upsampling::$name as &(dyn Dyn + Sync))),*]
    };
}

/// A folded set's bits: its wavelengths', its weights', its light and its display's name.
type SetBits = (Vec<u32>, Vec<u32>, Option<&'static str>, &'static str);

fn set_bits<const N: usize>(s: &FoldedSet<N>) -> SetBits {
    (
        s.wavelengths_nm().map(f32::to_bits).to_vec(),
        s.weights().iter().flatten().map(|w| w.to_bits()).collect(),
        s.samples().light(),
        s.display().name(),
    )
}

/// The set each upsampling must hold, by the upsampling's name: the folded set of that name for
/// a set's map, the first member of the light group of that name for a group's map.
fn expected_sets() -> Vec<(&'static str, SetBits)> {
    macro_rules! sets {
        ($($name:ident,)*) => {
            vec![$((stringify!($name), set_bits(&folded::$name))),*]
        };
    }
    macro_rules! firsts {
        ($($name:ident,)*) => {
            vec![$((stringify!($name), set_bits(&groups::$name.member(0).unwrap()))),*]
        };
    }
    let mut all = folded::all!(sets);
    all.extend(groups::all!(firsts));
    all
}

/// Each baked upsampling of the default scene (with its folded set) and its fresh bake.
fn all_maps() -> Vec<(&'static (dyn Dyn + Sync), Fresh)> {
    // The build's own list of the upsamplings it baked.
    let all = upsampling::all!(maps);
    assert_eq!(all.len(), upsampling::NAMES.len());
    // The list holds every upsampling the build baked.
    let baked = include_str!(concat!(env!("OUT_DIR"), "/tables.rs"));
    assert_eq!(baked.matches(": Upsampling<").count(), all.len());
    let (d, r) = fresh();
    assert_eq!(
        all.len(),
        r.upsamplings.len(),
        "every upsampling of the default scene is tested"
    );
    all.into_iter()
        .map(|(name, u)| {
            let baked = r
                .upsamplings
                .iter()
                .find(|b| format!("{}_{}", b.set, b.display) == name)
                .unwrap_or_else(|| panic!("{name} is not among the default scene's upsamplings"));
            let matrices = &r
                .displays
                .iter()
                .find(|(s, _)| s.name == baked.display)
                .unwrap()
                .1;
            // A light group's map is for its first member, which folds its light in.
            let radiance = baked.group_lights.is_none()
                && r.colour_sets
                    .iter()
                    .find(|s| s.name == baked.set)
                    .unwrap_or_else(|| panic!("{name}: {} is not a set of the scene", baked.set))
                    .light
                    .is_none();
            let light_at_nodes = radiance.then(|| {
                let light = builtin_illuminant(
                    std::path::Path::new(DATA_DIR),
                    &baked.light,
                    d.settings.range_nm,
                )
                .unwrap();
                baked
                    .wavelengths_nm
                    .iter()
                    .map(|&nm| light.at(nm))
                    .collect()
            });
            (
                u,
                Fresh {
                    name,
                    baked,
                    matrices,
                    light_at_nodes,
                },
            )
        })
        .collect()
}

/// Calls `f` with each baked upsampling of the default scene (with its folded set) and its fresh
/// bake, in order.
fn each(f: impl Fn(&dyn Dyn, &Fresh)) {
    for (u, fresh) in all_maps() {
        f(u, &fresh);
    }
}

/// As `each`, with the maps shared among as many threads as the machine has cores: for the scans
/// that take seconds per map, which would otherwise run alone on one core at the end of the test
/// binary (this file's tests come last). A panic in any thread fails the test with its message.
fn each_in_parallel(f: impl Fn(&dyn Dyn, &Fresh) + Sync) {
    let maps = all_maps();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|s| {
        for _ in 0..threads.min(maps.len()) {
            s.spawn(|| {
                while let Some((u, fresh)) =
                    maps.get(next.fetch_add(1, std::sync::atomic::Ordering::Relaxed))
                {
                    f(*u, fresh);
                }
            });
        }
    });
}

/// An upsampling, whatever N.
trait Dyn {
    /// The bits of the set it holds (`Upsampling::set`).
    fn set_bits(&self) -> SetBits;
    fn light(&self) -> &'static str;
    fn grid(&self) -> usize;
    fn lipschitz(&self) -> f32;
    fn max_round_trip(&self) -> f32;
    fn reachable_share(&self) -> f32;
    fn table(&self) -> Vec<Vec<u16>>;
    fn reflectance(&self, rgb: [f32; 3]) -> Vec<f32>;
    fn interp(&self, rgb: [f32; 3]) -> Vec<f32>;
    /// Whether the set's light is folded into its weights (its samples are reflectances).
    fn folded_light(&self) -> bool;
    /// The folded set's weights and its display's RGB → XYZ.
    fn weights(&self) -> Vec<Vec<f32>>;
    fn rgb_to_xyz(&self) -> [[f32; 3]; 3];
    fn batch_agrees(&self, rgb: &[[f32; 3]]) -> bool;
    /// The cells at the edge of what the set reaches, where the round trip's correction runs:
    /// one bit per cell (`RoundTrip::edge_cells`).
    fn edge_cells(&self) -> Vec<u32>;
}

impl<const N: usize> Dyn for Upsampling<N> {
    fn set_bits(&self) -> SetBits {
        let s = self.set();
        // The accessors read the set's.
        assert!(self.display() == s.display() && self.wavelengths_nm() == s.wavelengths_nm());
        set_bits(&s)
    }
    fn light(&self) -> &'static str {
        Upsampling::light(self)
    }
    fn grid(&self) -> usize {
        Upsampling::grid(self)
    }
    fn lipschitz(&self) -> f32 {
        Upsampling::lipschitz(self).expect("baked: measured")
    }
    fn max_round_trip(&self) -> f32 {
        Upsampling::max_round_trip_delta_e00(self).expect("baked: measured")
    }
    fn reachable_share(&self) -> f32 {
        Upsampling::reachable_share(self).expect("baked: measured")
    }
    fn table(&self) -> Vec<Vec<u16>> {
        Upsampling::table(self).iter().map(|e| e.to_vec()).collect()
    }
    fn reflectance(&self, rgb: [f32; 3]) -> Vec<f32> {
        Upsampling::reflectance(self, rgb).to_vec()
    }
    fn interp(&self, rgb: [f32; 3]) -> Vec<f32> {
        Upsampling::interpolate(self, rgb).to_vec()
    }
    fn folded_light(&self) -> bool {
        matches!(self.set().samples(), Samples::Reflectance { .. })
    }
    fn weights(&self) -> Vec<Vec<f32>> {
        self.set().weights().iter().map(|r| r.to_vec()).collect()
    }
    fn rgb_to_xyz(&self) -> [[f32; 3]; 3] {
        self.set().display().rgb_to_xyz()
    }
    fn edge_cells(&self) -> Vec<u32> {
        Upsampling::round_trip(self)
            .expect("baked: a round trip")
            .edge_cells()
            .to_vec()
    }
    fn batch_agrees(&self, rgb: &[[f32; 3]]) -> bool {
        let mut out = vec![[0.0f32; N]; rgb.len()];
        Upsampling::reflectance_batch(self, rgb, &mut out).unwrap();
        let mut short = vec![[0.0f32; N]; rgb.len() + 1];
        let mismatch = Upsampling::reflectance_batch(self, rgb, &mut short);
        mismatch
            == Err(Error::LengthMismatch {
                what: LengthOf::Output,
                expected: rgb.len(),
                got: rgb.len() + 1,
            })
            && short.iter().all(|o| o.iter().all(|&v| v == 0.0))
            && rgb
                .iter()
                .zip(&out)
                .all(|(p, o)| Upsampling::reflectance(self, *p).to_bits() == o.map(f32::to_bits))
    }
}

trait Bits<const N: usize> {
    fn to_bits(self) -> [u32; N];
}
impl<const N: usize> Bits<N> for [f32; N] {
    fn to_bits(self) -> [u32; N] {
        self.map(f32::to_bits)
    }
}

/// The linear RGB of node values under the map's reference light, white-balanced (node values
/// of 1 give (1, 1, 1)): the folded set's weights, times the light at the nodes for a set for
/// radiances.
fn encode(u: &dyn Dyn, f: &Fresh, values: &[f32]) -> [f64; 3] {
    let w = u.weights();
    let light = |i: usize| f.light_at_nodes.as_ref().map_or(1.0, |l| l[i]);
    let row = |c: usize, v: &dyn Fn(usize) -> f64| -> f64 {
        w[c].iter()
            .enumerate()
            .map(|(i, &x)| f64::from(x) * light(i) * v(i))
            .sum::<f64>()
    };
    core::array::from_fn(|c| row(c, &|i| f64::from(values[i])) / row(c, &|_| 1.0))
}

/// CIELAB of white-balanced linear RGB of the map's display, the display's white as the
/// reference white.
fn lab(u: &dyn Dyn, rgb: [f64; 3]) -> [f64; 3] {
    let m = u.rgb_to_xyz();
    let xyz = |v: [f64; 3]| -> [f64; 3] {
        core::array::from_fn(|r| (0..3).map(|k| f64::from(m[r][k]) * v[k]).sum())
    };
    lab_from_xyz(xyz(rgb), xyz([1.0; 3]))
}

#[test]
fn tables_equal_a_fresh_bake() {
    each(|u, f| {
        let b = f.baked;
        // The set, and so the display and the nodes, by type; the reference light the set's
        // (D65 for a set for radiances, as the generator's own constant says).
        let expected = expected_sets();
        let (_, want) = expected
            .iter()
            .find(|(n, _)| *n == f.name)
            .unwrap_or_else(|| panic!("{}: no folded set or light group of that name", f.name));
        assert!(u.set_bits() == *want, "{}", f.name);
        assert_eq!(u.light(), b.light, "{}", f.name);
        assert_eq!(u.grid(), b.grid, "{}", f.name);
        assert_eq!(u.table(), b.codes, "{}", f.name);
        assert_eq!(u.lipschitz(), b.lipschitz as f32, "{}", f.name);
        assert_eq!(u.max_round_trip(), b.max_round_trip_de00 as f32);
        assert_eq!(u.reachable_share(), b.reachable_share() as f32);
        assert_eq!(u.folded_light(), f.light_at_nodes.is_none(), "{}", f.name);
    });
    assert_eq!(upsampling::KQ_C_8_SRGB.light(), "C");
    assert_eq!(upsampling::KQ_F11_6_SRGB.light(), "F11");
    assert_eq!(upsampling::KQ_C_8_SRGB.display(), displays::SRGB);
    assert_eq!(upsampling::TABLE2_ROW1_REC2020.display(), displays::REC2020);
    assert_eq!(upsampling::TABLE2_ROW1_REC2020.light(), "D65");
    assert_eq!(
        upsampling::KQ_C_8_SRGB.wavelengths_nm(),
        folded::KQ_C_8_SRGB.wavelengths_nm()
    );
}

#[test]
fn white_black_and_greys() {
    each(|u, f| {
        assert!(
            u.reflectance([1.0; 3]).iter().all(|&v| v == 1.0),
            "{}",
            f.name
        );
        assert!(
            u.reflectance([0.0; 3]).iter().all(|&v| v == 0.0),
            "{}",
            f.name
        );
        for k in 0..=1000 {
            let g = k as f32 / 1000.0;
            let v = u.reflectance([g; 3]);
            // Flat: every node computes the same sum of the same codes.
            assert!(v.iter().all(|&x| x == v[0]), "{} grey {g}: {v:?}", f.name);
            // The grey itself, up to the codes' rounding (half a step, 0.5 / 65535) and the f32
            // sum (a few units of 2⁻²⁴).
            assert!(
                (v[0] - g).abs() <= 0.5 / 65535.0 + 4.0 * f32::EPSILON,
                "{} {g}",
                f.name
            );
        }
    });
}

#[test]
fn bounded_for_any_input() {
    let specials = [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MAX,
        -f32::MAX,
        f32::MIN_POSITIVE / 2.0,
        -0.0,
        1.0 + f32::EPSILON,
        1e30,
        -1e-30,
    ];
    each(|u, f| {
        for &a in &specials {
            for &b in &specials {
                for &c in &[0.3f32, f32::NAN, 2.0] {
                    let v = u.reflectance([a, b, c]);
                    assert!(
                        v.iter().all(|x| (0.0..=1.0).contains(x)),
                        "{} {v:?}",
                        f.name
                    );
                }
            }
        }
        // NaN and negative channels read as 0, channels above 1 as 1.
        assert_eq!(
            u.reflectance([f32::NAN, -3.0, 7.0]),
            u.reflectance([0.0, 0.0, 1.0])
        );
    });
    check_property(
        2000,
        "node values in [0, 1]",
        prop::array::uniform3(-0.5f32..1.5),
        |rgb| {
            each(|u, f| {
                let v = u.reflectance(rgb);
                assert!(
                    v.iter().all(|x| (0.0..=1.0).contains(x)),
                    "{} {v:?}",
                    f.name
                );
            });
            Ok(())
        },
    );
}

/// The round trip: at the reachable grid points within the baked figure (at most 0.05 ΔE00), and
/// between them, on a 17³ grid of the cube, within 0.05 ΔE00 wherever node values in [0, 1] reach
/// the colour at all; where they do not, the colour the output encodes to is the nearest
/// reachable one in CIELAB linearised at the requested colour (the f64 programme's, within
/// 0.05 ΔE00 of it).
#[test]
fn round_trip() {
    each(|u, f| {
        let b = f.baked;
        let m = f.matrices;
        let fit = b.fit.as_ref().unwrap();
        assert!(u.max_round_trip() <= 0.05, "{}", f.name);
        let g = u.grid();
        for (idx, &ok) in b.reachable.iter().enumerate() {
            if !ok {
                continue;
            }
            let p = spectral_quadrature_generator::upsampling::grid_point(g, idx);
            let v = u.reflectance(p.map(|x| x as f32));
            let de = delta_e2000(lab(u, p), lab(u, encode(u, f, &v)));
            // The f32 path adds a few units of f32 rounding to the baked figure.
            assert!(
                de <= f64::from(u.max_round_trip()) + 1e-3,
                "{} at {p:?}: {de}",
                f.name
            );
        }
        let (mut inside, mut edge, mut unreachable) = (0.0f64, 0.0f64, 0.0f64);
        let mut edge_interpolated = 0.0f64;
        let (mut n_edge, mut n_unreachable) = (0, 0);
        for idx in 0..17 * 17 * 17 {
            let p = spectral_quadrature_generator::upsampling::grid_point(17, idx);
            let (nearest, reachable) =
                spectral_quadrature_generator::upsampling::project(m, &b.encoding, &fit.map, p)
                    .unwrap();
            let v = u.reflectance(p.map(|x| x as f32));
            let got = lab(u, encode(u, f, &v));
            if !reachable {
                // Both are the colour nearest p in the same metric: one colour.
                let want = lab(
                    u,
                    spectral_quadrature_generator::upsampling::encode(&b.encoding, &nearest),
                );
                unreachable = unreachable.max(delta_e2000(want, got));
                n_unreachable += 1;
                continue;
            }
            let de = delta_e2000(lab(u, p), got);
            if corners_reachable(b, p) {
                inside = inside.max(de);
            } else {
                edge = edge.max(de);
                n_edge += 1;
                let w = u.interp(p.map(|x| x as f32));
                edge_interpolated =
                    edge_interpolated.max(delta_e2000(lab(u, p), lab(u, encode(u, f, &w))));
            }
        }
        // The requirement: 0.05 ΔE00 for every reachable point, in the edge cells too.
        assert!(inside <= 0.05, "{}: {inside}", f.name);
        assert!(edge <= 0.05, "{}: edge cells {edge}", f.name);
        assert!(unreachable <= 0.05, "{}: unreachable {unreachable}", f.name);
        println!(
            "{}: round trip inside {inside:.4}, edge cells {edge:.4} ({n_edge} points; \
             interpolate alone {edge_interpolated:.2}) ΔE00; unreachable ({n_unreachable} of \
             4913 points) within {unreachable:.4} of the nearest",
            f.name
        );
    });
}

/// Whether all four corners of the tetrahedron that holds `p` are reachable.
fn corners_reachable(b: &Baked, p: [f64; 3]) -> bool {
    let g = b.grid;
    let cells = (g - 1) as f64;
    let mut cell = [0usize; 3];
    let mut frac = [0.0; 3];
    for c in 0..3 {
        let x = p[c] * cells;
        cell[c] = (x.floor() as usize).min(g - 2);
        frac[c] = x - cell[c] as f64;
    }
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&a, &c| frac[c].total_cmp(&frac[a]));
    let strides = [g * g, g, 1];
    let mut i = (cell[0] * g + cell[1]) * g + cell[2];
    let mut all = b.reachable[i];
    for (k, &a) in axes.iter().enumerate() {
        i += strides[a];
        // A corner with zero weight does not count.
        let weight = if k == 2 {
            frac[a]
        } else {
            frac[a] - frac[axes[k + 1]]
        };
        all &= b.reachable[i] || weight == 0.0;
    }
    all
}

#[test]
fn lipschitz_bound() {
    check_property(
        2000,
        "Lipschitz",
        (
            prop::array::uniform3(0.0f32..=1.0),
            prop::array::uniform3(-0.2f32..0.2),
        ),
        |(p, dp)| {
            let q: [f32; 3] = core::array::from_fn(|c| (p[c] + dp[c]).clamp(0.0, 1.0));
            let dist = (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0f32, f32::max);
            each(|u, f| {
                let (a, b) = (u.reflectance(p), u.reflectance(q));
                let change = a
                    .iter()
                    .zip(&b)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f32::max);
                // f32 rounding of the two evaluations: each output within a few units of 2⁻²⁴
                // of the exact interpolant.
                let slack = 8.0 * f32::EPSILON;
                assert!(
                    change <= stated_lipschitz(u, f.name) * dist + slack,
                    "{}: {change} > {} · {dist}",
                    f.name,
                    stated_lipschitz(u, f.name)
                );
            });
            Ok(())
        },
    );
}

#[test]
fn continuous_across_cell_faces() {
    // Either side of every cell face on a line through the cube: no seam.
    each(|u, f| {
        let g = u.grid();
        for k in 1..g - 1 {
            let face = k as f32 / (g - 1) as f32;
            for c in 0..3 {
                let mut below = [0.37f32, 0.61, 0.18];
                let mut above = below;
                below[c] = face - 1e-6;
                above[c] = face + 1e-6;
                let (a, b) = (u.reflectance(below), u.reflectance(above));
                let jump = a
                    .iter()
                    .zip(&b)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f32::max);
                assert!(
                    jump <= stated_lipschitz(u, f.name) * 2e-6 + 8.0 * f32::EPSILON,
                    "{} {jump}",
                    f.name
                );
            }
        }
    });
}

#[test]
fn batch_is_per_pixel() {
    let rgb: Vec<[f32; 3]> = (0..300)
        .map(|i| {
            let t = i as f32 / 300.0;
            [t, (t * 7.3).fract(), (t * 3.1).fract()]
        })
        .collect();
    each(|u, f| assert!(u.batch_agrees(&rgb), "{}", f.name));
}

#[test]
fn new_checks_the_table() {
    static TABLE: [[u16; 2]; 8] = [[0; 2]; 8];
    let mine = FoldedSet::new(
        [450.0, 600.0],
        [[0.5, 0.5], [0.2, 0.8], [0.9, 0.1]],
        Samples::Radiance,
        displays::SRGB,
    )
    .unwrap();
    let new = |grid, table| Upsampling::new(mine, grid, table, None);
    assert!(new(2, &TABLE).is_ok());
    let refused = |grid: usize, table: &[[u16; 2]]| {
        Err(Error::UpsamplingTable {
            grid,
            entries: table.len(),
        })
    };
    assert_eq!(new(3, &TABLE), refused(3, &TABLE));
    assert_eq!(new(1, &TABLE[..1]), refused(1, &TABLE[..1]));
    assert_eq!(new(usize::MAX, &TABLE), refused(usize::MAX, &TABLE));
    let u = new(2, &TABLE).unwrap();
    assert_eq!(u.reflectance([0.5; 3]), [0.0; 2]);
    assert_eq!(u.grid(), 2);
    // The set's display and nodes; D65 for a set for radiances, the set's light otherwise.
    assert_eq!(
        (u.set(), u.display(), u.light()),
        (mine, displays::SRGB, "D65")
    );
    assert_eq!(u.wavelengths_nm(), [450.0, 600.0]);
    let under_a = FoldedSet::new(
        mine.wavelengths_nm(),
        mine.weights(),
        Samples::Reflectance { light: "A" },
        displays::DISPLAY_P3,
    )
    .unwrap();
    let u = Upsampling::new(under_a, 2, &TABLE, None).unwrap();
    assert_eq!((u.display(), u.light()), (displays::DISPLAY_P3, "A"));
    // A sensor's readings are not values at wavelengths: nothing to upsample to.
    let readings = Samples::Readings {
        sensor: "S",
        light: Some("C"),
    };
    let sensor = FoldedSet::new(
        mine.wavelengths_nm(),
        mine.weights(),
        readings,
        displays::SRGB,
    )
    .unwrap();
    assert_eq!(
        Upsampling::new(sensor, 2, &TABLE, None),
        Err(Error::UpsamplingReadings)
    );
    // Made at run time: no measured figures, and no NaN standing in for them.
    assert_eq!(u.lipschitz(), None);
    assert_eq!(u.max_round_trip_delta_e00(), None);
    assert_eq!(u.reachable_share(), None);
}

/// Which lines of a scan to walk: every one, or one in `one_in`, chosen by hashing the line
/// with `seed` (the same lines for the same seed, whatever the threads' order).
#[derive(Clone, Copy, Debug)]
struct Share {
    seed: u64,
    one_in: u64,
}

impl Share {
    /// Every line.
    const ALL: Share = Share { seed: 0, one_in: 1 };

    /// Whether the line `key` is walked.
    fn takes(&self, key: impl std::hash::Hash) -> bool {
        use std::hash::{Hash, Hasher};
        if self.one_in <= 1 {
            return true;
        }
        // `DefaultHasher::new` has fixed keys: the same choice for the same seed, on every
        // machine with this toolchain.
        let mut h = std::hash::DefaultHasher::new();
        (self.seed, key).hash(&mut h);
        h.finish().is_multiple_of(self.one_in)
    }
}

/// The largest change of a node value per unit of max-norm RGB change, in the cells at the edge
/// of what the set reaches (where the correction runs): lines along each axis and the grey
/// diagonals through every edge cell, 64 steps of `1 / steps_per_cell` of a cell around 81
/// points of each (a slope, not a jump, gives about the same figure at 256 and 2048 steps per
/// cell); of those lines, the ones `share` takes.
fn edge_lipschitz(
    u: &dyn Dyn,
    b: &Baked,
    steps_per_cell: f64,
    share: Share,
) -> (f64, [f32; 3], [f64; 3]) {
    let g = b.grid;
    let c = g - 1;
    let words = u.edge_cells();
    let h = 1.0 / (c as f64 * steps_per_cell);
    let dirs: [[f64; 3]; 7] = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [1.0, -1.0, 0.0],
        [0.0, 1.0, -1.0],
        [1.0, 0.0, -1.0],
    ];
    let mut worst = (0.0f64, [0.0f32; 3], [0.0f64; 3]);
    for idx in 0..c * c * c {
        if (words[idx / 32] >> (idx % 32)) & 1 == 0 {
            continue;
        }
        let lo = [idx / (c * c), (idx / c) % c, idx % c].map(|v| v as f64 / c as f64);
        for (d, dir) in dirs.into_iter().enumerate() {
            for s in 0..9 {
                for t in 0..9 {
                    let line = (&b.set, &b.display, steps_per_cell.to_bits(), idx, d, s, t);
                    if !share.takes(line) {
                        continue;
                    }
                    // A start point on a 9 × 9 lattice of the cell, walked 64 steps along dir.
                    let start = [
                        lo[0] + (s as f64 / 8.0) / c as f64,
                        lo[1] + (t as f64 / 8.0) / c as f64,
                        lo[2] + ((s * 7 + t * 3) % 9) as f64 / 8.0 / c as f64,
                    ];
                    let mut prev: Option<([f32; 3], Vec<f32>)> = None;
                    for k in 0..=64 {
                        let p: [f32; 3] = core::array::from_fn(|i| {
                            (start[i] + dir[i] * (k as f64 - 32.0) * h).clamp(0.0, 1.0) as f32
                        });
                        let v = u.reflectance(p);
                        if let Some((q, w)) = &prev {
                            let dist = (0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0, f32::max);
                            if dist > 0.0 {
                                let change = v
                                    .iter()
                                    .zip(w)
                                    .map(|(a, b)| (a - b).abs())
                                    .fold(0.0, f32::max);
                                let ratio = f64::from(change) / f64::from(dist);
                                if ratio > worst.0 {
                                    worst = (ratio, p, dir);
                                }
                            }
                        }
                        prev = Some((p, v));
                    }
                }
            }
        }
    }
    worst
}

/// The Lipschitz constant `docs/upsampling.md` states for `reflectance` in the edge cells of
/// each map: the largest figure the exhaustive scans (`edge_lipschitz` at 256 and 2048 steps per
/// cell, `face_scan`) or `lipschitz_in_the_edge_cells`' refined segments measure, rounded up to
/// two digits.
fn stated_edge_lipschitz(name: &str) -> f32 {
    match name {
        "KQ_C_4_SRGB" => 6.6,
        "KQ_C_4_DISPLAY_P3" => 21.0,
        "KQ_C_4_REC2020" => 45.0,
        "KQ_C_4_MEYER_1987" => 6.4,
        "KQ_C_6_SRGB" => 8.0,
        "KQ_C_6_DISPLAY_P3" => 46.0,
        "KQ_C_6_REC2020" => 110.0,
        "KQ_C_6_MEYER_1987" => 8.3,
        "KQ_C_8_DISPLAY_P3" => 370.0,
        "KQ_C_8_REC2020" => 1200.0,
        "KQ_C_8_MEYER_1987" => 31.0,
        "KQ_F11_6_SRGB" => 62.0,
        "KQ_F11_6_DISPLAY_P3" => 71.0,
        "KQ_F11_6_REC2020" => 260.0,
        "KQ_F11_6_MEYER_1987" => 62.0,
        "TABLE2_ROW1_SRGB" => 5.5,
        "TABLE2_ROW1_DISPLAY_P3" => 82.0,
        "TABLE2_ROW1_REC2020" => 260.0,
        "TABLE2_ROW1_MEYER_1987" => 5.7,
        "TABLE2_ROW2_SRGB" => 4.9,
        "TABLE2_ROW2_DISPLAY_P3" => 61.0,
        "TABLE2_ROW2_REC2020" => 120.0,
        "TABLE2_ROW2_MEYER_1987" => 4.5,
        "D65_A_F11_LED_B2_8_DISPLAY_P3" => 220.0,
        "D65_A_F11_LED_B2_8_REC2020" => 420.0,
        // KQ_C_8_SRGB, D65_A_F11_LED_B2_8_SRGB and D65_A_F11_LED_B2_8_MEYER_1987 have no edge
        // cells: the table's constant holds everywhere.
        _ => 0.0,
    }
}

/// The whole function's Lipschitz constant: the table's outside the edge cells, the measured
/// one inside (a segment through both is bounded by the larger).
fn stated_lipschitz(u: &dyn Dyn, name: &str) -> f32 {
    u.lipschitz().max(stated_edge_lipschitz(name))
}

/// The max-norm distance of two points and the largest change of a node value between them.
fn slope(u: &dyn Dyn, p: [f32; 3], vp: &[f32], q: [f32; 3], vq: &[f32]) -> Option<f64> {
    let dist = (0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0, f32::max);
    (dist > 0.0).then(|| {
        let change = vp
            .iter()
            .zip(vq)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        let _ = u;
        f64::from(change) / f64::from(dist)
    })
}

/// The seven directions the edge-cell scans walk: the axes and four diagonals.
const EDGE_DIRECTIONS: [[f64; 3]; 7] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
    [1.0, -1.0, 0.0],
    [0.0, 1.0, -1.0],
    [1.0, 0.0, -1.0],
];

/// The point `start + dir · t` clamped to the cube, in f32.
fn along(start: [f64; 3], dir: [f64; 3], t: f64) -> [f32; 3] {
    core::array::from_fn(|i| (start[i] + dir[i] * t).clamp(0.0, 1.0) as f32)
}

/// One segment of a scan line: from `start + dir · t0` to `start + dir · t1`, and its slope.
#[derive(Clone, Copy)]
struct Segment {
    start: [f64; 3],
    dir: [f64; 3],
    t0: f64,
    t1: f64,
    slope: f64,
}

/// The steepest segments of lines through every edge cell: along each of [`EDGE_DIRECTIONS`],
/// through the `lattice`² points of a lattice of the cell (the third coordinate shuffled),
/// half a cell either side of each, in steps of `1 / steps_per_cell` of a cell.
/// Returns the `keep` steepest segments, steepest first.
fn edge_scan(
    u: &dyn Dyn,
    b: &Baked,
    lattice: usize,
    steps_per_cell: usize,
    keep: usize,
) -> Vec<Segment> {
    let c = b.grid - 1;
    let words = u.edge_cells();
    let cell = 1.0 / c as f64;
    let h = cell / steps_per_cell as f64;
    let m = lattice - 1;
    let mut all = Vec::new();
    for idx in 0..c * c * c {
        if (words[idx / 32] >> (idx % 32)) & 1 == 0 {
            continue;
        }
        let lo = [idx / (c * c), (idx / c) % c, idx % c].map(|v| v as f64 * cell);
        for dir in EDGE_DIRECTIONS {
            for s in 0..lattice {
                for t in 0..lattice {
                    let start = [
                        lo[0] + (s as f64 / m as f64) * cell,
                        lo[1] + (t as f64 / m as f64) * cell,
                        lo[2] + ((s * 7 + t * 3) % lattice) as f64 / m as f64 * cell,
                    ];
                    let mut prev: Option<([f32; 3], Vec<f32>, f64)> = None;
                    for k in 0..=steps_per_cell {
                        let tk = (k as f64 - 0.5 * steps_per_cell as f64) * h;
                        let p = along(start, dir, tk);
                        let v = u.reflectance(p);
                        if let Some((q, w, tq)) = &prev {
                            if let Some(slope) = slope(u, p, &v, *q, w) {
                                all.push(Segment {
                                    start,
                                    dir,
                                    t0: *tq,
                                    t1: tk,
                                    slope,
                                });
                            }
                        }
                        prev = Some((p, v, tk));
                    }
                }
            }
        }
    }
    all.sort_by(|a, b| b.slope.total_cmp(&a.slope));
    all.truncate(keep);
    all
}

/// Halves `seg` `levels` times, each time keeping the steeper half: the slope and the length
/// (max norm) of the segment at each level, coarsest first, and where the last one lies. A slope cannot fall from one level to the next by more than rounding (the
/// change over a segment is at most the sum of its halves'), and it stays below the function's
/// Lipschitz constant at every level; across a jump it doubles with each halving.
fn refine(u: &dyn Dyn, seg: Segment, levels: usize) -> (Vec<(f64, f64)>, [f32; 3]) {
    let (mut t0, mut t1) = (seg.t0, seg.t1);
    let length = |t0: f64, t1: f64| {
        let (p, q) = (along(seg.start, seg.dir, t0), along(seg.start, seg.dir, t1));
        f64::from((0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0, f32::max))
    };
    let mut slopes = vec![(seg.slope, length(t0, t1))];
    for _ in 0..levels {
        let tm = 0.5 * (t0 + t1);
        let [p0, pm, p1] = [t0, tm, t1].map(|t| along(seg.start, seg.dir, t));
        let [v0, vm, v1] = [p0, pm, p1].map(|p| u.reflectance(p));
        let left = slope(u, p0, &v0, pm, &vm).unwrap_or(0.0);
        let right = slope(u, pm, &vm, p1, &v1).unwrap_or(0.0);
        if left >= right {
            t1 = tm;
            slopes.push((left, length(t0, t1)));
        } else {
            t0 = tm;
            slopes.push((right, length(t0, t1)));
        }
    }
    (slopes, along(seg.start, seg.dir, 0.5 * (t0 + t1)))
}

/// Where the exhaustive scans (`lipschitz_in_the_edge_cells_on_a_random_share` with
/// `SPECTRAL_QUADRATURE_EDGE_SCAN=all`) found each map's steepest segment (at steps of
/// 1/256 and 1/2048 of a cell; two more for `KQ_F11_6_REC2020` on the faces r = 0 and r = 1),
/// with the direction it walked: ramps narrower than the coarse scan's step, which its steepest
/// segments need not lead to (about 1/1000 of a cell wide, next to a face of the cube, where a
/// node value leaves its bound).
const STEEPEST_FOUND: [(&str, [f64; 3], [f64; 3]); 48] = [
    (
        "KQ_C_4_SRGB",
        [0.015625, 0.9951172, 0.0048828125],
        [0.0, 1.0, -1.0],
    ),
    (
        "KQ_C_4_SRGB",
        [0.046875, 0.9981079, 0.0018920898],
        [0.0, 1.0, -1.0],
    ),
    (
        "KQ_C_4_DISPLAY_P3",
        [0.8251953, 0.0, 0.0029296875],
        [1.0, 0.0, -1.0],
    ),
    (
        "KQ_C_4_DISPLAY_P3",
        [6.1035156e-5, 0.75006104, 6.1035156e-5],
        [1.0, 1.0, 1.0],
    ),
    (
        "KQ_C_4_REC2020",
        [0.016113281, 1.0, 0.06298828],
        [1.0, 1.0, 1.0],
    ),
    (
        "KQ_C_4_REC2020",
        [0.015930176, 1.0, 0.062805176],
        [1.0, 1.0, 1.0],
    ),
    ("KQ_C_4_MEYER_1987", [0.046875, 1.0, 0.0], [0.0, 1.0, -1.0]),
    (
        "KQ_C_6_SRGB",
        [0.8901367, 0.00048828125, 0.046875],
        [1.0, -1.0, 0.0],
    ),
    (
        "KQ_C_6_SRGB",
        [0.87438965, 0.00061035156, 0.03125],
        [1.0, -1.0, 0.0],
    ),
    (
        "KQ_C_6_DISPLAY_P3",
        [0.453125, 0.9458008, 0.022949219],
        [0.0, 1.0, -1.0],
    ),
    (
        "KQ_C_6_DISPLAY_P3",
        [0.390625, 0.04675293, 0.9844971],
        [0.0, 1.0, -1.0],
    ),
    (
        "KQ_C_6_REC2020",
        [0.00048828125, 0.8442383, 0.00048828125],
        [1.0, 1.0, 1.0],
    ),
    (
        "KQ_C_6_REC2020",
        [6.1035156e-5, 0.84381104, 6.1035156e-5],
        [1.0, 1.0, 1.0],
    ),
    (
        "KQ_C_6_MEYER_1987",
        [0.0, 0.98291016, 0.92041016],
        [1.0, 1.0, 1.0],
    ),
    (
        "KQ_C_6_MEYER_1987",
        [0.0, 0.9830322, 0.9205322],
        [1.0, 1.0, 1.0],
    ),
    ("KQ_C_8_DISPLAY_P3", [0.578125, 0.0, 0.0], [1.0, 0.0, -1.0]),
    (
        "KQ_C_8_DISPLAY_P3",
        [0.75, 0.0, 0.0007324219],
        [0.0, 0.0, 1.0],
    ),
    (
        "KQ_C_8_REC2020",
        [0.734375, 0.953125, 0.00048828125],
        [0.0, 0.0, 1.0],
    ),
    (
        "KQ_C_8_REC2020",
        [0.796875, 0.953125, 0.0],
        [0.0, 1.0, -1.0],
    ),
    (
        "KQ_C_8_MEYER_1987",
        [0.9941406, 0.005859375, 0.03125],
        [1.0, -1.0, 0.0],
    ),
    (
        "KQ_C_8_MEYER_1987",
        [1.0, 0.001953125, 0.033203125],
        [1.0, 1.0, 1.0],
    ),
    (
        "KQ_F11_6_SRGB",
        [0.9995117, 0.00048828125, 0.234375],
        [1.0, -1.0, 0.0],
    ),
    ("KQ_F11_6_SRGB", [0.984375, 0.0, 0.1875], [1.0, -1.0, 0.0]),
    (
        "KQ_F11_6_DISPLAY_P3",
        [0.98339844, 0.06347656, 0.546875],
        [1.0, -1.0, 0.0],
    ),
    (
        "KQ_F11_6_DISPLAY_P3",
        [0.951355, 0.06427002, 0.40625],
        [1.0, -1.0, 0.0],
    ),
    (
        "KQ_F11_6_REC2020",
        [0.08935547, 0.69189453, 0.5],
        [1.0, -1.0, 0.0],
    ),
    (
        "KQ_F11_6_REC2020",
        [0.0012817383, 0.016906738, 0.54815674],
        [1.0, 1.0, 1.0],
    ),
    (
        "KQ_F11_6_REC2020",
        [0.9993735, 0.984375, 0.5006265],
        [1.0, 0.0, -1.0],
    ),
    (
        "KQ_F11_6_REC2020",
        [0.0006103562, 0.015625, 0.49938965],
        [1.0, 0.0, -1.0],
    ),
    (
        "KQ_F11_6_MEYER_1987",
        [1.0, 0.0, 0.359375],
        [1.0, -1.0, 0.0],
    ),
    (
        "KQ_F11_6_MEYER_1987",
        [0.9677124, 0.0010375977, 0.21875],
        [1.0, -1.0, 0.0],
    ),
    (
        "TABLE2_ROW1_SRGB",
        [0.00036621094, 0.96875, 0.7496338],
        [1.0, 0.0, -1.0],
    ),
    (
        "TABLE2_ROW1_DISPLAY_P3",
        [0.12585449, 0.9696045, 0.0008544922],
        [1.0, 1.0, 1.0],
    ),
    (
        "TABLE2_ROW1_DISPLAY_P3",
        [0.125, 1.0, 0.00012207031],
        [0.0, 0.0, 1.0],
    ),
    (
        "TABLE2_ROW1_REC2020",
        [0.21936035, 0.85998535, 0.00061035156],
        [1.0, 1.0, 1.0],
    ),
    (
        "TABLE2_ROW1_REC2020",
        [0.234375, 0.890625, 0.00024414063],
        [0.0, 0.0, 1.0],
    ),
    (
        "TABLE2_ROW1_MEYER_1987",
        [0.032714844, 0.984375, 0.74853516],
        [1.0, 0.0, -1.0],
    ),
    (
        "TABLE2_ROW2_SRGB",
        [0.171875, 0.90625, 0.0],
        [0.0, 1.0, -1.0],
    ),
    (
        "TABLE2_ROW2_DISPLAY_P3",
        [0.17364502, 1.0, 0.0017700195],
        [1.0, 1.0, 1.0],
    ),
    (
        "TABLE2_ROW2_DISPLAY_P3",
        [0.140625, 1.0, 0.0026245117],
        [0.0, 0.0, 1.0],
    ),
    (
        "TABLE2_ROW2_REC2020",
        [0.4741211, 0.9897461, 0.0053710938],
        [1.0, 1.0, 1.0],
    ),
    (
        "TABLE2_ROW2_REC2020",
        [0.5, 1.0, 0.003479004],
        [0.0, 0.0, 1.0],
    ),
    (
        "TABLE2_ROW2_MEYER_1987",
        [0.046875, 0.40625, 0.0],
        [0.0, 1.0, -1.0],
    ),
    (
        "D65_A_F11_LED_B2_8_DISPLAY_P3",
        [0.921875, 0.99902344, 0.0009765625],
        [0.0, 1.0, -1.0],
    ),
    (
        "D65_A_F11_LED_B2_8_DISPLAY_P3",
        [0.078125, 0.0010986328, 0.99890137],
        [0.0, 1.0, -1.0],
    ),
    (
        "D65_A_F11_LED_B2_8_DISPLAY_P3",
        [0.25, 0.984375, 0.99993896],
        [0.0, 0.0, -1.0],
    ),
    (
        "D65_A_F11_LED_B2_8_REC2020",
        [0.546875, 0.90625, 0.0],
        [0.0, 1.0, -1.0],
    ),
    (
        "D65_A_F11_LED_B2_8_REC2020",
        [0.609375, 0.90625, 6.1035156e-5],
        [0.0, 0.0, 1.0],
    ),
];

/// The steepest slope on lines into the cube from its faces, through every edge cell that
/// touches a face: from the `lattice`² points of a lattice of the cell's square on the face,
/// `steps` steps of `1 / steps_per_cell` of a cell inward, along the face's normal. Where a
/// colour on a face needs a node value at its bound and one just inside does not, the node value
/// leaves the bound within about 1/1000 of a cell of the face: a ramp too narrow for the scans
/// through the cells. Returns the slope, where it was found and the direction.
fn face_scan(
    u: &dyn Dyn,
    b: &Baked,
    lattice: usize,
    steps_per_cell: f64,
    steps: usize,
    share: Share,
) -> (f64, [f32; 3], [f64; 3]) {
    let c = b.grid - 1;
    let words = u.edge_cells();
    let cell = 1.0 / c as f64;
    let h = cell / steps_per_cell;
    let m = (lattice - 1) as f64;
    let mut worst = (0.0f64, [0.0f32; 3], [0.0f64; 3]);
    for idx in 0..c * c * c {
        if (words[idx / 32] >> (idx % 32)) & 1 == 0 {
            continue;
        }
        let at = [idx / (c * c), (idx / c) % c, idx % c];
        for axis in 0..3 {
            for (face, inward) in [(0usize, 1.0f64), (c - 1, -1.0)] {
                if at[axis] != face {
                    continue;
                }
                let mut dir = [0.0f64; 3];
                dir[axis] = inward;
                let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
                for s in 0..lattice {
                    for t in 0..lattice {
                        let line = (&b.set, &b.display, lattice, idx, axis, face, s, t);
                        if !share.takes(line) {
                            continue;
                        }
                        let mut start = [0.0f64; 3];
                        start[axis] = if inward > 0.0 { 0.0 } else { 1.0 };
                        start[a1] = (at[a1] as f64 + s as f64 / m) * cell;
                        start[a2] = (at[a2] as f64 + t as f64 / m) * cell;
                        let mut prev: Option<([f32; 3], Vec<f32>)> = None;
                        for k in 0..=steps {
                            let p = along(start, dir, k as f64 * h);
                            let v = u.reflectance(p);
                            if let Some((q, w)) = &prev {
                                if let Some(slope) = slope(u, p, &v, *q, w) {
                                    if slope > worst.0 {
                                        worst = (slope, p, dir);
                                    }
                                }
                            }
                            prev = Some((p, v));
                        }
                    }
                }
            }
        }
    }
    worst
}

/// Holds every segment of `slopes` to `stated`, up to f32 rounding of the two evaluations (as
/// in `lipschitz_bound`).
fn assert_within(name: &str, stated: f64, slope: f64, length: f64, at: [f32; 3]) {
    let slack = 8.0 * f64::from(f32::EPSILON);
    assert!(
        slope * length <= stated * length + slack,
        "{name}: {slope} over {length} near {at:?}"
    );
}

/// The stated constants are measured at steps of 1/2048 of a cell; below that, the changes
/// between neighbouring f32 inputs are held to `stated_f32_jump`, at the steepest points the
/// scans find and along the lines where an earlier solve jumped (`JUMPS_FOUND`).
#[test]
fn lipschitz_in_the_edge_cells() {
    each_in_parallel(|u, f| {
        let edge_cells: u32 = u.edge_cells().iter().map(|w| w.count_ones()).sum();
        if edge_cells == 0 {
            return;
        }
        let stated = f64::from(stated_edge_lipschitz(f.name));
        // The 64 steepest segments of a coarse scan (1/32 of a cell), each halved six times
        // toward its steeper half (1/2048 of a cell): a slope stays, a jump doubles per halving.
        let steepest = edge_scan(u, f.baked, 5, 32, 64);
        let (mut worst, mut at) = (0.0f64, [0.0f32; 3]);
        let mut steep_points = Vec::new();
        for seg in &steepest {
            let (slopes, p) = refine(u, *seg, 6);
            for &(slope, length) in &slopes {
                if slope > worst {
                    (worst, at) = (slope, p);
                }
                assert_within(f.name, stated, slope, length, p);
            }
            steep_points.push(p);
        }
        // Into the cube from its faces, 1/64 of a cell deep, where the ramps too narrow for the
        // coarse scan lie.
        let (face, face_at, dir) = face_scan(u, f.baked, 5, 2048.0, 32, Share::ALL);
        let h = 1.0 / (2048.0 * (f.baked.grid - 1) as f64);
        assert_within(f.name, stated, face, h, face_at);
        steep_points.push(face_at);
        steep_points.push(face_scan(u, f.baked, 5, 65536.0, 32, Share::ALL).1);
        // The steepest spots the exhaustive scans found, 64 steps either side.
        let mut found = 0.0f64;
        for (_, start, dir) in STEEPEST_FOUND.iter().filter(|c| c.0 == f.name) {
            for k in -64..64 {
                let (p, q) = (
                    along(*start, *dir, k as f64 * h),
                    along(*start, *dir, (k + 1) as f64 * h),
                );
                let (vp, vq) = (u.reflectance(p), u.reflectance(q));
                if let Some(s) = slope(u, p, &vp, q, &vq) {
                    found = found.max(s);
                    let length = f64::from((0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0, f32::max));
                    assert_within(f.name, stated, s, length, p);
                }
            }
        }
        let jump = f32_jumps(u, f, &steep_points);
        println!(
            "{}: Lipschitz in the {edge_cells} edge cells {:.1} (steps of 1/32 of a cell), \
             {worst:.1} refined to 1/2048 (near {at:?}); from the faces {face:.1} (near \
             {face_at:?} along {dir:?}); at the spots found {found:.1}; stated {stated}; the \
             table's {:.3}; largest change between neighbouring f32 inputs {:.1e} near {:?}",
            f.name,
            steepest[0].slope,
            u.lipschitz(),
            jump.0,
            jump.1
        );
        assert!(
            jump.0 <= stated_f32_jump(f.name),
            "{}: a change of {:e} between neighbouring f32 inputs near {:?}",
            f.name,
            jump.0,
            jump.1
        );
    });
}

/// One in this many of the exhaustive scans' lines is walked by
/// `lipschitz_in_the_edge_cells_on_a_random_share` (about 11 s of CPU for the 24 maps in the
/// dev profile, where all of them take 177 s).
const EDGE_SCAN_ONE_IN: u64 = 16;

/// The exhaustive scans behind the stated constants (`edge_lipschitz` at 1/256 and 1/2048 of a
/// cell around 81 points of every edge cell along seven directions, `face_scan` from 81 points
/// of every face square) on one line in [`EDGE_SCAN_ONE_IN`], chosen afresh by a random seed
/// each run, so that the runs together walk every line. A failure prints its seed;
/// `SPECTRAL_QUADRATURE_EDGE_SCAN=<seed>` walks that run's share again, and
/// `SPECTRAL_QUADRATURE_EDGE_SCAN=all` every line (the measurement `docs/upsampling.md` quotes;
/// rerun it, and update `STEEPEST_FOUND` from what it prints, whenever the fit or the
/// correction changes).
#[test]
fn lipschitz_in_the_edge_cells_on_a_random_share() {
    let share = match std::env::var("SPECTRAL_QUADRATURE_EDGE_SCAN") {
        Ok(v) if v == "all" => Share::ALL,
        Ok(v) => Share {
            seed: v
                .parse()
                .expect("SPECTRAL_QUADRATURE_EDGE_SCAN: a seed (u64) or all"),
            one_in: EDGE_SCAN_ONE_IN,
        },
        Err(_) => Share {
            seed: {
                use std::hash::{BuildHasher, Hasher};
                std::collections::hash_map::RandomState::new()
                    .build_hasher()
                    .finish()
            },
            one_in: EDGE_SCAN_ONE_IN,
        },
    };
    println!(
        "edge scan: {share:?} (SPECTRAL_QUADRATURE_EDGE_SCAN={} repeats it)",
        share.seed
    );
    each_in_parallel(|u, f| {
        let (coarse, p, dir) = edge_lipschitz(u, f.baked, 256.0, share);
        let (fine, q, fine_dir) = edge_lipschitz(u, f.baked, 2048.0, share);
        let edge_cells: u32 = u.edge_cells().iter().map(|w| w.count_ones()).sum();
        println!(
            "{}: Lipschitz in the {edge_cells} edge cells {coarse:.3} (steps of 1/256 of a cell, \
             at {p:?} along {dir:?}), {fine:.3} (1/2048, at {q:?} along {fine_dir:?}); the \
             table's {:.3}",
            f.name,
            u.lipschitz()
        );
        // Into the cube from every face point of a finer lattice, 1/32 of a cell deep.
        let (face, face_at, face_dir) = face_scan(u, f.baked, 9, 2048.0, 64, share);
        println!(
            "{}: from the faces {face:.3} at {face_at:?} along {face_dir:?}",
            f.name
        );
        let stated = f64::from(stated_edge_lipschitz(f.name));
        assert!(
            coarse <= stated && fine <= stated && face <= stated,
            "{}: {coarse} at {p:?} along {dir:?}, {fine} at {q:?} along {fine_dir:?}, {face} at \
             {face_at:?} along {face_dir:?} (SPECTRAL_QUADRATURE_EDGE_SCAN={} repeats it)",
            f.name,
            share.seed
        );
    });
}

#[test]
fn round_trip_at_random_points() {
    // Points near the cube's faces, where the cells at the edge of what a set reaches lie.
    let channel = prop_oneof![0.0f32..0.15, 0.0f32..=1.0, 0.85f32..=1.0];
    check_property(
        1000,
        "round trip",
        [channel.clone(), channel.clone(), channel],
        |rgb| {
            let p = rgb.map(f64::from);
            each(|u, f| {
                let b = f.baked;
                let map = &b.fit.as_ref().unwrap().map;
                let (nearest, reachable) = spectral_quadrature_generator::upsampling::project(
                    f.matrices,
                    &b.encoding,
                    map,
                    p,
                )
                .unwrap();
                let got = lab(u, encode(u, f, &u.reflectance(rgb)));
                let want = if reachable {
                    lab(u, p)
                } else {
                    lab(
                        u,
                        spectral_quadrature_generator::upsampling::encode(&b.encoding, &nearest),
                    )
                };
                let de = delta_e2000(want, got);
                assert!(
                    de <= 0.05,
                    "{} at {rgb:?} (reachable {reachable}): {de}",
                    f.name
                );
            });
            Ok(())
        },
    );
}

#[test]
fn shader_words_hold_the_table_then_the_round_trip() {
    let u = upsampling::KQ_C_4_SRGB;
    let words: Vec<u32> = u.shader_words().collect();
    let codes: Vec<u16> = u.table().iter().flatten().copied().collect();
    let rt = u.round_trip().unwrap();
    let n_codes = codes.len().div_ceil(2);
    assert_eq!(words.len(), n_codes + rt.edge_cells().len() + 3 * 4 + 9 + 3);
    for (k, w) in words[..n_codes].iter().enumerate() {
        assert_eq!(*w & 0xffff, u32::from(codes[2 * k]));
        assert_eq!(
            *w >> 16,
            u32::from(codes.get(2 * k + 1).copied().unwrap_or(0))
        );
    }
    assert_eq!(
        &words[n_codes..n_codes + rt.edge_cells().len()],
        rt.edge_cells()
    );
    let f = n_codes + rt.edge_cells().len();
    assert_eq!(f32::from_bits(words[f + 5]), rt.weights()[1][1]);
    assert_eq!(f32::from_bits(words[f + 12 + 4]), rt.rgb_to_xyz()[1][1]);
}

/// The largest change of a node value between neighbouring f32 inputs that
/// `lipschitz_in_the_edge_cells` measures (`f32_jumps`), rounded up (`docs/upsampling.md`): f32
/// rounding in the correction's solve, and the steepest slopes of the function itself times
/// the inputs' spacing. A map not named has no edge cells or changes below 2e-5.
fn stated_f32_jump(name: &str) -> f32 {
    match name {
        "KQ_C_8_DISPLAY_P3" => 8.0e-5,
        "KQ_C_8_REC2020" => 3.0e-5,
        "KQ_F11_6_REC2020" => 2.5e-5,
        "D65_A_F11_LED_B2_8_REC2020" => 5.0e-5,
        _ => 2.0e-5,
    }
}

/// Lines, walked in steps of 1/1048576 of a cell, on which an earlier solve (normal equations
/// of the node values' colours, a multiplier test against a fixed threshold) jumped by up to
/// 6e-3 (the shared sets) and 1.4e-2 (Table 2's rows) between neighbouring f32 inputs.
const JUMPS_FOUND: [(&str, [f64; 3], [f64; 3]); 8] = [
    ("KQ_C_8_REC2020", [0.4375, 0.046875, 1.0], [0.0, 0.0, -1.0]),
    ("KQ_C_6_REC2020", [0.359375, 0.0, 0.953125], [0.0, 1.0, 0.0]),
    ("KQ_C_8_DISPLAY_P3", [0.40625, 1.0, 1.0], [0.0, 0.0, -1.0]),
    (
        "KQ_F11_6_REC2020",
        [0.90092003, 0.2552185, 0.5],
        [1.0, 0.0, 0.0],
    ),
    ("TABLE2_ROW1_SRGB", [0.0, 0.9998, 1.0], [0.0, 1.0, 0.0]),
    (
        "TABLE2_ROW1_REC2020",
        [0.09375, 0.998, 0.96875],
        [0.0, 1.0, 0.0],
    ),
    (
        "TABLE2_ROW1_MEYER_1987",
        [0.0, 0.9998, 0.99998474],
        [0.0, 1.0, 0.0],
    ),
    (
        "TABLE2_ROW2_DISPLAY_P3",
        [0.15625, 0.9998, 6.1035156e-5],
        [0.0, 1.0, 0.0],
    ),
];

/// The largest change of a node value between neighbouring f32 inputs, and where: 512 f32
/// neighbours along each axis through each of `points` (the steepest the scans find), and
/// 20 000 steps of 1/1048576 of a cell along the lines of `JUMPS_FOUND` for this map. Each
/// input evaluated once.
fn f32_jumps(u: &dyn Dyn, f: &Fresh, points: &[[f32; 3]]) -> (f32, [f32; 3]) {
    let change = |a: &[f32], b: &[f32]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f32, f32::max)
    };
    let mut worst = (0.0f32, [0.0f32; 3]);
    for &p in points {
        for axis in 0..3 {
            let mut q = p;
            q[axis] = f32::from_bits(q[axis].to_bits().saturating_sub(256));
            let mut vq = u.reflectance(q);
            for _ in 0..512 {
                let mut next = q;
                next[axis] = f32::from_bits(q[axis].to_bits() + 1);
                if next[axis] > 1.0 {
                    break;
                }
                let vn = u.reflectance(next);
                let c = change(&vq, &vn);
                if c > worst.0 {
                    worst = (c, next);
                }
                (q, vq) = (next, vn);
            }
        }
    }
    let h = 1.0 / (1_048_576.0 * (f.baked.grid - 1) as f64);
    for (_, start, dir) in JUMPS_FOUND.iter().filter(|j| j.0 == f.name) {
        let mut prev = u.reflectance(along(*start, *dir, -2000.0 * h));
        for k in -2000..18000 {
            let q = along(*start, *dir, (k + 1) as f64 * h);
            let vq = u.reflectance(q);
            let c = change(&prev, &vq);
            if c > worst.0 {
                worst = (c, q);
            }
            prev = vq;
        }
    }
    worst
}

/// The planar forms give `reflectance`'s bits on every pixel, for random and extreme RGB (NaN,
/// ±Inf, negative, huge, subnormal), and refuse length mismatches without writing.
#[test]
fn planar_forms_are_per_pixel() {
    let u = upsampling::KQ_C_4_SRGB;
    let specials = [
        f32::NAN,
        f32::INFINITY,
        -f32::INFINITY,
        -1.0,
        2.0,
        1e30,
        1e-45,
        0.0,
    ];
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let rgb: Vec<[f32; 3]> = (0..300)
        .map(|_| {
            std::array::from_fn(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                if state.is_multiple_of(6) {
                    specials[(state >> 8) as usize % specials.len()]
                } else {
                    ((state >> 40) as f32) / (1u64 << 24) as f32
                }
            })
        })
        .collect();
    let rgb_planes = [0, 1, 2].map(|c| rgb.iter().map(|p| p[c]).collect::<Vec<f32>>());
    let mut a = [0, 1, 2, 3].map(|_| vec![-1.0f32; rgb.len()]);
    let mut b = a.clone();
    let [a0, a1, a2, a3] = &mut a;
    let planes = rgb_planes.each_ref().map(|p| &p[..]);
    assert_eq!(u.reflectance_planar(planes, [a0, a1, a2, a3]), Ok(()));
    let [b0, b1, b2, b3] = &mut b;
    assert_eq!(
        u.reflectance_interleaved_to_planar(&rgb, [b0, b1, b2, b3]),
        Ok(())
    );
    for (p, px) in rgb.iter().enumerate() {
        let one = u.reflectance(*px).map(f32::to_bits);
        assert_eq!(
            a.each_ref().map(|n| n[p].to_bits()),
            one,
            "planar, pixel {p}"
        );
        assert_eq!(
            b.each_ref().map(|n| n[p].to_bits()),
            one,
            "interleaved, pixel {p}"
        );
    }
    // Length mismatches: an error, nothing written.
    let mut c = [0, 1, 2, 3].map(|_| vec![-1.0f32; 300]);
    let [c0, c1, c2, c3] = &mut c;
    let short = [planes[0], &planes[1][..299], planes[2]];
    let mismatch = |what| {
        Err(Error::LengthMismatch {
            what,
            expected: 300,
            got: 299,
        })
    };
    assert_eq!(
        u.reflectance_planar(short, [c0, c1, c2, c3]),
        mismatch(LengthOf::InputPlane)
    );
    let [c0, c1, c2, c3] = &mut c;
    let got = u.reflectance_planar(planes, [c0, c1, &mut c2[..299], c3]);
    assert_eq!(got, mismatch(LengthOf::OutputPlane));
    let [c0, c1, c2, c3] = &mut c;
    let got = u.reflectance_interleaved_to_planar(&rgb, [c0, c1, c2, &mut c3[..299]]);
    assert_eq!(got, mismatch(LengthOf::OutputPlane));
    assert!(c.iter().flatten().all(|&v| v == -1.0));
}
