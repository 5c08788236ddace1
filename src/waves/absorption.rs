//! Active absorption of the wave a beach reflects, at the paddle's own frequency: the paddle
//! reads two wave gauges in front of it, splits the first harmonic of the last wave period into
//! the wave going out and the wave coming back (the two-gauge method of Goda & Suzuki 1976,
//! run over a sliding window of one period),
//! and adds to its motion the one that radiates the opposite of the wave coming back, so that
//! it leaves the flume instead of being re-reflected towards the beach.
//!
//! With η = Re(Z e^{−iωt}) at each gauge and x measured from the face at rest,
//! Z(x) = P e^{ikx} + Q e^{−ikx}: Q is the arriving wave at the face. The progressive wave a
//! paddle radiates is in phase with its velocity at the still-water level, with the elevation
//! amplitude F(kh)/ω per unit velocity (F = H/S, the piston's or flap's transfer function), so
//! the absorbing velocity is U_a = −(ω/F) Re(Q e^{−iωt}) and the displacement
//! X_a = Re(X̂ e^{−iωt}) with X̂ = −i Q / F. Q needs no model of the paddle's own wave: what the
//! absorbing motion radiates goes out with P, so there is no loop through the gauges within a
//! wave's return trip. Only the first harmonic at the design period is absorbed; the mean and
//! the harmonics are left (the long waves are the piston's `LongWaveAbsorber`'s).

use std::collections::VecDeque;
use std::f64::consts::PI;

use nalgebra::Complex;

use super::linear::{self, PaddleKind};
use super::{Result, half_cosine_ramp};

/// The smallest |sin kΔx| the gauges' spacing may give (the split divides by it).
pub const MIN_GAUGE_SINE: f64 = 0.3;

/// Where the two gauges stand, m in front of the face at rest, for a wave of `period_s` in
/// `depth_m` with `flat_m` of flat bed in front of the face: the first one depth out (clear of
/// the paddle's evanescent modes), the second a quarter wavelength further, or as far as the
/// flat bed allows while ending one depth before its end. `Err` with the reason when the flat
/// bed is too short for a spacing with |sin kΔx| ≥ [`MIN_GAUGE_SINE`].
pub fn gauge_offsets_m(
    period_s: f64,
    depth_m: f64,
    gravity_m_s2: f64,
    flat_m: f64,
) -> std::result::Result<[f64; 2], String> {
    let k = linear::wavenumber(period_s, depth_m, gravity_m_s2).map_err(|e| e.to_string())?;
    let first = depth_m;
    let spacing = (0.25 * 2.0 * PI / k).min(flat_m - 2.0 * depth_m);
    if !(spacing > 0.0 && (k * spacing).sin() >= MIN_GAUGE_SINE) {
        let need = (MIN_GAUGE_SINE.asin() / k) + 2.0 * depth_m;
        return Err(format!(
            "the flat bed in front of the paddle is {flat_m:.2} m long; its two gauges, one depth \
             ({depth_m:.2} m) from the paddle and from the slope, need {need:.2} m at T = {period_s} s"
        ));
    }
    Ok([first, first + spacing])
}

/// Length of flat bed from `x0_m` towards `x_end_m` (where the bed first differs by more than a
/// micrometre from its height at `x0_m`, sampled every millimetre), m.
pub fn flat_length_m(x0_m: f64, x_end_m: f64, bed_y: impl Fn(f64) -> f64) -> f64 {
    let y0 = bed_y(x0_m);
    let n = ((x_end_m - x0_m) / 1e-3).floor().max(0.0) as usize;
    (1..=n)
        .map(|i| x0_m + i as f64 * 1e-3)
        .find(|&x| (bed_y(x) - y0).abs() > 1e-6)
        .map_or(x_end_m - x0_m, |x| x - 1e-3 - x0_m)
}

/// The sliding two-gauge absorber's state.
#[derive(Debug, Clone)]
pub struct ReflectionAbsorber {
    omega_rad_s: f64,
    wavenumber_per_m: f64,
    /// F = H/S of the paddle at kh.
    transfer: f64,
    gauges_m: [f64; 2],
    period_s: f64,
    /// Absorbing starts at `start_s` and comes in over one period.
    start_s: f64,
    /// (t, η₁, η₂) over the last period, m.
    samples: VecDeque<(f64, f64, f64)>,
    /// The arriving wave at the face, and the wave going out, from the last full window, m
    /// (complex amplitudes).
    arriving: Complex<f64>,
    outgoing: Complex<f64>,
    /// |X̂| stays within this, m (the room the case's check left for it).
    limit_m: f64,
}

impl ReflectionAbsorber {
    /// An absorber for a `kind` paddle making waves of `period_s` in `depth_m`, reading gauges
    /// `gauges_m` in front of its face at rest, starting at `start_s` (after the start-up ramp:
    /// the split assumes a steady wave) and never moving more than `limit_m` at the still-water
    /// level.
    pub fn new(
        kind: PaddleKind,
        period_s: f64,
        depth_m: f64,
        gravity_m_s2: f64,
        gauges_m: [f64; 2],
        start_s: f64,
        limit_m: f64,
    ) -> Result<Self> {
        let k = linear::wavenumber(period_s, depth_m, gravity_m_s2)?;
        let transfer = match kind {
            PaddleKind::Piston => linear::piston_height_to_stroke(k * depth_m),
            PaddleKind::Flap => linear::flap_height_to_stroke(k * depth_m),
        };
        Ok(Self {
            omega_rad_s: 2.0 * PI / period_s,
            wavenumber_per_m: k,
            transfer,
            gauges_m,
            period_s,
            start_s,
            samples: VecDeque::new(),
            arriving: Complex::new(0.0, 0.0),
            outgoing: Complex::new(0.0, 0.0),
            limit_m,
        })
    }

    /// The gauges' positions, m in front of the face at rest.
    pub fn gauges_m(&self) -> [f64; 2] {
        self.gauges_m
    }

    /// The arriving wave's amplitude at the face from the last full window, m.
    pub fn arriving_amplitude_m(&self) -> f64 {
        self.arriving.norm()
    }

    /// The outgoing wave's amplitude from the last full window, m.
    pub fn outgoing_amplitude_m(&self) -> f64 {
        self.outgoing.norm()
    }

    /// The absorbing displacement at the still-water level at `t_s`, m.
    pub fn offset_at(&self, t_s: f64) -> f64 {
        let ramp = half_cosine_ramp(t_s - self.start_s, self.period_s);
        if ramp == 0.0 {
            return 0.0;
        }
        let mut amplitude = Complex::new(0.0, -1.0) * self.arriving / self.transfer;
        if amplitude.norm() > self.limit_m {
            amplitude *= self.limit_m / amplitude.norm();
        }
        ramp * (amplitude * Complex::from_polar(1.0, -self.omega_rad_s * t_s)).re
    }

    /// Before a step from `t_s`: η at the two gauges then (m above still water; `None` when
    /// either was dry, which skips the sample). Updates the arriving wave once a full period
    /// has been read.
    pub fn update(&mut self, t_s: f64, eta_m: Option<[f64; 2]>) {
        let Some([a, b]) = eta_m else { return };
        self.samples.push_back((t_s, a, b));
        while self
            .samples
            .get(1)
            .is_some_and(|s| s.0 <= t_s - self.period_s)
        {
            self.samples.pop_front();
        }
        let span = t_s - self.samples[0].0;
        if span < self.period_s - 1e-9 {
            return;
        }
        // First harmonic over [t − T, t], trapezoidal, the first interval cut at t − T:
        // Z = (2/T) ∫ η e^{iωt} dt.
        let from = t_s - self.period_s;
        let w = self.omega_rad_s;
        let mut z = [Complex::new(0.0, 0.0); 2];
        for (p, q) in self.samples.iter().zip(self.samples.iter().skip(1)) {
            let (t0, a0, b0) = if p.0 < from {
                let f = (from - p.0) / (q.0 - p.0);
                (from, p.1 + f * (q.1 - p.1), p.2 + f * (q.2 - p.2))
            } else {
                *p
            };
            let (e0, e1) = (
                Complex::from_polar(1.0, w * t0),
                Complex::from_polar(1.0, w * q.0),
            );
            let half_dt = 0.5 * (q.0 - t0);
            z[0] += (e0 * a0 + e1 * q.1) * half_dt;
            z[1] += (e0 * b0 + e1 * q.2) * half_dt;
        }
        let scale = 2.0 / self.period_s;
        let (z1, z2) = (z[0] * scale, z[1] * scale);
        // Z₁ e^{ikx₂} − Z₂ e^{ikx₁} = 2i sin(kΔx) Q and Z₂ e^{−ikx₁} − Z₁ e^{−ikx₂} =
        // 2i sin(kΔx) P.
        let k = self.wavenumber_per_m;
        let [x1, x2] = self.gauges_m;
        let e = |x: f64| Complex::from_polar(1.0, k * x);
        let denominator = Complex::new(0.0, 2.0 * (k * (x2 - x1)).sin());
        self.arriving = (z1 * e(x2) - z2 * e(x1)) / denominator;
        self.outgoing = (z2 * e(-x1) - z1 * e(-x2)) / denominator;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flap in d = 0.7 m at T = 2.5 s: gauges fed an incident wave of 5 cm and a reflected
    /// one of 2 cm arriving with a phase, plus a mean, a second harmonic and a set-down: the
    /// split finds the reflected wave, and the displacement radiates its opposite.
    #[test]
    fn the_arriving_wave_is_found_and_answered() {
        let (period, depth, g) = (2.5, 0.7, 9.81);
        let flat = 3.0;
        let gauges = gauge_offsets_m(period, depth, g, flat).unwrap();
        let k = linear::wavenumber(period, depth, g).unwrap();
        let w = 2.0 * PI / period;
        println!(
            "gauges at {:.3}, {:.3} m; kΔx = {:.3}",
            gauges[0],
            gauges[1],
            k * (gauges[1] - gauges[0])
        );
        let mut a =
            ReflectionAbsorber::new(PaddleKind::Flap, period, depth, g, gauges, 5.0, 1.0).unwrap();
        let (incident, reflected, phase) = (0.05, 0.02, 0.7);
        let eta = |x: f64, t: f64| {
            incident * (k * x - w * t).cos()
                + reflected * (-k * x - w * t + phase).cos()
                + 0.01 * (2.0 * (k * x - w * t)).cos()
                - 0.003
        };
        let dt = 0.004;
        let mut t = 0.0;
        while t < 12.0 {
            a.update(t, Some([eta(gauges[0], t), eta(gauges[1], t)]));
            t += dt;
        }
        let q = a.arriving;
        println!(
            "arriving wave: {:.5} m at {:.4} rad (fed {reflected} m at {phase} rad)",
            q.norm(),
            q.arg()
        );
        assert!((q.norm() - reflected).abs() < 2e-4, "{q}");
        assert!((q.arg() - phase).abs() < 1e-2, "{q}");
        assert!((a.outgoing_amplitude_m() - incident).abs() < 2e-4);
        // The wave the absorbing motion radiates at the face, F (U/ω)-wise: −Re(Q e^{−iωt}).
        let f = linear::flap_height_to_stroke(k * depth);
        for t in [12.0, 12.3, 13.1] {
            let h = 1e-5;
            let u = (a.offset_at(t + h) - a.offset_at(t - h)) / (2.0 * h);
            let radiated = f * u / w;
            let arriving = (q * Complex::from_polar(1.0, -w * t)).re;
            assert!(
                (radiated + arriving).abs() < 1e-6,
                "{radiated} vs {arriving}"
            );
        }
        // Before the start and its ramp: still.
        assert_eq!(a.offset_at(4.9), 0.0);
    }

    #[test]
    fn a_short_flat_bed_is_refused_with_the_length_it_needs() {
        let e = gauge_offsets_m(4.0, 0.7, 9.81, 1.5).unwrap_err();
        println!("{e}");
        assert!(e.contains("1.50 m long"), "{e}");
        let ok = gauge_offsets_m(4.0, 0.7, 9.81, 3.0).unwrap();
        assert!(
            (ok[0] - 0.7).abs() < 1e-12 && (ok[1] - 2.3).abs() < 1e-12,
            "{ok:?}"
        );
    }
}
