//! The box's geometry: its quads read from `data/cornell_box_geometry.csv`, meshed into patches,
//! the form factors between patches (with visibility), and rays for the camera.
//!
//! **Form factors.** `F[i][j]`, the share of the light leaving patch i that reaches patch j, is
//! computed from patch i's centre: the analytic form factor from a differential area to the
//! polygon of patch j (Lambert's contour integral, `F = (1/2π) Σ γₖ n·(Rₖ × Rₖ₊₁)/|Rₖ ×
//! Rₖ₊₁|` over the polygon's edges, after clipping the polygon to the hemisphere above i),
//! times the share of the rays from the centre of i to `VIS_RAYS`² points spread over j (those
//! above i's plane) that no box face blocks. The room's walls are convex and never block; only
//! the two boxes' faces are tested.

use crate::Error;
use spectral_quadrature_tools as tools;

/// A point or direction in the box's coordinates, mm.
pub type V3 = [f64; 3];

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(crate) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub(crate) fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
pub(crate) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub(crate) fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}
pub(crate) fn unit(a: V3) -> V3 {
    scale(a, 1.0 / norm(a))
}

/// What a surface is made of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Material {
    /// The white paint.
    White,
    /// The red paint (the left wall).
    Red,
    /// The green paint (the right wall).
    Green,
    /// The light: it emits and reflects nothing.
    Light,
}

impl Material {
    /// The paints, in the order of the reflectance file's columns.
    pub const PAINTS: [Material; 3] = [Material::White, Material::Red, Material::Green];

    /// The paint's column index, `None` for the light.
    pub fn paint_index(self) -> Option<usize> {
        match self {
            Material::White => Some(0),
            Material::Red => Some(1),
            Material::Green => Some(2),
            Material::Light => None,
        }
    }
}

/// A planar quad of the box: `P(u, v) = (1−u)(1−v) a + u(1−v) b + uv c + (1−u)v d` for corners
/// `[a, b, c, d]`, facing `normal`.
#[derive(Debug, Clone, PartialEq)]
pub struct Quad {
    /// The geometry file's surface name (`floor`, `tall_box`, …).
    pub name: String,
    /// Its material.
    pub material: Material,
    /// The corners, mm.
    pub corners: [V3; 4],
    /// The unit normal, pointing into the room (out of a box).
    pub normal: V3,
    /// Whether it can block light between other surfaces (a box's face).
    pub occluder: bool,
}

impl Quad {
    /// The point at `(u, v)` in [0, 1]².
    pub fn at(&self, u: f64, v: f64) -> V3 {
        let [a, b, c, d] = self.corners;
        let w = [(1.0 - u) * (1.0 - v), u * (1.0 - v), u * v, (1.0 - u) * v];
        [0, 1, 2].map(|k| w[0] * a[k] + w[1] * b[k] + w[2] * c[k] + w[3] * d[k])
    }

    /// Where a ray `o + t·dir` (t > `t_min`) meets the quad's front, as (t, u, v); `None` when it
    /// misses, runs parallel, or meets the back.
    pub fn hit(&self, o: V3, dir: V3, t_min: f64) -> Option<(f64, f64, f64)> {
        let den = dot(dir, self.normal);
        if den >= -1e-12 {
            return None;
        }
        let t = dot(sub(self.corners[0], o), self.normal) / den;
        if t <= t_min {
            return None;
        }
        let p = add(o, scale(dir, t));
        if !self.contains(p) {
            return None;
        }
        let (u, v) = self.uv(p);
        Some((t, u, v))
    }

    /// Whether `p`, on the quad's plane, lies inside it (the quads are convex).
    pub fn contains(&self, p: V3) -> bool {
        (0..4).all(|k| {
            let a = self.corners[k];
            let b = self.corners[(k + 1) % 4];
            dot(cross(sub(b, a), sub(p, a)), self.normal) >= -1e-9
        })
    }

    /// The parameters (u, v) of a point on the quad: Newton's method on `P(u, v) = p` in the
    /// least-squares sense (the quad is planar, so the residual is zero at the answer).
    pub fn uv(&self, p: V3) -> (f64, f64) {
        let [a, b, c, d] = self.corners;
        let (mut u, mut v) = (0.5, 0.5);
        for _ in 0..20 {
            let r = sub(self.at(u, v), p);
            let pu = add(scale(sub(b, a), 1.0 - v), scale(sub(c, d), v));
            let pv = add(scale(sub(d, a), 1.0 - u), scale(sub(c, b), u));
            let (a11, a12, a22) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
            let (b1, b2) = (dot(pu, r), dot(pv, r));
            let det = a11 * a22 - a12 * a12;
            let du = (a22 * b1 - a12 * b2) / det;
            let dv = (a11 * b2 - a12 * b1) / det;
            u -= du;
            v -= dv;
            if du.abs() + dv.abs() < 1e-12 {
                break;
            }
        }
        (u.clamp(0.0, 1.0), v.clamp(0.0, 1.0))
    }

    /// The area, mm² (the quads are planar: half the cross product of the diagonals).
    pub fn area(&self) -> f64 {
        let [a, b, c, d] = self.corners;
        0.5 * norm(cross(sub(c, a), sub(d, b)))
    }
}

/// One patch: a piece of a quad on which radiosity is taken as constant.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// The quad's corners for this piece, in the quad's order.
    pub corners: [V3; 4],
    /// Its centre, `P` at the middle of its parameter range.
    pub centre: V3,
    /// The quad's normal.
    pub normal: V3,
    /// Area, mm².
    pub area: f64,
    /// Its material.
    pub material: Material,
}

/// A quad meshed into `nu × nv` patches, `first` the index of its patch (0, 0); patch (i, j)
/// is `first + j·nu + i`.
#[derive(Debug, Clone, PartialEq)]
pub struct Surface {
    /// The quad.
    pub quad: Quad,
    /// Patches along the quad's first edge (a→b).
    pub nu: usize,
    /// Patches along its second edge (a→d).
    pub nv: usize,
    /// The index of its first patch.
    pub first: usize,
}

/// The meshed box.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// The surfaces, each a meshed quad.
    pub surfaces: Vec<Surface>,
    /// Every patch.
    pub patches: Vec<Patch>,
}

/// Reads the geometry file: one quad per row (`surface,material,x1,y1,z1,…,x4,y4,z4`). The
/// ceiling is cut into the eight rectangles around the light (the light is coplanar with it
/// in the data: cut out, nothing is counted twice); normals point toward the room's centre for
/// the room's surfaces and the light, away from its box's centre for a box's faces. With
/// `closed`, a front wall (white) closes the open side the camera looks through, at the corners
/// where the data's floor, side walls and ceiling end at z = 0: the enclosure the tests check
/// form factors in.
pub fn read_quads(text: &str, closed: bool) -> Result<Vec<Quad>, Error> {
    let bad = |line: usize, m: &str| {
        Error::Derive(spectral_quadrature_generator::Error::Numerical(format!(
            "cornell_box_geometry.csv line {line}: {m}"
        )))
    };
    let mut raw: Vec<(String, Material, [V3; 4])> = Vec::new();
    for (k, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if f.len() != 14 {
            return Err(bad(k + 1, "expected 14 fields"));
        }
        let material = match f[1] {
            "white" => Material::White,
            "red" => Material::Red,
            "green" => Material::Green,
            "light" => Material::Light,
            m => return Err(bad(k + 1, &format!("unknown material {m}"))),
        };
        let mut c = [[0.0; 3]; 4];
        for (i, v) in f[2..].iter().enumerate() {
            c[i / 3][i % 3] = v.parse().map_err(|_| bad(k + 1, "not a number"))?;
        }
        raw.push((f[0].to_string(), material, c));
    }
    let room_centre = [278.0, 274.4, 279.6];
    let box_centre = |name: &str| {
        let pts: Vec<V3> = raw
            .iter()
            .filter(|r| r.0 == name)
            .flat_map(|r| r.2)
            .collect();
        scale(
            pts.iter().fold([0.0; 3], |s, p| add(s, *p)),
            1.0 / pts.len() as f64,
        )
    };
    let light = raw
        .iter()
        .find(|r| r.1 == Material::Light)
        .map(|r| r.2)
        .ok_or_else(|| bad(0, "no light"))?;
    let mut quads = Vec::new();
    let mut push = |name: &str, material: Material, c: [V3; 4], occluder: bool, inside: V3| {
        let n = unit(cross(sub(c[1], c[0]), sub(c[3], c[0])));
        let toward = sub(inside, c[0]);
        let sign = if dot(n, toward) >= 0.0 { 1.0 } else { -1.0 };
        // For a box, `inside` is the box's centre and the normal points away from it.
        let sign = if occluder { -sign } else { sign };
        quads.push(Quad {
            name: name.to_string(),
            material,
            corners: c,
            normal: scale(n, sign),
            occluder,
        });
    };
    for (name, material, c) in &raw {
        let is_box = name.contains("box");
        if name == "ceiling" {
            // The ceiling is the rectangle x × z at one height; cut it at the light's edges.
            let y = c[0][1];
            let xs = [
                c.iter().map(|p| p[0]).fold(f64::MAX, f64::min),
                light.iter().map(|p| p[0]).fold(f64::MAX, f64::min),
                light.iter().map(|p| p[0]).fold(f64::MIN, f64::max),
                c.iter().map(|p| p[0]).fold(f64::MIN, f64::max),
            ];
            let zs = [
                c.iter().map(|p| p[2]).fold(f64::MAX, f64::min),
                light.iter().map(|p| p[2]).fold(f64::MAX, f64::min),
                light.iter().map(|p| p[2]).fold(f64::MIN, f64::max),
                c.iter().map(|p| p[2]).fold(f64::MIN, f64::max),
            ];
            for i in 0..3 {
                for j in 0..3 {
                    if i == 1 && j == 1 {
                        continue;
                    }
                    let r = [
                        [xs[i], y, zs[j]],
                        [xs[i + 1], y, zs[j]],
                        [xs[i + 1], y, zs[j + 1]],
                        [xs[i], y, zs[j + 1]],
                    ];
                    push(name, *material, r, false, room_centre);
                }
            }
        } else if is_box {
            push(name, *material, *c, true, box_centre(name));
        } else {
            push(name, *material, *c, false, room_centre);
        }
    }
    if closed {
        push(
            "front_wall",
            Material::White,
            [
                [552.8, 0.0, 0.0],
                [0.0, 0.0, 0.0],
                [0.0, 548.8, 0.0],
                [556.0, 548.8, 0.0],
            ],
            false,
            room_centre,
        );
    }
    Ok(quads)
}

/// Meshes each quad into patches no longer than `patch_mm` along either edge.
pub fn mesh(quads: &[Quad], patch_mm: f64) -> Mesh {
    let mut surfaces = Vec::new();
    let mut patches = Vec::new();
    for q in quads {
        let [a, b, c, d] = q.corners;
        let count = |l1: f64, l2: f64| ((l1.max(l2) / patch_mm).ceil() as usize).max(1);
        let nu = count(norm(sub(b, a)), norm(sub(c, d)));
        let nv = count(norm(sub(d, a)), norm(sub(c, b)));
        let first = patches.len();
        for j in 0..nv {
            for i in 0..nu {
                let (u0, u1) = (i as f64 / nu as f64, (i + 1) as f64 / nu as f64);
                let (v0, v1) = (j as f64 / nv as f64, (j + 1) as f64 / nv as f64);
                let corners = [q.at(u0, v0), q.at(u1, v0), q.at(u1, v1), q.at(u0, v1)];
                let piece = Quad {
                    corners,
                    ..q.clone()
                };
                patches.push(Patch {
                    corners,
                    centre: q.at(0.5 * (u0 + u1), 0.5 * (v0 + v1)),
                    normal: q.normal,
                    area: piece.area(),
                    material: q.material,
                });
            }
        }
        surfaces.push(Surface {
            quad: q.clone(),
            nu,
            nv,
            first,
        });
    }
    Mesh { surfaces, patches }
}

/// Rays per patch side for visibility: `VIS_RAYS²` rays from a patch's centre to points spread
/// over the other patch.
pub const VIS_RAYS: usize = 3;

/// The form factor from a differential area at `x` facing `n` to the polygon `poly`, unoccluded:
/// Lambert's contour integral after clipping the polygon to the half-space above `x`.
pub fn point_to_polygon(x: V3, n: V3, poly: &[V3]) -> f64 {
    // Clip (Sutherland-Hodgman) to n·(p − x) ≥ ε: the part of the polygon above the plane.
    const EPS: f64 = 1e-9;
    let mut clipped: Vec<V3> = Vec::with_capacity(poly.len() + 2);
    for k in 0..poly.len() {
        let p = poly[k];
        let q = poly[(k + 1) % poly.len()];
        let (dp, dq) = (dot(n, sub(p, x)) - EPS, dot(n, sub(q, x)) - EPS);
        if dp >= 0.0 {
            clipped.push(p);
        }
        if (dp >= 0.0) != (dq >= 0.0) {
            let t = dp / (dp - dq);
            clipped.push(add(p, scale(sub(q, p), t)));
        }
    }
    if clipped.len() < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for k in 0..clipped.len() {
        let r0 = sub(clipped[k], x);
        let r1 = sub(clipped[(k + 1) % clipped.len()], x);
        let c = cross(r0, r1);
        let cn = norm(c);
        if cn < 1e-15 {
            continue;
        }
        let gamma = (dot(r0, r1) / (norm(r0) * norm(r1)))
            .clamp(-1.0, 1.0)
            .acos();
        sum += gamma * dot(n, c) / cn;
    }
    (sum / (2.0 * std::f64::consts::PI)).abs()
}

/// An axis-aligned bounding box around a group of occluders, tested first.
struct Group {
    lo: V3,
    hi: V3,
    quads: Vec<Quad>,
}

impl Group {
    fn segment_meets_box(&self, o: V3, d: V3) -> bool {
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for k in 0..3 {
            if d[k].abs() < 1e-15 {
                if o[k] < self.lo[k] || o[k] > self.hi[k] {
                    return false;
                }
                continue;
            }
            let (a, b) = ((self.lo[k] - o[k]) / d[k], (self.hi[k] - o[k]) / d[k]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
            if t0 > t1 {
                return false;
            }
        }
        true
    }
}

/// The occluders of a mesh: its boxes' faces, grouped by box.
pub struct Occluders {
    groups: Vec<Group>,
}

impl Occluders {
    /// The faces of `quads` marked as occluders, grouped by name.
    pub fn new(quads: &[Quad]) -> Occluders {
        let mut groups: Vec<(String, Group)> = Vec::new();
        for q in quads.iter().filter(|q| q.occluder) {
            let k = match groups.iter().position(|g| g.0 == q.name) {
                Some(k) => k,
                None => {
                    groups.push((
                        q.name.clone(),
                        Group {
                            lo: [f64::MAX; 3],
                            hi: [f64::MIN; 3],
                            quads: Vec::new(),
                        },
                    ));
                    groups.len() - 1
                }
            };
            let g = &mut groups[k].1;
            for p in q.corners {
                for ((lo, hi), v) in g.lo.iter_mut().zip(g.hi.iter_mut()).zip(p) {
                    *lo = lo.min(v - 1e-6);
                    *hi = hi.max(v + 1e-6);
                }
            }
            g.quads.push(q.clone());
        }
        Occluders {
            groups: groups.into_iter().map(|g| g.1).collect(),
        }
    }

    /// Whether the open segment from `a` to `b` crosses an occluder's face (either side).
    pub fn blocked(&self, a: V3, b: V3) -> bool {
        let d = sub(b, a);
        self.groups.iter().any(|g| {
            g.segment_meets_box(a, d)
                && g.quads.iter().any(|q| {
                    let den = dot(d, q.normal);
                    if den.abs() < 1e-12 {
                        return false;
                    }
                    let t = dot(sub(q.corners[0], a), q.normal) / den;
                    t > 1e-9 && t < 1.0 - 1e-9 && q.contains(add(a, scale(d, t)))
                })
        })
    }
}

/// The form factors `F[i][j]` (row-major, n × n) of the mesh's patches, with visibility.
pub fn form_factors(mesh: &Mesh, quads: &[Quad]) -> Vec<f64> {
    let occ = Occluders::new(quads);
    let n = mesh.patches.len();
    // Points spread over each patch for the visibility rays, lifted a hair off the surface.
    const LIFT_MM: f64 = 1e-3;
    let targets: Vec<Vec<V3>> = mesh
        .patches
        .iter()
        .map(|p| {
            let q = Quad {
                name: String::new(),
                material: p.material,
                corners: p.corners,
                normal: p.normal,
                occluder: false,
            };
            let mut pts = Vec::with_capacity(VIS_RAYS * VIS_RAYS);
            for j in 0..VIS_RAYS {
                for i in 0..VIS_RAYS {
                    let u = (i as f64 + 0.5) / VIS_RAYS as f64;
                    let v = (j as f64 + 0.5) / VIS_RAYS as f64;
                    pts.push(add(q.at(u, v), scale(p.normal, LIFT_MM)));
                }
            }
            pts
        })
        .collect();
    let rows: Vec<usize> = (0..n).collect();
    let rows = tools::par_map(&rows, |&i| {
        let pi = &mesh.patches[i];
        let x = add(pi.centre, scale(pi.normal, LIFT_MM));
        let mut row = vec![0.0; n];
        for (j, pj) in mesh.patches.iter().enumerate() {
            if i == j || dot(pj.normal, sub(pi.centre, pj.centre)) <= 1e-9 {
                continue;
            }
            let f = point_to_polygon(pi.centre, pi.normal, &pj.corners);
            if f == 0.0 {
                continue;
            }
            // The rays to the part of j above i's plane: the part below is already clipped
            // out of `f`, and would otherwise be counted as hidden a second time.
            let (mut above, mut seen) = (0usize, 0usize);
            for &t in &targets[j] {
                if dot(pi.normal, sub(t, pi.centre)) > 1e-9 {
                    above += 1;
                    if !occ.blocked(x, t) {
                        seen += 1;
                    }
                }
            }
            if above > 0 {
                row[j] = f * seen as f64 / above as f64;
            }
        }
        row
    });
    rows.concat()
}
