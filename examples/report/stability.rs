//! Section 6 of the report: numerical stability. Where the method and its numbers hold, where
//! they break, and how close each classification is to flipping.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::derive::sensitivity::{shifts, standard_variants};
use crate::derive::Settings;

const CHANNELS: [&str; 3] = ["A", "C1", "C2"];

/// The sensitivity table: node shifts against the baseline for each variant, orders 1-8.
pub fn sensitivity(o: &mut String, csv: &mut String) -> Result<(), String> {
    let rows = shifts(&Settings::default(), &standard_variants(), 8).map_err(|e| e.to_string())?;
    writeln!(o, "   6c. sensitivity: how far each rule moves (largest node shift in nm; '-' where either is undefined)").ok();
    writeln!(
        o,
        "   {:<14} {:<3} {}",
        "variant",
        "ch",
        (1..=8).map(|n| format!("{n:>8}")).collect::<String>()
    )
    .ok();
    csv.push_str("variant,channel,order,baseline_status,variant_status,max_node_shift_nm,max_weight_change\n");
    for v in standard_variants() {
        for (c, ch) in CHANNELS.iter().enumerate() {
            let cells: String = rows
                .iter()
                .filter(|r| r.variant == v.name && r.channel == c)
                .map(|r| match r.max_node_shift_nm {
                    Some(s) => format!("{s:>8.2}"),
                    None if r.baseline != r.changed => format!(
                        "{:>8}",
                        format!(
                            "{}>{}",
                            short(r.baseline.as_str()),
                            short(r.changed.as_str())
                        )
                    ),
                    None => format!("{:>8}", "-"),
                })
                .collect();
            writeln!(o, "   {:<14} {:<3} {cells}", v.name, ch).ok();
        }
    }
    for r in &rows {
        writeln!(
            csv,
            "{},{},{},{},{},{},{}",
            r.variant,
            CHANNELS[r.channel],
            r.order,
            r.baseline.as_str(),
            r.changed.as_str(),
            r.max_node_shift_nm
                .map_or(String::new(), |v| format!("{v:.4}")),
            r.max_weight_change
                .map_or(String::new(), |v| format!("{v:.3e}"))
        )
        .ok();
    }
    writeln!(
        o,
        "   (d>o: defined in the baseline, outside in the variant; c = complex)\n"
    )
    .ok();
    Ok(())
}

fn short(status: &str) -> &'static str {
    match status {
        "defined" => "d",
        "outside" => "o",
        "complex" => "c",
        _ => "v",
    }
}

/// Runs every part of the section; returns the text and the files written.
pub fn section(out: &Path) -> Result<(String, Vec<PathBuf>), String> {
    let mut o = String::new();
    let mut files = Vec::new();
    writeln!(o, "6. Stability").ok();
    let mut csv = String::new();
    sensitivity(&mut o, &mut csv)?;
    files.push(crate::write(out, "sensitivity.csv", &csv)?);
    Ok((o, files))
}
