//! The 3D pressure's sealed pieces: a connected piece of the kept tetrahedra with no node of
//! imposed pressure gets one node pinned, as the 2D step's `solver::pieces` does
//! (`pressure.rs` calls [`sealed_tops`] while it numbers the unknowns).

use crate::fem::tet::P1Tet;
use crate::mesh::components_of;
use crate::mesh3d::{AlphaShape, Tetrahedralisation};

/// Per node: whether it is the highest node of a connected piece of the kept, non-flat
/// tetrahedra (`support`, the nodes' summed element volume, > 0) that has no node with an
/// imposed pressure (water sealed from the air by walls, or a pocket whose every node has a
/// continuity row, `has_row`), which would leave that piece's pressure undetermined up to a
/// constant. Such a node is held at its imposed pressure (0). With the weak surface (`weak`) a
/// free-surface node anchors its piece (its Robin term).
pub(super) fn sealed_tops(
    points: &[[f64; 3]],
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
    elements: &[P1Tet],
    support: &[f64],
    has_row: &dyn Fn(usize) -> bool,
    weak: bool,
) -> Vec<bool> {
    let n = support.len();
    // Flat tetrahedra (zero volume in `elements`) couple nothing in the operators: they do not
    // join pieces either.
    let cells = shape
        .kept
        .iter()
        .zip(elements)
        .filter(|(_, e)| e.volume > 0.0)
        .map(|(&t, _)| mesh.tets[t as usize]);
    let (label, count) = components_of(n, cells, |i| support[i] > 0.0);
    let mut anchored = vec![false; count];
    let mut top: Vec<Option<usize>> = vec![None; count];
    for i in (0..n).filter(|&i| label[i] != u32::MAX) {
        let c = label[i] as usize;
        if !has_row(i) || (weak && shape.free_surface[i]) {
            anchored[c] = true;
        }
        if top[c].is_none_or(|j| points[i][1] > points[j][1]) {
            top[c] = Some(i);
        }
    }
    let mut pinned = vec![false; n];
    for (&a, &t) in anchored.iter().zip(&top) {
        if let (false, Some(i)) = (a, t) {
            pinned[i] = true;
        }
    }
    pinned
}
