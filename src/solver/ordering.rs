//! Fill-reducing ordering of the pressure unknowns for the sparse Cholesky factor: geometric
//! nested dissection.
//!
//! The unknowns are mesh nodes with coordinates, so the node graph can be cut by position
//! instead of by the degree bookkeeping of approximate minimum degree (AMD). A set of nodes
//! is split at the median of its longer extent; the nodes of the upper half with a neighbour
//! in the lower half form the separator; the lower half, then the upper half, each ordered
//! the same way, come first and the separator last. Eliminating a half then never creates
//! fill in the other, and a separator of a 2D mesh holds about √n nodes.
//!
//! Measured on the dam break (about 5 400 unknowns, 2-core machine): the ordering takes
//! 0.9 ms where AMD took about 3 ms, and although its factor has more entries (204 000
//! against 118 000) they fall into dense blocks, so the supernodal factorisation takes
//! 2.8–3.2 ms against 4.6–5.8 ms for AMD's simplicial one.
//!
//! A long, thin set of nodes (its longest extent above [`BAND_RATIO`] times the next one: a
//! flume's water, 15–90 times longer than deep) is not cut but ordered along its length, so
//! that the factor is a band as wide as the water is deep. Its factor has about as many
//! entries and operations as the dissected one, but in half the supernodes, and faer's
//! left-looking factorisation pays about 2 µs per supernode over its arithmetic. `surflab
//! bench` (medians over 200 steps, two runs each, one sitting; numeric factor and solve, the
//! wait for the symbolic analysis, step): teaching beach 2.9–3.1 → 1.6–1.7 ms, 0.47 → 0.03 ms,
//! 11.8–12.9 → 9.3–9.7 ms (731 → 315 supernodes, 3.70 → 3.60 Mflop); Ting & Kirby spilling
//! (11 799 nodes) 6.3–6.5 → 3.5–3.6 ms, 1.0 → 0.01 ms, 30.2–31.0 → 25.7–25.8 ms; the flap
//! flume (19 207 nodes) 12.8–13.1 → 9.6–11.1 ms. At half the teaching beach's spacing (40
//! nodes deep) the band still wins (12.4 → 11.0 ms, though 27 → 38 Mflop). Not below a ratio
//! of 4: at 2 the dam break's and the sloshing tank's water were banded and their factors took
//! 2.4 and 3 times the operations (3.0–3.4 → 3.7–3.9 ms, 3.0–3.7 → 4.4–5.1 ms).
//!
//! The same cut serves the 3D pressure on tetrahedra (positions in three dimensions), where a
//! separator holds about n^(2/3) nodes.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

/// Node sets at most this large are not split further (8–64 measured alike; 16 was best).
const LEAF_NODES: usize = 16;

/// A set of nodes whose longest extent exceeds this many times the next longest is ordered
/// along its length instead of cut (see the module's doc).
const BAND_RATIO: f64 = 4.0;

/// Symbolic Cholesky analysis of a symmetric pattern (full CSR = CSC) whose rows are nodes at
/// `position` (2D or 3D): nested-dissection ordering, supernodal structure.
pub fn symbolic_cholesky<const D: usize>(
    position: &[[f64; D]],
    row_ptr: &[usize],
    col: &[usize],
) -> Result<SymbolicCholesky<usize>, String> {
    let n = position.len();
    let order = nested_dissection(position, row_ptr, col);
    let mut inverse = vec![0; n];
    for (k, &i) in order.iter().enumerate() {
        inverse[i] = k;
    }
    let permutation = faer::perm::PermRef::new_checked(&order, &inverse, n);
    let pattern = SymbolicSparseColMatRef::new_checked(n, n, row_ptr, None, col);
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    factorize_symbolic_cholesky(
        pattern,
        faer::Side::Lower,
        SymmetricOrdering::Custom(permutation),
        params,
    )
    .map_err(|e| format!("symbolic Cholesky analysis failed: {e:?}"))
}

/// Factors `matrix` (its lower triangle) numerically on `symbolic` into `factor` (resized; its
/// memory kept by the caller between steps) and solves for `b` in place, on one thread (the
/// lab leaves the other core to the window). An error means the matrix is not positive
/// definite.
pub fn factor_and_solve(
    symbolic: &SymbolicCholesky<usize>,
    matrix: SparseColMatRef<'_, usize, f64>,
    factor: &mut Vec<f64>,
    b: faer::MatMut<'_, f64>,
) -> Result<(), String> {
    let par = faer::Par::Seq;
    factor.clear();
    factor.resize(symbolic.len_val(), 0.0);
    let scratch = symbolic
        .factorize_numeric_llt_scratch::<f64>(par, Default::default())
        .or(symbolic.solve_in_place_scratch::<f64>(1, par));
    let mut mem = MemBuffer::new(scratch);
    let llt = symbolic
        .factorize_numeric_llt(
            factor,
            matrix,
            faer::Side::Lower,
            Default::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(|e| format!("sparse Cholesky failed ({e:?}): matrix not positive definite"))?;
    llt.solve_in_place_with_conj(faer::Conj::No, b, par, MemStack::new(&mut mem));
    Ok(())
}

/// The elimination order of the nodes at `position` whose symmetric adjacency is the CSR
/// pattern (`row_ptr`, `col`): `order[k]` is the node eliminated k-th.
pub fn nested_dissection<const D: usize>(
    position: &[[f64; D]],
    row_ptr: &[usize],
    col: &[usize],
) -> Vec<usize> {
    let n = position.len();
    assert_eq!(row_ptr.len(), n + 1, "one pattern row per node");
    let mut cut = Cut {
        position,
        row_ptr,
        col,
        part: vec![0; n],
        next_part: 1,
        order: Vec::with_capacity(n),
    };
    cut.dissect((0..n).collect());
    cut.order
}

struct Cut<'a, const D: usize> {
    position: &'a [[f64; D]],
    row_ptr: &'a [usize],
    col: &'a [usize],
    /// The label of the part each node was last put in.
    part: Vec<u32>,
    next_part: u32,
    order: Vec<usize>,
}

impl<const D: usize> Cut<'_, D> {
    fn dissect(&mut self, mut nodes: Vec<usize>) {
        if nodes.len() <= LEAF_NODES {
            self.order.extend_from_slice(&nodes);
            return;
        }
        let pos = self.position;
        let (mut lo, mut hi) = ([f64::INFINITY; D], [f64::NEG_INFINITY; D]);
        for &i in &nodes {
            for a in 0..D {
                lo[a] = lo[a].min(pos[i][a]);
                hi[a] = hi[a].max(pos[i][a]);
            }
        }
        // The longest extent (the first of equal ones).
        let axis = (1..D).fold(0, |best, a| {
            if hi[a] - lo[a] > hi[best] - lo[best] {
                a
            } else {
                best
            }
        });
        let next_longest = (0..D)
            .filter(|&a| a != axis)
            .map(|a| hi[a] - lo[a])
            .fold(0.0, f64::max);
        if hi[axis] - lo[axis] > BAND_RATIO * next_longest {
            // A long, thin set: along its length (a stable sort, so ties keep their order).
            nodes.sort_by(|&a, &b| pos[a][axis].total_cmp(&pos[b][axis]));
            self.order.extend_from_slice(&nodes);
            return;
        }
        let mid = nodes.len() / 2;
        nodes.select_nth_unstable_by(mid, |&a, &b| pos[a][axis].total_cmp(&pos[b][axis]));
        let (lower, upper) = (self.next_part, self.next_part + 1);
        self.next_part += 2;
        for &i in &nodes[..mid] {
            self.part[i] = lower;
        }
        for &i in &nodes[mid..] {
            self.part[i] = upper;
        }
        let mut upper_nodes = Vec::with_capacity(nodes.len() - mid);
        let mut separator = Vec::new();
        for &i in &nodes[mid..] {
            let touches_lower = self.col[self.row_ptr[i]..self.row_ptr[i + 1]]
                .iter()
                .any(|&j| self.part[j] == lower);
            if touches_lower {
                separator.push(i);
            } else {
                upper_nodes.push(i);
            }
        }
        nodes.truncate(mid);
        self.dissect(nodes);
        self.dissect(upper_nodes);
        self.order.extend_from_slice(&separator);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 5-point pattern of an nx × ny grid, with node positions.
    fn grid(nx: usize, ny: usize) -> (Vec<[f64; 2]>, Vec<usize>, Vec<usize>) {
        let id = |i: usize, j: usize| j * nx + i;
        let mut position = Vec::new();
        let (mut row_ptr, mut col) = (vec![0], Vec::new());
        for j in 0..ny {
            for i in 0..nx {
                position.push([i as f64, j as f64]);
                let mut row = vec![id(i, j)];
                if i > 0 {
                    row.push(id(i - 1, j));
                }
                if i + 1 < nx {
                    row.push(id(i + 1, j));
                }
                if j > 0 {
                    row.push(id(i, j - 1));
                }
                if j + 1 < ny {
                    row.push(id(i, j + 1));
                }
                row.sort_unstable();
                col.extend(row);
                row_ptr.push(col.len());
            }
        }
        (position, row_ptr, col)
    }

    /// Entries of the Cholesky factor for the elimination order (symbolic elimination).
    fn factor_entries(order: &[usize], row_ptr: &[usize], col: &[usize]) -> usize {
        let n = order.len();
        let mut rank = vec![0; n];
        for (k, &i) in order.iter().enumerate() {
            rank[i] = k;
        }
        let mut adj: Vec<std::collections::BTreeSet<usize>> = (0..n)
            .map(|k| {
                let i = order[k];
                col[row_ptr[i]..row_ptr[i + 1]]
                    .iter()
                    .map(|&j| rank[j])
                    .filter(|&r| r > k)
                    .collect()
            })
            .collect();
        let mut entries = n;
        for k in 0..n {
            let later: Vec<usize> = adj[k].iter().copied().collect();
            entries += later.len();
            if let Some((&first, rest)) = later.split_first() {
                for &r in rest {
                    adj[first].insert(r);
                }
            }
        }
        entries
    }

    #[test]
    fn the_order_is_a_permutation() {
        let (position, row_ptr, col) = grid(37, 11);
        let mut order = nested_dissection(&position, &row_ptr, &col);
        order.sort_unstable();
        assert_eq!(order, (0..37 * 11).collect::<Vec<_>>());
    }

    /// A strip 28 times longer than wide is ordered along its length, column by column: a band
    /// whose factor holds at most ny + 1 entries per column.
    #[test]
    fn a_long_strip_is_ordered_along_its_length() {
        let (nx, ny) = (200, 8);
        let (position, row_ptr, col) = grid(nx, ny);
        let order = nested_dissection(&position, &row_ptr, &col);
        assert!(
            order
                .windows(2)
                .all(|w| position[w[0]][0] <= position[w[1]][0])
        );
        let entries = factor_entries(&order, &row_ptr, &col);
        println!("200×8 strip: factor entries {entries}");
        assert!(entries <= nx * ny * (ny + 1), "{entries}");
        // A square is still cut: its order does not run along x.
        let (position, row_ptr, col) = grid(30, 30);
        let order = nested_dissection(&position, &row_ptr, &col);
        assert!(
            order
                .windows(2)
                .any(|w| position[w[0]][0] > position[w[1]][0])
        );
    }

    #[test]
    fn dissection_fills_less_than_the_natural_order() {
        let (position, row_ptr, col) = grid(60, 60);
        let natural: Vec<usize> = (0..3600).collect();
        let dissected = nested_dissection(&position, &row_ptr, &col);
        let (f_natural, f_dissected) = (
            factor_entries(&natural, &row_ptr, &col),
            factor_entries(&dissected, &row_ptr, &col),
        );
        println!("60×60 grid: factor entries {f_natural} natural, {f_dissected} dissected");
        // Banded natural order: about n·nx = 216 000; nested dissection: O(n log n).
        assert!(
            (f_dissected as f64) < 0.5 * f_natural as f64,
            "{f_dissected} vs {f_natural}"
        );
    }
}
