//! Every function of the C header (`tables::c::HEADER`), compiled with the system C compiler,
//! against the runtime: on the extreme inputs (NaN, ±∞, ±0, subnormals, ±f32::MAX, negative
//! values, in every position) and on [`COUNT`] random inputs per function of the runtime (a
//! free function, each display's, and each family of the baked items' functions: the folded
//! sets' `encode_u8`, say, [`COUNT`] spread evenly over the items, at least [`MIN_PER_ITEM`]
//! each; `SQ_C_TESTS_COUNT=1000000` gives every item's function that many), the
//! same bits (NaN for NaN: the runtime documents NaN, not its payload) and the same bytes. The
//! one exception the header states: its 16-bit encoders of the sRGB curve and of power laws call
//! the C library's `powf`, and where that differs from the runtime's (Rust `libm`), a channel
//! may differ by one step of 65 535; each such test counts the differences, prints them and
//! asserts that none is larger than one step.

use spectral_quadrature::{
    ac1c2_from_xyz, quantize_u16, quantize_u8, srgb8_from_linear, tables, uv_from_xyz,
    xyz_from_ac1c2, Calibration, CountCalibration, Display, FoldedSet, GamutMapping, IntegerSet,
    LightGroupSet, LuxScale, TransferFunction, Upsampling, WavelengthSet,
};
use spectral_quadrature_c_tests::{find, function_names};

/// Random inputs per function (after the extreme ones).
const COUNT: usize = 1_000_000;
/// The fewest random inputs for one item's function.
const MIN_PER_ITEM: usize = 1 << 16;

/// Random inputs for each of `items` items of one family: COUNT spread over them, at least
/// MIN_PER_ITEM, or SQ_C_TESTS_COUNT each.
fn per_item(items: usize) -> usize {
    match std::env::var("SQ_C_TESTS_COUNT") {
        Ok(v) => v.parse().expect("SQ_C_TESTS_COUNT is a count"),
        Err(_) => (COUNT / items.max(1)).max(MIN_PER_ITEM),
    }
}

type F1 = unsafe extern "C" fn(*const f32, *mut f32);
type Enc8 = unsafe extern "C" fn(i32, *const f32, *mut u8);
type Enc16 = unsafe extern "C" fn(i32, *const f32, *mut u16);
type MapFn = unsafe extern "C" fn(i32, *const f32, *mut f32);
type Under = unsafe extern "C" fn(*const f32, *const f32, *mut f32);
type IntEnc = unsafe extern "C" fn(*const u16, *mut u8);
type IntFixed = unsafe extern "C" fn(*const u16, *mut i64);
type IntF32 = unsafe extern "C" fn(*const u16, *mut f32);

/// The header's function `name` with the C signature `T` (one of the aliases above).
fn get<T: Copy>(name: &str) -> T {
    let f = find(name);
    assert_eq!(
        core::mem::size_of::<T>(),
        core::mem::size_of::<unsafe extern "C" fn()>()
    );
    // SAFETY: T is a function pointer type matching the C definition of `name` (each test
    // names the alias of the header's signature); C allows casting function pointers to
    // another function pointer type and back.
    unsafe { core::mem::transmute_copy(&f) }
}

const MAPPINGS: [(GamutMapping, i32); 2] = [(GamutMapping::Clip, 0), (GamutMapping::PreserveA, 1)];

/// xorshift64*: the same inputs on every run.
struct Rng(u64);

impl Rng {
    fn new(seed: &str) -> Rng {
        Rng(seed.bytes().fold(0x9e37_79b9_7f4a_7c15, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
        }) | 1)
    }
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    /// A sample: mostly a plausible value (−0.1..1.3), some tiny ones, some any f32 at all.
    fn sample(&mut self) -> f32 {
        match self.next() % 16 {
            0..=10 => self.unit() * 1.4 - 0.1,
            11 => self.unit() * 1e-6,
            12 => f32::from_bits((self.next() >> 32) as u32 & 0x807f_ffff),
            _ => f32::from_bits((self.next() >> 32) as u32),
        }
    }
    fn count(&mut self) -> u16 {
        let v = (self.next() >> 48) as u16;
        match self.next() % 4 {
            0 => v,
            1 => v >> (self.next() % 16),
            2 => v >> 6,
            _ => v >> 2,
        }
    }
}

const SPECIALS: [f32; 14] = [
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    0.0,
    -0.0,
    1e-45,
    -1e-45,
    f32::MIN_POSITIVE,
    f32::MAX,
    f32::MIN,
    -1.0,
    1.0,
    0.5,
    1e30,
];

/// The extreme inputs of N samples (each special value in each position, the others 0.5, and
/// every sample the same special value), then `count` random ones.
fn inputs<const N: usize>(seed: &str, count: usize) -> impl Iterator<Item = [f32; N]> {
    let mut extremes = Vec::new();
    for &v in &SPECIALS {
        extremes.push([v; N]);
        for i in 0..N {
            let mut s = [0.5f32; N];
            s[i] = v;
            extremes.push(s);
        }
    }
    let mut rng = Rng::new(seed);
    extremes
        .into_iter()
        .chain((0..count).map(move |_| core::array::from_fn(|_| rng.sample())))
}

fn count_inputs<const N: usize>(seed: &str, count: usize) -> impl Iterator<Item = [u16; N]> {
    let mut extremes = vec![[0u16; N], [u16::MAX; N], [1; N]];
    for i in 0..N {
        for v in [u16::MAX, 1] {
            let mut x = [0u16; N];
            x[i] = v;
            extremes.push(x);
        }
    }
    let mut rng = Rng::new(seed);
    extremes
        .into_iter()
        .chain((0..count).map(move |_| core::array::from_fn(|_| rng.count())))
}

fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

#[track_caller]
fn assert_same<const K: usize>(
    what: &str,
    input: &dyn core::fmt::Debug,
    rust: [f32; K],
    c: [f32; K],
) {
    assert!(
        rust.iter().zip(&c).all(|(&a, &b)| same(a, b)),
        "{what} on {input:?}: runtime {rust:?}, header {c:?}"
    );
}

fn lower(name: &str) -> String {
    name.to_ascii_lowercase()
}

/// The 16-bit encoders: equal, or (where the curve calls powf) within one step; returns how
/// many channels differ.
#[track_caller]
fn check_u16(
    what: &str,
    input: &dyn core::fmt::Debug,
    pow: bool,
    rust: [u16; 3],
    c: [u16; 3],
) -> usize {
    let mut differ = 0;
    for (a, b) in rust.iter().zip(&c) {
        if a != b {
            assert!(
                pow && a.abs_diff(*b) <= 1,
                "{what} on {input:?}: runtime {rust:?}, header {c:?}"
            );
            differ += 1;
        }
    }
    differ
}

fn uses_pow(d: &Display) -> bool {
    matches!(
        d.transfer(),
        TransferFunction::Srgb | TransferFunction::Gamma(_)
    )
}

#[test]
fn the_header_defines_what_the_scene_bakes() {
    let names = function_names();
    let header = tables::c::HEADER;
    assert!(header.contains(tables::HEADER.lines().nth(3).unwrap_or("Inputs:")));
    for (file, sha) in tables::INPUTS {
        assert!(header.contains(&format!("{file} sha256={sha}")), "{file}");
    }
    for name in tables::folded::NAMES {
        let n = format!("sq_folded_{}_encode_u8", lower(name));
        assert!(names.contains(&n), "{n}");
    }
    for name in tables::sets::NAMES {
        let n = format!("sq_sets_{}_xyz", lower(name));
        assert!(names.contains(&n), "{n}");
    }
    for name in tables::integer::NAMES {
        let n = format!("sq_integer_{}_encode_u8", lower(name));
        assert!(names.contains(&n), "{n}");
    }
    for name in tables::groups::NAMES {
        let n = format!("sq_groups_{}_linear_rgb", lower(name));
        assert!(names.contains(&n), "{n}");
    }
    for name in tables::upsampling::NAMES {
        let n = format!("sq_upsampling_{}_interpolate", lower(name));
        assert!(names.contains(&n), "{n}");
    }
    println!(
        "the header: {} bytes, {} functions",
        header.len(),
        names.len()
    );
}

#[test]
fn srgb8_and_quantizers() {
    let srgb8: unsafe extern "C" fn(f32) -> u8 = get("sq_srgb8_from_linear");
    let q8: unsafe extern "C" fn(f32) -> u8 = get("sq_quantize_u8");
    let q16: unsafe extern "C" fn(f32) -> u16 = get("sq_quantize_u16");
    let mut rng = Rng::new("srgb8");
    // Every threshold's neighbourhood, the extremes, and random values and bits.
    let mut xs: Vec<f32> = SPECIALS.to_vec();
    for k in 1..256 {
        let boundary = ((k as f64 - 0.5) / 255.0 + 0.055) / 1.055;
        let t = boundary.powf(2.4) as f32;
        for d in -4i32..=4 {
            xs.push(f32::from_bits(t.to_bits().wrapping_add_signed(d)));
        }
    }
    xs.extend((0..4 * COUNT).map(|_| rng.sample()));
    for x in xs {
        // SAFETY: the header's `uint8_t sq_srgb8_from_linear(float)` and the quantizers.
        let (a, b, c) = unsafe { (srgb8(x), q8(x), q16(x)) };
        assert_eq!(a, srgb8_from_linear(x), "srgb8_from_linear({x:e})");
        assert_eq!(b, quantize_u8(x), "quantize_u8({x:e})");
        assert_eq!(c, quantize_u16(x), "quantize_u16({x:e})");
    }
}

#[test]
fn opponent_matrices() {
    let to_xyz: F1 = get("sq_xyz_from_ac1c2");
    let from_xyz: F1 = get("sq_ac1c2_from_xyz");
    for v in inputs::<3>("opponent", COUNT) {
        let mut a = [0.0f32; 3];
        let mut b = [0.0f32; 3];
        // SAFETY: 3 floats in, 3 out.
        unsafe {
            to_xyz(v.as_ptr(), a.as_mut_ptr());
            from_xyz(v.as_ptr(), b.as_mut_ptr());
        }
        assert_same("xyz_from_ac1c2", &v, xyz_from_ac1c2(v), a);
        assert_same("ac1c2_from_xyz", &v, ac1c2_from_xyz(v), b);
    }
}

fn check_set<const N: usize>(module: &str, name: &str, set: &WavelengthSet<N>, count: usize) {
    let c = format!("sq_{module}_{}", lower(name));
    let ac1c2: F1 = get(&format!("{c}_ac1c2"));
    let xyz: F1 = get(&format!("{c}_xyz"));
    for s in inputs::<N>(&c, count) {
        let mut a = [0.0f32; 3];
        let mut b = [0.0f32; 3];
        // SAFETY: N floats in, 3 out.
        unsafe {
            ac1c2(s.as_ptr(), a.as_mut_ptr());
            xyz(s.as_ptr(), b.as_mut_ptr());
        }
        assert_same(&format!("{c}_ac1c2"), &s, set.ac1c2(&s), a);
        assert_same(&format!("{c}_xyz"), &s, set.xyz(&s), b);
    }
    // WavelengthSet::fold for every display, at the baked scale and at extreme ones.
    type Fold = unsafe extern "C" fn(*const [f32; 3], f32, *mut f32);
    let fold: Fold = get(&format!("{c}_fold"));
    let scales = [
        1.0 / tables::UNIT_SPECTRUM_Y,
        1.0,
        -2.5,
        0.0,
        1e-45,
        3e38,
        f32::INFINITY,
        f32::NAN,
    ];
    for display in tables::displays::ALL {
        for scale in scales {
            let mut w = [[0.0f32; N]; 3];
            // SAFETY: a 3×3 matrix and a scale in, 3·N floats out.
            unsafe { fold(display.xyz_to_rgb().as_ptr(), scale, w.as_mut_ptr().cast()) };
            let r = set.fold(&display, scale).weights();
            for (rr, cr) in r.iter().zip(&w) {
                assert_same(&format!("{c}_fold {scale}"), &display.name(), *rr, *cr);
            }
        }
    }
}

#[test]
fn wavelength_sets() {
    macro_rules! each {
        ($($name:ident,)*) => {
            $( check_set("sets", stringify!($name), &tables::sets::$name, per_item(tables::sets::NAMES.len())); )*
        };
    }
    tables::sets::all!(each);
}

#[test]
fn rule_sets() {
    // The rule sets of the default scene's `[extras] rules`, where the scene has them.
    let names = function_names();
    macro_rules! each {
        ($($name:ident),*) => {
            $( if names.contains(&format!("sq_rules_{}_ac1c2", lower(stringify!($name)))) {
                check_set("rules", stringify!($name), &tables::rules::$name, per_item(5));
            } )*
        };
    }
    each!(A_1, A_8, A_16, C1_8, C2_7);
}

/// The displays of the scene, in the header's order (the order of `tables::displays::ALL`).
fn display_names() -> Vec<String> {
    function_names()
        .into_iter()
        .filter_map(|n| {
            n.strip_prefix("sq_displays_")?
                .strip_suffix("_encode_u8")
                .map(str::to_string)
        })
        .collect()
}

#[test]
fn displays() {
    let names = display_names();
    assert_eq!(names.len(), tables::displays::ALL.len());
    for (d, name) in tables::displays::ALL.iter().zip(&names) {
        let c = format!("sq_displays_{name}");
        let e8: Enc8 = get(&format!("{c}_encode_u8"));
        let e16: Enc16 = get(&format!("{c}_encode_u16"));
        let map: MapFn = get(&format!("{c}_map_gamut"));
        let from_xyz: F1 = get(&format!("{c}_linear_from_xyz"));
        let to_xyz: F1 = get(&format!("{c}_xyz_from_linear"));
        let mut differ = 0;
        for rgb in inputs::<3>(&c, COUNT) {
            for (mapping, m) in MAPPINGS {
                let (mut a, mut b, mut g) = ([0u8; 3], [0u16; 3], [0.0f32; 3]);
                // SAFETY: 3 floats in, 3 values out.
                unsafe {
                    e8(m, rgb.as_ptr(), a.as_mut_ptr());
                    e16(m, rgb.as_ptr(), b.as_mut_ptr());
                    map(m, rgb.as_ptr(), g.as_mut_ptr());
                }
                assert_eq!(
                    a,
                    d.encode_u8(mapping, rgb),
                    "{c}_encode_u8 {mapping:?} {rgb:?}"
                );
                differ += check_u16(&c, &rgb, uses_pow(d), d.encode_u16(mapping, rgb), b);
                assert_same(
                    &format!("{c}_map_gamut"),
                    &rgb,
                    d.map_gamut(mapping, rgb),
                    g,
                );
            }
            let (mut x, mut y) = ([0.0f32; 3], [0.0f32; 3]);
            // SAFETY: 3 floats in, 3 out.
            unsafe {
                from_xyz(rgb.as_ptr(), x.as_mut_ptr());
                to_xyz(rgb.as_ptr(), y.as_mut_ptr());
            }
            assert_same("linear_from_xyz", &rgb, d.linear_from_xyz(rgb), x);
            assert_same("xyz_from_linear", &rgb, d.xyz_from_linear(rgb), y);
        }
        println!(
            "{c}_encode_u16: {differ} channels of {} one step off the runtime (powf)",
            2 * 3 * COUNT
        );
    }
}

fn check_folded<const N: usize>(name: &str, set: &FoldedSet<N>, count: usize) {
    let c = format!("sq_folded_{}", lower(name));
    let lin: F1 = get(&format!("{c}_linear_rgb"));
    let under: Under = get(&format!("{c}_linear_rgb_under"));
    let e8: Enc8 = get(&format!("{c}_encode_u8"));
    let e16: Enc16 = get(&format!("{c}_encode_u16"));
    let pow = uses_pow(&set.display());
    let mut differ = 0;
    let mut previous = [0.7f32; N];
    for s in inputs::<N>(&c, count) {
        let (mut l, mut u) = ([0.0f32; 3], [0.0f32; 3]);
        // SAFETY: N floats in (twice for `under`), 3 out.
        unsafe {
            lin(s.as_ptr(), l.as_mut_ptr());
            under(previous.as_ptr(), s.as_ptr(), u.as_mut_ptr());
        }
        assert_same(&format!("{c}_linear_rgb"), &s, set.linear_rgb(&s), l);
        assert_same(
            &format!("{c}_linear_rgb_under"),
            &s,
            set.linear_rgb_under(&previous, &s),
            u,
        );
        for (mapping, m) in MAPPINGS {
            let (mut a, mut b) = ([0u8; 3], [0u16; 3]);
            // SAFETY: N floats in, 3 values out.
            unsafe {
                e8(m, s.as_ptr(), a.as_mut_ptr());
                e16(m, s.as_ptr(), b.as_mut_ptr());
            }
            assert_eq!(
                a,
                set.encode_u8(mapping, &s),
                "{c}_encode_u8 {mapping:?} {s:?}"
            );
            differ += check_u16(&c, &s, pow, set.encode_u16(mapping, &s), b);
        }
        previous = s;
    }
    println!(
        "{c}_encode_u16: {differ} channels of {} one step off the runtime (powf)",
        6 * count
    );
}

#[test]
fn folded_sets() {
    macro_rules! each {
        ($($name:ident,)*) => {
            $( check_folded(stringify!($name), &tables::folded::$name, per_item(tables::folded::NAMES.len())); )*
        };
    }
    tables::folded::all!(each);
}

fn check_group<const N: usize, const L: usize>(
    name: &str,
    group: &LightGroupSet<N, L>,
    count: usize,
) {
    let c = format!("sq_groups_{}", lower(name));
    let lin: F1 = get(&format!("{c}_linear_rgb"));
    let e8: Enc8 = get(&format!("{c}_encode_u8"));
    let e16: Enc16 = get(&format!("{c}_encode_u16"));
    let pow = uses_pow(&group.display());
    let mut differ = 0;
    let mut rng = Rng::new(&c);
    let extremes = SPECIALS.iter().map(|&v| [[v; N]; L]);
    let random =
        (0..count).map(|_| core::array::from_fn(|_| core::array::from_fn(|_| rng.sample())));
    for s in extremes.chain(random) {
        let s: [[f32; N]; L] = s;
        let flat: Vec<f32> = s.iter().flatten().copied().collect();
        let mut l = [0.0f32; 3];
        // SAFETY: L·N floats in, 3 out.
        unsafe { lin(flat.as_ptr(), l.as_mut_ptr()) };
        assert_same(&format!("{c}_linear_rgb"), &s, group.linear_rgb(&s), l);
        for (mapping, m) in MAPPINGS {
            let (mut a, mut b) = ([0u8; 3], [0u16; 3]);
            // SAFETY: L·N floats in, 3 values out.
            unsafe {
                e8(m, flat.as_ptr(), a.as_mut_ptr());
                e16(m, flat.as_ptr(), b.as_mut_ptr());
            }
            assert_eq!(
                a,
                group.encode_u8(mapping, &s),
                "{c}_encode_u8 {mapping:?} {s:?}"
            );
            differ += check_u16(&c, &s, pow, group.encode_u16(mapping, &s), b);
        }
    }
    println!(
        "{c}_encode_u16: {differ} channels of {} one step off the runtime (powf)",
        6 * count
    );
}

#[test]
fn light_groups() {
    macro_rules! each {
        ($($name:ident,)*) => {
            $( check_group(stringify!($name), &tables::groups::$name, per_item(tables::groups::NAMES.len())); )*
        };
    }
    tables::groups::all!(each);
}

/// Returns how many inputs the round trip corrected (where `reflectance` is not `interpolate`).
fn check_upsampling<const N: usize>(name: &str, map: &Upsampling<N>, count: usize) -> usize {
    let c = format!("sq_upsampling_{}", lower(name));
    let interpolate: F1 = get(&format!("{c}_interpolate"));
    let reflectance: F1 = get(&format!("{c}_reflectance"));
    let mut corrected = 0;
    for rgb in inputs::<3>(&c, count) {
        let (mut r, mut f) = ([0.0f32; N], [0.0f32; N]);
        // SAFETY: 3 floats in, N out.
        unsafe {
            interpolate(rgb.as_ptr(), r.as_mut_ptr());
            reflectance(rgb.as_ptr(), f.as_mut_ptr());
        }
        let plain = map.interpolate(rgb);
        let full = map.reflectance(rgb);
        assert_same(&format!("{c}_interpolate"), &rgb, plain, r);
        assert_same(&format!("{c}_reflectance"), &rgb, full, f);
        corrected += usize::from(plain.iter().zip(&full).any(|(a, b)| !same(*a, *b)));
    }
    corrected
}

#[test]
fn upsamplings() {
    let mut corrected = 0;
    macro_rules! each {
        ($($name:ident,)*) => {
            $( corrected += check_upsampling(stringify!($name), &tables::upsampling::$name, per_item(tables::upsampling::NAMES.len())); )*
        };
    }
    tables::upsampling::all!(each);
    // The round trip's correction ran, and gave the runtime's bits there too.
    println!("upsampling reflectance: {corrected} inputs corrected by the round trip");
    assert!(
        tables::upsampling::NAMES.is_empty() || corrected > 1000,
        "{corrected}"
    );
}

fn check_integer<const N: usize>(name: &str, set: &IntegerSet<N>, count: usize) {
    let c = format!("sq_integer_{}", lower(name));
    let e8: IntEnc = get(&format!("{c}_encode_u8"));
    let fixed: IntFixed = get(&format!("{c}_linear_fixed"));
    let as_f32: IntF32 = get(&format!("{c}_counts_as_f32"));
    for x in count_inputs::<N>(&c, count) {
        let (mut a, mut f, mut g) = ([0u8; 3], [0i64; 3], [0.0f32; N]);
        // SAFETY: N counts in, 3 or N values out.
        unsafe {
            e8(x.as_ptr(), a.as_mut_ptr());
            fixed(x.as_ptr(), f.as_mut_ptr());
            as_f32(x.as_ptr(), g.as_mut_ptr());
        }
        assert_eq!(a, set.encode_u8(&x), "{c}_encode_u8 {x:?}");
        assert_eq!(f, set.linear_fixed(&x), "{c}_linear_fixed {x:?}");
        assert_same(&format!("{c}_counts_as_f32"), &x, set.counts_as_f32(&x), g);
    }
}

#[test]
fn integer_sets() {
    macro_rules! each {
        ($($name:ident,)*) => {
            $( check_integer(stringify!($name), &tables::integer::$name, per_item(tables::integer::NAMES.len())); )*
        };
    }
    tables::integer::all!(each);
}

/// XYZ of a chromaticity (CIE 1960 u, v) at luminance y.
fn xyz_from_uv(u: f32, v: f32, y: f32) -> [f32; 3] {
    [1.5 * u / v * y, y, (4.0 - u - 10.0 * v) / (2.0 * v) * y]
}

#[test]
fn cct_duv_and_uv() {
    let names = function_names();
    let uv: unsafe extern "C" fn(*const f32, *mut f32) -> i32 = get("sq_uv_from_xyz");
    let mut rng = Rng::new("cct");
    let near_locus = |rng: &mut Rng| {
        xyz_from_uv(
            0.17 + 0.3 * rng.unit(),
            0.25 + 0.12 * rng.unit(),
            rng.unit() * 100.0,
        )
    };
    let extremes: Vec<[f32; 3]> = inputs::<3>("cct extremes", 0).collect();
    let mut xyzs = extremes.clone();
    for _ in 0..COUNT {
        xyzs.push(if rng.next().is_multiple_of(4) {
            core::array::from_fn(|_| rng.sample())
        } else {
            near_locus(&mut rng)
        });
    }
    for xyz in &xyzs {
        let mut out = [0.0f32; 2];
        // SAFETY: 3 floats in, 2 out.
        let ok = unsafe { uv(xyz.as_ptr(), out.as_mut_ptr()) };
        match uv_from_xyz(*xyz) {
            Some(r) => {
                assert_eq!(ok, 1, "uv_from_xyz {xyz:?}");
                assert_same("uv_from_xyz", xyz, r, out);
            }
            None => assert_eq!(ok, 0, "uv_from_xyz {xyz:?}"),
        }
    }
    if !names.iter().any(|n| n == "sq_planckian_locus_cct") {
        return;
    }
    #[repr(C)]
    struct SqCct {
        kelvin: f32,
        duv: f32,
    }
    let cct: unsafe extern "C" fn(*const f32, *mut SqCct) -> i32 = get("sq_planckian_locus_cct");
    let cct_uv: unsafe extern "C" fn(*const f32, *mut SqCct) -> i32 =
        get("sq_planckian_locus_cct_from_uv");
    let locus = &tables::PLANCKIAN_LOCUS;
    let mut found = 0;
    for xyz in &xyzs {
        let mut out = SqCct {
            kelvin: 0.0,
            duv: 0.0,
        };
        // SAFETY: 3 floats in, the struct out.
        let ok = unsafe { cct(xyz.as_ptr(), &mut out) };
        match locus.cct(*xyz) {
            Some(r) => {
                assert_eq!(ok, 1, "cct {xyz:?}");
                assert_same("cct", xyz, [r.kelvin, r.duv], [out.kelvin, out.duv]);
                found += 1;
            }
            None => assert_eq!(ok, 0, "cct {xyz:?}"),
        }
    }
    let uvs = (0..COUNT).map(|_| [rng.sample() * 0.6, rng.sample() * 0.5]);
    for p in extremes.iter().map(|x| [x[0], x[1]]).chain(uvs) {
        let mut out = SqCct {
            kelvin: 0.0,
            duv: 0.0,
        };
        // SAFETY: 2 floats in, the struct out.
        let ok = unsafe { cct_uv(p.as_ptr(), &mut out) };
        match locus.cct_from_uv(p) {
            Some(r) => {
                assert_eq!(ok, 1, "cct_from_uv {p:?}");
                assert_same("cct_from_uv", &p, [r.kelvin, r.duv], [out.kelvin, out.duv]);
            }
            None => assert_eq!(ok, 0, "cct_from_uv {p:?}"),
        }
    }
    // Most of the inputs near the locus have a CCT: the test compared numbers, not only Nones.
    assert!(found > COUNT / 4, "{found}");
}

#[test]
fn calibrations_and_lux() {
    type Apply = unsafe extern "C" fn(usize, *const f32, *const f32, *const f32, *mut f32);
    type CountApply = unsafe extern "C" fn(usize, *const u16, *const u32, *const u16, *mut u16);
    type FromDarkWhite =
        unsafe extern "C" fn(usize, *const u16, *const u16, *const u16, *mut u32) -> usize;
    let apply: Apply = get("sq_calibration_apply");
    let count_apply: CountApply = get("sq_count_calibration_apply");
    let from_dark_white: FromDarkWhite = get("sq_count_calibration_from_dark_white");
    let lux: unsafe extern "C" fn(f32, *const f32) -> f32 = get("sq_lux_scale_lux");
    const N: usize = 8;
    let mut rng = Rng::new("calibration");
    for i in 0..COUNT {
        let dark: [f32; N] = core::array::from_fn(|_| rng.unit() * 100.0);
        let gain: [f32; N] = core::array::from_fn(|_| 0.5 + rng.unit());
        let readings: [f32; N] = core::array::from_fn(|_| rng.sample() * 1000.0);
        let mut out = [0.0f32; N];
        // SAFETY: N floats in each, N out.
        unsafe {
            apply(
                N,
                dark.as_ptr(),
                gain.as_ptr(),
                readings.as_ptr(),
                out.as_mut_ptr(),
            )
        };
        let cal = Calibration::new(dark, gain).expect("finite, positive gains");
        assert_same("calibration apply", &readings, cal.apply(&readings), out);

        let dark: [u16; N] = core::array::from_fn(|_| rng.count() >> 4);
        let gain_q16: [u32; N] =
            core::array::from_fn(|_| (rng.next() >> 32) as u32 >> (rng.next() % 16));
        let counts: [u16; N] = core::array::from_fn(|_| rng.count());
        let mut c = [0u16; N];
        // SAFETY: N values in each, N out.
        unsafe {
            count_apply(
                N,
                dark.as_ptr(),
                gain_q16.as_ptr(),
                counts.as_ptr(),
                c.as_mut_ptr(),
            )
        };
        assert_eq!(
            c,
            CountCalibration::new(dark, gain_q16).apply(&counts),
            "{dark:?} {gain_q16:?} {counts:?}"
        );

        let white: [u16; N] = core::array::from_fn(|_| rng.count());
        let reference: [u16; N] =
            core::array::from_fn(|_| if i.is_multiple_of(64) { 0 } else { rng.count() });
        let mut g = [0u32; N];
        // SAFETY: N values in each, N out.
        let bad = unsafe {
            from_dark_white(
                N,
                dark.as_ptr(),
                white.as_ptr(),
                reference.as_ptr(),
                g.as_mut_ptr(),
            )
        };
        match CountCalibration::from_dark_white(&dark, &white, &reference) {
            Ok(cal) => {
                assert_eq!(bad, 0);
                assert_eq!(g, cal.gain_q16());
            }
            Err(spectral_quadrature::Error::Calibration { channel_index, .. }) => {
                assert_eq!(bad, channel_index + 1)
            }
            Err(e) => panic!("{e:?}"),
        }

        let xyz = [rng.sample(), rng.sample(), rng.sample()];
        let scale = 1.0 + rng.unit() * 1e4;
        // SAFETY: 3 floats in.
        let l = unsafe { lux(scale, xyz.as_ptr()) };
        let r = LuxScale::new(scale).expect("positive").lux(xyz);
        assert!(same(l, r), "lux {scale} {xyz:?}: {r} {l}");
    }
}

#[test]
fn calibrations_and_lux_from_readings() {
    type FromDarkWhite =
        unsafe extern "C" fn(usize, *const f32, *const f32, *const f32, *mut f32) -> usize;
    type ToCounts =
        unsafe extern "C" fn(usize, *const f32, *const f32, f32, *mut u16, *mut u32) -> usize;
    let from_dark_white: FromDarkWhite = get("sq_calibration_from_dark_white");
    let to_counts: ToCounts = get("sq_calibration_to_counts");
    let from_reading: unsafe extern "C" fn(f32, f32, *mut f32) -> i32 =
        get("sq_lux_scale_from_reading");
    const N: usize = 8;
    let mut rng = Rng::new("calibration from readings");
    // Mostly plausible readings, one channel in eight any sample at all (NaN, ±∞, huge, tiny,
    // negative): every error of each channel is reached.
    let reading = |rng: &mut Rng, scale: f32| -> f32 {
        if rng.next().is_multiple_of(8) {
            rng.sample()
        } else {
            rng.unit() * scale
        }
    };
    let (mut ok, mut refused) = (0, 0);
    for _ in 0..COUNT {
        let dark: [f32; N] = core::array::from_fn(|_| reading(&mut rng, 3000.0));
        let white: [f32; N] = core::array::from_fn(|k| dark[k] + reading(&mut rng, 60000.0));
        let reference: [f32; N] = core::array::from_fn(|_| reading(&mut rng, 2.0));
        let mut gain = [0.0f32; N];
        // SAFETY: N floats in each, N out.
        let bad = unsafe {
            from_dark_white(
                N,
                dark.as_ptr(),
                white.as_ptr(),
                reference.as_ptr(),
                gain.as_mut_ptr(),
            )
        };
        match Calibration::from_dark_white(&dark, &white, &reference) {
            Ok(cal) => {
                assert_eq!(bad, 0, "{dark:?} {white:?} {reference:?}");
                assert_same("calibration gain", &(dark, white), cal.gain(), gain);
                ok += 1;
            }
            Err(spectral_quadrature::Error::Calibration { channel_index, .. }) => {
                assert_eq!(bad, channel_index + 1, "{dark:?} {white:?} {reference:?}");
                refused += 1;
            }
            Err(e) => panic!("{e:?}"),
        }

        // to_counts of any calibration: darks and gains near and past the counts' range.
        let dark: [f32; N] = core::array::from_fn(|_| reading(&mut rng, 70000.0) - 1.0);
        let gain: [f32; N] = core::array::from_fn(|_| 0.01 + rng.unit() * 2.0);
        let unit = match rng.next() % 8 {
            0 => rng.sample(),
            1 => rng.unit() * 1e-7,
            _ => (0.5 + rng.unit()) * 2f32.powi(-((rng.next() % 20) as i32)),
        };
        let (mut d, mut g) = ([0u16; N], [0u32; N]);
        // SAFETY: N floats in each, N values out.
        let bad = unsafe {
            to_counts(
                N,
                dark.as_ptr(),
                gain.as_ptr(),
                unit,
                d.as_mut_ptr(),
                g.as_mut_ptr(),
            )
        };
        let cal = Calibration::new(dark, gain);
        match cal.map(|c| c.to_counts(unit)) {
            Ok(Ok(c)) => {
                assert_eq!(bad, 0, "{dark:?} {gain:?} {unit:e}");
                assert_eq!(
                    (d, g),
                    (c.dark(), c.gain_q16()),
                    "{dark:?} {gain:?} {unit:e}"
                );
            }
            Ok(Err(spectral_quadrature::Error::Calibration { channel_index, .. })) => {
                assert_eq!(bad, channel_index + 1, "{dark:?} {gain:?} {unit:e}");
            }
            // Calibration::new refuses a dark that is not finite: to_counts never sees it.
            Err(_) => {}
            Ok(Err(e)) => panic!("{e:?}"),
        }

        let (y, lux) = (rng.sample() * 100.0, rng.sample() * 1e4);
        let mut l = f32::NAN;
        // SAFETY: one float out.
        let made = unsafe { from_reading(y, lux, &mut l) };
        match LuxScale::from_reading(y, lux) {
            Ok(s) => {
                assert_eq!(made, 1, "{y:e} {lux:e}");
                assert!(same(l, s.lux_per_y()), "{y:e} {lux:e}: {l} {s:?}");
            }
            Err(_) => assert_eq!(made, 0, "{y:e} {lux:e}"),
        }
    }
    // Both outcomes were compared, many times each.
    println!("Calibration::from_dark_white: {ok} made, {refused} refused");
    assert!(ok > COUNT / 10 && refused > COUNT / 10, "{ok} {refused}");
}

/// IntegerSet::new on `folded` with its weights scaled and random sample units, against the
/// header's `sq_integer_set_new` with the display's curve `q63`; then each set made through
/// the encoder on `count` inputs.
fn check_run_time_integer<const N: usize>(
    name: &str,
    folded: &FoldedSet<N>,
    q63: *const u64,
    count: usize,
) -> (usize, usize) {
    type New = unsafe extern "C" fn(usize, *const f32, f32, *const u64, *mut i32) -> u32;
    type Fixed = unsafe extern "C" fn(usize, *const i32, *const u16, *mut i64);
    type Enc = unsafe extern "C" fn(usize, u32, *const i32, *const u64, *const u16, *mut u8);
    let new: New = get("sq_integer_set_new");
    let fixed_sums: Fixed = get("sq_integer_set_linear_fixed");
    let encode: Enc = get("sq_integer_set_encode_u8");
    let mut rng = Rng::new(name);
    let (mut made, mut refused) = (0, 0);
    for round in 0..64 {
        // The set's own weights, then scaled by 2^-8..2^40 (the last too large for any P), a
        // weight made NaN or infinite now and then.
        let scale = if round == 0 {
            1.0
        } else {
            2f32.powi((rng.next() % 49) as i32 - 8) * (0.5 + rng.unit())
        };
        let mut weights = folded.weights().map(|row| row.map(|w| w * scale));
        if round % 16 == 15 {
            weights[(rng.next() % 3) as usize][(rng.next() % N as u64) as usize] =
                SPECIALS[(rng.next() % 3) as usize];
        }
        let Ok(f) = FoldedSet::new(
            folded.wavelengths_nm(),
            weights,
            folded.samples(),
            folded.display(),
        ) else {
            continue;
        };
        let unit = match round % 8 {
            0 => 1.0 / 65535.0,
            1 => SPECIALS[(rng.next() % SPECIALS.len() as u64) as usize],
            _ => (0.5 + rng.unit()) * 2f32.powi(-((rng.next() % 24) as i32)),
        };
        let mut fixed = [[0i32; N]; 3];
        // SAFETY: 3 rows of N weights in, 3 rows of N out, the header's own curve table.
        let p = unsafe {
            new(
                N,
                weights.as_ptr().cast(),
                unit,
                q63,
                fixed.as_mut_ptr().cast(),
            )
        };
        let Ok(set) = IntegerSet::new(&f, unit) else {
            assert_eq!(p, 0, "{name} × {scale:e}, unit {unit:e}");
            refused += 1;
            continue;
        };
        assert_eq!(p, set.frac_bits(), "{name} × {scale:e}, unit {unit:e}");
        assert_eq!(fixed, set.weights(), "{name} × {scale:e}, unit {unit:e}");
        made += 1;
        for x in count_inputs::<N>(name, count / 64) {
            let (mut a, mut s) = ([0u8; 3], [0i64; 3]);
            // SAFETY: N counts in, 3 values out; the weights and curve as above.
            unsafe {
                encode(N, p, fixed.as_ptr().cast(), q63, x.as_ptr(), a.as_mut_ptr());
                fixed_sums(N, fixed.as_ptr().cast(), x.as_ptr(), s.as_mut_ptr());
            }
            assert_eq!(
                a,
                set.encode_u8(&x),
                "{name} × {scale:e}, unit {unit:e}: {x:?}"
            );
            assert_eq!(s, set.linear_fixed(&x), "{name} × {scale:e}: {x:?}");
        }
    }
    (made, refused)
}

#[test]
fn integer_sets_made_at_run_time() {
    let (mut made, mut refused) = (0, 0);
    macro_rules! each {
        ($($name:ident,)*) => {
            $(
                let f = &tables::folded::$name;
                let curve = match f.display().transfer() {
                    TransferFunction::Srgb => spectral_quadrature_c_tests::q63("sq_srgb8_q63"),
                    TransferFunction::Linear => spectral_quadrature_c_tests::q63("sq_linear8_q63"),
                    _ => None,
                };
                if let Some(q63) = curve {
                    let (m, r) = check_run_time_integer(
                        stringify!($name),
                        f,
                        q63,
                        per_item(tables::folded::NAMES.len()),
                    );
                    made += m;
                    refused += r;
                }
            )*
        };
    }
    tables::folded::all!(each);
    println!("IntegerSet::new at run time: {made} sets made, {refused} refused");
    // Where the header has an integer curve, both outcomes were compared.
    if !tables::integer::NAMES.is_empty() {
        assert!(made > 10 && refused > 5, "{made} {refused}");
    }
}
