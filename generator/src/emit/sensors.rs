//! The scene's sensors beyond their sets (`tables::sensors`): each one's white reference for a
//! dark and white calibration at run time and, where the scene gives a device's readings, the
//! calibration fitted to them.

use std::string::String;
use std::vec::Vec;

use super::layout::{self, f32s, Expr};
use super::lists::Constant;
use super::model::Sensor;

/// The module `sensors` for `sensors` (empty text if there are none), each constant registered
/// in `consts`; a fitted calibration is made by `Calibration::new`, which checks it.
pub(crate) fn sensors_rs(sensors: &[Sensor], consts: &mut Vec<Constant>) -> String {
    if sensors.is_empty() {
        return String::new();
    }
    let mut o = layout::comment(
        0,
        "///",
        "Each sensor's white reference, and the calibration fitted to a device's readings where the scene gives them (`calibration = \"readings.csv\"`).",
        0,
    );
    o.push_str("pub mod sensors {\n");
    for s in sensors {
        let n = s.white.len();
        let doc = std::format!(
            "What the golden {0} reads on a perfect white under the light its set was fitted for (illuminant E for radiances), at the luminance the folded sets show as the display's white: the `reference` of [`Calibration::from_dark_white`](crate::Calibration::from_dark_white). Scale it by the white tile's reflectance. The same numbers are the set's samples of white: the integer forms `tables::integer::{0}_<DISPLAY>` take the largest of them as 65 535 counts.",
            s.name
        );
        o.push_str(&layout::comment(4, "///", &doc, 0));
        let name = std::format!("{}_WHITE", s.name);
        o.push_str(&layout::item(
            4,
            &std::format!("pub const {name}: [f32; {n}] ="),
            &f32s(&s.white),
        ));
        o.push('\n');
        consts.push(Constant::new(
            std::format!("sensors::{name}"),
            std::format!("[f32; {n}]"),
        ));
        if let Some(fit) = &s.calibration {
            let doc = std::format!(
                "The device's calibration fitted at build time to its readings of known reflectances: `apply` turns its raw readings into the golden {}'s, for the set's weights. Root-mean-square residual of the fit per channel, in the readings' units: {}.",
                s.name,
                fit.rms_residual
                    .iter()
                    .map(|r| std::format!("{r:.3}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            o.push_str(&layout::comment(4, "///", &doc, 0));
            let name = std::format!("{}_CALIBRATION", s.name);
            let value = Expr::Call(
                "super::checked".into(),
                std::vec![Expr::Call(
                    "crate::Calibration::new".into(),
                    std::vec![f32s(&fit.dark), f32s(&fit.gain)],
                )],
            );
            o.push_str(&layout::item(
                4,
                &std::format!("pub const {name}: crate::Calibration<{n}> ="),
                &value,
            ));
            o.push('\n');
            consts.push(Constant::new(
                std::format!("sensors::{name}"),
                std::format!("crate::Calibration<{n}>"),
            ));
        }
    }
    o.push_str("}\n\n");
    o
}
