//! Links every table the scene baked, so that `size` shows what a scene costs when nothing is
//! left unused (consts a program does not use never reach its binary at all):
//!
//! ```text
//! cargo build --release --example size_probe && size target/release/examples/size_probe
//! SPECTRAL_QUADRATURE_SCENE=examples/scenes/minimal.toml cargo build --release --example size_probe
//! ```

use spectral_quadrature::tables;

fn main() {
    let all = std::hint::black_box(tables::ALL_TABLES);
    let floats: usize = all.iter().map(|(_, t)| t.len()).sum();
    let checksum: f64 = all
        .iter()
        .flat_map(|(_, t)| t.iter())
        .map(|&v| f64::from(v))
        .sum();
    println!(
        "scene {}: {} tables, {floats} f32 values ({} bytes linked), TABLE_BYTES = {}, checksum {checksum:.6e}",
        tables::SCENE,
        all.len(),
        4 * floats,
        tables::TABLE_BYTES
    );
}
