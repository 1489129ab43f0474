//! The generated header names every file that went into the tables, with its checksum: the
//! observer, the scene and any file it names, and the data files behind the shared sets.

use std::path::{Path, PathBuf};

use spectral_quadrature_generator::generate;

/// The runtime crate (its `data/` holds the data files).
fn crate_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The `  <label> sha256=<hex>` lines of a generated header. The header comment wraps a line
/// too long for 100 columns, its continuation indented four more (`//       sha256=<hex>`).
fn inputs(tables_rs: &str) -> Vec<(String, String)> {
    let mut lines: Vec<String> = Vec::new();
    for l in tables_rs.lines().take_while(|l| l.starts_with("//")) {
        match (l.strip_prefix("//     "), lines.last_mut()) {
            (Some(rest), Some(last)) => {
                last.push(' ');
                last.push_str(rest.trim_start());
            }
            _ => lines.push(l.to_string()),
        }
    }
    lines
        .iter()
        .filter_map(|l| l.strip_prefix("//   "))
        .map(|l| {
            let (label, sha) = l.split_once(" sha256=").expect("label sha256=hex");
            (label.to_string(), sha.to_string())
        })
        .collect()
}

/// The file's SHA-256 in hex, computed here with `sha2` rather than by the generator's helper.
fn sha256_of(path: &Path) -> String {
    use sha2::Digest;
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    sha2::Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// A scratch copy of the runtime crate's data/ (removed when dropped).
struct Scratch(PathBuf);

impl Scratch {
    fn new(tag: &str) -> Scratch {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .as_nanos();
        let dir = std::env::temp_dir().join(format!(
            "spectral_quadrature_provenance_{tag}_{}_{nanos}",
            std::process::id()
        ));
        std::fs::create_dir_all(dir.join("data")).unwrap();
        for entry in std::fs::read_dir(crate_dir().join("data")).unwrap() {
            let path = entry.unwrap().path();
            std::fs::copy(&path, dir.join("data").join(path.file_name().unwrap())).unwrap();
        }
        Scratch(dir)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn the_default_tables_name_every_input_with_its_checksum() {
    let out = generate(&crate_dir(), None).unwrap();
    let inputs = inputs(&out.tables_rs);
    let labels: Vec<&str> = inputs.iter().map(|(l, _)| l.as_str()).collect();
    // The default scene bakes KQ_C_4/6/8 and KQ_F11_6: their training set, lights and cache;
    // then the upsamplings' other training file, the upsampling cache, and D65, the reference
    // light of Table 2's rows (sets for radiances); then what the light group adds (the
    // ColorChecker, its third training file, and its lights A and LED_B2).
    assert_eq!(
        labels,
        [
            "data/cmf_cie1931_2deg_1nm.csv",
            "data/reflectance_cie_tcs.csv",
            "data/illuminant_C.csv",
            "data/shared_nodes.csv",
            "data/illuminant_F11.csv",
            "data/reflectance_rawtoaces_190.csv",
            "data/upsampling_codes.csv",
            "data/illuminant_D65.csv",
            "data/reflectance_colorchecker_ohta.csv",
            "data/illuminant_A.csv",
            "data/illuminant_LED_B2.csv",
        ]
    );
    for (label, sha) in &inputs {
        assert_eq!(*sha, sha256_of(&crate_dir().join(label)), "{label}");
    }
    // The same header is a const, for firmware to log.
    assert!(out
        .tables_rs
        .contains("pub const HEADER: &str = \"@generated"));
}

#[test]
fn a_scene_without_shared_sets_names_only_the_observer_and_itself() {
    let scene = crate_dir().join("examples/scenes/minimal.toml");
    let out = generate(&crate_dir(), Some(scene.as_os_str())).unwrap();
    let labels: Vec<String> = inputs(&out.tables_rs).into_iter().map(|(l, _)| l).collect();
    assert_eq!(
        labels,
        [
            "data/cmf_cie1931_2deg_1nm.csv",
            "examples/scenes/minimal.toml"
        ]
    );
}

#[test]
fn changing_one_input_in_a_scratch_copy_changes_its_line_and_only_its_line() {
    let scratch = Scratch::new("f11");
    let before = inputs(&generate(&scratch.0, None).unwrap().tables_rs);
    // One value of F11 a little higher.
    let file = scratch.0.join("data/illuminant_F11.csv");
    let text = std::fs::read_to_string(&file).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let row = lines
        .iter()
        .position(|l| l.starts_with("550,"))
        .expect("F11 has a row at 550 nm");
    let (nm, value) = lines[row].split_once(',').unwrap();
    let value: f64 = value.trim().parse().unwrap();
    lines[row] = format!("{nm},{}", value * 1.001);
    std::fs::write(&file, lines.join("\n") + "\n").unwrap();
    let after = inputs(&generate(&scratch.0, None).unwrap().tables_rs);
    assert_eq!(before.len(), after.len());
    for ((label, a), (label_after, b)) in before.iter().zip(&after) {
        assert_eq!(label, label_after);
        if label == "data/illuminant_F11.csv" {
            assert_ne!(a, b, "{label}: the checksum must change");
            assert_eq!(*b, sha256_of(&file));
        } else {
            assert_eq!(a, b, "{label} did not change");
        }
    }
}
