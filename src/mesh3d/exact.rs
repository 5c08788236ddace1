//! The in-sphere predicate of the tetrahedralisation, exact, for the cases the cached spheres
//! cannot decide.
//!
//! Those are nearly all ties: a PFEM cloud starts on a lattice and its wall nodes stay on one,
//! so five points on one sphere (to the last bit or nearly) are the common case there, not the
//! exception. `robust`'s adaptive predicate settles a tie only in its last, exact stage, which
//! zeroes over 200 kB of fixed scratch arrays per call before summing its expansions; on the
//! narrow piston tank that stage took over half the samples of a whole 3D step.
//!
//! Here the floating-point determinant is tried first with Shewchuk's static error bound
//! (the bound of `robust`'s first stage); when it cannot decide, the same determinant is
//! evaluated in integers. Every finite double is an integer times a power of two, so the
//! points' coordinates are written as integers in units of the smallest power among them; the
//! differences to the fifth point then hold at most 101 bits and the 4 × 4 lifted determinant
//! at most 512, which [`Int`] (nine 64-bit limbs, sign and magnitude) holds exactly (the minors
//! and lifts in i128 when the differences are below 2⁶², as nearly always). When the
//! coordinates' exponents span more than 47 binary orders (a coordinate within 10⁻¹⁴ of zero
//! beside others of order one), `robust` decides instead.

use super::delaunay::coord;
use robust::insphere;

/// Shewchuk's error bound of the in-sphere determinant evaluated in doubles, relative to its
/// permanent: (16 + 224 ε) ε, ε = 2⁻⁵³.
const IN_SPHERE_BOUND: f64 = (16.0 + 224.0 * EPS) * EPS;
const EPS: f64 = f64::EPSILON * 0.5;

/// Integer coordinates hold at most this many bits (53 of mantissa and the exponents' span).
const MAX_COORD_BITS: i32 = 100;

const LIMBS: usize = 9;

/// Positive when `e` lies strictly inside the sphere through `a`, `b`, `c`, `d` (positively
/// oriented, as `robust::orient3d` orients them), negative outside, zero on it: the sign of
/// `robust::insphere`, exactly. The value is the determinant when the doubles decide, ±1 or 0
/// otherwise.
pub fn in_sphere(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3], e: &[f64; 3]) -> f64 {
    let [aex, aey, aez] = [a[0] - e[0], a[1] - e[1], a[2] - e[2]];
    let [bex, bey, bez] = [b[0] - e[0], b[1] - e[1], b[2] - e[2]];
    let [cex, cey, cez] = [c[0] - e[0], c[1] - e[1], c[2] - e[2]];
    let [dex, dey, dez] = [d[0] - e[0], d[1] - e[1], d[2] - e[2]];
    let (aexbey, bexaey) = (aex * bey, bex * aey);
    let (bexcey, cexbey) = (bex * cey, cex * bey);
    let (cexdey, dexcey) = (cex * dey, dex * cey);
    let (dexaey, aexdey) = (dex * aey, aex * dey);
    let (aexcey, cexaey) = (aex * cey, cex * aey);
    let (bexdey, dexbey) = (bex * dey, dex * bey);
    let (ab, bc, cd) = (aexbey - bexaey, bexcey - cexbey, cexdey - dexcey);
    let (da, ac, bd) = (dexaey - aexdey, aexcey - cexaey, bexdey - dexbey);
    let abc = aez * bc - bez * ac + cez * ab;
    let bcd = bez * cd - cez * bd + dez * bc;
    let cda = cez * da + dez * ac + aez * cd;
    let dab = dez * ab + aez * bd + bez * da;
    let alift = aex * aex + aey * aey + aez * aez;
    let blift = bex * bex + bey * bey + bez * bez;
    let clift = cex * cex + cey * cey + cez * cez;
    let dlift = dex * dex + dey * dey + dez * dez;
    let det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);
    let (az, bz, cz, dz) = (aez.abs(), bez.abs(), cez.abs(), dez.abs());
    let p_ab = aexbey.abs() + bexaey.abs();
    let p_bc = bexcey.abs() + cexbey.abs();
    let p_cd = cexdey.abs() + dexcey.abs();
    let p_da = dexaey.abs() + aexdey.abs();
    let p_ac = aexcey.abs() + cexaey.abs();
    let p_bd = bexdey.abs() + dexbey.abs();
    let permanent = (p_cd * bz + p_bd * cz + p_bc * dz) * alift
        + (p_da * cz + p_ac * dz + p_cd * az) * blift
        + (p_ab * dz + p_bd * az + p_da * bz) * clift
        + (p_bc * az + p_ac * bz + p_ab * cz) * dlift;
    let bound = IN_SPHERE_BOUND * permanent;
    if det > bound || -det > bound {
        return det;
    }
    match exact_sign([a, b, c, d, e]) {
        Some(s) => f64::from(s),
        None => insphere(coord(a), coord(b), coord(c), coord(d), coord(e)),
    }
}

/// A finite double as (mantissa, binary exponent): x = m 2^k; `None` for zero.
fn split(x: f64) -> Option<(i64, i32)> {
    if x == 0.0 {
        return None;
    }
    let bits = x.to_bits();
    let field = ((bits >> 52) & 0x7ff) as i32;
    let fraction = (bits & ((1 << 52) - 1)) as i64;
    let (m, k) = if field == 0 {
        (fraction, -1074)
    } else {
        (fraction | 1 << 52, field - 1075)
    };
    Some((if x < 0.0 { -m } else { m }, k))
}

/// The sign of the lifted determinant of `robust::insphere` (the same polynomial), evaluated
/// in integers; `None` when a coordinate is not finite or the exponents span too far.
fn exact_sign(p: [&[f64; 3]; 5]) -> Option<i32> {
    let mut parts = [[None; 3]; 5];
    let (mut lo, mut hi) = (i32::MAX, i32::MIN);
    for (i, q) in p.iter().enumerate() {
        for a in 0..3 {
            if !q[a].is_finite() {
                return None;
            }
            parts[i][a] = split(q[a]);
            if let Some((_, k)) = parts[i][a] {
                lo = lo.min(k);
                hi = hi.max(k);
            }
        }
    }
    if lo == i32::MAX {
        // Five points at the origin.
        return Some(0);
    }
    if hi - lo + 53 > MAX_COORD_BITS {
        return None;
    }
    let int = |i: usize, a: usize| parts[i][a].map_or(0i128, |(m, k)| i128::from(m) << (k - lo));
    // Differences to the fifth point: at most 101 bits.
    let d = [0, 1, 2, 3].map(|i| [0, 1, 2].map(|a| int(i, a) - int(4, a)));
    let narrow = d.iter().flatten().all(|v| v.unsigned_abs() < 1 << 62);
    Some(if narrow {
        det_sign_narrow(&d)
    } else {
        det_sign_wide(&d)
    })
}

/// The sign of the lifted determinant of the differences `d` (rows a, b, c, d; columns x, y,
/// z), every one below 2⁶² in magnitude: the 2 × 2 minors and the lifts then fit in i128
/// (below 2¹²⁶), and only the last products need [`Int`].
fn det_sign_narrow(d: &[[i128; 3]; 4]) -> i32 {
    let [
        [aex, aey, aez],
        [bex, bey, bez],
        [cex, cey, cez],
        [dex, dey, dez],
    ] = *d;
    let int = Int::from_i128;
    let (ab, bc) = (int(aex * bey - bex * aey), int(bex * cey - cex * bey));
    let (cd, da) = (int(cex * dey - dex * cey), int(dex * aey - aex * dey));
    let (ac, bd) = (int(aex * cey - cex * aey), int(bex * dey - dex * bey));
    let lift = |x: i128, y: i128, z: i128| int(x * x + y * y + z * z);
    let (alift, blift) = (lift(aex, aey, aez), lift(bex, bey, bez));
    let (clift, dlift) = (lift(cex, cey, cez), lift(dex, dey, dez));
    lifted_sign(
        [ab, bc, cd, da, ac, bd],
        [aez, bez, cez, dez].map(int),
        [alift, blift, clift, dlift],
    )
}

/// [`det_sign_narrow`] for differences of up to 101 bits: every product in [`Int`].
fn det_sign_wide(d: &[[i128; 3]; 4]) -> i32 {
    let [
        [aex, aey, aez],
        [bex, bey, bez],
        [cex, cey, cez],
        [dex, dey, dez],
    ] = d.map(|row| row.map(Int::from_i128));
    let minor = |p: &Int, q: &Int, r: &Int, s: &Int| p.mul(q).sub(&r.mul(s));
    let ab = minor(&aex, &bey, &bex, &aey);
    let bc = minor(&bex, &cey, &cex, &bey);
    let cd = minor(&cex, &dey, &dex, &cey);
    let da = minor(&dex, &aey, &aex, &dey);
    let ac = minor(&aex, &cey, &cex, &aey);
    let bd = minor(&bex, &dey, &dex, &bey);
    let lift = |x: &Int, y: &Int, z: &Int| x.mul(x).add(&y.mul(y)).add(&z.mul(z));
    let (alift, blift) = (lift(&aex, &aey, &aez), lift(&bex, &bey, &bez));
    let (clift, dlift) = (lift(&cex, &cey, &cez), lift(&dex, &dey, &dez));
    lifted_sign(
        [ab, bc, cd, da, ac, bd],
        [aez, bez, cez, dez],
        [alift, blift, clift, dlift],
    )
}

/// The sign of the lifted determinant from the xy minors (ab, bc, cd, da, ac, bd), the z
/// differences and the lifts of rows a, b, c, d: `robust::insphere`'s last products.
fn lifted_sign(minors: [Int; 6], z: [Int; 4], lifts: [Int; 4]) -> i32 {
    let [ab, bc, cd, da, ac, bd] = minors;
    let [az, bz, cz, dz] = z;
    let [alift, blift, clift, dlift] = lifts;
    let abc = az.mul(&bc).sub(&bz.mul(&ac)).add(&cz.mul(&ab));
    let bcd = bz.mul(&cd).sub(&cz.mul(&bd)).add(&dz.mul(&bc));
    let cda = cz.mul(&da).add(&dz.mul(&ac)).add(&az.mul(&cd));
    let dab = dz.mul(&ab).add(&az.mul(&bd)).add(&bz.mul(&da));
    dlift
        .mul(&abc)
        .sub(&clift.mul(&dab))
        .add(&blift.mul(&cda).sub(&alift.mul(&bcd)))
        .signum()
}

/// A signed integer of up to 576 bits, sign and magnitude (little-endian limbs, `len` of them
/// in use, the top one non-zero). Enough for the determinant above; larger results panic.
#[derive(Clone, Copy, Debug)]
struct Int {
    negative: bool,
    len: usize,
    mag: [u64; LIMBS],
}

impl Int {
    fn from_i128(v: i128) -> Int {
        let m = v.unsigned_abs();
        let mut out = Int {
            negative: v < 0,
            len: 2,
            mag: [0; LIMBS],
        };
        out.mag[0] = m as u64;
        out.mag[1] = (m >> 64) as u64;
        out.trim();
        out
    }

    fn trim(&mut self) {
        while self.len > 0 && self.mag[self.len - 1] == 0 {
            self.len -= 1;
        }
        if self.len == 0 {
            self.negative = false;
        }
    }

    fn signum(&self) -> i32 {
        match (self.len, self.negative) {
            (0, _) => 0,
            (_, true) => -1,
            _ => 1,
        }
    }

    fn mul(&self, o: &Int) -> Int {
        let mut out = Int {
            negative: self.negative != o.negative,
            len: self.len + o.len,
            mag: [0; LIMBS],
        };
        if self.len == 0 || o.len == 0 {
            return Int::from_i128(0);
        }
        assert!(
            out.len <= LIMBS,
            "exact in-sphere: a product beyond 576 bits"
        );
        for i in 0..self.len {
            let mut carry = 0u128;
            for j in 0..o.len {
                let t = u128::from(self.mag[i]) * u128::from(o.mag[j])
                    + u128::from(out.mag[i + j])
                    + carry;
                out.mag[i + j] = t as u64;
                carry = t >> 64;
            }
            out.mag[i + o.len] = carry as u64;
        }
        out.trim();
        out
    }

    /// |self| compared with |o|.
    fn cmp_mag(&self, o: &Int) -> std::cmp::Ordering {
        if self.len != o.len {
            return self.len.cmp(&o.len);
        }
        for i in (0..self.len).rev() {
            if self.mag[i] != o.mag[i] {
                return self.mag[i].cmp(&o.mag[i]);
            }
        }
        std::cmp::Ordering::Equal
    }

    fn add(&self, o: &Int) -> Int {
        if self.negative == o.negative {
            let len = self.len.max(o.len);
            let mut out = Int {
                negative: self.negative,
                len: len + 1,
                mag: [0; LIMBS],
            };
            let mut carry = 0u64;
            for i in 0..len {
                let (s, c1) = self.mag[i].overflowing_add(o.mag[i]);
                let (s, c2) = s.overflowing_add(carry);
                out.mag[i] = s;
                carry = u64::from(c1 || c2);
            }
            if len < LIMBS {
                out.mag[len] = carry;
            } else {
                assert_eq!(carry, 0, "exact in-sphere: a sum beyond 576 bits");
                out.len = LIMBS;
            }
            out.trim();
            return out;
        }
        // Opposite signs: the larger magnitude less the smaller, with the larger's sign.
        let (big, small) = if self.cmp_mag(o) == std::cmp::Ordering::Less {
            (o, self)
        } else {
            (self, o)
        };
        let mut out = Int {
            negative: big.negative,
            len: big.len,
            mag: [0; LIMBS],
        };
        let mut borrow = 0u64;
        for i in 0..big.len {
            let (d, b1) = big.mag[i].overflowing_sub(small.mag[i]);
            let (d, b2) = d.overflowing_sub(borrow);
            out.mag[i] = d;
            borrow = u64::from(b1 || b2);
        }
        out.trim();
        out
    }

    fn sub(&self, o: &Int) -> Int {
        let mut negated = *o;
        if negated.len > 0 {
            negated.negative = !negated.negative;
        }
        self.add(&negated)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use robust::orient3d;

    fn robust_sign(p: [&[f64; 3]; 5]) -> f64 {
        let [a, b, c, d, e] = p.map(coord);
        sign(insphere(a, b, c, d, e))
    }

    /// −1, 0 or 1 (`f64::signum` gives 1 for 0).
    fn sign(x: f64) -> f64 {
        if x == 0.0 { 0.0 } else { x.signum() }
    }

    fn orient(p: [&[f64; 3]; 4]) -> f64 {
        let [a, b, c, d] = p.map(coord);
        orient3d(a, b, c, d)
    }

    /// The big integers against i128 where i128 holds the result.
    #[test]
    fn the_integers_add_subtract_and_multiply() {
        let values = [
            0i128,
            1,
            -1,
            7,
            -12_345_678_901_234,
            1 << 62,
            -(1 << 63),
            (1 << 100) + 3,
        ];
        for &x in &values {
            for &y in &values {
                let (a, b) = (Int::from_i128(x), Int::from_i128(y));
                let expect = |v: i128| Int::from_i128(v);
                assert_eq!(a.add(&b).cmp_mag(&expect(x + y)), std::cmp::Ordering::Equal);
                assert_eq!(a.add(&b).signum(), (x + y).signum() as i32);
                assert_eq!(a.sub(&b).cmp_mag(&expect(x - y)), std::cmp::Ordering::Equal);
                assert_eq!(a.sub(&b).signum(), (x - y).signum() as i32);
                if let Some(p) = x.checked_mul(y) {
                    assert_eq!(a.mul(&b).cmp_mag(&expect(p)), std::cmp::Ordering::Equal);
                    assert_eq!(a.mul(&b).signum(), p.signum() as i32);
                }
            }
        }
        // (2¹⁰⁰ + 3)⁵ has 501 bits; it and its negative cancel to zero.
        let big = Int::from_i128((1 << 100) + 3);
        let p5 = big.mul(&big).mul(&big).mul(&big).mul(&big);
        assert_eq!(p5.len, 8);
        assert_eq!(p5.sub(&p5).signum(), 0);
    }

    /// The sign of `robust::insphere`, on the ties of lattices (exactly co-spherical, and
    /// co-spherical but for the rounding of h k), on points a few ulps off them, on random
    /// points, near and far from the origin: no disagreement.
    #[test]
    fn the_sign_is_robusts_on_ties_near_ties_and_random_points() {
        let mut r = crate::mesh3d::xorshift(0x5eed);
        let (mut ties, mut exact_calls, mut checked) = (0, 0, 0);
        for case in 0..40_000 {
            let h = [1.0, 0.02, 0.1 / 3.0, 0.025][case % 4];
            let origin = [[0.0; 3], [4.5, 0.0, 0.04], [-3.0, 7.0, 1e3]][case % 3];
            let lattice = |r: &mut dyn FnMut() -> f64| -> [f64; 3] {
                [0, 1, 2].map(|a| origin[a] + h * ((r() * 3.0).floor()))
            };
            // Five distinct corners of one lattice cube: on one sphere.
            let cube = [0, 1, 2].map(|_| (r() * 5.0).floor());
            let mut corners: Vec<usize> = (0..8).collect();
            for k in (1..8).rev() {
                corners.swap(k, (r() * (k + 1) as f64) as usize);
            }
            let corner = |k: usize| {
                let bits = [k & 1, (k >> 1) & 1, (k >> 2) & 1];
                [0, 1, 2].map(|a| origin[a] + h * (cube[a] + bits[a] as f64))
            };
            let mut pts: [[f64; 3]; 5] = [[0.0; 3]; 5];
            for (i, q) in pts.iter_mut().enumerate() {
                *q = match case % 5 {
                    0 => corner(corners[i]),
                    1 => lattice(&mut r),
                    2 => {
                        // A lattice point nudged by a few ulps.
                        let mut q = lattice(&mut r);
                        let a = (r() * 3.0) as usize;
                        q[a] = f64::from_bits(q[a].to_bits() + (r() * 4.0) as u64);
                        q
                    }
                    3 => [0, 1, 2].map(|a| origin[a] + h * r()),
                    _ => [0, 1, 2].map(|_| h * (r() - 0.5) * 1e-3),
                };
            }
            let [a, b, c, d, e] = &pts;
            let o = orient([a, b, c, d]);
            if o == 0.0 {
                continue;
            }
            let (b, c) = if o > 0.0 { (b, c) } else { (c, b) };
            let ours = sign(in_sphere(a, b, c, d, e));
            let theirs = robust_sign([a, b, c, d, e]);
            assert_eq!(ours, theirs, "{pts:?}");
            checked += 1;
            if theirs == 0.0 {
                ties += 1;
            }
            if exact_sign([a, b, c, d, e]).is_some() {
                exact_calls += 1;
            }
        }
        println!("{checked} non-flat cases, {ties} exact ties, {exact_calls} within integer range");
        assert!(ties > 1_000 && checked > 30_000, "{ties} ties of {checked}");
    }

    /// The two integer evaluations agree where both apply, on random differences below 2⁶²
    /// and on exact ties (the corners of an integer cube, scaled).
    #[test]
    fn the_narrow_and_wide_integer_determinants_agree() {
        let mut r = crate::mesh3d::xorshift(0xfeed);
        let mut zeros = 0;
        for case in 0..20_000 {
            let d: [[i128; 3]; 4] = if case % 2 == 0 {
                let bits = [4, 20, 40, 61][case % 4 / 2 * 2 + (case / 7) % 2];
                [0, 1, 2, 3].map(|_| [0, 1, 2].map(|_| ((r() - 0.5) * 2f64.powi(bits)) as i128))
            } else {
                // Four corners of a cube less a fifth: co-spherical.
                let scale = 1i128 << (r() * 58.0) as u32;
                let corner = |k: i128| [k & 1, (k >> 1) & 1, (k >> 2) & 1].map(|b| b * scale);
                let e = corner(7);
                [0, 1, 2, 4].map(|k| {
                    let c = corner(k);
                    [c[0] - e[0], c[1] - e[1], c[2] - e[2]]
                })
            };
            let (narrow, wide) = (det_sign_narrow(&d), det_sign_wide(&d));
            assert_eq!(narrow, wide, "{d:?}");
            zeros += usize::from(wide == 0);
        }
        println!("{zeros} zero determinants of 20 000");
        assert!(zeros > 5_000);
    }

    /// Coordinates whose exponents span too far go to `robust`.
    #[test]
    fn a_wide_span_of_exponents_is_left_to_robust() {
        let p = [
            [1e-20, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.3, 0.3, 0.3],
        ];
        assert!(exact_sign([&p[0], &p[1], &p[2], &p[3], &p[4]]).is_none());
        let ours = sign(in_sphere(&p[0], &p[1], &p[2], &p[3], &p[4]));
        assert_eq!(ours, robust_sign([&p[0], &p[1], &p[2], &p[3], &p[4]]));
    }
}
