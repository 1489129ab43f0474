//! Section 1: the paper's Table 2, its sets' mean ΔE*ab on the ColorChecker under illuminant C
//! beside the paper's printed values (`tools::paper`), and the report's header above it.

use std::fmt::Write as _;

use spectral_quadrature_generator::Derivation;
use spectral_quadrature_spectra::{Reference, Stimulus};

use crate::tools::csv_table::Table;
use crate::tools::paper;

/// One row of Table 2.
pub struct Table2Row {
    name: String,
    wavelengths: Vec<f64>,
    mean_de76: f64,
    paper: f64,
}

/// Table 2's rows: each set of the paper's Table 2 judged on `stimuli` (the ColorChecker under
/// C) against `reference`.
pub fn rows(d: &Derivation, stimuli: &[Stimulus], reference: &Reference) -> Vec<Table2Row> {
    d.table2
        .iter()
        .zip(paper::TABLE2_MEAN_DELTA_E)
        .map(|(set, paper)| {
            let es = d.eval_set(set, "Table 2");
            Table2Row {
                name: name(&set.name),
                wavelengths: set.wavelengths_nm.clone(),
                mean_de76: reference.errors(&es, stimuli).mean_de76(),
                paper,
            }
        })
        .collect()
}

/// `TABLE2_ROW1` → `table2 row1`.
pub fn name(const_name: &str) -> String {
    const_name.to_lowercase().replace('_', " ")
}

/// table2.csv.
pub fn csv(rows: &[Table2Row]) -> Table {
    let mut t = Table::new("row,wavelengths_nm,mean_de76,paper_mean_de76,difference");
    for r in rows {
        let w: Vec<String> = r.wavelengths.iter().map(|l| format!("{l:.1}")).collect();
        t.row([
            r.name.clone(),
            w.join(" "),
            format!("{:.4}", r.mean_de76),
            r.paper.to_string(),
            format!("{:+.4}", r.mean_de76 - r.paper),
        ]);
    }
    t
}

/// The report's header: what every section's errors are measured against, and on what.
pub fn header(o: &mut String, stimuli: &[Stimulus]) {
    writeln!(o, "spectral-quadrature report: error against run time").ok();
    writeln!(o, "reference: full integration at 1 nm, 380-770 nm, CIE 1931 2°; CIELAB white integrated by the same rule as each colour").ok();
    writeln!(
        o,
        "{} stimuli (first: {}; last: {})\n",
        stimuli.len(),
        stimuli[0].name,
        stimuli[stimuli.len() - 1].name
    )
    .ok();
}

/// Section 1's text.
pub fn text(o: &mut String, table2: &[Table2Row]) {
    writeln!(
        o,
        "1. Table 2: ColorChecker (Ohta) under illuminant C, mean ΔE*ab"
    )
    .ok();
    writeln!(
        o,
        "   {:<12} {:<40} {:>8} {:>8} {:>8}",
        "row", "wavelengths (nm)", "derived", "paper", "diff"
    )
    .ok();
    for r in table2 {
        let w: Vec<String> = r.wavelengths.iter().map(|l| format!("{l:.1}")).collect();
        writeln!(
            o,
            "   {:<12} {:<40} {:>8.3} {:>8.3} {:>+8.3}",
            r.name,
            w.join(" "),
            r.mean_de76,
            r.paper,
            r.mean_de76 - r.paper
        )
        .ok();
    }
    writeln!(
        o,
        "   (the paper used McCamy's reflectances of the chart; these are Ohta's)\n"
    )
    .ok();
}
