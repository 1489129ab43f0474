//! Links every constant of numbers the scene baked (`tables::ALL_TABLES`: the sets, displays,
//! folded and integer sets, light groups, lights, upsampling maps, sensors, the Planckian locus
//! and the rules), so that `size` shows what a scene costs when nothing is left unused (consts a
//! program does not use never reach its binary at all):
//!
//! ```text
//! cargo build --release --example size_probe && size target/release/examples/size_probe
//! SPECTRAL_QUADRATURE_SCENE=examples/scenes/minimal.toml cargo build --release --example size_probe
//! ```

use spectral_quadrature::tables;

fn main() {
    let all = std::hint::black_box(tables::ALL_TABLES);
    let bytes: usize = all.iter().map(|&(_, bytes, _)| bytes).sum();
    // Each constant's own bytes, the size of its type, read through the reference that links it;
    // the rest are the slices its rules and upsampling maps point to.
    let own: usize = all
        .iter()
        .map(|&(_, _, value)| std::mem::size_of_val(value))
        .sum();
    println!(
        "scene {}: {} constants, {bytes} bytes ({own} in their types, {} in the slices they point to), TABLE_BYTES = {}",
        tables::SCENE,
        all.len(),
        bytes - own,
        tables::TABLE_BYTES
    );
}
