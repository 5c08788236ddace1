//! Incomplete Cholesky with no fill, IC(0), as the preconditioner of the 3D pressure's
//! conjugate gradients: L Lᵀ ≈ K with L on the lower triangle's own pattern. K is the P1
//! Laplacian of the kept tetrahedra, symmetric positive definite but not an M-matrix (a
//! tetrahedron with an obtuse dihedral angle gives a positive off-diagonal entry), so the
//! incomplete factor can meet a non-positive pivot; it is then made again from K with its
//! diagonal raised by a shift that doubles until every pivot is positive (Manteuffel's shifted
//! incomplete Cholesky).

use faer::dyn_stack::{MemStack, StackReq};
use faer::reborrow::ReborrowMut;
use faer::sparse::SparseColMat;
use faer::{MatMut, MatRef, Par};

/// The incomplete factor L (rows of the lower triangle, each ending with its diagonal).
#[derive(Debug)]
pub struct Ic0 {
    row_ptr: Vec<usize>,
    col: Vec<usize>,
    val: Vec<f64>,
    /// The diagonal shift the factor needed (0 when none), relative to each diagonal entry.
    pub shift: f64,
}

impl Ic0 {
    /// The factor of the symmetric positive definite `k` (both triangles stored, columns
    /// sorted, as faer builds it from triplets); an error names what is wrong with `k` when no
    /// shift up to 1e3 of the diagonal gives positive pivots (a non-finite entry, or a matrix
    /// that is not positive definite).
    pub fn new(k: &SparseColMat<usize, f64>) -> Result<Ic0, String> {
        let n = k.nrows();
        let (col_ptr, row_idx) = (k.symbolic().col_ptr(), k.symbolic().row_idx());
        let values = k.val();
        // Row i of the lower triangle is column i's entries with row index ≤ i (symmetry).
        let mut row_ptr = Vec::with_capacity(n + 1);
        row_ptr.push(0);
        let (mut col, mut a) = (Vec::new(), Vec::new());
        for i in 0..n {
            for p in col_ptr[i]..col_ptr[i + 1] {
                if row_idx[p] <= i {
                    col.push(row_idx[p]);
                    a.push(values[p]);
                }
            }
            row_ptr.push(col.len());
        }
        let mut ic = Ic0 {
            row_ptr,
            col,
            val: Vec::new(),
            shift: 0.0,
        };
        if let Some(v) = a.iter().find(|v| !v.is_finite()) {
            return Err(format!("the pressure matrix has an entry {v}"));
        }
        let mut shift = 0.0;
        while !ic.factor(&a, shift) {
            shift = if shift == 0.0 { 1e-3 } else { 2.0 * shift };
            if shift > 1e3 {
                return Err(
                    "no shifted incomplete Cholesky factor: the pressure matrix is not \
                     positive definite"
                        .into(),
                );
            }
        }
        ic.shift = shift;
        Ok(ic)
    }

    /// L from the lower triangle `a` with its diagonal scaled by 1 + `shift`; false at a
    /// non-positive pivot.
    fn factor(&mut self, a: &[f64], shift: f64) -> bool {
        let (rp, col) = (&self.row_ptr, &self.col);
        self.val.clear();
        self.val.extend_from_slice(a);
        let l = &mut self.val;
        for i in 0..rp.len() - 1 {
            let (s, e) = (rp[i], rp[i + 1]);
            debug_assert_eq!(col[e - 1], i, "each row ends with its diagonal");
            // Off-diagonal entries in column order: L_ik = (a_ik − Σ_{j<k} L_ij L_kj) / L_kk,
            // the sum over the columns rows i and k share.
            for p in s..e - 1 {
                let k = col[p];
                let (ks, ke) = (rp[k], rp[k + 1]);
                let (mut q, mut r, mut sum) = (s, ks, 0.0);
                while q < p && r < ke - 1 {
                    match col[q].cmp(&col[r]) {
                        std::cmp::Ordering::Less => q += 1,
                        std::cmp::Ordering::Greater => r += 1,
                        std::cmp::Ordering::Equal => {
                            sum += l[q] * l[r];
                            q += 1;
                            r += 1;
                        }
                    }
                }
                l[p] = (l[p] - sum) / l[ke - 1];
            }
            let d = a[e - 1] * (1.0 + shift) - l[s..e - 1].iter().map(|v| v * v).sum::<f64>();
            if d.is_nan() || d <= 0.0 {
                return false;
            }
            l[e - 1] = d.sqrt();
        }
        true
    }

    /// x ← (L Lᵀ)⁻¹ x.
    fn solve_in_place(&self, x: &mut [f64]) {
        let (rp, col, l) = (&self.row_ptr, &self.col, &self.val);
        let n = rp.len() - 1;
        for i in 0..n {
            let (s, e) = (rp[i], rp[i + 1]);
            let sum: f64 = (s..e - 1).map(|p| l[p] * x[col[p]]).sum();
            x[i] = (x[i] - sum) / l[e - 1];
        }
        for i in (0..n).rev() {
            let (s, e) = (rp[i], rp[i + 1]);
            x[i] /= l[e - 1];
            let xi = x[i];
            for p in s..e - 1 {
                x[col[p]] -= l[p] * xi;
            }
        }
    }
}

impl faer::matrix_free::LinOp<f64> for Ic0 {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }

    fn nrows(&self) -> usize {
        self.row_ptr.len() - 1
    }

    fn ncols(&self) -> usize {
        self.row_ptr.len() - 1
    }

    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _: Par, _: &mut MemStack) {
        out.copy_from(rhs);
        self.solve_columns(out);
    }

    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, s: &mut MemStack) {
        self.apply(out, rhs, par, s);
    }
}

impl Ic0 {
    /// Each column of `x` ← (L Lᵀ)⁻¹ of itself, in its own memory when it is contiguous (CG's
    /// vectors are), through a copy otherwise.
    fn solve_columns(&self, mut x: MatMut<'_, f64>) {
        for j in 0..x.ncols() {
            let col = x.rb_mut().col_mut(j);
            match col.try_as_col_major_mut() {
                Some(c) => self.solve_in_place(c.as_slice_mut()),
                None => {
                    let mut col = x.rb_mut().col_mut(j);
                    let mut v: Vec<f64> = (0..col.nrows()).map(|i| col[i]).collect();
                    self.solve_in_place(&mut v);
                    for (i, vi) in v.into_iter().enumerate() {
                        col[i] = vi;
                    }
                }
            }
        }
    }
}

/// Applied in place, with no scratch and no copy (the default goes through a temporary).
impl faer::matrix_free::Precond<f64> for Ic0 {
    fn apply_in_place_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }

    fn apply_in_place(&self, rhs: MatMut<'_, f64>, _: Par, _: &mut MemStack) {
        self.solve_columns(rhs);
    }

    fn conj_apply_in_place(&self, rhs: MatMut<'_, f64>, _: Par, _: &mut MemStack) {
        self.solve_columns(rhs);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;

    /// On a tridiagonal matrix IC(0) is the exact Cholesky factor: one application solves.
    #[test]
    fn on_a_tridiagonal_matrix_the_incomplete_factor_is_exact() {
        let n = 50;
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, 2.5 + 0.01 * i as f64));
            if i > 0 {
                t.push(Triplet::new(i, i - 1, -1.0));
                t.push(Triplet::new(i - 1, i, -1.0));
            }
        }
        let k = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
        let ic = Ic0::new(&k).unwrap();
        assert_eq!(ic.shift, 0.0);
        let x_true: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut b = vec![0.0; n];
        for tr in &t {
            b[tr.row] += tr.val * x_true[tr.col];
        }
        ic.solve_in_place(&mut b);
        let err = b
            .iter()
            .zip(&x_true)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-13, "{err}");
    }

    /// A matrix whose incomplete factor meets a negative pivot is factored with a shift.
    #[test]
    fn a_non_positive_pivot_is_met_with_a_shift_and_a_bad_matrix_refused() {
        // Positive definite (its exact Cholesky factor has L33² = 0.28), but IC(0) drops the
        // fill at (2, 1) and (3, 0) and ends with L33² = 1 − 0.75² − 0.75² = −0.125.
        let a = [
            [1.0, 0.6, 0.6, 0.0],
            [0.6, 1.0, 0.0, 0.6],
            [0.6, 0.0, 1.0, -0.6],
            [0.0, 0.6, -0.6, 1.0],
        ];
        let mut t = Vec::new();
        for (i, row) in a.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                if v != 0.0 {
                    t.push(Triplet::new(i, j, v));
                }
            }
        }
        let k = SparseColMat::<usize, f64>::try_new_from_triplets(4, 4, &t).unwrap();
        let ic = Ic0::new(&k).unwrap();
        println!("shift needed: {}", ic.shift);
        assert!(ic.val.iter().all(|v| v.is_finite()));
        assert!(
            ic.shift > 0.0,
            "this pattern's incomplete factor has a non-positive pivot"
        );
    }
}
