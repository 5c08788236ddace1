//! The order in which the tetrahedralisation inserts its points: a biased randomised insertion
//! order whose rounds are each sorted along a 3D Hilbert curve, so that each walk to the next
//! point is short and points near one another along the curve are near in memory too.

/// Spreads the low 21 bits of `v` to every third bit.
fn spread3(v: u64) -> u64 {
    let mut x = v & 0x1f_ffff;
    x = (x | x << 32) & 0x1f00000000ffff;
    x = (x | x << 16) & 0x1f0000ff0000ff;
    x = (x | x << 8) & 0x100f00f00f00f00f;
    x = (x | x << 4) & 0x10c30c30c30c30c3;
    (x | x << 2) & 0x1249249249249249
}

/// The position of a cell of the 2²¹-cell grid along a 3D Hilbert curve (Skilling 2004: the
/// coordinates turned into the curve's transposed index, then interleaved).
fn hilbert3(mut x: [u32; 3]) -> u64 {
    const BITS: u32 = 21;
    let m = 1u32 << (BITS - 1);
    let mut q = m;
    while q > 1 {
        let p = q - 1;
        for i in 0..3 {
            if x[i] & q != 0 {
                x[0] ^= p;
            } else {
                let t = (x[0] ^ x[i]) & p;
                x[0] ^= t;
                x[i] ^= t;
            }
        }
        q >>= 1;
    }
    x[1] ^= x[0];
    x[2] ^= x[1];
    let mut t = 0;
    let mut q = m;
    while q > 1 {
        if x[2] & q != 0 {
            t ^= q - 1;
        }
        q >>= 1;
    }
    for v in &mut x {
        *v ^= t;
    }
    spread3(x[0] as u64) << 2 | spread3(x[1] as u64) << 1 | spread3(x[2] as u64)
}

/// A small deterministic generator (SplitMix64) for the insertion order and the walk.
pub(super) struct Rng(pub(super) u64);
impl Rng {
    pub(super) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

/// The insertion order: a biased randomised insertion order (Amenta, Choi & Rote 2003) whose
/// rounds (the last half of the points, the quarter before, …) are each sorted along a Hilbert
/// curve of the bounding box.
pub(super) fn insertion_order(
    points: &[[f64; 3]],
    lo: [f64; 3],
    extent: f64,
    seed: u64,
) -> Vec<u32> {
    let n = points.len();
    let mut rng = Rng(0x05ee_d0f5_a1ab ^ seed.wrapping_mul(0x9e37_79b9_7f4a_7c15));
    let mut order: Vec<u32> = (0..n as u32).collect();
    for i in (1..n).rev() {
        let j = (rng.next() % (i as u64 + 1)) as usize;
        order.swap(i, j);
    }
    let scale = ((1u64 << 21) - 1) as f64 / extent;
    let key = |i: u32| {
        let p = &points[i as usize];
        let q = |k: usize| ((p[k] - lo[k]) * scale) as u32;
        hilbert3([q(0), q(1), q(2)])
    };
    let mut keyed: Vec<(u64, u32)> = order.iter().map(|&i| (key(i), i)).collect();
    let mut end = n;
    while end > 0 {
        let start = if end > 64 { end / 2 } else { 0 };
        keyed[start..end].sort_unstable();
        end = start;
    }
    keyed.into_iter().map(|(_, i)| i).collect()
}

#[cfg(test)]
mod curve_tests {
    use super::hilbert3;

    #[test]
    fn the_hilbert_order_steps_to_a_neighbouring_cell() {
        // The 8 × 8 × 8 cells of the grid's top three bits, sorted by their curve position:
        // each is a face neighbour of the one before.
        let mut cells = Vec::new();
        for i in 0..8u32 {
            for j in 0..8u32 {
                for k in 0..8u32 {
                    let key = hilbert3([i << 18, j << 18, k << 18]);
                    cells.push((key, [i as i32, j as i32, k as i32]));
                }
            }
        }
        cells.sort_unstable();
        for w in cells.windows(2) {
            let step: i32 = (0..3).map(|a| (w[0].1[a] - w[1].1[a]).abs()).sum();
            assert_eq!(step, 1, "{:?} → {:?}", w[0].1, w[1].1);
        }
    }
}
