//! A Jacobi-preconditioned conjugate-gradient loop for the matrix-free momentum predictor.
//! Rows whose preconditioner entry is zero are Dirichlet rows: they stay at zero.

#[derive(Default)]
pub struct Scratch {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    ap: Vec<f64>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solves A x = b from the initial `x`; `apply(v, out)` writes A v. Returns the iteration count,
/// or the relative residual reached when `max_iterations` ran out.
pub fn pcg(
    mut apply: impl FnMut(&[f64], &mut [f64]),
    diag_inv: &[f64],
    b: &[f64],
    x: &mut [f64],
    rel_tolerance: f64,
    max_iterations: usize,
    s: &mut Scratch,
) -> Result<usize, f64> {
    let n = b.len();
    for v in [&mut s.r, &mut s.z, &mut s.p, &mut s.ap] {
        v.clear();
        v.resize(n, 0.0);
    }
    apply(x, &mut s.ap);
    for i in 0..n {
        s.r[i] = if diag_inv[i] == 0.0 {
            0.0
        } else {
            b[i] - s.ap[i]
        };
        s.z[i] = diag_inv[i] * s.r[i];
    }
    let b_norm = dot(b, b).sqrt().max(f64::MIN_POSITIVE);
    s.p.copy_from_slice(&s.z);
    let mut rz = dot(&s.r, &s.z);
    for it in 0..max_iterations {
        if dot(&s.r, &s.r).sqrt() <= rel_tolerance * b_norm {
            return Ok(it);
        }
        apply(&s.p, &mut s.ap);
        let pap = dot(&s.p, &s.ap);
        if pap.is_nan() || pap <= 0.0 {
            return Err(dot(&s.r, &s.r).sqrt() / b_norm);
        }
        let a = rz / pap;
        for i in 0..n {
            x[i] += a * s.p[i];
            s.r[i] -= a * s.ap[i];
            s.z[i] = diag_inv[i] * s.r[i];
        }
        let rz_new = dot(&s.r, &s.z);
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..n {
            s.p[i] = s.z[i] + beta * s.p[i];
        }
    }
    let res = dot(&s.r, &s.r).sqrt() / b_norm;
    if res <= rel_tolerance {
        Ok(max_iterations)
    } else {
        Err(res)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_tridiagonal_system() {
        let n = 50;
        let apply = |v: &[f64], out: &mut [f64]| {
            for i in 0..n {
                let l = if i > 0 { v[i - 1] } else { 0.0 };
                let r = if i + 1 < n { v[i + 1] } else { 0.0 };
                out[i] = 4.0 * v[i] - l - r;
            }
        };
        let b = vec![1.0; n];
        let mut x = vec![0.0; n];
        let it = pcg(
            apply,
            &vec![0.25; n],
            &b,
            &mut x,
            1e-12,
            200,
            &mut Scratch::default(),
        )
        .unwrap();
        let mut ax = vec![0.0; n];
        apply(&x, &mut ax);
        let err: f64 = ax
            .iter()
            .zip(&b)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-10 && it < 60, "{err} after {it}");
    }
}
