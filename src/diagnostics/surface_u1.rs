//! The 3D tank's free-surface velocity seen from above (issue 26; the thesis's figures of u1
//! on the free surface, §3.4): the largest onshore and offshore u1 of the water's free-surface
//! nodes in each cell of an (x, z) grid, over the output times from the spin-up on, and what
//! the thesis says of its barred tank: the fastest water lies over the bars, not in the
//! channel between them.

use crate::case::Bar;

/// The largest and smallest u1 of the free-surface nodes in each cell of an (x, z) grid.
#[derive(Debug, Clone)]
pub struct SurfaceU1Map {
    /// Cell size along x and z, m.
    pub cell_m: f64,
    pub nx: usize,
    pub nz: usize,
    /// From this time on the output times count, s.
    pub from_s: f64,
    /// Per cell (index ix * nz + iz): the largest u1, m/s (−∞ while empty).
    pub max_m_s: Vec<f64>,
    /// Per cell: the smallest u1, m/s (+∞ while empty).
    pub min_m_s: Vec<f64>,
    /// Per cell: nodes counted, over all the output times.
    pub samples: Vec<u32>,
}

impl SurfaceU1Map {
    /// A grid of `cell_m` cells over a tank `length_m` × `width_m`, counting from `from_s`.
    pub fn new(length_m: f64, width_m: f64, cell_m: f64, from_s: f64) -> Self {
        let nx = (length_m / cell_m).ceil().max(1.0) as usize;
        let nz = (width_m / cell_m).ceil().max(1.0) as usize;
        Self {
            cell_m,
            nx,
            nz,
            from_s,
            max_m_s: vec![f64::NEG_INFINITY; nx * nz],
            min_m_s: vec![f64::INFINITY; nx * nz],
            samples: vec![0; nx * nz],
        }
    }

    /// Counts the nodes at `t_s` whose `on_surface` is true: positions `x` ([x, y, z], m) and
    /// horizontal velocities `u1` (m/s).
    pub fn record(&mut self, t_s: f64, x: &[[f64; 3]], u1: &[f64], on_surface: &[bool]) {
        if t_s < self.from_s - 1e-12 {
            return;
        }
        for ((p, &u), _) in x.iter().zip(u1).zip(on_surface).filter(|(_, s)| **s) {
            let (ix, iz) = ((p[0] / self.cell_m).floor(), (p[2] / self.cell_m).floor());
            if ix < 0.0 || iz < 0.0 || ix >= self.nx as f64 || iz >= self.nz as f64 {
                continue;
            }
            let c = ix as usize * self.nz + iz as usize;
            self.max_m_s[c] = self.max_m_s[c].max(u);
            self.min_m_s[c] = self.min_m_s[c].min(u);
            self.samples[c] += 1;
        }
    }

    /// The centre of cell `c`, (x, z) in m.
    pub fn centre(&self, c: usize) -> (f64, f64) {
        let (ix, iz) = (c / self.nz, c % self.nz);
        (
            (ix as f64 + 0.5) * self.cell_m,
            (iz as f64 + 0.5) * self.cell_m,
        )
    }

    /// Over the raised bars against the channel (see [`BarsU1`]); `None` without a raised bar
    /// (a sunken one has no crest to be over) or without a counted cell on either side.
    pub fn over_bars(&self, bars: &[Bar]) -> Option<BarsU1> {
        let raised: Vec<&Bar> = bars.iter().filter(|b| b.height_m > 0.0).collect();
        if raised.is_empty() {
            return None;
        }
        let bars = raised;
        let lo = bars.iter().map(|b| b.x_m[1]).fold(f64::INFINITY, f64::min);
        let hi = bars
            .iter()
            .map(|b| b.x_m[2])
            .fold(f64::NEG_INFINITY, f64::max);
        let (mut on, mut off) = (Vec::new(), Vec::new());
        for c in (0..self.max_m_s.len()).filter(|&c| self.samples[c] > 0) {
            let (x, z) = self.centre(c);
            if x < lo || x > hi {
                continue;
            }
            let inside = |b: &&Bar, i: usize, j: usize| {
                x >= b.x_m[i] && x <= b.x_m[j] && z >= b.z_m[i] && z <= b.z_m[j]
            };
            if bars.iter().any(|b| inside(b, 1, 2)) {
                on.push(self.max_m_s[c]);
            } else if !bars.iter().any(|b| inside(b, 0, 3)) {
                off.push(self.max_m_s[c]);
            }
        }
        if on.is_empty() || off.is_empty() {
            return None;
        }
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Some(BarsU1 {
            x_from_m: lo,
            x_to_m: hi,
            crest_cells: on.len(),
            channel_cells: off.len(),
            crest_max_m_s: max(&on),
            crest_mean_m_s: mean(&on),
            channel_max_m_s: max(&off),
            channel_mean_m_s: mean(&off),
        })
    }
}

/// The largest onshore u1 of the free surface over the bars' crests against the channel
/// between and beside them, in the band of x of the crests: the cells whose centre lies over a
/// crest (each bar's flat top), against those over no part of any bar.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BarsU1 {
    pub x_from_m: f64,
    pub x_to_m: f64,
    pub crest_cells: usize,
    pub channel_cells: usize,
    /// The largest, and the mean over the cells of each cell's largest, u1 over the crests,
    /// m/s.
    pub crest_max_m_s: f64,
    pub crest_mean_m_s: f64,
    /// The same in the channel, m/s.
    pub channel_max_m_s: f64,
    pub channel_mean_m_s: f64,
}

impl BarsU1 {
    /// The thesis's finding: the fastest water over the bars, by the largest and by the mean.
    pub fn fastest_over_the_bars(&self) -> bool {
        self.crest_max_m_s > self.channel_max_m_s && self.crest_mean_m_s > self.channel_mean_m_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bar(z_m: [f64; 4]) -> Bar {
        Bar {
            x_m: [7.8, 8.2, 8.8, 9.2],
            z_m,
            height_m: 0.1,
        }
    }

    #[test]
    fn surface_nodes_faster_over_a_crest_than_in_the_channel_are_found_there() {
        let bars = [bar([-1.0, -0.5, 1.6, 1.9]), bar([3.1, 3.4, 5.5, 6.0])];
        let mut map = SurfaceU1Map::new(11.2, 5.0, 0.1, 2.0);
        // A node over each crest, one in the channel, one off the bars' band, one under water.
        let x = [
            [8.5, 0.4, 1.0],
            [8.5, 0.4, 4.0],
            [8.5, 0.4, 2.5],
            [5.0, 0.4, 2.5],
            [8.5, 0.2, 2.5],
        ];
        let surface = [true, true, true, true, false];
        map.record(1.0, &x, &[9.0; 5], &surface); // before the spin-up: not counted
        map.record(2.0, &x, &[0.6, 0.5, 0.3, 0.9, 2.0], &surface);
        map.record(2.1, &x, &[-0.2, 0.7, 0.35, 0.1, 2.0], &surface);
        let cell =
            |x: f64, z: f64| (x / 0.1).floor() as usize * map.nz + (z / 0.1).floor() as usize;
        assert_eq!(map.samples[cell(8.5, 1.0)], 2);
        assert_eq!(map.max_m_s[cell(8.5, 1.0)], 0.6);
        assert_eq!(map.min_m_s[cell(8.5, 1.0)], -0.2);
        let b = map.over_bars(&bars).expect("cells on both sides");
        assert_eq!((b.crest_cells, b.channel_cells), (2, 1));
        assert!((b.crest_max_m_s - 0.7).abs() < 1e-12);
        assert!((b.crest_mean_m_s - 0.65).abs() < 1e-12);
        assert!((b.channel_max_m_s - 0.35).abs() < 1e-12);
        assert!(b.fastest_over_the_bars());
        assert_eq!(map.over_bars(&[]), None);
        // Sunken bars have no crests: nothing to compare.
        let sunken = bars.map(|b| Bar {
            height_m: -0.1,
            ..b
        });
        assert_eq!(map.over_bars(&sunken), None);
    }
}
