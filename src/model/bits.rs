//! Equality by bits, in `const fn`s (where `PartialEq` cannot be called): f32 slices, bit for
//! bit, and strings, byte for byte. A leaf: the types' own const equality (`Display`'s,
//! `TransferFunction`'s) and the light-group set's check of its members' wavelengths use it.

#![forbid(unsafe_code)]

/// Whether two slices hold the same f32 bit patterns (so 0.0 and −0.0 differ, and a NaN equals
/// the same NaN).
pub(crate) const fn same_f32_bits(a: &[f32], b: &[f32]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i].to_bits() != b[i].to_bits() {
            return false;
        }
        i += 1;
    }
    true
}

/// Whether two strings are the same text.
pub(crate) const fn same_str(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}
