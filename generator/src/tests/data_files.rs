//! Reading data files in the generator: the embedded CIE observers, observer tables (three
//! evenly spaced value columns), the shipped spectra of the runtime crate's `data/`, reading
//! observers from disk and grids on an observer table. The reader's own tests (malformed tables,
//! negative values, how a `DataError` is displayed) are `spectral-quadrature-spectra`'s, in
//! spectra/tests/.

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

/// The text of an observer's data file.
fn csv_text(id: ObserverId) -> String {
    let path = data_path(std::path::Path::new(DATA_DIR), id.file());
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

use crate::observer::{Observer, ObserverId};
use spectral_quadrature_spectra::{
    data_path, read_table, DataError, Spacing, Spectra, BUILTIN_FILES,
};

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

const HEADER: &str = "wavelength_nm,x_bar,y_bar,z_bar";

/// An observer-shaped table: `HEADER` then the given rows, one per line.
fn table_text(rows: &[&str]) -> String {
    let mut text = String::from(HEADER);
    text.push('\n');
    for row in rows {
        text.push_str(row);
        text.push('\n');
    }
    text
}

/// Asserts that `e` names `file`, `line`, and that its message contains every keyword
/// (case-insensitive).
fn assert_error(e: &DataError, file: &str, line: u64, keywords: &[&str]) {
    assert_eq!(e.file, file, "wrong file in {e:?}");
    assert_eq!(e.line, line, "wrong line in {e:?}");
    let message = e.message.to_lowercase();
    for k in keywords {
        assert!(
            message.contains(&k.to_lowercase()),
            "message of {e:?} lacks {k:?}"
        );
    }
}

/// A path under the temp directory that no other test (or run) uses.
fn unique_temp_path(stem: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    std::env::temp_dir().join(format!(
        "spectral_quadrature_{stem}_{}_{}_{nanos}.csv",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ))
}

/// Removes a temp file when dropped, so a failing assertion does not leave it behind.
struct TempFile(PathBuf);

impl TempFile {
    fn new(stem: &str, text: &str) -> TempFile {
        let path = unique_temp_path(stem);
        std::fs::write(&path, text).expect("write temp file");
        TempFile(path)
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

fn load(id: ObserverId) -> Observer {
    id.load(std::path::Path::new(DATA_DIR))
        .unwrap_or_else(|e| panic!("{} does not load: {e}", id.name()))
}

// ---------------------------------------------------------------------------------------------
// 1. The embedded observers.

#[test]
fn every_embedded_observer_loads_with_its_name_and_file() {
    for id in ObserverId::ALL {
        let obs = load(id);
        assert_eq!(obs.name, id.name());
        assert_eq!(obs.file, id.file());
        assert_eq!(obs.wavelengths.len(), obs.xyz.len(), "{}", id.name());
        assert_eq!(ObserverId::from_name(id.name()), Some(id));
    }
    assert_eq!(ObserverId::from_name("cie1931"), None);
}

#[test]
fn embedded_observers_are_distinct() {
    let observers: Vec<Observer> = ObserverId::ALL.into_iter().map(load).collect();
    for i in 0..observers.len() {
        for j in i + 1..observers.len() {
            assert_ne!(observers[i].name, observers[j].name);
            assert_ne!(observers[i].sha256, observers[j].sha256);
            assert_ne!(observers[i].xyz, observers[j].xyz);
        }
    }
}

#[test]
fn embedded_observer_checksum_is_sha256_of_the_text() {
    use sha2::Digest;
    for id in ObserverId::ALL {
        let obs = load(id);
        let expected: String = sha2::Sha256::digest(csv_text(id).as_bytes())
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        assert_eq!(obs.sha256.len(), 64);
        assert_eq!(obs.sha256, expected, "{}", id.name());
    }
}

#[test]
fn embedded_wavelengths_increase_at_1nm() {
    for id in ObserverId::ALL {
        let obs = load(id);
        assert!(obs.wavelengths.len() > 2, "{}", id.name());
        assert_eq!(obs.step(), 1.0, "{}", id.name());
        for (k, pair) in obs.wavelengths.windows(2).enumerate() {
            assert!(
                pair[1] > pair[0],
                "{}: row {k} not increasing: {pair:?}",
                id.name()
            );
            assert_eq!(pair[1] - pair[0], 1.0, "{}: row {k}: {pair:?}", id.name());
        }
        for &l in &obs.wavelengths {
            assert_eq!(l, l.round(), "{}: {l} nm is not whole", id.name());
        }
    }
}

#[test]
fn embedded_observer_ranges() {
    let expected = [
        (ObserverId::Cie1931_2deg, 360.0, 830.0, 471),
        (ObserverId::Cie1964_10deg, 360.0, 830.0, 471),
        (ObserverId::Cie2015_2deg, 390.0, 830.0, 441),
        (ObserverId::Cie2015_10deg, 390.0, 830.0, 441),
    ];
    for (id, first, last, rows) in expected {
        let obs = load(id);
        assert_eq!(obs.wavelengths.first(), Some(&first), "{}", id.name());
        assert_eq!(obs.wavelengths.last(), Some(&last), "{}", id.name());
        assert_eq!(obs.wavelengths.len(), rows, "{}", id.name());
    }
}

#[test]
fn embedded_values_are_finite_and_non_negative() {
    for id in ObserverId::ALL {
        let obs = load(id);
        for (l, v) in obs.wavelengths.iter().zip(&obs.xyz) {
            for (c, &x) in v.iter().enumerate() {
                assert!(x.is_finite(), "{} at {l} nm, column {c}: {x}", id.name());
                assert!(x >= 0.0, "{} at {l} nm, column {c}: {x}", id.name());
            }
        }
    }
}

#[test]
fn embedded_y_bar_peaks_near_555nm_at_about_one() {
    for id in ObserverId::ALL {
        let obs = load(id);
        let (k, peak) = obs.xyz.iter().map(|v| v[1]).enumerate().fold(
            (0, f64::NEG_INFINITY),
            |best, (k, y)| {
                if y > best.1 {
                    (k, y)
                } else {
                    best
                }
            },
        );
        let at = obs.wavelengths[k];
        assert!(
            (at - 555.0).abs() <= 5.0,
            "{}: y_bar peaks at {at} nm",
            id.name()
        );
        assert!(
            (peak - 1.0).abs() < 0.01,
            "{}: y_bar peak is {peak}",
            id.name()
        );
    }
}

#[test]
fn cie1931_2deg_known_values() {
    // Spot checks against the published CIE 1931 2° table (CIE 018:2019, 1 nm).
    let obs = load(ObserverId::Cie1931_2deg);
    let at = |nm: f64| obs.xyz[obs.wavelengths.iter().position(|&l| l == nm).unwrap()];
    assert_eq!(at(360.0), [0.0001299, 3.917e-06, 0.0006061]);
    let y555 = at(555.0)[1];
    assert!((y555 - 1.0).abs() < 1e-3, "y_bar(555) = {y555}");
    assert_eq!(at(830.0)[2], 0.0);
}

// ---------------------------------------------------------------------------------------------
// 2. Malformed observer tables: each is an error naming the label, the exact line and what is
// wrong. An observer is a table of three evenly spaced value columns; the reader's own
// malformed-table tests are in spectra/tests/table.rs.

#[test]
fn bad_row_deep_in_a_real_table_is_found_on_its_line() {
    // Corrupt one row of the embedded CIE 1931 table and check the line number.
    let text = csv_text(ObserverId::Cie1931_2deg);
    let text = text.as_str();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    // Line 197 (1-based) is the row for 555 nm: header + (555 - 360) rows before it.
    assert!(lines[196].starts_with("555,"), "{}", lines[196]);
    lines[196] = "555,0.5,NaN,0.005".to_string();
    let corrupted = lines.join("\n");
    let e = Observer::parse("cie1931_2deg", "corrupt.csv", &corrupted).unwrap_err();
    assert_error(&e, "corrupt.csv", 197, &["not finite", "y_bar"]);
}

#[test]
fn observer_parse_requires_three_value_columns() {
    let e = Observer::parse("two", "two.csv", "wavelength_nm,x,y\n400,1,2\n").unwrap_err();
    assert_error(&e, "two.csv", 1, &["expected 3"]);
}

#[test]
fn observer_parse_requires_even_spacing() {
    let text = table_text(&["400,1,2,3", "401,1,2,3", "403,1,2,3"]);
    let e = Observer::parse("uneven", "uneven.csv", &text).unwrap_err();
    assert_error(&e, "uneven.csv", 4, &["uneven"]);
}

#[test]
fn observer_parse_keeps_values_in_order() {
    let text = table_text(&["400,0.1,0.2,0.3", "402,0.4,0.5,0.6"]);
    let obs = Observer::parse("mine", "mine.csv", &text).unwrap();
    assert_eq!(obs.name, "mine");
    assert_eq!(obs.file, "mine.csv");
    assert_eq!(obs.wavelengths, [400.0, 402.0]);
    assert_eq!(obs.xyz, [[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]]);
    assert_eq!(obs.step(), 2.0);
}

// ---------------------------------------------------------------------------------------------
// 2b. Negative values in observer tables and in the shipped spectra: rounding noise read as 0
// and reported once, anything more negative an error naming line and column. The reader's rule
// itself (and the clamp) is tested in spectra/tests/negatives.rs.

#[test]
fn observer_tables_follow_the_same_rule() {
    let text = table_text(&["400,0.1,0.2,0.3", "402,0.4,-1e-17,0.6"]);
    let obs = Observer::parse("noisy", "noisy.csv", &text).unwrap();
    assert_eq!(obs.xyz[1], [0.4, 0.0, 0.6]);
    let z = obs.zeroed.unwrap();
    assert_eq!(
        (z.file.as_str(), z.first.line, z.first.column),
        ("noisy.csv", 3, 3)
    );
    let text = table_text(&["400,0.1,0.2,0.3", "402,0.4,-0.01,0.6"]);
    let e = Observer::parse("bad", "bad.csv", &text).unwrap_err();
    assert_error(&e, "bad.csv", 3, &["column 3 (y_bar)", "negative"]);
}

#[test]
fn the_rawtoaces_reflectances_read_with_their_rounding_noise_zeroed() {
    let file = "data/reflectance_rawtoaces_190.csv";
    let s = Spectra::builtin(std::path::Path::new(DATA_DIR), file).unwrap();
    assert_eq!(s.len(), 190);
    let curves = s.curves([380.0, 770.0]).unwrap();
    assert_eq!(curves[0].wavelengths.len(), 81);
    assert!(curves.iter().all(|c| c.values.iter().all(|v| *v >= 0.0)));
    // The file's 19 negative values (python3: any cell below 0) are all rounding residues of
    // about 1e-16, far inside the tolerance of its largest value, 1.4394.
    let z = s.zeroed().unwrap();
    assert_eq!((z.count, z.beyond_tolerance, z.largest), (19, 0, 1.4394));
    assert_eq!(
        (z.first.line, z.first.column, z.first.name.as_str()),
        (2, 20, "patch19")
    );
    assert_eq!(z.first.value, -6.93889390391e-18);
    assert_eq!((z.most_negative.line, z.most_negative.column), (2, 86));
    assert_eq!(z.most_negative.value, -2.22044604925e-16);
    assert!(
        z.to_string().starts_with(
            "data/reflectance_rawtoaces_190.csv:2: column 20 (patch19): 19 negative values read as 0, the first here (-6.93889390391e-18)"
        ),
        "{z}"
    );
}

#[test]
fn every_builtin_file_parses_and_covers_the_range() {
    for file in BUILTIN_FILES {
        let s = Spectra::builtin(std::path::Path::new(DATA_DIR), file)
            .unwrap_or_else(|e| panic!("{e}"));
        s.curves([380.0, 770.0]).unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn the_other_shipped_files_have_no_negative_values() {
    for file in BUILTIN_FILES {
        let s = Spectra::builtin(std::path::Path::new(DATA_DIR), file).unwrap();
        if file.ends_with("rawtoaces_190.csv") {
            continue;
        }
        assert_eq!(s.zeroed(), None, "{file}");
    }
    for id in ObserverId::ALL {
        assert_eq!(load(id).zeroed, None, "{}", id.name());
    }
}

// ---------------------------------------------------------------------------------------------
// 3. How errors are displayed: a `DataError` through the generator's `Error`. Its own display
// is tested in spectra/tests/error.rs.

#[test]
fn derive_error_displays_the_data_error() {
    let e = DataError {
        file: "x.csv".to_string(),
        line: 3,
        message: "bad".to_string(),
    };
    let wrapped: crate::Error = e.clone().into();
    assert_eq!(wrapped, crate::Error::Data(e));
    assert_eq!(wrapped.to_string(), "x.csv:3: bad");
}

// ---------------------------------------------------------------------------------------------
// 4. Reading from disk.

#[test]
fn read_missing_file_names_the_path() {
    let path = unique_temp_path("does_not_exist");
    assert!(!path.exists());
    let e = Observer::read("missing", &path).unwrap_err();
    let label = path.display().to_string();
    assert_error(&e, &label, 0, &["cannot read"]);
    let shown = e.to_string();
    assert!(shown.starts_with(&format!("{label}: ")), "{shown}");

    let e = read_table(&path, Some(3), Spacing::Even).unwrap_err();
    assert_error(&e, &label, 0, &["cannot read"]);
}

#[test]
fn read_directory_is_an_error_naming_it() {
    let dir = std::env::temp_dir();
    let e = Observer::read("dir", &dir).unwrap_err();
    assert_error(&e, &dir.display().to_string(), 0, &["cannot read"]);
}

#[test]
fn read_file_with_bad_row_names_path_and_line() {
    let file = TempFile::new(
        "bad_row",
        &table_text(&["400,1,2,3", "401,1,2,3", "402,1,2,3", "403,1,inf,3"]),
    );
    let label = file.0.display().to_string();
    let e = Observer::read("bad", &file.0).unwrap_err();
    assert_error(&e, &label, 5, &["not finite"]);
    assert!(e.to_string().starts_with(&format!("{label}:5: ")), "{e}");

    let e = read_table(&file.0, Some(3), Spacing::Any).unwrap_err();
    assert_error(&e, &label, 5, &["not finite"]);
}

#[test]
fn read_good_file_matches_parse() {
    let text = table_text(&["500,0.1,0.2,0.3", "501,0.4,0.5,0.6", "502,0.7,0.8,0.9"]);
    let file = TempFile::new("good", &text);
    let read = Observer::read("mine", &file.0).unwrap();
    let parsed = Observer::parse("mine", &file.0.display().to_string(), &text).unwrap();
    assert_eq!(read, parsed);
    assert_eq!(read.file, file.0.display().to_string());
}

#[test]
fn read_copy_of_embedded_table_matches_load() {
    let id = ObserverId::Cie2015_2deg;
    let file = TempFile::new("cie2015", &csv_text(id));
    let read = Observer::read(id.name(), &file.0).unwrap();
    let loaded = load(id);
    assert_eq!(read.wavelengths, loaded.wavelengths);
    assert_eq!(read.xyz, loaded.xyz);
    assert_eq!(read.sha256, loaded.sha256);
    assert_ne!(read.file, loaded.file);
}

#[test]
fn read_empty_file_is_a_whole_file_error() {
    let file = TempFile::new("empty", "");
    let e = Observer::read("empty", &file.0).unwrap_err();
    assert_error(&e, &file.0.display().to_string(), 0, &["empty"]);
}

// ---------------------------------------------------------------------------------------------
// 5. Grids on an observer table.

#[test]
fn grid_rows_paper_grid_on_cie1931() {
    let obs = load(ObserverId::Cie1931_2deg);
    let rows = obs.grid_rows(380.0, 770.0, 5.0).unwrap();
    assert_eq!(rows.len(), 79);
    let grid: Vec<f64> = rows.iter().map(|&r| obs.wavelengths[r]).collect();
    let expected: Vec<f64> = (0..79).map(|k| 380.0 + 5.0 * f64::from(k)).collect();
    assert_eq!(grid, expected);
    assert_eq!(rows[0], 20);
    assert_eq!(*rows.last().unwrap(), 410);
}

#[test]
fn grid_rows_full_table_at_1nm() {
    for id in ObserverId::ALL {
        let obs = load(id);
        let first = obs.wavelengths[0];
        let last = *obs.wavelengths.last().unwrap();
        let rows = obs.grid_rows(first, last, 1.0).unwrap();
        let all: Vec<usize> = (0..obs.wavelengths.len()).collect();
        assert_eq!(rows, all, "{}", id.name());
    }
}

#[test]
fn grid_rows_on_cie2015_from_390() {
    let obs = load(ObserverId::Cie2015_2deg);
    let rows = obs.grid_rows(390.0, 830.0, 10.0).unwrap();
    assert_eq!(rows.len(), 45);
    assert_eq!(obs.wavelengths[rows[0]], 390.0);
    assert_eq!(obs.wavelengths[*rows.last().unwrap()], 830.0);
}

fn grid_err(obs: &Observer, start: f64, end: f64, step: f64) -> String {
    match obs.grid_rows(start, end, step) {
        Ok(rows) => panic!(
            "{start}-{end} step {step}: expected an error, got {} rows",
            rows.len()
        ),
        // Grid mistakes are settings the derivation cannot honour.
        Err(crate::Error::Settings(message)) => message,
        Err(e) => panic!("{start}-{end} step {step}: expected Error::Settings, got {e:?}"),
    }
}

#[test]
fn grid_rows_range_not_covered() {
    let obs2015 = load(ObserverId::Cie2015_2deg);
    let e = grid_err(&obs2015, 380.0, 770.0, 5.0);
    assert!(e.contains("not covered"), "{e}");
    assert!(e.contains(ObserverId::Cie2015_2deg.file()), "{e}");
    let obs1931 = load(ObserverId::Cie1931_2deg);
    let e = grid_err(&obs1931, 380.0, 835.0, 5.0);
    assert!(e.contains("not covered"), "{e}");
    let e = grid_err(&obs1931, 355.0, 770.0, 5.0);
    assert!(e.contains("not covered"), "{e}");
}

#[test]
fn grid_rows_step_not_a_multiple_of_1nm() {
    let obs = load(ObserverId::Cie1931_2deg);
    for step in [2.5, 0.5, 1.0000001] {
        let e = grid_err(&obs, 380.0, 770.0, step);
        assert!(e.contains("whole multiple"), "step {step}: {e}");
    }
}

#[test]
fn grid_rows_range_not_a_whole_number_of_steps() {
    let obs = load(ObserverId::Cie1931_2deg);
    let e = grid_err(&obs, 380.0, 772.0, 5.0);
    assert!(e.contains("whole number"), "{e}");
}

#[test]
fn grid_rows_start_off_the_table_grid() {
    let obs = load(ObserverId::Cie1931_2deg);
    let e = grid_err(&obs, 380.5, 770.5, 5.0);
    assert!(e.contains("not on"), "{e}");
}

#[test]
fn grid_rows_invalid_ranges_and_steps() {
    let obs = load(ObserverId::Cie1931_2deg);
    let cases = [
        (770.0, 380.0, 5.0),
        (500.0, 500.0, 5.0),
        (380.0, 770.0, 0.0),
        (380.0, 770.0, -5.0),
        (f64::NAN, 770.0, 5.0),
        (380.0, f64::INFINITY, 5.0),
        (380.0, 770.0, f64::NAN),
    ];
    for (start, end, step) in cases {
        let e = grid_err(&obs, start, end, step);
        assert!(
            e.contains("not a valid grid"),
            "{start}-{end} step {step}: {e}"
        );
    }
}

#[test]
fn grid_rows_on_a_single_row_observer_is_an_error_not_a_panic() {
    let obs = Observer::parse("one", "one.csv", &table_text(&["500,1,2,3"])).unwrap();
    assert!(obs.grid_rows(500.0, 505.0, 5.0).is_err());
}
