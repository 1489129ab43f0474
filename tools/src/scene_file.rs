//! The planner's output: a scene file naming the set `plan` chose
//! ([`spectral_quadrature_generator::plan::plan`]), with comment lines saying how it was chosen.

use spectral_quadrature_generator::plan::{fmt_de, Plan};

/// A scene file (TOML) naming the chosen set: comment lines saying how it was chosen and what
/// it measures (and what the best set with fewer wavelengths measures), then the keys
/// `observer`, `sets` and `displays`:
///
/// ```toml
/// # Scene written by the planner: <note>
/// # AC1C2_3_2_1 (6 wavelengths) meets mean ΔE00 <= 1 on 38 stimuli (measured ...); the best ...
/// observer = "cie1931_2deg"
/// sets = ["AC1C2_3_2_1"]
/// displays = ["SRGB"]
/// ```
pub fn scene_toml(plan: &Plan, observer_name: &str, displays: &[&str], note: &str) -> String {
    let mut s = String::new();
    let note = comment_text(note);
    if note.trim().is_empty() {
        s.push_str("# Scene written by the planner.\n");
    } else {
        s.push_str(&format!(
            "# Scene written by the planner: {}\n",
            note.trim()
        ));
    }
    s.push_str(&format!("# {}\n", sentence(plan)));
    s.push_str(&format!("observer = {}\n", toml_string(observer_name)));
    s.push_str(&format!("sets = [{}]\n", toml_string(&plan.chosen.name)));
    let displays: Vec<String> = displays.iter().map(|d| toml_string(d)).collect();
    s.push_str(&format!("displays = [{}]\n", displays.join(", ")));
    s
}

/// One sentence saying what was chosen and why: the set, its wavelengths, the budget, the
/// measured error, and what the best set with fewer wavelengths measures.
fn sentence(plan: &Plan) -> String {
    let c = &plan.chosen;
    let m = plan.metric;
    let mut s = format!(
        "{} ({} wavelengths) meets {m} ΔE00 <= {} on {} (measured {}; mean {}, max {}); ",
        c.name,
        c.wavelengths,
        plan.budget,
        if plan.stimuli == 1 {
            "1 stimulus".to_string()
        } else {
            format!("{} stimuli", plan.stimuli)
        },
        fmt_de(c.error(m)),
        fmt_de(c.mean_de00),
        fmt_de(c.max_de00),
    );
    match &plan.runner_up_with_fewer {
        Some(r) => s.push_str(&format!(
            "the best set with fewer wavelengths, {} ({} wavelengths), measures {}",
            r.name,
            r.wavelengths,
            fmt_de(r.error(m))
        )),
        None => s.push_str("no set has fewer wavelengths"),
    }
    s.push_str(&format!(" ({} sets evaluated).", plan.candidates.len()));
    s
}

/// A TOML basic string: quoted, with `"`, `\` and control characters escaped.
pub fn toml_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for ch in s.chars() {
        match ch {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if (c as u32) < 0x20 || c as u32 == 0x7f => {
                out.push_str(&format!("\\u{:04X}", c as u32))
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Text for a TOML comment: one line (line breaks and other control characters become spaces).
fn comment_text(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}
