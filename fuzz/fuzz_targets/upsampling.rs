//! RGB upsamplings on arbitrary colours: bytes → f32 RGB triples (raw bit patterns, NaN payloads,
//! ±Inf, subnormals, ±MAX, −0.0, and the landmarks of `common::INTERESTING` moved by a few ulps,
//! among them 0, 1 and the grid's cell edges' neighbours) → every upsampling the default scene
//! bakes (`tables::upsampling::all!`: the sets' maps and the light groups' maps, on every
//! display), through `reflectance`, `interpolate`, `reflectance_batch`, `reflectance_planar` and
//! `reflectance_interleaved_to_planar`.
//!
//! Checked: no panic; every node value in [0, 1], never NaN; the batch and planar paths give the
//! per-pixel bits; the node values' colour through the map's set is finite. For a light group's
//! map (`tables::groups::all!`: every group of the default scene has one), its set is the
//! group's first member, and the node values through every member of the group, each light's
//! accumulator, give finite linear RGB: a texel is meant for every light of its group.
#![no_main]

use common::Bytes;
use libfuzzer_sys::fuzz_target;
use spectral_quadrature::tables::{groups, upsampling};
use spectral_quadrature::{LightGroupSet, Upsampling};

/// At most this many pixels per input (longer inputs are truncated).
const MAX_PIXELS: usize = 16;

/// Every path of `up` on `px` against `reflectance`, and the bounds.
fn check<const N: usize>(name: &str, up: &Upsampling<N>, px: &[[f32; 3]]) {
    let n = px.len();
    let mut batch = vec![[f32::NAN; N]; n];
    up.reflectance_batch(px, &mut batch).unwrap();
    let channels: [Vec<f32>; 3] = std::array::from_fn(|c| px.iter().map(|p| p[c]).collect());
    let mut planes: [Vec<f32>; N] = std::array::from_fn(|_| vec![f32::NAN; n]);
    up.reflectance_planar(
        channels.each_ref().map(|c| &c[..]),
        planes.each_mut().map(|p| &mut p[..]),
    )
    .unwrap();
    let mut from_interleaved: [Vec<f32>; N] = std::array::from_fn(|_| vec![f32::NAN; n]);
    up.reflectance_interleaved_to_planar(px, from_interleaved.each_mut().map(|p| &mut p[..]))
        .unwrap();
    for (p, rgb) in px.iter().enumerate() {
        let r = up.reflectance(*rgb);
        let i = up.interpolate(*rgb);
        let hex = common::hex(rgb);
        for v in r.iter().chain(&i) {
            assert!((0.0..=1.0).contains(v), "{name} at {hex:?}: {r:?} {i:?}");
        }
        for k in 0..N {
            assert_eq!(
                batch[p][k].to_bits(),
                r[k].to_bits(),
                "{name} batch at {hex:?}"
            );
            assert_eq!(
                planes[k][p].to_bits(),
                r[k].to_bits(),
                "{name} planar at {hex:?}"
            );
            assert_eq!(
                from_interleaved[k][p].to_bits(),
                r[k].to_bits(),
                "{name} interleaved to planar at {hex:?}"
            );
        }
        let colour = up.set().linear_rgb(&r);
        assert!(
            colour.iter().all(|c| c.is_finite()),
            "{name} at {hex:?}: {colour:?}"
        );
    }
}

/// A light group's map: its set is the group's first member, and its node values through every
/// member give finite linear RGB.
fn check_group<const N: usize, const L: usize>(
    name: &str,
    up: &Upsampling<N>,
    group: &LightGroupSet<N, L>,
    px: &[[f32; 3]],
) {
    assert_eq!(
        Some(up.set()),
        group.member(0),
        "{name}: its set is the first member"
    );
    for rgb in px {
        let r = up.reflectance(*rgb);
        for k in 0..L {
            let member = group.member(k).unwrap();
            let colour = member.linear_rgb(&r);
            assert!(
                colour.iter().all(|c| c.is_finite()),
                "{name} under {}: {colour:?}",
                member.samples().light().unwrap_or("?")
            );
        }
    }
}

macro_rules! every_map {
    ($($name:ident,)*) => {
        fn every_map(px: &[[f32; 3]]) {
            $(check(stringify!($name), &upsampling::$name, px);)*
        }
    };
}
upsampling::all!(every_map);

macro_rules! every_group {
    ($($name:ident,)*) => {
        fn every_group(px: &[[f32; 3]]) {
            $(check_group(stringify!($name), &upsampling::$name, &groups::$name, px);)*
        }
    };
}
groups::all!(every_group);

fuzz_target!(|data: &[u8]| {
    let mut bytes = Bytes::new(data);
    let mut px = Vec::new();
    while !bytes.is_empty() && px.len() < MAX_PIXELS {
        px.push([bytes.value(), bytes.value(), bytes.value()]);
    }
    every_map(&px);
    every_group(&px);
});
