//! The Planckian locus, the exact CCT reference and the baked locus table.

use crate::planckian::{self, PlanckianLocus};
use crate::scene::Scene;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

fn locus(observer: crate::ObserverId) -> PlanckianLocus {
    let settings = crate::Settings::for_observer(observer, DATA_DIR).unwrap();
    let d = crate::derive(&settings).unwrap();
    PlanckianLocus::standard(&d.observer).unwrap()
}

fn tables(text: &str) -> String {
    let scene = Scene::parse("scene.toml", text, std::path::Path::new(DATA_DIR)).unwrap();
    let d = crate::derive(&scene.settings).unwrap();
    crate::tests::tables_rs(&d, &[], &scene.resolve(&d).unwrap()).unwrap()
}

/// The tangent the table bakes is the derivative of the locus: a central difference agrees.
#[test]
fn the_tangent_is_the_derivative() {
    let l = locus(crate::ObserverId::Cie1931_2deg);
    for mired in [10.0, 50.0, 153.8, 350.0, 700.0, 1000.0] {
        let (_, t) = l.uv_and_tangent(mired);
        let h = 1e-3;
        let (a, b) = (l.uv_and_tangent(mired - h).0, l.uv_and_tangent(mired + h).0);
        for c in 0..2 {
            let fd = (b[c] - a[c]) / (2.0 * h);
            // A central difference errs by h²/6 · L‴ (below 1e-12 here) plus rounding
            // (1e-16 / 1e-3): relative 1e-8 of the tangent is ample.
            assert!(
                (fd - t[c]).abs() <= 1e-8 * t[0].hypot(t[1]),
                "{mired}: {fd} vs {}",
                t[c]
            );
        }
    }
}

/// The table: its ends, its tolerance at points the generator did not check, and the size the
/// docs state; another observer gives another locus.
#[test]
fn the_table() {
    let l = locus(crate::ObserverId::Cie1931_2deg);
    let nodes = l.table();
    assert_eq!(
        nodes.len(),
        111,
        "docs/colour-temperature-and-calibration.md states the size"
    );
    assert_eq!(nodes[0].mired, planckian::TABLE_MIRED[0]);
    assert!((nodes[nodes.len() - 1].mired - planckian::TABLE_MIRED[1]).abs() < 1e-9);
    assert!(nodes.windows(2).all(|w| w[0].mired < w[1].mired));
    // Every segment's cubic Hermite interpolant stays within the tolerance of the locus, checked
    // here at odd sixteenths, between the quarters the table's construction checks.
    for w in nodes.windows(2) {
        for k in (1..16).step_by(2) {
            let t = k as f64 / 16.0;
            let h = planckian::hermite(&w[0], &w[1], t);
            let e = l
                .uv_and_tangent(w[0].mired + t * (w[1].mired - w[0].mired))
                .0;
            let dist = (h[0] - e[0]).hypot(h[1] - e[1]);
            // A cubic Hermite's error is ∝ t²(1 − t)² to leading order, largest at the half,
            // which the construction checks: elsewhere it stays under the same bound.
            assert!(
                dist <= planckian::TABLE_TOLERANCE_UV,
                "segment at {} mired, t = {t}: {dist:e}",
                w[0].mired
            );
        }
    }
    let ten = locus(crate::ObserverId::Cie1964_10deg);
    let (a, b) = (l.uv_and_tangent(153.8).0, ten.uv_and_tangent(153.8).0);
    // D65's neighbourhood moves by 3.5e-4 in (u, v) from the 2° to the 10° observer.
    assert!((a[0] - b[0]).hypot(a[1] - b[1]) > 1e-4, "{a:?} {b:?}");
}

/// The numbers of one field of the baked `PLANCKIAN_LOCUS` in `tables`, in order (pairs
/// flattened): the argument of `PlanckianLocus::new` of that name.
fn baked_field(tables: &str, field: &str) -> Vec<f64> {
    let fields = [
        "mired",
        "uv",
        "tangent",
        "chord",
        "unit_tangent_q14",
        "along_q30",
    ];
    let index = fields.iter().position(|f| *f == field).unwrap();
    let start = tables.find("pub const PLANCKIAN_LOCUS").unwrap();
    let call = "crate::PlanckianLocus::new(";
    let mut text = &tables[start + tables[start..].find(call).unwrap() + call.len()..];
    // The arguments are arrays: skip `index` of them, then take the next.
    for k in 0..=index {
        let open = text.find('[').unwrap();
        let mut depth = 0;
        let end = open
            + text[open..]
                .char_indices()
                .find(|&(_, c)| {
                    depth += match c {
                        '[' => 1,
                        ']' => -1,
                        _ => 0,
                    };
                    depth == 0
                })
                .unwrap()
                .0;
        if k == index {
            text = &text[open + 1..end];
            break;
        }
        text = &text[end + 1..];
    }
    text.split(|c: char| c == ',' || c == '[' || c == ']' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap())
        .collect()
}

/// The baked table holds the table's nodes: each one's μ, point and tangent rounded to f32,
/// the chord to the next, and the tangent's direction and `L · T̂` in fixed point.
#[test]
fn the_baked_table_holds_the_nodes() {
    let text = tables("sets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\"]\n[extras]\ncct = true\n");
    let nodes = locus(crate::ObserverId::Cie1931_2deg).table();
    let f32s = |v: Vec<f64>| -> Vec<f32> { v.into_iter().map(|x| x as f32).collect() };
    let chords: Vec<[f64; 2]> = (0..nodes.len())
        .map(|i| match nodes.get(i + 1) {
            Some(next) => [0, 1].map(|c| next.uv[c] - nodes[i].uv[c]),
            None => [0.0; 2],
        })
        .collect();
    let fixed: Vec<([i16; 2], i32)> = nodes.iter().map(|n| n.fixed_point()).collect();
    for (field, expected) in [
        ("mired", nodes.iter().map(|n| n.mired).collect::<Vec<_>>()),
        ("uv", nodes.iter().flat_map(|n| n.uv).collect()),
        ("tangent", nodes.iter().flat_map(|n| n.tangent).collect()),
        ("chord", chords.into_iter().flatten().collect()),
    ] {
        let baked: Vec<f32> = baked_field(&text, field)
            .into_iter()
            .map(|x| x as f32)
            .collect();
        assert_eq!(baked, f32s(expected), "{field}");
    }
    let unit: Vec<f64> = fixed.iter().flat_map(|(u, _)| u.map(f64::from)).collect();
    assert_eq!(baked_field(&text, "unit_tangent_q14"), unit);
    let along: Vec<f64> = fixed.iter().map(|&(_, a)| f64::from(a)).collect();
    assert_eq!(baked_field(&text, "along_q30"), along);
}

/// `[extras] cct = true` bakes the locus; a scene without it does not; the default scene does.
#[test]
fn the_scene_decides() {
    let plain = tables("sets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\"]\n");
    assert!(!plain.contains("PLANCKIAN_LOCUS"));
    let with = tables("sets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\"]\n[extras]\ncct = true\n");
    assert!(with.contains("pub const PLANCKIAN_LOCUS: crate::PlanckianLocus<111> ="));
    assert!(
        with.contains("\"PLANCKIAN_LOCUS\","),
        "ALL_TABLES lists the table"
    );
    let d = crate::derive(&crate::Settings::new(DATA_DIR)).unwrap();
    let default = Scene::default_scene(std::path::Path::new(DATA_DIR))
        .resolve(&d)
        .unwrap();
    assert!(default.extras.cct);
}

/// The locus is integrated over CIE 015's 360-830 nm whatever the derivation's range, clipped
/// to the observer's table (the CIE 2015 tables start at 390 nm).
#[test]
fn the_locus_range_is_cie_015s() {
    assert_eq!(planckian::CIE_015_RANGE_NM, [360.0, 830.0]);
    for (observer, range) in [
        (crate::ObserverId::Cie1931_2deg, [360.0, 830.0]),
        (crate::ObserverId::Cie1964_10deg, [360.0, 830.0]),
        (crate::ObserverId::Cie2015_2deg, [390.0, 830.0]),
        (crate::ObserverId::Cie2015_10deg, [390.0, 830.0]),
    ] {
        let settings = crate::Settings::for_observer(observer, DATA_DIR).unwrap();
        let o = observer.load(std::path::Path::new(DATA_DIR)).unwrap();
        assert_eq!(planckian::standard_range_nm(&o), range, "{observer:?}");
        let standard = PlanckianLocus::standard(&o).unwrap();
        assert_eq!(standard, PlanckianLocus::new(&o, range).unwrap());
        // The derivation's own range (380-770 or 390-770 nm) is another locus.
        let scene = PlanckianLocus::new(&o, settings.range_nm).unwrap();
        assert_ne!(
            standard.uv_and_tangent(153.8).0,
            scene.uv_and_tangent(153.8).0,
            "{observer:?}"
        );
    }
    // A scene integrating over another range bakes the same locus, and its doc says the range.
    let default = tables("sets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\"]\n[extras]\ncct = true\n");
    let narrow = tables(
        "range_nm = [400, 700]\nsets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\"]\n[extras]\ncct = true\n",
    );
    let locus = |t: &str| {
        let start = t.find("pub const PLANCKIAN_LOCUS").unwrap();
        let end = start + t[start..].find("));").unwrap();
        t[start..end].to_string()
    };
    assert_eq!(locus(&default), locus(&narrow));
    let doc = default.replace("\n/// ", " ");
    assert!(doc.contains("at 1 nm over 360-830 nm, CIE 015's range, whatever range the scene"));
    let cie2015 = tables(
        "observer = \"cie2015_2deg\"\nsets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\"]\n[extras]\ncct = true\n",
    )
    .replace("\n/// ", " ");
    assert!(cie2015
        .contains("at 1 nm over 390-830 nm, CIE 015's 360-830 nm clipped to the observer's table"));
}
