//! The state of the particle cloud, as a struct of arrays owned by the caller.
//!
//! Wall nodes come first (indices `0..n_wall`) and move only with their wall (a paddle); fluid
//! particles follow.

use nalgebra::Vector2;

/// What a node is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    /// A Lagrangian water particle.
    Fluid,
    /// A solid-boundary node: Dirichlet velocity, free pressure.
    Wall,
}

#[derive(Debug, Clone, Default)]
pub struct Particles {
    /// Position in the flume frame (x along the flume, y up), m.
    pub position: Vec<Vector2<f64>>,
    /// Velocity, m/s.
    pub velocity: Vec<Vector2<f64>>,
    /// Pressure relative to the atmosphere, Pa.
    pub pressure: Vec<f64>,
    /// Projected pressure gradient π ≈ −∇p of the FIC stabilisation, Pa/m.
    pub pressure_gradient_projection: Vec<Vector2<f64>>,
    pub kind: Vec<NodeKind>,
    /// Unit tangent of a slip wall node (its velocity is kept along it); zero for fluid
    /// particles, no-slip walls and corners, whose velocity is not free along any direction.
    pub wall_tangent: Vec<Vector2<f64>>,
    /// Velocity of the solid a wall node belongs to (the paddle's, zero for fixed walls), m/s:
    /// the Dirichlet value of a no-slip wall node, and how far it moves per step.
    pub wall_velocity: Vec<Vector2<f64>>,
}

impl Particles {
    /// Wall nodes at rest followed by fluid particles at rest.
    pub fn new(walls: &[Vector2<f64>], fluid: &[Vector2<f64>]) -> Particles {
        let n = walls.len() + fluid.len();
        let mut kind = vec![NodeKind::Wall; walls.len()];
        kind.resize(n, NodeKind::Fluid);
        Particles {
            position: walls.iter().chain(fluid).copied().collect(),
            velocity: vec![Vector2::zeros(); n],
            pressure: vec![0.0; n],
            pressure_gradient_projection: vec![Vector2::zeros(); n],
            kind,
            wall_tangent: vec![Vector2::zeros(); n],
            wall_velocity: vec![Vector2::zeros(); n],
        }
    }

    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    pub fn is_fluid(&self, i: usize) -> bool {
        self.kind[i] == NodeKind::Fluid
    }

    /// Whether node i slides along a wall (a slip wall node that is not a corner): only those
    /// have a tangent.
    pub fn slides(&self, i: usize) -> bool {
        self.wall_tangent[i] != Vector2::zeros()
    }

    /// Whether any wall node slides: false in a no-slip flume, whose wall nodes hold their
    /// velocity.
    pub fn any_wall_slides(&self) -> bool {
        (0..self.len()).any(|i| self.slides(i))
    }

    pub fn fluid_count(&self) -> usize {
        self.kind.iter().filter(|k| **k == NodeKind::Fluid).count()
    }

    /// Removes the nodes for which `drop` is true, keeping the order of the others.
    pub fn remove_where(&mut self, drop: &[bool]) {
        let mut k = 0;
        for i in 0..self.len() {
            if !drop[i] {
                self.position[k] = self.position[i];
                self.velocity[k] = self.velocity[i];
                self.pressure[k] = self.pressure[i];
                self.pressure_gradient_projection[k] = self.pressure_gradient_projection[i];
                self.kind[k] = self.kind[i];
                self.wall_tangent[k] = self.wall_tangent[i];
                self.wall_velocity[k] = self.wall_velocity[i];
                k += 1;
            }
        }
        self.position.truncate(k);
        self.velocity.truncate(k);
        self.pressure.truncate(k);
        self.pressure_gradient_projection.truncate(k);
        self.kind.truncate(k);
        self.wall_tangent.truncate(k);
        self.wall_velocity.truncate(k);
    }

    /// Appends one fluid particle.
    pub fn push_fluid(
        &mut self,
        position: Vector2<f64>,
        velocity: Vector2<f64>,
        pressure: f64,
        projection: Vector2<f64>,
    ) {
        self.position.push(position);
        self.velocity.push(velocity);
        self.pressure.push(pressure);
        self.pressure_gradient_projection.push(projection);
        self.kind.push(NodeKind::Fluid);
        self.wall_tangent.push(Vector2::zeros());
        self.wall_velocity.push(Vector2::zeros());
    }

    /// The velocity a node may have: all of `u` for a fluid particle; for a wall node, the
    /// velocity of its wall plus, on a slip wall, the part of `u` relative to it along the wall.
    #[inline]
    pub fn admissible_velocity(&self, i: usize, u: Vector2<f64>) -> Vector2<f64> {
        match self.kind[i] {
            NodeKind::Fluid => u,
            NodeKind::Wall => {
                let (t, w) = (self.wall_tangent[i], self.wall_velocity[i]);
                w + (u - w).dot(&t) * t
            }
        }
    }
}
