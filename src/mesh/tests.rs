//! Tests of the triangulation and the α-shape.
use super::*;

fn shape(alpha: f64, h: f64) -> ShapeParams {
    ShapeParams {
        alpha,
        alpha_boundary: 1.0,
        delta: 0.0,
        spacing: crate::case::Spacing::uniform(h),
    }
}

fn square_block(n: usize, h: f64) -> Particles {
    let mut walls = Vec::new();
    let mut fluid = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let p = Vector2::new(i as f64 * h, j as f64 * h);
            if j == 0 || i == 0 || i == n {
                walls.push(p);
            } else {
                fluid.push(p);
            }
        }
    }
    Particles::new(&walls, &fluid)
}

#[test]
fn a_block_of_water_meshes_to_its_area_with_the_top_free() {
    let h = 0.1;
    let p = square_block(10, h);
    let tri = triangulate(&p, 1.3 * h, false).unwrap();
    let mut mesh = Mesh::default();
    alpha_shape(&tri, &p, &shape(1.2, h), None, &mut mesh);
    assert!((mesh.area(&p.position) - 1.0).abs() < 1e-12);
    // The top row is free surface, its two wall nodes (contact points) included; nothing
    // else is.
    for i in 0..p.len() {
        let top = (p.position[i].y - 1.0).abs() < 1e-9;
        assert_eq!(mesh.free_surface[i], top, "node {i}");
    }
    let (_, count) = mesh.components(p.len());
    assert_eq!(count, 1);
}

/// With a local spacing each triangle is judged against α h at its centroid: the same lattice
/// triangles (R = 0.71 × 0.1 m) pass α h = 0.12 m where h = 0.1 m and fail α h = 0.06 m where
/// the spacing asked for is 0.05 m.
#[test]
fn the_alpha_test_takes_the_local_spacing() {
    let h = 0.1;
    let p = square_block(10, h);
    let tri = triangulate(&p, 1.3 * h, false).unwrap();
    let settings = crate::case::ParticleSettings {
        spacing_m: h,
        refine: Some(crate::case::Refinement {
            x_m: 0.55,
            spacing_m: 0.05,
            transition_m: Some(0.1),
        }),
    };
    let mut refined = shape(1.2, h);
    refined.spacing = settings.spacing();
    let mut mesh = Mesh::default();
    alpha_shape(&tri, &p, &refined, None, &mut mesh);
    let centroid_x = |t: &[u32; 3]| t.iter().map(|&i| p.position[i as usize].x).sum::<f64>() / 3.0;
    let kept: Vec<f64> = mesh.triangles.iter().map(centroid_x).collect();
    // The left 0.4 m: 4 columns of 10 cells, two triangles each.
    assert_eq!(kept.iter().filter(|&&x| x < 0.4).count(), 80);
    assert!(kept.iter().all(|&x| x < 0.5), "{kept:?}");
}

/// The triangles as sorted node triples, in sorted order.
fn triples(c: &[Candidate]) -> Vec<[u32; 3]> {
    let mut t: Vec<[u32; 3]> = c
        .iter()
        .map(|c| {
            let mut n = c.nodes;
            n.sort_unstable();
            n
        })
        .collect();
    t.sort_unstable();
    t
}

#[test]
fn the_two_pieces_give_the_small_triangles_of_the_whole_cloud() {
    let h = 0.01;
    for jitter in [0.0, 0.3] {
        // A 90 × 30 lattice (exactly co-circular cells when not jittered) with a
        // deterministic jitter of up to ±0.15 h.
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let fluid: Vec<Vector2<f64>> = (0..90 * 30)
            .map(|k| {
                let (i, j) = ((k % 90) as f64, (k / 90) as f64);
                Vector2::new((i + jitter * next()) * h, (j + jitter * next()) * h)
            })
            .collect();
        let p = Particles::new(&[], &fluid);
        let max_r = 1.3 * h;
        let split = triangulate(&p, max_r, true).unwrap();
        let serial = triangulate(&p, max_r, false).unwrap();
        let mut piece = Piece::default();
        piece.load(&p.position, 0..p.len() as u32);
        piece.triangulate(max_r, |_| true).unwrap();
        let whole = &piece.triangles;
        assert!(whole.len() > 2 * 89 * 29 - 10, "{} triangles", whole.len());
        assert_eq!(triples(&split), triples(whole), "jitter {jitter}");
        assert_eq!(triples(&serial), triples(whole), "jitter {jitter}");
        // Kept and reused from step to step, the triangulator gives the same triangles, here
        // after a cloud of another size.
        let mut kept = Triangulator::default();
        let other = Particles::new(&[], &fluid[..1000]);
        let second = crate::second_core::SecondCore::start();
        for cloud in [&p, &other, &p] {
            kept.run(cloud, max_r, second.as_ref()).unwrap();
        }
        assert_eq!(triples(&kept.triangles), triples(whole), "jitter {jitter}");
    }
}

#[test]
fn morton_keys_interleave_the_bits() {
    assert_eq!(morton_key(0, 0), 0);
    assert_eq!(morton_key(1, 0), 1);
    assert_eq!(morton_key(0, 1), 2);
    assert_eq!(morton_key(3, 3), 15);
    assert_eq!(morton_key(u16::MAX, 0), 0x5555_5555);
    assert_eq!(morton_key(u16::MAX, u16::MAX), u32::MAX);
}

#[test]
fn a_far_particle_is_isolated() {
    let h = 0.1;
    let mut p = square_block(5, h);
    p.push_fluid(
        Vector2::new(0.25, 2.0),
        Vector2::zeros(),
        0.0,
        Vector2::zeros(),
    );
    let tri = triangulate(&p, 1.3 * h, false).unwrap();
    let mut mesh = Mesh::default();
    alpha_shape(&tri, &p, &shape(1.3, h), None, &mut mesh);
    assert!(!mesh.in_mesh[p.len() - 1]);
}
