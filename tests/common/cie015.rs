//! CIE 015's colorimetry by plain sums, read straight from the data files with the csv crate
//! and not through the derivation: the independent side of the tests that compare the crate
//! with the standard.

/// The data files (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

/// CIE 015's range of integration, nm.
pub const CIE_015_NM: [u32; 2] = [360, 830];

/// A data file's rows of numbers, read with the csv crate (the header skipped).
pub fn read_rows(file: &str) -> Vec<Vec<f64>> {
    let path = std::path::Path::new(DATA_DIR).join(file);
    csv::Reader::from_path(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .records()
        .map(|r| {
            let r = r.unwrap_or_else(|e| panic!("{file}: {e}"));
            r.iter().map(|f| f.trim().parse::<f64>().unwrap()).collect()
        })
        .collect()
}

/// data/cmf_cie1931_2deg_1nm.csv over CIE 015's 360-830 nm: x̄, ȳ, z̄ at each whole nm.
pub fn cie1931_2deg() -> &'static Vec<[f64; 3]> {
    static T: std::sync::OnceLock<Vec<[f64; 3]>> = std::sync::OnceLock::new();
    T.get_or_init(|| {
        let rows = read_rows("cmf_cie1931_2deg_1nm.csv");
        let t: Vec<[f64; 3]> = (CIE_015_NM[0]..=CIE_015_NM[1])
            .enumerate()
            .map(|(i, nm)| {
                let r = &rows[i];
                assert_eq!(r[0], f64::from(nm), "the table is every nm from 360");
                [r[1], r[2], r[3]]
            })
            .collect();
        t
    })
}

/// XYZ of a spectrum by a plain 1 nm sum over 360-830 nm against the CIE 1931 2° functions.
pub fn plain_xyz(power: impl Fn(f64) -> f64) -> [f64; 3] {
    plain_xyz_over(CIE_015_NM, power)
}

/// The same over `range` (within 360-830 nm), nm.
pub fn plain_xyz_over(range: [u32; 2], power: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut xyz = [0.0; 3];
    for nm in range[0]..=range[1] {
        let w = cie1931_2deg()[(nm - CIE_015_NM[0]) as usize];
        let p = power(f64::from(nm));
        for c in 0..3 {
            xyz[c] += p * w[c];
        }
    }
    xyz
}

/// The XYZ of a light's 5 nm file in data/ by the plain method of CIE 015: the file linearly
/// interpolated to every nm of 360-830 nm, zero outside its range, summed against the CIE 1931
/// 2° functions (dλ = 1 nm).
pub fn plain_light_xyz(name: &str) -> [f64; 3] {
    plain_light_xyz_over(CIE_015_NM, name)
}

/// The same over `range` (within 360-830 nm), nm.
pub fn plain_light_xyz_over(range: [u32; 2], name: &str) -> [f64; 3] {
    let rows = read_rows(&format!("illuminant_{name}.csv"));
    plain_xyz_over(range, |nm| {
        let i = rows.partition_point(|r| r[0] < nm);
        match (i.checked_sub(1).and_then(|j| rows.get(j)), rows.get(i)) {
            (_, Some(b)) if b[0] == nm => b[1],
            (Some(a), Some(b)) => a[1] + (nm - a[0]) / (b[0] - a[0]) * (b[1] - a[1]),
            _ => 0.0,
        }
    })
}
