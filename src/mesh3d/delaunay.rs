//! The 3D Delaunay tetrahedralisation of a particle cloud: incremental Bowyer–Watson on exact
//! predicates (`robust`'s orientation; the in-sphere test of `exact.rs`, which decides ties in
//! integers), points inserted in a biased randomised order (rounds of doubling size, each
//! sorted along a Hilbert curve) so that each walk to the new point is short.
//!
//! The points are first enclosed in a tetrahedron whose corners lie `FAR` box diagonals away;
//! the tetrahedra that touch a corner are dropped at the end. A tetrahedron of the points'
//! own Delaunay tetrahedralisation is missing from the result only if its circumsphere reaches
//! a corner, i.e. only flat slivers on the convex hull whose circumradius exceeds about
//! `FAR` / 2 box diagonals: far beyond anything an α-shape keeps (radius < α h).
//!
//! Ties (five or more co-spherical points, as on a lattice) are resolved by the insertion
//! order: a tetrahedron is replaced only when the new point lies strictly inside its
//! circumsphere, so every tetrahedron returned has an empty circumsphere (no point strictly
//! inside) and a strictly positive volume.

use super::order::{Rng, insertion_order};
use robust::{Coord3D, orient3d};

/// No neighbour across this face (the face is on the boundary of the tetrahedralisation).
pub const NONE: u32 = u32::MAX;

/// The most points one tetrahedralisation takes: the links of [`Tet::n`] number tetrahedra
/// in 30 bits, and a tetrahedralisation holds about 7 per point (27 made per insertion).
pub const MAX_POINTS: usize = 1 << 26;

/// How far the enclosing tetrahedron's corners are, in diagonals of the points' bounding box.
const FAR: f64 = 1.0e5;

/// The tetrahedra of a point cloud.
#[derive(Debug, Clone, Default)]
pub struct Tetrahedralisation {
    /// Node indices of each tetrahedron, ordered so that `orient3d` of the four is positive.
    pub tets: Vec<[u32; 4]>,
    /// `neighbours[t][i]`: the tetrahedron across the face opposite `tets[t][i]`, or [`NONE`].
    pub neighbours: Vec<[u32; 4]>,
    /// Points left out because they coincide with another point (one of each such group is
    /// kept, whichever the insertion order met first).
    pub duplicates: Vec<u32>,
}

pub(super) fn coord(p: &[f64; 3]) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

/// `robust`'s orientation of the four nodes: positive for every tetrahedron we keep.
fn orient(p: &[[f64; 3]], v: [u32; 4]) -> f64 {
    orient3d(
        coord(&p[v[0] as usize]),
        coord(&p[v[1] as usize]),
        coord(&p[v[2] as usize]),
        coord(&p[v[3] as usize]),
    )
}

/// Positive when `q` lies strictly inside the circumsphere of the positively oriented `v`
/// (the sign of `robust::insphere`, exactly; [`super::exact`]). Out of line: the cached
/// spheres decide nearly every test on a random cloud.
#[cold]
#[inline(never)]
fn in_sphere(p: &[[f64; 3]], v: [u32; 4], q: &[f64; 3]) -> f64 {
    let node = |k: usize| &p[v[k] as usize];
    super::exact::in_sphere(node(0), node(1), node(2), node(3), q)
}

#[inline(always)]
pub(super) fn sub(u: &[f64; 3], w: &[f64; 3]) -> [f64; 3] {
    [u[0] - w[0], u[1] - w[1], u[2] - w[2]]
}

#[inline(always)]
pub(super) fn cross(u: [f64; 3], w: [f64; 3]) -> [f64; 3] {
    [
        u[1] * w[2] - u[2] * w[1],
        u[2] * w[0] - u[0] * w[2],
        u[0] * w[1] - u[1] * w[0],
    ]
}

#[inline(always)]
pub(super) fn dot(u: [f64; 3], w: [f64; 3]) -> f64 {
    u[0] * w[0] + u[1] * w[1] + u[2] * w[2]
}

/// The circumcentre of (a, b, c, d) relative to a, with 1 / (12 V) (signed, for the rounding
/// bound of [`Sphere::of`]) and the longest squared edge from a.
#[inline(always)]
fn centre_from_a(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> ([f64; 3], f64, f64) {
    let (ba, ca, da) = (sub(b, a), sub(c, a), sub(d, a));
    let (bb, cc, dd) = (dot(ba, ba), dot(ca, ca), dot(da, da));
    let (cd, db, bc) = (cross(ca, da), cross(da, ba), cross(ba, ca));
    let inv = 0.5 / dot(ba, cd);
    let o = [
        (bb * cd[0] + cc * db[0] + dd * bc[0]) * inv,
        (bb * cd[1] + cc * db[1] + dd * bc[1]) * inv,
        (bb * cd[2] + cc * db[2] + dd * bc[2]) * inv,
    ];
    (o, inv, bb.max(cc).max(dd))
}

/// Centre and radius of the sphere through the four points.
pub fn circumsphere(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> ([f64; 3], f64) {
    let (o, _, _) = centre_from_a(a, b, c, d);
    ([a[0] + o[0], a[1] + o[1], a[2] + o[2]], dot(o, o).sqrt())
}

/// Edge-keyed scratch table pairing the new tetrahedra's inner faces within one insertion.
struct FaceTable {
    keys: Vec<u64>,
    vals: Vec<(u32, u8)>,
    used: Vec<usize>,
}

impl FaceTable {
    const EMPTY: u64 = u64::MAX;
    fn new() -> Self {
        Self {
            keys: vec![Self::EMPTY; 256],
            vals: vec![(0, 0); 256],
            used: Vec::new(),
        }
    }
    fn reserve(&mut self, entries: usize) {
        if 2 * entries > self.keys.len() {
            let cap = (4 * entries).next_power_of_two();
            self.keys = vec![Self::EMPTY; cap];
            self.vals = vec![(0, 0); cap];
        }
    }
    /// Returns the other face stored under `key`, or stores this one.
    fn pair(&mut self, key: u64, val: (u32, u8)) -> Option<(u32, u8)> {
        let mask = self.keys.len() - 1;
        let mut s = (key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40) as usize & mask;
        loop {
            if self.keys[s] == Self::EMPTY {
                self.keys[s] = key;
                self.vals[s] = val;
                self.used.push(s);
                return None;
            }
            if self.keys[s] == key {
                // Each inner edge is shared by exactly two new faces: free the slot's key
                // lazily (cleared in `clear`), mark it taken by a key no edge has.
                self.keys[s] = Self::EMPTY - 1;
                return Some(self.vals[s]);
            }
            s = (s + 1) & mask;
        }
    }
    fn clear(&mut self) {
        for &s in &self.used {
            self.keys[s] = Self::EMPTY;
        }
        self.used.clear();
    }
}

/// The float filter's band, relative to r²: within it only the exact predicate decides.
const BAND: f64 = 1.0 / (1u64 << 17) as f64;

/// A tetrahedron's circumsphere, cached as a float filter for [`Builder::conflict`].
#[derive(Clone, Copy, Default)]
struct Sphere {
    c: [f64; 3],
    /// r², or NaN for a sliver whose centre is not to be trusted (then only the exact test
    /// decides: every comparison with NaN is false).
    r2: f64,
}

impl Sphere {
    /// The circumsphere of the positively oriented `v`, trusted when a generous bound `err`
    /// on the centre's rounding error (ε times the tetrahedron's condition κ — longest edge
    /// from `v[0]` cubed over six times its volume — times its size) is below 2⁻²⁰ r.
    /// Computing |q − c|² − r² then errs by at most 2 (d + r) err + 8 ε (d² + r²),
    /// d = |q − c|, which for d ≤ 2 r is at most 6 r err + 40 ε r² < [`BAND`] r²; a point
    /// computed outside r² (1 + BAND) is outside whatever d.
    fn of(p: &[[f64; 3]], v: [u32; 4]) -> Sphere {
        let a = &p[v[0] as usize];
        let (o, inv, l2) =
            centre_from_a(a, &p[v[1] as usize], &p[v[2] as usize], &p[v[3] as usize]);
        let l = l2.sqrt();
        let r2 = dot(o, o);
        let kappa = 2.0 * l2 * l * inv.abs();
        let c = [a[0] + o[0], a[1] + o[1], a[2] + o[2]];
        // The centre's error: |δo| ≲ 20 ε κ (l + r) from the quotient, with a margin of ten
        // (tested against the exact predicate below), plus rounding of the absolute
        // coordinates.
        let size = c[0].abs().max(c[1].abs()).max(c[2].abs());
        let r = r2.sqrt();
        let err = 256.0 * f64::EPSILON * (kappa * (l + r) + size);
        let trusted = err.is_finite() && r2.is_finite() && err <= r / (1u64 << 20) as f64;
        Sphere {
            c,
            r2: if trusted { r2 } else { f64::NAN },
        }
    }

    /// Some(true) when `q` is strictly inside, Some(false) when it is outside or on the
    /// sphere, None when the filter cannot tell.
    #[inline(always)]
    fn decide(&self, q: &[f64; 3]) -> Option<bool> {
        let d = [q[0] - self.c[0], q[1] - self.c[1], q[2] - self.c[2]];
        let diff = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - self.r2;
        let band = BAND * self.r2;
        if diff > band {
            Some(false)
        } else if diff < -band {
            Some(true)
        } else {
            None
        }
    }
}

/// One tetrahedron: its nodes (positively oriented), the tetrahedra across the faces opposite
/// them and its circumsphere (the float filter of [`Builder::conflict`]), in one 64-byte
/// cache line, so that testing a neighbour reads one line of memory.
#[derive(Clone, Copy)]
#[repr(C, align(64))]
struct Tet {
    v: [u32; 4],
    /// Across the face opposite `v[i]`: [`link`] of the neighbour and the index of that face
    /// in it, or [`NONE`].
    n: [u32; 4],
    sphere: Sphere,
}

/// [`Builder::marks`] of a tetrahedron that was removed.
const DEAD: u32 = u32::MAX;

/// A neighbour link: tetrahedron `t` and the index `j` of the shared face in it (opposite
/// its node `j`), so that crossing a face back needs no search.
#[inline(always)]
fn link(t: u32, j: usize) -> u32 {
    t << 2 | j as u32
}

struct Builder {
    p: Vec<[f64; 3]>,
    tets: Vec<Tet>,
    /// Per tetrahedron: `2 epoch`: in this insertion's cavity; `2 epoch + 1`: tested, not in
    /// it; [`DEAD`] (apart from the records: 4 bytes a tetrahedron stay in cache better).
    marks: Vec<u32>,
    free: Vec<u32>,
    epoch: u32,
    last: u32,
    rng: Rng,
    stack: Vec<u32>,
    cavity: Vec<u32>,
    /// (cavity tetrahedron, its face, the outer neighbour, the neighbour's face)
    boundary: Vec<(u32, u8, u32, u8)>,
    verts: Vec<[u32; 4]>,
    faces: FaceTable,
    /// The output's numbering of the tetrahedra (scratch of the last pass).
    index: Vec<u32>,
}

impl Builder {
    fn new() -> Self {
        Builder {
            p: Vec::new(),
            tets: Vec::new(),
            marks: Vec::new(),
            free: Vec::new(),
            epoch: 0,
            last: 0,
            rng: Rng(0),
            stack: Vec::new(),
            cavity: Vec::new(),
            boundary: Vec::new(),
            verts: Vec::new(),
            faces: FaceTable::new(),
            index: Vec::new(),
        }
    }

    /// Empties the builder for a new cloud, keeping its memory; room for `tets` tetrahedra.
    fn reset(&mut self, tets: usize) {
        self.p.clear();
        self.tets.clear();
        self.tets.reserve(tets);
        self.marks.clear();
        self.marks.reserve(tets);
        self.free.clear();
        self.epoch = 0;
        self.last = 0;
        self.rng = Rng(0x0ddba11);
    }

    fn alloc(&mut self, v: [u32; 4]) -> u32 {
        let tet = Tet {
            v,
            n: [NONE; 4],
            sphere: Sphere::of(&self.p, v),
        };
        if let Some(t) = self.free.pop() {
            self.tets[t as usize] = tet;
            self.marks[t as usize] = 0;
            t
        } else {
            self.tets.push(tet);
            self.marks.push(0);
            assert!(
                self.tets.len() < 1 << 30,
                "too many tetrahedra for 30-bit links"
            );
            (self.tets.len() - 1) as u32
        }
    }

    /// Whether `q` lies strictly inside the circumsphere of tetrahedron `t`: the cached sphere
    /// decides when `q` is clearly in or out, the exact predicate otherwise.
    fn conflict(&self, t: u32, q: &[f64; 3]) -> bool {
        let tet = &self.tets[t as usize];
        tet.sphere
            .decide(q)
            .unwrap_or_else(|| in_sphere(&self.p, tet.v, q) > 0.0)
    }

    /// A tetrahedron of `q`'s cavity, or `None` when `q` coincides with a node: a visibility
    /// walk from the last new tetrahedron (its faces tried from a random one, so that the walk
    /// cannot cycle) that stops at the first tetrahedron whose sphere holds `q`. The cavity is
    /// connected, so any of its tetrahedra starts its search; the tetrahedron that contains
    /// `q` (closed) holds it strictly unless `q` is one of its nodes.
    fn locate(&mut self, q: u32) -> Option<u32> {
        let mut t = self.last;
        let qp = self.p[q as usize];
        'walk: loop {
            if self.conflict(t, &qp) {
                return Some(t);
            }
            let first = (self.rng.next() & 3) as usize;
            let tet = self.tets[t as usize];
            for k in 0..4 {
                let i = (first + k) & 3;
                let mut v = tet.v;
                v[i] = q;
                if orient(&self.p, v) < 0.0 {
                    debug_assert_ne!(tet.n[i], NONE, "the point left the enclosing tetrahedron");
                    t = tet.n[i] >> 2;
                    continue 'walk;
                }
            }
            return None;
        }
    }

    /// Inserts point `q` (Bowyer–Watson); false if it coincides with a node.
    fn insert(&mut self, q: u32) -> bool {
        let Some(start) = self.locate(q) else {
            return false;
        };
        let qp = self.p[q as usize];
        // The cavity: the tetrahedra whose circumsphere holds q strictly, connected to start.
        self.epoch += 1;
        let (inside, outside) = (2 * self.epoch, 2 * self.epoch + 1);
        self.cavity.clear();
        self.boundary.clear();
        self.stack.clear();
        self.stack.push(start);
        self.marks[start as usize] = inside;
        while let Some(c) = self.stack.pop() {
            self.cavity.push(c);
            let nbrs = self.tets[c as usize].n;
            for (i, &l) in nbrs.iter().enumerate() {
                if l == NONE {
                    self.boundary.push((c, i as u8, NONE, 0));
                    continue;
                }
                let n = l >> 2;
                let m = self.marks[n as usize];
                if m == inside {
                    continue;
                }
                if m != outside {
                    if self.conflict(n, &qp) {
                        self.marks[n as usize] = inside;
                        self.stack.push(n);
                        continue;
                    }
                    self.marks[n as usize] = outside;
                }
                self.boundary.push((c, i as u8, n, (l & 3) as u8));
            }
        }
        // The new tetrahedra: each boundary face joined to q, q taking the place of the node
        // opposite the face (so positively oriented: q sees the face from the cavity's side).
        let mut verts = std::mem::take(&mut self.verts);
        verts.clear();
        for &(c, i, _, _) in &self.boundary {
            let mut v = self.tets[c as usize].v;
            v[i as usize] = q;
            verts.push(v);
        }
        for &c in &self.cavity {
            self.marks[c as usize] = DEAD;
            self.free.push(c);
        }
        self.faces.reserve(3 * self.boundary.len() / 2);
        for (b, &v) in verts.iter().enumerate() {
            let (_, i, n, j) = self.boundary[b];
            let i = i as usize;
            let t = self.alloc(v);
            if n != NONE {
                self.tets[t as usize].n[i] = link(n, j as usize);
                self.tets[n as usize].n[j as usize] = link(t, i);
            }
            // The three faces through q: the one opposite v[k] holds q and the boundary
            // face's edge without v[k]; the new tetrahedron across it shares that edge.
            for k in (0..4).filter(|&k| k != i) {
                let (a, b) = match (k.min(i), k.max(i)) {
                    (0, 1) => (v[2], v[3]),
                    (0, 2) => (v[1], v[3]),
                    (0, 3) => (v[1], v[2]),
                    (1, 2) => (v[0], v[3]),
                    (1, 3) => (v[0], v[2]),
                    _ => (v[0], v[1]),
                };
                let key = (a.min(b) as u64) << 32 | a.max(b) as u64;
                if let Some((t2, k2)) = self.faces.pair(key, (t, k as u8)) {
                    self.tets[t as usize].n[k] = link(t2, k2 as usize);
                    self.tets[t2 as usize].n[k2 as usize] = link(t, k);
                }
            }
            self.last = t;
        }
        self.faces.clear();
        self.verts = verts;
        true
    }
}

/// The Delaunay tetrahedralisation of `points` (see the module's notes on ties and on the
/// enclosing tetrahedron), with fresh working memory; [`Tetrahedraliser`] keeps it between
/// calls. Points that are not finite are a caller's bug: they panic.
pub fn tetrahedralise(points: &[[f64; 3]]) -> Tetrahedralisation {
    Tetrahedraliser::default().tetrahedralise(points)
}

/// The tetrahedralisation's working memory (about 0.5 kB per point: some 7 tetrahedra of 68
/// bytes each), kept between calls: a stepper that meshes every step reuses it instead of
/// asking the system for fresh pages each time (at 10⁵ points the page faults of a fresh build
/// were a seventh of its time).
#[derive(Default)]
pub struct Tetrahedraliser {
    scratch: Option<Builder>,
    /// Mixed into the seed of the insertion order's shuffle (0: the default order).
    seed: u64,
}

/// A clone starts with fresh working memory (the scratch holds nothing a clone needs) and the
/// same insertion order.
impl Clone for Tetrahedraliser {
    fn clone(&self) -> Self {
        Self::with_seed(self.seed)
    }
}

impl std::fmt::Debug for Tetrahedraliser {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let room = self.scratch.as_ref().map_or(0, |b| b.tets.capacity());
        write!(f, "Tetrahedraliser {{ room for {room} tetrahedra }}")
    }
}

impl Tetrahedraliser {
    /// A mesher whose insertion order is shuffled with `seed`: the same tetrahedralisation
    /// where it is unique, another of the valid ones where points are co-spherical (for tests
    /// of what follows the mesher).
    pub fn with_seed(seed: u64) -> Self {
        Self {
            scratch: None,
            seed,
        }
    }

    /// The Delaunay tetrahedralisation of `points`, as [`tetrahedralise`].
    pub fn tetrahedralise(&mut self, points: &[[f64; 3]]) -> Tetrahedralisation {
        let n = points.len();
        assert!(
            n < MAX_POINTS,
            "too many points: {n} (the neighbour links hold 2³⁰ tetrahedra, about 7 per point)"
        );
        assert!(
            points.iter().flatten().all(|x| x.is_finite()),
            "a point is not finite"
        );
        if n < 4 {
            return Tetrahedralisation::default();
        }
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in points {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let diag = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2))
            .sqrt()
            .max(f64::MIN_POSITIVE.sqrt());
        let extent = (0..3)
            .map(|k| hi[k] - lo[k])
            .fold(0.0, f64::max)
            .max(diag * 1e-12);
        let centre = [
            0.5 * (lo[0] + hi[0]),
            0.5 * (lo[1] + hi[1]),
            0.5 * (lo[2] + hi[2]),
        ];
        // A regular tetrahedron's corners (±1, ±1, ±1 with an even number of minus signs).
        let r = FAR * diag;
        let corner = |s: [f64; 3]| {
            [
                centre[0] + s[0] * r,
                centre[1] + s[1] * r,
                centre[2] + s[2] * r,
            ]
        };
        // The builder numbers the points in insertion order, so that points near one another
        // along the curve are near one another in memory too; `order` maps back.
        let order = insertion_order(points, lo, extent, self.seed);
        let mut b = self.scratch.take().unwrap_or_else(Builder::new);
        b.reset(7 * n);
        b.p.extend(order.iter().map(|&i| points[i as usize]));
        b.p.push(corner([1.0, 1.0, 1.0]));
        b.p.push(corner([1.0, -1.0, -1.0]));
        b.p.push(corner([-1.0, 1.0, -1.0]));
        b.p.push(corner([-1.0, -1.0, 1.0]));
        let s = n as u32;
        let mut first = [s, s + 1, s + 2, s + 3];
        if orient(&b.p, first) < 0.0 {
            first.swap(0, 1);
        }
        b.alloc(first);
        let mut duplicates = Vec::new();
        for q in 0..s {
            if !b.insert(q) {
                duplicates.push(order[q as usize]);
            }
        }
        // Keep the tetrahedra of the points alone; renumber them and their neighbours.
        let mut index = std::mem::take(&mut b.index);
        index.clear();
        index.resize(b.tets.len(), NONE);
        let mut out = Tetrahedralisation {
            duplicates,
            ..Default::default()
        };
        out.tets.reserve(b.tets.len() - b.free.len());
        for t in 0..b.tets.len() {
            if b.marks[t] != DEAD && b.tets[t].v.iter().all(|&v| v < s) {
                index[t] = out.tets.len() as u32;
                out.tets.push(b.tets[t].v.map(|v| order[v as usize]));
            }
        }
        out.neighbours.reserve(out.tets.len());
        for t in 0..b.tets.len() {
            if index[t] != NONE {
                out.neighbours.push(b.tets[t].n.map(|m| {
                    if m == NONE {
                        NONE
                    } else {
                        index[(m >> 2) as usize]
                    }
                }));
            }
        }
        b.index = index;
        self.scratch = Some(b);
        out
    }
}

#[cfg(test)]
mod filter_tests {
    use super::{Rng, Sphere, in_sphere};

    fn uniform(rng: &mut Rng) -> f64 {
        (rng.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The cached sphere's filter never contradicts the exact predicate: on regular, flat and
    /// needle tetrahedra far from and near the origin, for points on, just inside and just
    /// outside the sphere (relative offsets from 10⁻¹⁶ to 10⁻²) and far away.
    #[test]
    fn the_sphere_filter_agrees_with_the_exact_predicate() {
        let mut rng = Rng(42);
        let (mut decided, mut undecided) = (0usize, 0usize);
        // Points clearly off the sphere (|t| ≥ 10⁻⁴) of tetrahedra that are not flat: the
        // filter must decide nearly all of them, or it saves nothing.
        let (mut clear, mut clear_decided) = (0usize, 0usize);
        for case in 0..3000 {
            let offset = [30.0, 0.0, 1e3][case % 3];
            let flat = [1.0, 1e-6, 1e-12][(case / 3) % 3];
            let mut p: Vec<[f64; 3]> = (0..4)
                .map(|_| {
                    [
                        offset + uniform(&mut rng),
                        offset + uniform(&mut rng),
                        offset + flat * uniform(&mut rng),
                    ]
                })
                .collect();
            let mut v = [0, 1, 2, 3];
            let o = super::orient(&p, v);
            if o == 0.0 {
                continue;
            }
            if o < 0.0 {
                v.swap(0, 1);
            }
            let s = Sphere::of(&p, v);
            let (c, r) = super::circumsphere(&p[0], &p[1], &p[2], &p[3]);
            for k in 0..40 {
                // A direction, and a distance from the centre of r (1 + t).
                let dir = [
                    uniform(&mut rng) - 0.5,
                    uniform(&mut rng) - 0.5,
                    uniform(&mut rng) - 0.5,
                ];
                let norm = super::dot(dir, dir).sqrt();
                let t = match k % 4 {
                    0 => 0.0,
                    1 => 10f64.powf(-16.0 + 14.0 * uniform(&mut rng)),
                    2 => -10f64.powf(-16.0 + 14.0 * uniform(&mut rng)),
                    _ => 3.0 * uniform(&mut rng) - 1.0,
                };
                let q = [
                    c[0] + dir[0] / norm * r * (1.0 + t),
                    c[1] + dir[1] / norm * r * (1.0 + t),
                    c[2] + dir[2] / norm * r * (1.0 + t),
                ];
                if !q.iter().all(|x| x.is_finite()) {
                    continue;
                }
                p.push(q);
                let exact = in_sphere(&p, v, &q) > 0.0;
                p.pop();
                if flat == 1.0 && t.abs() >= 1e-4 {
                    clear += 1;
                    clear_decided += s.decide(&q).is_some() as usize;
                }
                match s.decide(&q) {
                    Some(inside) => {
                        assert_eq!(inside, exact, "case {case}, t = {t:e}, flat = {flat:e}");
                        decided += 1;
                    }
                    None => undecided += 1,
                }
            }
        }
        println!(
            "filter: {decided} decided, {undecided} left to the exact predicate; \
             {clear_decided} of {clear} points clearly off the sphere of a non-flat \
             tetrahedron decided"
        );
        assert!(
            clear_decided as f64 >= 0.99 * clear as f64,
            "{clear_decided} of {clear}"
        );
    }
}
