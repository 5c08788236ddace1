//! Tests of the Laplace coordinates and the polygon element: reproduction of linear fields,
//! the P1 and edge limits, smoothed-gradient consistency, weights, patch tests on mixed meshes
//! of polygons and triangles, and timing.

use super::*;
use nalgebra::Matrix2;
use std::f64::consts::TAU;

type V = Vector2<f64>;

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

/// Whether every node turns left by more than `min_turn` (a cross product, m²).
fn convex(nodes: &[V], min_turn: f64) -> bool {
    let n = nodes.len();
    (0..n).all(|k| {
        let (a, b, c) = (nodes[k], nodes[(k + 1) % n], nodes[(k + 2) % n]);
        (b - a).perp(&(c - b)) > min_turn
    })
}

/// A random convex polygon of n nodes, counter-clockwise: sorted random angles on a circle of
/// random radius (0.05–1.05 m) and centre, each radius jittered by ±15 % unless `cyclic`;
/// redrawn until every turn is clearly convex.
fn random_convex(rng: &mut Lcg, n: usize, cyclic: bool) -> (Vec<V>, f64) {
    loop {
        let scale = 0.05 + rng.next();
        let centre = V::new(rng.next() - 0.5, rng.next() - 0.5) * 3.0;
        let mut angles: Vec<f64> = (0..n).map(|_| rng.next() * TAU).collect();
        angles.sort_by(f64::total_cmp);
        let nodes: Vec<V> = angles
            .iter()
            .map(|a| {
                let jitter = if cyclic {
                    0.0
                } else {
                    0.3 * (rng.next() - 0.5)
                };
                centre + V::new(a.cos(), a.sin()) * scale * (1.0 + jitter)
            })
            .collect();
        if convex(&nodes, 0.01 * scale * scale) {
            return (nodes, scale);
        }
    }
}

/// A random point strictly inside a convex polygon: alternately a random convex combination
/// of the nodes, or a point up to 99.9 % of the way from the centroid to a random point of a
/// random edge (so that points near the boundary are tried too).
fn random_inside(rng: &mut Lcg, nodes: &[V], k: usize) -> V {
    let n = nodes.len();
    let centroid = nodes.iter().sum::<V>() / n as f64;
    if k.is_multiple_of(2) {
        let w: Vec<f64> = (0..n).map(|_| rng.next() + 1e-3).collect();
        nodes.iter().zip(&w).map(|(p, w)| p * *w).sum::<V>() / w.iter().sum::<f64>()
    } else {
        let e = ((rng.next() * n as f64) as usize).min(n - 1);
        let on_edge = nodes[e] + (nodes[(e + 1) % n] - nodes[e]) * rng.next();
        centroid + (on_edge - centroid) * (0.999 * rng.next())
    }
}

/// Shoelace area, from the first node (so that it keeps its precision away from the origin).
fn polygon_area(nodes: &[V]) -> f64 {
    let n = nodes.len();
    let at = |k: usize| nodes[k % n] - nodes[0];
    0.5 * (1..n - 1).map(|k| at(k).perp(&at(k + 1))).sum::<f64>()
}

#[test]
fn the_coordinates_are_a_partition_of_unity_reproducing_linear_fields() {
    let mut rng = Lcg(11);
    let (mut unity, mut linear, mut lowest) = (0.0f64, 0.0f64, 0.0f64);
    for n in 4..=8 {
        for _ in 0..100 {
            let (nodes, scale) = random_convex(&mut rng, n, false);
            let mut w = vec![0.0; n];
            for k in 0..20 {
                let x = random_inside(&mut rng, &nodes, k);
                laplace_coordinates(&nodes, x, &mut w);
                unity = unity.max((w.iter().sum::<f64>() - 1.0).abs());
                let mapped: V = nodes.iter().zip(&w).map(|(p, w)| p * *w).sum();
                linear = linear.max((mapped - x).norm() / scale);
                lowest = lowest.min(w.iter().copied().fold(f64::INFINITY, f64::min));
            }
        }
    }
    println!(
        "n = 4–8, 10 000 points: max |Σ N − 1| = {unity:.1e}, max |Σ N x − x|/r = {linear:.1e}, \
         min N = {lowest:.1e}"
    );
    assert!(unity < 1e-12 && linear < 1e-12, "{unity} {linear}");
    assert!(lowest > -1e-15, "{lowest}");
}

#[test]
fn on_a_cyclic_polygon_the_coordinates_are_wachspress_ones() {
    // An independent check of the clipping: on a polygon inscribed in a circle the Laplace
    // coordinates equal Wachspress's closed form w_i = A(x_{i−1}, x_i, x_{i+1}) /
    // (A(x, x_{i−1}, x_i) A(x, x_i, x_{i+1})), normalised.
    let area = |a: V, b: V, c: V| 0.5 * (b - a).perp(&(c - a));
    let mut rng = Lcg(5);
    let mut worst = 0.0f64;
    for n in 4..=8 {
        for _ in 0..50 {
            let (nodes, _) = random_convex(&mut rng, n, true);
            let mut w = vec![0.0; n];
            for k in 0..20 {
                let x = random_inside(&mut rng, &nodes, k);
                laplace_coordinates(&nodes, x, &mut w);
                let wachspress: Vec<f64> = (0..n)
                    .map(|i| {
                        let (prev, next) = (nodes[(i + n - 1) % n], nodes[(i + 1) % n]);
                        area(prev, nodes[i], next)
                            / (area(x, prev, nodes[i]) * area(x, nodes[i], next))
                    })
                    .collect();
                let total: f64 = wachspress.iter().sum();
                for (a, b) in w.iter().zip(&wachspress) {
                    worst = worst.max((a - b / total).abs());
                }
            }
        }
    }
    println!("cyclic n = 4–8: max |Laplace − Wachspress| = {worst:.1e}");
    assert!(worst < 1e-12, "{worst}");
}

#[test]
fn on_a_triangle_the_coordinates_are_barycentric() {
    let mut rng = Lcg(3);
    let mut worst = 0.0f64;
    for _ in 0..300 {
        // Centred on the origin: the test is of the method, not of how x − x_i rounds far
        // from the origin (which limits any formula, barycentric ones included).
        let (mut t, _) = random_convex(&mut rng, 3, false);
        let centroid = t.iter().sum::<V>() / 3.0;
        t.iter_mut().for_each(|p| *p -= centroid);
        let whole = polygon_area(&t);
        let mut w = [0.0; 3];
        for k in 0..20 {
            let x = random_inside(&mut rng, &t, k);
            laplace_coordinates(&t, x, &mut w);
            for i in 0..3 {
                let (b, c) = (t[(i + 1) % 3], t[(i + 2) % 3]);
                let barycentric = 0.5 * (b - x).perp(&(c - x)) / whole;
                worst = worst.max((w[i] - barycentric).abs());
            }
        }
    }
    println!("triangles: max |N − λ| = {worst:.1e}");
    assert!(worst < 1e-14, "{worst}");
}

#[test]
fn along_an_edge_the_coordinates_are_linear() {
    let mut rng = Lcg(17);
    let offsets = [1e-4, 1e-7, 1e-10, 1e-12, 0.0];
    let mut worst = [0.0f64; 5];
    for n in 4..=8 {
        for _ in 0..40 {
            let (nodes, scale) = random_convex(&mut rng, n, false);
            let mut w = vec![0.0; n];
            for k in 0..n {
                let (a, b) = (nodes[k], nodes[(k + 1) % n]);
                let inward = V::new(-(b - a).y, (b - a).x).normalize();
                for s in 1..10 {
                    let t = s as f64 / 10.0;
                    for (o, offset) in offsets.iter().enumerate() {
                        let x = a + (b - a) * t + inward * (offset * scale);
                        laplace_coordinates(&nodes, x, &mut w);
                        for (i, wi) in w.iter().enumerate() {
                            let linear = match i {
                                i if i == k => 1.0 - t,
                                i if i == (k + 1) % n => t,
                                _ => 0.0,
                            };
                            worst[o] = worst[o].max((wi - linear).abs());
                        }
                    }
                }
            }
        }
    }
    println!(
        "max |N − linear| at distances {offsets:?} × r from the edge: {}",
        worst.map(|w| format!("{w:.1e}")).join(" ")
    );
    // The approach is linear in the distance (the coordinates are smooth up to the edge).
    for (o, offset) in offsets.iter().enumerate() {
        assert!(worst[o] <= 50.0 * offset + 1e-12, "{offset}: {}", worst[o]);
    }
}

#[test]
fn three_nodes_give_the_p1_element_bit_for_bit() {
    let t = [V::new(0.1, 0.2), V::new(0.9, 0.35), V::new(0.3, 1.1)];
    let e = polygon_element(&t);
    let reference = p1(t[0], t[1], t[2]);
    assert_eq!(e.cell_area, vec![reference.area]);
    assert_eq!(e.cell_grad, reference.grad.to_vec());
    assert_eq!(e.node_weight, vec![reference.area / 3.0; 3]);
    assert_eq!(e.cell_weight, vec![reference.area / 3.0; 3]);
}

/// Per-cell consistency of one element: returns (max |Σ ∇̃N|·r, max |Σ x ⊗ ∇̃N − I|).
fn cell_consistency(nodes: &[V], e: &PolygonElement, scale: f64) -> (f64, f64) {
    let n = nodes.len();
    let (mut constant, mut linear) = (0.0f64, 0.0f64);
    for c in 0..e.cell_count() {
        let grad = &e.cell_grad[c * n..(c + 1) * n];
        let sum: V = grad.iter().sum();
        let identity: Matrix2<f64> = nodes.iter().zip(grad).map(|(x, g)| x * g.transpose()).sum();
        constant = constant.max(sum.norm() * scale);
        linear = linear.max((identity - Matrix2::identity()).norm());
    }
    (constant, linear)
}

#[test]
fn smoothed_gradients_are_consistent_in_every_cell() {
    let mut rng = Lcg(23);
    let (mut constant, mut linear, mut areas, mut weights, mut moment) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for n in 4..=8 {
        for _ in 0..200 {
            let (nodes, scale) = random_convex(&mut rng, n, false);
            let e = polygon_element(&nodes);
            assert_eq!(e.cell_count(), n);
            let (c, l) = cell_consistency(&nodes, &e, scale);
            constant = constant.max(c);
            linear = linear.max(l);
            let area = polygon_area(&nodes);
            areas = areas.max((e.cell_area.iter().sum::<f64>() - area).abs() / area);
            weights = weights.max((e.node_weight.iter().sum::<f64>() - area).abs() / area);
            for (k, cell_area) in e.cell_area.iter().enumerate() {
                let in_cell: f64 = e.cell_weight[k * n..(k + 1) * n].iter().sum();
                weights = weights.max((in_cell - cell_area).abs() / area);
            }
            // Σ_i x_i ∫N_i = ∫x dA exactly, since Σ_i N_i x_i = x is linear and the
            // edge-midpoint rule is exact for it; ∫x dA = A × centroid (both from node 0).
            let at = |k: usize| nodes[k % n] - nodes[0];
            let first: V = (0..n).map(|k| at(k) * e.node_weight[k]).sum();
            let centroid = (1..n - 1)
                .map(|k| (at(k) + at(k + 1)) * at(k).perp(&at(k + 1)))
                .sum::<V>()
                / (6.0 * area);
            moment = moment.max((first / area - centroid).norm() / scale);
        }
    }
    println!(
        "n = 4–8, 1000 polygons: max |Σ∇̃N|·r = {constant:.1e}, max |Σ x⊗∇̃N − I| = {linear:.1e}, \
         areas {areas:.1e}, weights {weights:.1e}, first moment {moment:.1e} (relative)"
    );
    assert!(constant < 1e-12 && linear < 1e-12, "{constant} {linear}");
    assert!(
        areas < 1e-14 && weights < 1e-14 && moment < 1e-12,
        "{areas} {weights} {moment}"
    );
}

#[test]
fn regular_polygons_have_equal_node_weights() {
    for n in [4, 5, 6, 8] {
        let nodes: Vec<V> = (0..n)
            .map(|k| {
                let a = 0.3 + TAU * k as f64 / n as f64;
                V::new(2.0 + 0.1 * a.cos(), -1.0 + 0.1 * a.sin())
            })
            .collect();
        let area = polygon_area(&nodes);
        let e = polygon_element(&nodes);
        let worst = e
            .node_weight
            .iter()
            .map(|w| (w - area / n as f64).abs() / (area / n as f64))
            .fold(0.0, f64::max);
        println!("regular {n}-gon: max |w − A/n|/(A/n) = {worst:.1e}");
        assert!(worst < 1e-13, "{n}: {worst}");
    }
}

/// Assembles K_ij = Σ_cells A ∇̃N_i·∇̃N_j over a mesh of elements (node lists, counter-
/// clockwise) and applies it to the linear field p = 1.3 + 0.7x − 2.1y. Returns the largest
/// |(K p)_i| / (K_ii max|p|) over interior nodes, the largest |∇̃p − ∇p|/|∇p| over all cells,
/// and the largest |Σ_cells A ∇̃N_i|·h / A_i over interior nodes (the discrete divergence of a
/// constant field), with A_i the node's weight and h the longest edge.
fn patch_test(points: &[V], elements: &[Vec<u32>]) -> (f64, f64, f64) {
    let count = points.len();
    let gradient = V::new(0.7, -2.1);
    let p: Vec<f64> = points.iter().map(|x| 1.3 + gradient.dot(x)).collect();
    let p_scale = p.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut k = vec![0.0; count * count];
    let mut constant = vec![V::zeros(); count];
    let mut weight = vec![0.0; count];
    let mut edges: Vec<(u32, u32)> = Vec::new();
    let mut cell_error = 0.0f64;
    let mut longest = 0.0f64;
    for element in elements {
        let nodes: Vec<V> = element.iter().map(|&i| points[i as usize]).collect();
        let n = nodes.len();
        assert!(convex(&nodes, 0.0), "{element:?}");
        let e = polygon_element(&nodes);
        for c in 0..e.cell_count() {
            let grad = &e.cell_grad[c * n..(c + 1) * n];
            let cell_p: V = element
                .iter()
                .zip(grad)
                .map(|(&j, g)| g * p[j as usize])
                .sum();
            cell_error = cell_error.max((cell_p - gradient).norm() / gradient.norm());
            for (a, &i) in element.iter().enumerate() {
                constant[i as usize] += grad[a] * e.cell_area[c];
                for (b, &j) in element.iter().enumerate() {
                    k[i as usize * count + j as usize] += e.cell_area[c] * grad[a].dot(&grad[b]);
                }
            }
        }
        for (a, &i) in element.iter().enumerate() {
            weight[i as usize] += e.node_weight[a];
            let j = element[(a + 1) % n];
            edges.push((i.min(j), i.max(j)));
            longest = longest.max((points[j as usize] - points[i as usize]).norm());
        }
    }
    // Boundary nodes: those on an edge that only one element has; every edge has one or two.
    edges.sort_unstable();
    let mut boundary = vec![false; count];
    let mut s = 0;
    while s < edges.len() {
        let same = edges[s..].iter().take_while(|e| **e == edges[s]).count();
        assert!(same <= 2, "{:?}", edges[s]);
        if same == 1 {
            boundary[edges[s].0 as usize] = true;
            boundary[edges[s].1 as usize] = true;
        }
        s += same;
    }
    assert!(boundary.iter().any(|b| !b));
    let (mut residual, mut divergence) = (0.0f64, 0.0f64);
    for i in (0..count).filter(|&i| !boundary[i]) {
        let row = &k[i * count..(i + 1) * count];
        let kp: f64 = row.iter().zip(&p).map(|(a, b)| a * b).sum();
        residual = residual.max(kp.abs() / (row[i] * p_scale));
        divergence = divergence.max(constant[i].norm() * longest / weight[i]);
    }
    (residual, cell_error, divergence)
}

/// Nodes of an nx × ny lattice of unit squares, index j·nx + i; `jitter` moves the interior
/// nodes by up to ±jitter/2.
fn square_nodes(nx: usize, ny: usize, jitter: f64, rng: &mut Lcg) -> Vec<V> {
    (0..nx * ny)
        .map(|k| {
            let (i, j) = (k % nx, k / nx);
            let interior = i > 0 && j > 0 && i + 1 < nx && j + 1 < ny;
            let mut x = V::new(i as f64, j as f64);
            if interior {
                x += V::new(rng.next() - 0.5, rng.next() - 0.5) * jitter;
            }
            x
        })
        .collect()
}

/// The cells of a lattice of nx × ny nodes: a cell is one quadrilateral element where
/// `polygon(i, j)`, else two triangles (diagonal alternating from cell to cell).
fn square_elements(nx: usize, ny: usize, polygon: impl Fn(usize, usize) -> bool) -> Vec<Vec<u32>> {
    let mut elements = Vec::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let a = (j * nx + i) as u32;
            let (b, c, d) = (a + 1, a + 1 + nx as u32, a + nx as u32);
            if polygon(i, j) {
                elements.push(vec![a, b, c, d]);
            } else if (i + j) % 2 == 0 {
                elements.extend([vec![a, b, c], vec![a, c, d]]);
            } else {
                elements.extend([vec![a, b, d], vec![b, c, d]]);
            }
        }
    }
    elements
}

/// A central convex n-gon (jittered radii and angles) inside a ring of quadrilaterals to an
/// outer n-gon; every other ring cell is one quadrilateral element, the rest two triangles.
fn ring_mesh(n: usize, rng: &mut Lcg) -> (Vec<V>, Vec<Vec<u32>>) {
    let mut points = Vec::with_capacity(2 * n);
    for radius in [1.0, 2.2] {
        for k in 0..n {
            let a = TAU * (k as f64 + 0.3 * (rng.next() - 0.5)) / n as f64;
            let r = radius * (1.0 + 0.1 * (rng.next() - 0.5));
            points.push(V::new(0.4 + r * a.cos(), -0.2 + r * a.sin()));
        }
    }
    let mut elements = vec![(0..n as u32).collect::<Vec<u32>>()];
    for k in 0..n as u32 {
        let next = (k + 1) % n as u32;
        let (inner, outer, outer_next, inner_next) = (k, k + n as u32, next + n as u32, next);
        if k.is_multiple_of(2) {
            elements.push(vec![inner, outer, outer_next, inner_next]);
        } else {
            elements.extend([
                vec![inner, outer, outer_next],
                vec![inner, outer_next, inner_next],
            ]);
        }
    }
    (points, elements)
}

#[test]
fn mixed_meshes_pass_the_patch_test() {
    let mut rng = Lcg(31);
    let report = |name: &str, points: &[V], elements: &[Vec<u32>]| {
        let (residual, cell, divergence) = patch_test(points, elements);
        println!(
            "{name}: max |Kp|/(K_ii |p|) = {residual:.1e}, cell gradient {cell:.1e}, \
             Σ A∇̃N {divergence:.1e}"
        );
        assert!(
            residual < 1e-10 && cell < 1e-12 && divergence < 1e-12,
            "{name}"
        );
    };
    // 3 × 3 unit squares: the middle one a polygon element, the others triangles.
    let points = square_nodes(4, 4, 0.0, &mut rng);
    report(
        "3×3 squares, middle polygon",
        &points,
        &square_elements(4, 4, |i, j| i == 1 && j == 1),
    );
    // A jittered 4 × 4 checkerboard of quadrilateral elements and triangle pairs.
    let points = square_nodes(5, 5, 0.3, &mut rng);
    report(
        "jittered checkerboard",
        &points,
        &square_elements(5, 5, |i, j| (i + j) % 2 == 0),
    );
    // An n-gon sharing edges with quadrilateral elements and with triangles.
    for n in 4..=8 {
        let (points, elements) = ring_mesh(n, &mut rng);
        report(&format!("{n}-gon in a ring"), &points, &elements);
    }
}

#[test]
fn bad_geometry_does_not_panic() {
    let square = [
        V::new(0., 0.),
        V::new(1., 0.),
        V::new(1., 1.),
        V::new(0., 1.),
    ];
    let mut w = [0.0; 4];
    // On a node, on an edge, outside: the edge's linear interpolant.
    laplace_coordinates(&square, V::new(1.0, 1.0), &mut w);
    assert_eq!(w, [0.0, 0.0, 1.0, 0.0]);
    laplace_coordinates(&square, V::new(0.25, 0.0), &mut w);
    assert_eq!(w, [0.75, 0.25, 0.0, 0.0]);
    laplace_coordinates(&square, V::new(0.5, -3.0), &mut w);
    assert_eq!(w, [0.5, 0.5, 0.0, 0.0]);
    laplace_coordinates(&square, V::new(f64::NAN, 0.5), &mut w);
    // Collinear nodes, a repeated node, fewer than three nodes.
    let line = [
        V::new(0., 0.),
        V::new(1., 0.),
        V::new(2., 0.),
        V::new(1., 0.),
    ];
    laplace_coordinates(&line, V::new(0.5, 0.0), &mut w);
    assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    let _ = polygon_element(&line);
    let repeated = [
        V::new(0., 0.),
        V::new(1., 0.),
        V::new(1., 0.),
        V::new(0., 1.),
    ];
    laplace_coordinates(&repeated, V::new(0.3, 0.3), &mut w);
    assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    let mut two = [0.0; 2];
    laplace_coordinates(&square[..2], V::new(0.25, 0.5), &mut two);
    assert_eq!(two, [0.75, 0.25]);
    assert_eq!(polygon_element(&square[..2]).cell_count(), 0);
    // Clockwise or non-convex input gives numbers, not a panic.
    let clockwise: Vec<V> = square.iter().rev().copied().collect();
    let _ = polygon_element(&clockwise);
    let dart = [
        V::new(0., 0.),
        V::new(2., 1.),
        V::new(0., 2.),
        V::new(0.5, 1.),
    ];
    let _ = polygon_element(&dart);
    // Many nodes (heap buffers).
    let many: Vec<V> = (0..20)
        .map(|k| V::new((TAU * k as f64 / 20.0).cos(), (TAU * k as f64 / 20.0).sin()))
        .collect();
    let mut w = vec![0.0; 20];
    laplace_coordinates(&many, V::new(0.1, -0.2), &mut w);
    let mapped: V = many.iter().zip(&w).map(|(p, w)| p * *w).sum();
    assert!((mapped - V::new(0.1, -0.2)).norm() < 1e-14);
}

#[test]
fn element_timing() {
    let mut rng = Lcg(41);
    for n in [4, 6, 8] {
        let (nodes, _) = random_convex(&mut rng, n, false);
        let runs = 20_000;
        let start = std::time::Instant::now();
        for _ in 0..runs {
            std::hint::black_box(polygon_element(std::hint::black_box(&nodes)));
        }
        let element_s = start.elapsed().as_secs_f64() / runs as f64;
        let x = nodes.iter().sum::<V>() / n as f64;
        let mut w = vec![0.0; n];
        let start = std::time::Instant::now();
        for _ in 0..runs {
            laplace_coordinates(&nodes, std::hint::black_box(x), &mut w);
            std::hint::black_box(&w);
        }
        let point_s = start.elapsed().as_secs_f64() / runs as f64;
        println!(
            "n = {n}: {:.2} µs per polygon_element, {:.3} µs per laplace_coordinates",
            element_s * 1e6,
            point_s * 1e6
        );
    }
}
