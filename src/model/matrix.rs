//! 3×3 products in f32: AC1C2 ↔ XYZ for one colour, and the matrix products the displays and
//! the folding of sets use.

#![forbid(unsafe_code)]

/// `[X, Y, Z]` from `[A, C1, C2]` with [`tables::AC1C2_TO_XYZ`](crate::tables::AC1C2_TO_XYZ).
/// IEEE arithmetic: NaN and ±Inf propagate; never panics.
#[inline]
pub fn xyz_from_ac1c2(ac1c2: [f32; 3]) -> [f32; 3] {
    mat3_vec(&crate::tables::AC1C2_TO_XYZ, ac1c2)
}

/// `[A, C1, C2]` from `[X, Y, Z]` with [`tables::XYZ_TO_AC1C2`](crate::tables::XYZ_TO_AC1C2)
/// (Eq. 9). IEEE arithmetic: NaN and ±Inf propagate; never panics.
#[inline]
pub fn ac1c2_from_xyz(xyz: [f32; 3]) -> [f32; 3] {
    mat3_vec(&crate::tables::XYZ_TO_AC1C2, xyz)
}

/// `m · v` in f32, each row summed left to right.
#[inline]
pub(crate) fn mat3_vec(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// `a · b` in f32, each entry summed left to right.
pub(crate) fn mat3_mul(a: &[[f32; 3]; 3], b: &[[f32; 3]; 3]) -> [[f32; 3]; 3] {
    let mut out = [[0.0f32; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    out
}
