//! The pressure's Dirichlet set by connected piece of the mesh: a piece sealed from the air
//! gets one node pinned, a thin piece on slip walls is pinned whole (`pressure.rs` calls
//! `pin_pieces` while it prepares the system).

use crate::mesh::Mesh;
use crate::particles::Particles;

/// Both rules over one labelling of the mesh's connected pieces.
pub(super) fn pin_pieces(mesh: &Mesh, particles: &Particles, dirichlet: &mut [bool]) {
    let pieces = mesh.components(particles.len());
    pin_sealed_components(&pieces, mesh, particles, dirichlet);
    pin_thin_pieces_on_slip_walls(&pieces, mesh, particles, dirichlet);
}

/// Where the walls slide, a connected piece of the mesh with no interior fluid node (a drop, a
/// film or a puddle of surface nodes on a wall) has no pressure to solve: every node of it is
/// pinned to p = 0 and the piece moves with its predicted velocity, as a lone particle flies.
/// Such a piece keeps continuity rows only at its wall nodes, and a slip wall node takes the
/// water's velocity, so nothing in the piece holds its pressure: a drop in the 1:4 beach's far
/// corner got 3.1e7 Pa from one wall node's row and stopped the run (docs/sweep.md). On
/// no-slip walls a film's wall nodes stand still and their rows keep its area, so those pieces
/// are left to the solve (pinning them there moved the committed no-slip figures).
fn pin_thin_pieces_on_slip_walls(
    (label, count): &(Vec<u32>, usize),
    mesh: &Mesh,
    particles: &Particles,
    dirichlet: &mut [bool],
) {
    if !particles.any_wall_slides() {
        return;
    }
    let (n, count) = (particles.len(), *count);
    let mut interior = vec![false; count];
    for i in 0..n {
        let c = label[i];
        if c != u32::MAX && particles.is_fluid(i) && !mesh.free_surface[i] {
            interior[c as usize] = true;
        }
    }
    for i in 0..n {
        let c = label[i];
        if c != u32::MAX && !interior[c as usize] {
            dirichlet[i] = true;
        }
    }
}

/// A connected piece of the mesh with no free-surface node (water sealed by walls, or a
/// pocket whose surface nodes are all wall nodes) would leave the pressure undetermined up to
/// a constant: pin its highest node to p = 0.
/// A free-surface node held weakly anchors its piece as well (its Robin term).
fn pin_sealed_components(
    (label, count): &(Vec<u32>, usize),
    mesh: &Mesh,
    particles: &Particles,
    dirichlet: &mut [bool],
) {
    let (n, count) = (particles.len(), *count);
    let mut has_dirichlet = vec![false; count];
    let mut top: Vec<Option<usize>> = vec![None; count];
    for i in 0..n {
        let c = label[i];
        if c == u32::MAX {
            continue;
        }
        let c = c as usize;
        if dirichlet[i] || mesh.free_surface[i] {
            has_dirichlet[c] = true;
        }
        if top[c].is_none_or(|j| particles.position[i].y > particles.position[j].y) {
            top[c] = Some(i);
        }
    }
    for c in 0..count {
        if let (false, Some(i)) = (has_dirichlet[c], top[c]) {
            dirichlet[i] = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    /// A film of one fluid node on two bed nodes, and a body with an interior node on three
    /// others: on a slip bed the film is pinned whole and the body keeps its wall rows; on a
    /// no-slip bed nothing is pinned.
    #[test]
    fn thin_pieces_are_pinned_only_where_the_walls_slide() {
        let at = |x: f64, y: f64| Vector2::new(x, y);
        let walls = [
            at(0.0, 0.0),
            at(1.0, 0.0),
            at(3.0, 0.0),
            at(4.0, 0.0),
            at(5.0, 0.0),
        ];
        let fluid = [at(0.5, 0.5), at(4.0, 1.0), at(3.5, 2.0), at(4.5, 2.0)];
        let mut particles = Particles::new(&walls, &fluid);
        let triangles = vec![
            [0, 1, 5],
            [2, 3, 6],
            [3, 4, 6],
            [4, 8, 6],
            [6, 8, 7],
            [2, 6, 7],
        ];
        let mut mesh = Mesh::from_triangles(particles.len(), triangles);
        mesh.free_surface = vec![false, false, false, false, false, true, false, true, true];
        mesh.in_mesh = vec![true; particles.len()];
        let pinned = |particles: &Particles| {
            let mut dirichlet = mesh.free_surface.clone();
            let pieces = mesh.components(particles.len());
            pin_thin_pieces_on_slip_walls(&pieces, &mesh, particles, &mut dirichlet);
            dirichlet
        };
        let f = false;
        let no_slip = [f, f, f, f, f, true, f, true, true];
        assert_eq!(pinned(&particles), no_slip);
        for i in 0..walls.len() {
            particles.wall_tangent[i] = Vector2::x();
        }
        let slip = [true, true, f, f, f, true, f, true, true];
        assert_eq!(pinned(&particles), slip);
    }
}
