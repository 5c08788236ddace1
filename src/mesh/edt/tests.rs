//! Tests of the EDT merge: lattices triangulated by spade, hand-made groups, timing.

use super::*;
use spade::{DelaunayTriangulation, Point2, Triangulation};

/// A 64-bit linear congruential generator: uniform numbers in [0, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// An nx × ny lattice of spacing h, row by row, each node moved by up to ±jitter/2 · h.
fn lattice(nx: usize, ny: usize, h: f64, jitter: f64, seed: u64) -> Vec<Vector2<f64>> {
    let mut rng = Lcg(seed);
    (0..nx * ny)
        .map(|k| {
            let (i, j) = ((k % nx) as f64, (k / nx) as f64);
            let dx = jitter * (rng.next() - 0.5);
            let dy = jitter * (rng.next() - 0.5);
            Vector2::new((i + dx) * h, (j + dy) * h)
        })
        .collect()
}

/// The Delaunay triangles (counter-clockwise, as indices into `points`) with the points
/// inserted into spade in the given order.
fn delaunay(points: &[Vector2<f64>], order: &[u32]) -> Vec<[u32; 3]> {
    let mut tri: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::new();
    for &i in order {
        let p = points[i as usize];
        tri.insert(Point2::new(p.x, p.y)).unwrap();
    }
    tri.inner_faces()
        .map(|f| f.vertices().map(|v| order[v.fix().index()]))
        .collect()
}

/// The triangles (or polygons) as sorted node sets, sorted.
fn node_sets<'a>(groups: impl Iterator<Item = &'a [u32]>) -> Vec<Vec<u32>> {
    let mut sets: Vec<Vec<u32>> = groups
        .map(|g| {
            let mut g = g.to_vec();
            g.sort_unstable();
            g
        })
        .collect();
    sets.sort_unstable();
    sets
}

#[test]
fn every_lattice_square_becomes_one_polygon() {
    let (nx, ny, h) = (6, 5, 0.1);
    let points = lattice(nx, ny, h, 0.0, 1);
    let order: Vec<u32> = (0..points.len() as u32).collect();
    let triangles = delaunay(&points, &order);
    assert_eq!(triangles.len(), 2 * (nx - 1) * (ny - 1));
    let polygons = merge(&points, &triangles, 0.01);
    assert_eq!(polygons.len(), (nx - 1) * (ny - 1));
    let mut max_radius_error = 0.0f64;
    for p in &polygons {
        assert_eq!(p.nodes.len(), 4);
        assert_eq!(p.triangles.len(), 2);
        assert!(p.triangles[0] < p.triangles[1]);
        assert_eq!(p.nodes[0], *p.nodes.iter().min().unwrap());
        // A lattice square: corners i, i + 1, i + 1 + nx, i + nx, counter-clockwise.
        let i = p.nodes[0];
        assert_eq!(p.nodes, vec![i, i + 1, i + 1 + nx as u32, i + nx as u32]);
        max_radius_error = max_radius_error.max((p.radius_m - h / 2f64.sqrt()).abs());
    }
    println!("max |radius − h/√2| = {max_radius_error:.2e} m");
    assert!(max_radius_error < 1e-15);
    assert!(
        polygons
            .windows(2)
            .all(|w| w[0].triangles[0] < w[1].triangles[0])
    );
}

#[test]
fn the_merged_mesh_does_not_depend_on_the_insertion_order() {
    let points = lattice(6, 5, 0.1, 0.0, 1);
    let count = points.len() as u32;
    let row: Vec<u32> = (0..count).collect();
    let reversed: Vec<u32> = (0..count).rev().collect();
    let mut shuffled = row.clone();
    let mut rng = Lcg(2024);
    for k in (1..shuffled.len()).rev() {
        let j = (rng.next() * (k + 1) as f64) as usize;
        shuffled.swap(k, j);
    }
    // Column order.
    let columns: Vec<u32> = (0..count).map(|k| (k % 5) * 6 + k / 5).collect();
    let mut triangle_sets = Vec::new();
    let mut polygon_sets = Vec::new();
    // One Merger for all orders, with an empty mesh in between: reused buffers must not leak.
    let (mut merger, mut reused) = (Merger::default(), Vec::new());
    for order in [&row, &reversed, &shuffled, &columns] {
        let triangles = delaunay(&points, order);
        let polygons = merge(&points, &triangles, 0.01);
        merger.merge_into(&points, &triangles, 0.01, &mut reused);
        assert_eq!(reused, polygons);
        merger.merge_into(&points, &triangles[..1], 0.01, &mut reused);
        assert!(reused.is_empty());
        triangle_sets.push(node_sets(triangles.iter().map(|t| &t[..])));
        polygon_sets.push(node_sets(polygons.iter().map(|p| &p.nodes[..])));
    }
    // The test means something only if the plain triangulations differ.
    let differing = triangle_sets
        .iter()
        .filter(|s| **s != triangle_sets[0])
        .count();
    println!("{differing} of 3 insertion orders split the squares differently from row order");
    assert!(differing > 0);
    for sets in &polygon_sets {
        assert_eq!(sets, &polygon_sets[0]);
        assert_eq!(sets.len(), 20);
    }
}

#[test]
fn a_jittered_lattice_merges_almost_nothing() {
    for (jitter, seed) in [(0.4, 7), (0.4, 8), (0.2, 9)] {
        let points = lattice(30, 20, 0.1, jitter, seed);
        let order: Vec<u32> = (0..points.len() as u32).collect();
        let triangles = delaunay(&points, &order);
        let merged = |delta: f64| -> usize {
            merge(&points, &triangles, delta)
                .iter()
                .map(|p| p.triangles.len())
                .sum()
        };
        let (coarse, fine) = (merged(0.01), merged(0.001));
        println!(
            "jitter ±{} h: {coarse} (δ = 0.01) and {fine} (δ = 0.001) of {} triangles merged",
            jitter / 2.0,
            triangles.len()
        );
        let bound = if jitter > 0.3 { 3 } else { 5 };
        assert!(coarse * 100 <= bound * triangles.len(), "{coarse}");
        assert!(fine * 200 <= triangles.len(), "{fine}");
        assert!(merge(&points, &triangles, 0.0).is_empty());
        assert!(merge(&points, &triangles, -1.0).is_empty());
        assert!(merge(&points, &triangles, f64::NAN).is_empty());
    }
}

#[test]
fn non_convex_large_or_holed_groups_stay_triangles() {
    let v = |x: f64, y: f64| Vector2::new(x, y);
    // An L of four triangles (nodes 0–5), non-convex at node 3; a huge δ merges it.
    let l_shape = [
        v(0., 0.),
        v(2., 0.),
        v(2., 1.),
        v(1., 1.),
        v(1., 2.),
        v(0., 2.),
    ];
    let l_triangles = [[0, 1, 2], [0, 2, 3], [0, 3, 5], [3, 4, 5]];
    assert!(merge(&l_shape, &l_triangles, 1e6).is_empty());
    // Its convex half (a quadrilateral) is returned.
    let p = merge(&l_shape, &l_triangles[..2], 1e6);
    assert_eq!(p.len(), 1);
    assert_eq!(p[0].nodes, vec![0, 1, 2, 3]);
    assert_eq!(p[0].triangles, vec![0, 1]);

    // A hexagon fanned around a centre node: convex, but the centre would be lost.
    let mut hexagon = vec![v(0., 0.)];
    hexagon.extend((0..6).map(|k| {
        let a = k as f64 * std::f64::consts::FRAC_PI_3;
        v(a.cos(), a.sin())
    }));
    let fan: Vec<[u32; 3]> = (0..6).map(|k| [0, k + 1, (k + 1) % 6 + 1]).collect();
    assert!(merge(&hexagon, &fan, 1e6).is_empty());
    // Half of it: the centre is a straight node on the boundary, which is accepted.
    let half = merge(&hexagon, &fan[..3], 1e6);
    assert_eq!(half.len(), 1);
    assert_eq!(half[0].nodes, vec![0, 1, 2, 3, 4]);
    // Four of the six turn right at the centre.
    assert!(merge(&hexagon, &fan[..4], 1e6).is_empty());

    // A ring of six triangles around a triangular hole.
    let ring_points = [
        v(0., 0.),
        v(4., 0.),
        v(2., 4.),
        v(1.5, 1.),
        v(2.5, 1.),
        v(2., 2.),
    ];
    let ring = [
        [0, 1, 4],
        [0, 4, 3],
        [1, 2, 5],
        [1, 5, 4],
        [2, 0, 3],
        [2, 3, 5],
    ];
    assert!(merge(&ring_points, &ring, 1e6).is_empty());

    // A whole lattice merged by a huge δ: far more than MAX_POLYGON_NODES nodes.
    let points = lattice(4, 4, 0.1, 0.0, 1);
    let order: Vec<u32> = (0..16).collect();
    let triangles = delaunay(&points, &order);
    assert!(merge(&points, &triangles, 1e6).is_empty());
    // Three squares in a row: eight nodes, accepted; four would be ten.
    let row: Vec<[u32; 3]> = triangles
        .iter()
        .copied()
        .filter(|t| t.iter().all(|&i| i < 8))
        .collect();
    let p = merge(&points, &row, 1e6);
    assert_eq!(p.len(), 1);
    assert_eq!(p[0].nodes, vec![0, 1, 2, 3, 7, 6, 5, 4]);
    let two_rows: Vec<[u32; 3]> = triangles
        .iter()
        .copied()
        .filter(|t| t.iter().all(|&i| i < 12 && i % 4 < 3))
        .collect();
    assert_eq!(two_rows.len(), 8);
    assert!(merge(&points, &two_rows, 1e6).is_empty());
}

#[test]
fn degenerate_triangles_never_merge() {
    let v = |x: f64, y: f64| Vector2::new(x, y);
    let points = [
        v(0., 0.),
        v(1., 0.),
        v(1., 1.),
        v(0., 1.),
        v(2., 0.),
        v(f64::NAN, 0.),
    ];
    let square = [[0, 1, 2], [0, 2, 3]];
    assert_eq!(merge(&points, &square, 0.01).len(), 1);
    // Collinear, clockwise, repeated, out of range or NaN: each is left alone.
    for bad in [[0, 1, 4], [0, 3, 2], [0, 2, 2], [0, 2, 9], [0, 2, 5]] {
        let triangles = [square[0], bad];
        assert!(merge(&points, &triangles, 1e6).is_empty(), "{bad:?}");
    }
}

#[test]
fn merge_time_on_twenty_thousand_triangles() {
    for jitter in [0.0, 0.4] {
        let points = lattice(101, 101, 0.01, jitter, 3);
        let order: Vec<u32> = (0..points.len() as u32).collect();
        let triangles = delaunay(&points, &order);
        let runs = 50;
        let start = std::time::Instant::now();
        let mut fresh = Vec::new();
        for _ in 0..runs {
            fresh = std::hint::black_box(merge(&points, &triangles, 0.01));
        }
        let fresh_s = start.elapsed().as_secs_f64() / runs as f64;
        let (mut merger, mut reused) = (Merger::default(), Vec::new());
        let start = std::time::Instant::now();
        for _ in 0..runs {
            merger.merge_into(&points, &triangles, 0.01, &mut reused);
            std::hint::black_box(&reused);
        }
        let reused_s = start.elapsed().as_secs_f64() / runs as f64;
        assert_eq!(fresh, reused);
        println!(
            "jitter ±{} h: {} triangles, {} polygons, {:.2} ms per merge, {:.2} ms with a Merger",
            jitter / 2.0,
            triangles.len(),
            fresh.len(),
            fresh_s * 1e3,
            reused_s * 1e3
        );
    }
}
