//! Sets assembled at run time from baked per-channel rules, in a fixed capacity.

#![forbid(unsafe_code)]

use heapless::Vec;

use crate::model::error::check_length;
use crate::{Channel, Error, GaussRule, LengthOf, RuleStatus};

/// A wavelength set merged at run time from per-channel [`GaussRule`]s, for up to `CAP`
/// distinct wavelengths, without allocating (for example A order 4 + C1 order 2 + C2 order 1
/// chosen by a user setting). Baked sets ([`WavelengthSet`](crate::WavelengthSet)) are the
/// faster choice when the combination is known at compile time.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DynamicSet<const CAP: usize> {
    wavelengths_nm: Vec<f32, CAP>,
    weights: [Vec<f32, CAP>; 3],
}

impl<const CAP: usize> Default for DynamicSet<CAP> {
    fn default() -> Self {
        DynamicSet {
            wavelengths_nm: Vec::new(),
            weights: [Vec::new(), Vec::new(), Vec::new()],
        }
    }
}

impl<const CAP: usize> DynamicSet<CAP> {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// The union of the rules' nodes (equal wavelengths shared), each rule's weights added to
    /// its channel's row. Errors: [`Error::UndefinedRule`] for a rule that is not `Defined`,
    /// [`Error::Capacity`] when more than `CAP` distinct wavelengths would be needed. On error
    /// nothing is returned; never panics.
    pub fn from_rules(rules: &[GaussRule]) -> Result<Self, Error> {
        let mut set = Self::new();
        for rule in rules {
            set.add_rule(rule)?;
        }
        Ok(set)
    }

    /// Adds one rule (see [`from_rules`](Self::from_rules)). On error the set is unchanged.
    pub fn add_rule(&mut self, rule: &GaussRule) -> Result<(), Error> {
        if rule.status() != RuleStatus::Defined {
            return Err(Error::UndefinedRule {
                channel: rule.channel(),
                order: rule.order(),
            });
        }
        let new = rule
            .wavelengths_nm()
            .iter()
            .filter(|l| !self.wavelengths_nm.contains(l))
            .count();
        if self.wavelengths_nm.len() + new > CAP {
            return Err(Error::Capacity { capacity: CAP });
        }
        let c = rule.channel().index();
        for (&l, &w) in rule.wavelengths_nm().iter().zip(rule.weights()) {
            let i = match self.wavelengths_nm.iter().position(|&x| x == l) {
                Some(i) => i,
                None => {
                    let at = self.wavelengths_nm.partition_point(|&x| x < l);
                    // Capacity was checked above, so these inserts succeed.
                    let _ = self.wavelengths_nm.insert(at, l);
                    for row in self.weights.iter_mut() {
                        let _ = row.insert(at, 0.0);
                    }
                    at
                }
            };
            self.weights[c][i] += w;
        }
        Ok(())
    }

    /// Distinct wavelengths in nm, ascending.
    pub fn wavelengths_nm(&self) -> &[f32] {
        &self.wavelengths_nm
    }

    /// Channel `c`'s row of the weights, one weight per wavelength (dλ in nm).
    pub fn weights(&self, c: Channel) -> &[f32] {
        &self.weights[c.index()]
    }

    /// The number of distinct wavelengths.
    pub fn len(&self) -> usize {
        self.wavelengths_nm.len()
    }

    /// Whether the set has no wavelengths.
    pub fn is_empty(&self) -> bool {
        self.wavelengths_nm.is_empty()
    }

    /// `[A, C1, C2]` from samples at [`wavelengths_nm`](Self::wavelengths_nm).
    /// [`Error::LengthMismatch`] unless `samples.len() == self.len()`: [`LengthOf::Samples`],
    /// `expected` the set's wavelengths, `got` the samples. IEEE arithmetic as
    /// [`WavelengthSet::ac1c2`](crate::WavelengthSet::ac1c2).
    pub fn ac1c2(&self, samples: &[f32]) -> Result<[f32; 3], Error> {
        check_length(LengthOf::Samples, self.len(), samples.len())?;
        let mut out = [0.0f32; 3];
        for (o, row) in out.iter_mut().zip(&self.weights) {
            let mut acc = 0.0f32;
            for (w, s) in row.iter().zip(samples) {
                acc += w * s;
            }
            *o = acc;
        }
        Ok(out)
    }
}
