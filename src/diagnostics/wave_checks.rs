//! Wavemaker validation (issue 3): what a flume's gauge and probe records say about the waves
//! it made, against linear or cnoidal theory. Pure functions of the records; reading
//! `gauges.csv` and printing the verdicts is the binary's job.

use crate::case::{Case, WaveTheory};
use crate::waves::cnoidal::CnoidalWave;
use crate::waves::linear::{self, PaddleKind};
use serde::Serialize;
use std::f64::consts::{PI, TAU};

/// Time series of a run's gauges and probes: `columns[j][i]` is column `j` at `t_s[i]`
/// (`None` where the gauge was dry). Column names as in `gauges.csv`.
#[derive(Debug, Clone, Default)]
pub struct GaugeRecord {
    pub t_s: Vec<f64>,
    pub names: Vec<String>,
    pub columns: Vec<Vec<Option<f64>>>,
}

impl GaugeRecord {
    /// The elevation gauges, `(x, column)`, in the order of the record.
    pub fn elevation_gauges(&self) -> Vec<(f64, &[Option<f64>])> {
        self.names
            .iter()
            .zip(&self.columns)
            .filter_map(|(n, c)| {
                let x = n.strip_prefix("eta_")?.parse().ok()?;
                Some((x, c.as_slice()))
            })
            .collect()
    }

    /// The horizontal-velocity probes, `(x, y, column)`.
    pub fn u_probes(&self) -> Vec<(f64, f64, &[Option<f64>])> {
        self.names
            .iter()
            .zip(&self.columns)
            .filter_map(|(n, c)| {
                let mut parts = n.strip_prefix("u_")?.split('_');
                let x = parts.next()?.parse().ok()?;
                let y = parts.next()?.parse().ok()?;
                Some((x, y, c.as_slice()))
            })
            .collect()
    }
}

/// One verdict: a measured figure against its target and tolerance.
#[derive(Debug, Clone, Serialize)]
pub struct Check {
    pub what: String,
    pub measured: f64,
    pub target: f64,
    /// Allowed |measured/target − 1|; `None` when the bar is an upper bound, measured < target.
    pub relative_tolerance: Option<f64>,
    pub unit: String,
    pub passed: bool,
}

impl Check {
    fn new(what: impl Into<String>, measured: f64, target: f64, tol: f64, unit: &str) -> Self {
        let error = (measured / target - 1.0).abs();
        Self {
            what: what.into(),
            measured,
            target,
            relative_tolerance: Some(tol),
            unit: unit.into(),
            passed: error.is_finite() && error <= tol,
        }
    }

    fn below(what: impl Into<String>, measured: f64, limit: f64, unit: &str) -> Self {
        Self {
            what: what.into(),
            measured,
            target: limit,
            relative_tolerance: None,
            unit: unit.into(),
            passed: measured < limit,
        }
    }

    /// The bar in words: `±5 %` or `< 0.005`.
    pub fn bar(&self) -> String {
        match self.relative_tolerance {
            Some(tol) => format!("{:.4} {} ± {} %", self.target, self.unit, 100.0 * tol),
            None => format!("< {} {}", self.target, self.unit),
        }
    }

    /// Signed relative error, measured/target − 1.
    pub fn error(&self) -> f64 {
        self.measured / self.target - 1.0
    }
}

/// A figure reported without a bar.
#[derive(Debug, Clone, Serialize)]
pub struct Figure {
    pub what: String,
    pub value: f64,
    pub unit: String,
}

/// What a validation found: verdicts, reported figures, and the averaging window.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub kind: String,
    pub window_s: [f64; 2],
    pub checks: Vec<Check>,
    pub figures: Vec<Figure>,
}

impl Report {
    fn new(kind: &str, window_s: [f64; 2]) -> Report {
        Report {
            kind: kind.into(),
            window_s,
            checks: Vec::new(),
            figures: Vec::new(),
        }
    }

    pub fn passed(&self) -> bool {
        !self.checks.is_empty() && self.checks.iter().all(|c| c.passed)
    }

    fn figure(&mut self, what: impl Into<String>, value: f64, unit: &str) {
        self.figures.push(Figure {
            what: what.into(),
            value,
            unit: unit.into(),
        });
    }
}

#[derive(Debug, thiserror::Error)]
pub enum CheckError {
    #[error("{0}")]
    NotApplicable(String),
    #[error("the record is too short: {0}")]
    TooShort(String),
    #[error(transparent)]
    Theory(#[from] crate::waves::WaveError),
}

/// Least-squares fit of `c + a cos ωt + b sin ωt` to the wet samples with t in `window`.
/// Returns `(mean, amplitude, phase)` with the signal ≈ mean + amplitude·cos(ωt − phase),
/// or `None` with fewer than 8 samples.
pub fn harmonic_fit(
    t_s: &[f64],
    y: &[Option<f64>],
    omega_rad_s: f64,
    window_s: [f64; 2],
) -> Option<(f64, f64, f64)> {
    let mut m = nalgebra::Matrix3::<f64>::zeros();
    let mut r = nalgebra::Vector3::<f64>::zeros();
    let mut n = 0usize;
    for (t, v) in t_s.iter().zip(y) {
        let Some(v) = v else { continue };
        if *t < window_s[0] || *t > window_s[1] {
            continue;
        }
        let basis = nalgebra::Vector3::new(1.0, (omega_rad_s * t).cos(), (omega_rad_s * t).sin());
        m += basis * basis.transpose();
        r += basis * *v;
        n += 1;
    }
    if n < 8 {
        return None;
    }
    let c = m.lu().solve(&r)?;
    Some((c[0], c[1].hypot(c[2]), c[2].atan2(c[1])))
}

/// Zero-crossing heights and the mean period over `window` (at most `last_waves` waves).
fn crossing_stats(
    t_s: &[f64],
    eta: &[Option<f64>],
    window_s: [f64; 2],
) -> Option<super::WaveStats> {
    let (t, e): (Vec<f64>, Vec<Option<f64>>) = t_s
        .iter()
        .zip(eta)
        .filter(|(t, _)| **t <= window_s[1])
        .map(|(t, e)| (*t, *e))
        .unzip();
    super::wave_stats(&t, &e, window_s[0], 10_000)
}

/// Mean of the column at the times of the crests of `eta` within `window` (each crest the
/// highest wet sample between two up-crossings of the mean level).
fn mean_at_crests(
    t_s: &[f64],
    eta: &[Option<f64>],
    column: &[Option<f64>],
    window_s: [f64; 2],
) -> Option<f64> {
    let idx: Vec<usize> = (0..t_s.len())
        .filter(|&i| t_s[i] >= window_s[0] && t_s[i] <= window_s[1] && eta[i].is_some())
        .collect();
    if idx.len() < 3 {
        return None;
    }
    let mean = idx.iter().map(|&i| eta[i].unwrap_or(0.0)).sum::<f64>() / idx.len() as f64;
    let ups: Vec<usize> = idx
        .windows(2)
        .filter(|w| eta[w[0]].unwrap_or(0.0) < mean && eta[w[1]].unwrap_or(0.0) >= mean)
        .map(|w| w[1])
        .collect();
    let mut values = Vec::new();
    for w in ups.windows(2) {
        let crest = idx
            .iter()
            .copied()
            .filter(|&i| i >= w[0] && i < w[1])
            .max_by(|&a, &b| eta[a].unwrap_or(0.0).total_cmp(&eta[b].unwrap_or(0.0)))?;
        if let Some(v) = column[crest] {
            values.push(v);
        }
    }
    (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
}

/// Least-squares line through `(x, y)`: `(slope, intercept)`.
fn line_fit(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let slope = sxy / sxx;
    (slope, my - slope * mx)
}

/// Unwraps phases measured at increasing x so that each step is the one nearest `k Δx`
/// (the choice of the multiple of 2π only; the fit then measures k).
fn unwrap_phases(points: &[(f64, f64)], k_guess: f64) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(points.len());
    for &(x, p) in points {
        let q = match out.last() {
            None => p,
            Some(&(x0, p0)) => {
                let expected = p0 + k_guess * (x - x0);
                p + TAU * ((expected - p) / TAU).round()
            }
        };
        out.push((x, q));
    }
    out
}

/// The last `periods` whole periods of the record.
fn last_periods(record: &GaugeRecord, period_s: f64, periods: f64) -> Result<[f64; 2], CheckError> {
    let end = record.t_s.last().copied().unwrap_or(0.0);
    let start = end - periods * period_s;
    if start <= 0.0 {
        return Err(CheckError::TooShort(format!(
            "{periods} periods of {period_s} s need more than the {end:.2} s recorded"
        )));
    }
    Ok([start, end])
}

fn linear_wave(case: &Case) -> Result<(f64, f64, f64, f64, f64), CheckError> {
    let w = case
        .wavemaker
        .as_ref()
        .ok_or_else(|| CheckError::NotApplicable("the case has no wavemaker".into()))?;
    if w.theory != WaveTheory::Linear {
        return Err(CheckError::NotApplicable(
            "this check is for a linear-theory paddle".into(),
        ));
    }
    let depth = case
        .water
        .first()
        .map(|r| r.depth_m)
        .ok_or_else(|| CheckError::NotApplicable("the case has no water".into()))?;
    let g = case.fluid.gravity_m_s2;
    let k = linear::wavenumber(w.period_s, depth, g)?;
    Ok((w.height_m, w.period_s, depth, k, w.x_m))
}

/// Progressive waves from a linear paddle into an absorbing end (thesis §3.2): height at every
/// gauge within `reach_wavelengths` of the paddle, wavelength from the phase of the fundamental
/// along those gauges, the first-harmonic u(z) of the probes against linear theory, the height
/// decay per wavelength, and the volume drift over the run.
pub fn progressive(
    case: &Case,
    record: &GaugeRecord,
    volume_drift_max: f64,
    simulated_s: f64,
) -> Result<Report, CheckError> {
    let (height, period, depth, k, x_paddle) = linear_wave(case)?;
    if simulated_s / period < 20.0 - 1e-6 {
        return Err(CheckError::TooShort(format!(
            "the volume bar is over 20 periods; the run covers {:.1}",
            simulated_s / period
        )));
    }
    let omega = TAU / period;
    let wavelength = TAU / k;
    let reach = 4.0;
    let window = last_periods(record, period, 5.0)?;
    let mut report = Report::new("progressive waves (flap or piston, linear theory)", window);
    report.figure("linear wavelength L", wavelength, "m");
    report.figure("kh", k * depth, "");
    let gauges: Vec<(f64, &[Option<f64>])> = record
        .elevation_gauges()
        .into_iter()
        .filter(|(x, _)| *x - x_paddle <= reach * wavelength + 1e-9)
        .collect();
    if gauges.len() < 3 {
        return Err(CheckError::NotApplicable(format!(
            "need three elevation gauges within {reach} wavelengths ({:.2} m) of the paddle",
            reach * wavelength
        )));
    }
    // Heights (zero-crossing, the whole waves of the window) and phases.
    let mut phases = Vec::new();
    let mut log_heights = Vec::new();
    for (x, eta) in &gauges {
        let stats = crossing_stats(&record.t_s, eta, window)
            .ok_or_else(|| CheckError::TooShort(format!("no whole wave at x = {x} m")))?;
        report.checks.push(Check::new(
            format!(
                "wave height at x = {x:.3} m ({:.2} L)",
                (x - x_paddle) / wavelength
            ),
            stats.mean_height_m,
            height,
            0.05,
            "m",
        ));
        log_heights.push(((x - x_paddle) / wavelength, stats.mean_height_m.ln()));
        let (_, _, phase) = harmonic_fit(&record.t_s, eta, omega, window)
            .ok_or_else(|| CheckError::TooShort(format!("gauge at x = {x} m")))?;
        phases.push((*x, phase));
    }
    let (k_measured, _) = line_fit(&unwrap_phases(&phases, k));
    report.checks.push(Check::new(
        "wavelength from the phase along the gauges",
        TAU / k_measured,
        wavelength,
        0.03,
        "m",
    ));
    let (decay, _) = line_fit(&log_heights);
    report.figure(
        "height change per wavelength (fit of ln H over the gauges)",
        100.0 * (decay.exp() - 1.0),
        "%",
    );
    // Probes: first harmonic of u against a σ cosh(k y)/sinh(k d), y above the bed; and the
    // value under the crests of the gauge at the probes' x.
    let probes = record.u_probes();
    if !probes.is_empty() {
        let x_probe = probes[0].0;
        let eta = record
            .elevation_gauges()
            .into_iter()
            .find(|(x, _)| (x - x_probe).abs() < 1e-6)
            .map(|(_, e)| e);
        let a_local = eta
            .and_then(|e| harmonic_fit(&record.t_s, e, omega, window))
            .map(|f| f.1);
        let mut worst: Option<Check> = None;
        for (x, y, u) in &probes {
            let Some((mean, amplitude, _)) = harmonic_fit(&record.t_s, u, omega, window) else {
                continue;
            };
            let theory = 0.5 * height * omega * (k * y).cosh() / (k * depth).sinh();
            let c = Check::new(
                format!("u1 amplitude at x = {x:.3} m, {y:.2} m above the bed"),
                amplitude,
                theory,
                0.10,
                "m/s",
            );
            report.figure(
                format!("u1 amplitude/theory at y = {y:.2} m"),
                c.measured / c.target,
                "",
            );
            report.figure(format!("mean u1 at y = {y:.2} m"), mean, "m/s");
            if let Some(crest) = eta.and_then(|e| mean_at_crests(&record.t_s, e, u, window)) {
                report.figure(format!("u1 under the crests at y = {y:.2} m"), crest, "m/s");
                report.figure(
                    format!("(u1 under the crests − mean u1)/theory at y = {y:.2} m"),
                    (crest - mean) / theory,
                    "",
                );
            }
            if worst
                .as_ref()
                .is_none_or(|w| c.error().abs() > w.error().abs())
            {
                worst = Some(c);
            }
        }
        // Linear waves carry g H²/(8c) m²/s onshore (Stokes drift); in a closed flume a
        // uniform current returns it, which the mean u1 of the probes should show.
        let celerity = omega / k;
        report.figure(
            "return current −g H²/(8 c d) of linear theory",
            -case.fluid.gravity_m_s2 * height * height / (8.0 * celerity * depth),
            "m/s",
        );
        if let Some(mut w) = worst {
            w.what = format!("u1(z) under a crest, worst probe: {}", w.what);
            report.checks.push(w);
        }
        if let Some(a) = a_local {
            report.figure(
                "first-harmonic height 2a at the probes' gauge",
                2.0 * a,
                "m",
            );
        }
    }
    report.figure("simulated", simulated_s, "s");
    report.figure("periods simulated", simulated_s / period, "");
    report.checks.push(Check::below(
        "volume drift max |V/V0 - 1| over the run",
        volume_drift_max,
        0.005,
        "",
    ));
    Ok(report)
}

/// A standing wave in front of a vertical wall (thesis §3.2.1), by the least-squares
/// separation of incident and reflected waves (Mansard & Funke 1980) with the wavenumber free:
/// the first harmonic Z(x) of every gauge over the last three periods is fitted by
/// P e^{ik'(x − x_w)} + Q e^{−ik'(x − x_w)}. Antinode height 2(|P| + |Q|) against 2H,
/// node–antinode spacing π/(2k') against L/4; the node height, the reflection coefficient
/// |Q|/|P| and where the antinode nearest the wall lies are reported. Three periods: the
/// reflected wave at full height reaches the farthest gauge only a few periods before the
/// case's end.
pub fn standing(case: &Case, record: &GaugeRecord) -> Result<Report, CheckError> {
    let (height, period, _depth, k, _) = linear_wave(case)?;
    if case.absorber.is_some() || case.flume.beach.is_some() {
        return Err(CheckError::NotApplicable(
            "this check is for a flume that ends in a vertical wall".into(),
        ));
    }
    let omega = TAU / period;
    let wavelength = TAU / k;
    let x_wall = case.flume.length_m;
    let window = last_periods(record, period, 3.0)?;
    let mut report = Report::new("standing wave at a vertical wall (linear theory)", window);
    report.figure("linear wavelength L", wavelength, "m");
    // (x, Re Z, Im Z) with the signal ≈ Re{Z e^{−iωt}}.
    let mut points = Vec::new();
    for (x, eta) in record.elevation_gauges() {
        let (_, a, phase) = harmonic_fit(&record.t_s, eta, omega, window)
            .ok_or_else(|| CheckError::TooShort(format!("gauge at x = {x} m")))?;
        report.figure(
            format!("first-harmonic height at x = {x:.3} m"),
            2.0 * a,
            "m",
        );
        points.push((x, a * phase.cos(), a * phase.sin()));
    }
    if points.len() < 4 {
        return Err(CheckError::NotApplicable(
            "need at least four elevation gauges".into(),
        ));
    }
    // For a given k': the best P, Q ([Re P, Im P, Re Q, Im Q]) and the squared residual.
    let fit = |kk: f64| -> Option<(f64, nalgebra::Vector4<f64>)> {
        let mut m = nalgebra::Matrix4::<f64>::zeros();
        let mut r = nalgebra::Vector4::<f64>::zeros();
        let rows = |x: f64| {
            let (sn, cs) = (kk * (x - x_wall)).sin_cos();
            (
                nalgebra::Vector4::new(cs, -sn, cs, sn),
                nalgebra::Vector4::new(sn, cs, -sn, cs),
            )
        };
        for &(x, zr, zi) in &points {
            let (re, im) = rows(x);
            m += re * re.transpose() + im * im.transpose();
            r += re * zr + im * zi;
        }
        let c = m.lu().solve(&r)?;
        let res = points
            .iter()
            .map(|&(x, zr, zi)| {
                let (re, im) = rows(x);
                (re.dot(&c) - zr).powi(2) + (im.dot(&c) - zi).powi(2)
            })
            .sum();
        Some((res, c))
    };
    // Scan k' over ±40 % of the linear k, then refine by golden section.
    let (mut lo, mut hi) = (0.6 * k, 1.4 * k);
    let n = 400;
    let best = (0..=n)
        .map(|i| lo + (hi - lo) * i as f64 / n as f64)
        .filter_map(|kk| fit(kk).map(|(r, _)| (kk, r)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .ok_or_else(|| CheckError::TooShort("the fit failed".into()))?;
    let step = (hi - lo) / n as f64;
    (lo, hi) = (best.0 - step, best.0 + step);
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let a = hi - ratio * (hi - lo);
        let b = lo + ratio * (hi - lo);
        let fa = fit(a).map_or(f64::INFINITY, |f| f.0);
        let fb = fit(b).map_or(f64::INFINITY, |f| f.0);
        if fa < fb {
            hi = b;
        } else {
            lo = a;
        }
    }
    let k_fit = 0.5 * (lo + hi);
    let (residual, c) = fit(k_fit).ok_or_else(|| CheckError::TooShort("the fit failed".into()))?;
    let incident = c[0].hypot(c[1]);
    let reflected = c[2].hypot(c[3]);
    // |Z|² = |P|² + |Q|² + 2 Re(P Q̄ e^{2ik'(x − x_w)}): antinodes where 2k'(x_w − x) = arg(P Q̄).
    let arg = (c[1] * c[2] - c[0] * c[3]).atan2(c[0] * c[2] + c[1] * c[3]);
    let mut distance = arg.rem_euclid(TAU) / (2.0 * k_fit);
    if distance > PI / (2.0 * k_fit) {
        distance -= PI / k_fit;
    }
    report.checks.push(Check::new(
        "antinode height 2(|P| + |Q|)",
        2.0 * (incident + reflected),
        2.0 * height,
        0.10,
        "m",
    ));
    if let Some(&(x, zr, zi)) = points.iter().max_by(|a, b| a.0.total_cmp(&b.0)) {
        report.checks.push(Check::new(
            format!("first-harmonic height at the gauge nearest the wall, x = {x:.3} m"),
            2.0 * zr.hypot(zi),
            2.0 * height,
            0.10,
            "m",
        ));
    }
    report.checks.push(Check::new(
        "node-to-antinode spacing π/(2k')",
        PI / (2.0 * k_fit),
        wavelength / 4.0,
        0.05,
        "m",
    ));
    report.figure("incident height 2|P|", 2.0 * incident, "m");
    report.figure("reflected height 2|Q|", 2.0 * reflected, "m");
    report.figure("reflection coefficient |Q|/|P|", reflected / incident, "");
    report.figure(
        "node height 2||P| − |Q||",
        2.0 * (incident - reflected).abs(),
        "m",
    );
    report.figure(
        "antinode nearest the wall: distance from the wall",
        distance,
        "m",
    );
    let norm: f64 = points.iter().map(|p| p.1 * p.1 + p.2 * p.2).sum();
    report.figure("fit residual / signal (rms)", (residual / norm).sqrt(), "");
    Ok(report)
}

/// A cnoidal piston (Goring/Zhang): at the gauge two wavelengths out, the zero-crossing height
/// against H and the period against T; the crest elevation against cnoidal theory's η_c.
pub fn cnoidal(case: &Case, record: &GaugeRecord) -> Result<Report, CheckError> {
    let w = case
        .wavemaker
        .as_ref()
        .filter(|w| w.theory == WaveTheory::Cnoidal && w.paddle == PaddleKind::Piston)
        .ok_or_else(|| CheckError::NotApplicable("this check is for a cnoidal piston".into()))?;
    let depth = case
        .water
        .first()
        .map(|r| r.depth_m)
        .ok_or_else(|| CheckError::NotApplicable("the case has no water".into()))?;
    let wave = CnoidalWave::new(w.height_m, w.period_s, depth, case.fluid.gravity_m_s2)?;
    let window = last_periods(record, w.period_s, 5.0)?;
    let mut report = Report::new("cnoidal piston", window);
    report.figure("cnoidal wavelength L", wave.wavelength_m, "m");
    report.figure("Ursell number", wave.ursell_number(), "");
    let target_x = w.x_m + 2.0 * wave.wavelength_m;
    let (x, eta) = record
        .elevation_gauges()
        .into_iter()
        .min_by(|a, b| (a.0 - target_x).abs().total_cmp(&(b.0 - target_x).abs()))
        .filter(|(x, _)| (x - target_x).abs() <= 0.25 * wave.wavelength_m)
        .ok_or_else(|| {
            CheckError::NotApplicable(format!(
                "no elevation gauge within L/4 of two wavelengths out (x = {target_x:.2} m)"
            ))
        })?;
    let stats = crossing_stats(&record.t_s, eta, window)
        .ok_or_else(|| CheckError::TooShort(format!("no whole wave at x = {x} m")))?;
    report.checks.push(Check::new(
        format!(
            "wave height at x = {x:.3} m ({:.2} L)",
            (x - w.x_m) / wave.wavelength_m
        ),
        stats.mean_height_m,
        w.height_m,
        0.05,
        "m",
    ));
    // The period: the output interval resolves an up-crossing to a fraction of a sample; 1 %
    // of 2 s is one output interval of the case.
    report.checks.push(Check::new(
        format!("wave period at x = {x:.3} m"),
        stats.mean_period_s,
        w.period_s,
        0.01,
        "s",
    ));
    // Crests: mean of the highest wet sample of each wave, measured from the still water.
    let crest = mean_crest(&record.t_s, eta, window);
    if let Some(c) = crest {
        report.figure("mean crest elevation above still water", c, "m");
    }
    report.figure("cnoidal theory's crest elevation η_c", wave.crest_m(), "m");
    if let Some(c) = crest {
        report.figure("crest / η_c", c / wave.crest_m(), "");
        // η_c is measured from the wave's mean level; a flume that lost water has its mean
        // level below the still water it started from.
        report.figure("mean level over the window", stats.mean_level_m, "m");
        report.figure(
            "crest above the mean level / η_c",
            (c - stats.mean_level_m) / wave.crest_m(),
            "",
        );
    }
    Ok(report)
}

/// Mean of the highest wet sample between successive up-crossings of the window's mean level.
fn mean_crest(t_s: &[f64], eta: &[Option<f64>], window_s: [f64; 2]) -> Option<f64> {
    mean_at_crests(t_s, eta, eta, window_s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(t: &[f64], cols: Vec<(String, Vec<Option<f64>>)>) -> GaugeRecord {
        GaugeRecord {
            t_s: t.to_vec(),
            names: cols.iter().map(|c| c.0.clone()).collect(),
            columns: cols.into_iter().map(|c| c.1).collect(),
        }
    }

    #[test]
    fn harmonic_fit_recovers_amplitude_and_phase() {
        let t: Vec<f64> = (0..4000).map(|i| i as f64 * 0.01).collect();
        let y: Vec<Option<f64>> = t
            .iter()
            .map(|t| Some(0.2 + 0.03 * (2.0 * t - 0.7).cos() + 0.005 * (4.0 * t).sin()))
            .collect();
        let (m, a, p) = harmonic_fit(&t, &y, 2.0, [0.0, 10.0 * PI]).unwrap();
        assert!((m - 0.2).abs() < 1e-4 && (a - 0.03).abs() < 1e-4 && (p - 0.7).abs() < 1e-3);
    }

    /// A linear progressive wave, sampled like the flap case's gauges and probes, passes;
    /// the same with a wavelength 5 % long fails the wavelength check only.
    #[test]
    fn progressive_checks_on_a_synthetic_wave() {
        let case = Case::load(std::path::Path::new("cases/flap_deep_water.toml"), &[]).unwrap();
        let (h, period, d, k, xp) = linear_wave(&case).unwrap();
        let omega = TAU / period;
        let t: Vec<f64> = (0..4000).map(|i| i as f64 * 0.0455).collect();
        let make = |kk: f64| {
            let mut cols = Vec::new();
            for &x in &case.output.gauges_x_m {
                let c = t
                    .iter()
                    .map(|t| Some(0.5 * h * (kk * (x - xp) - omega * t).cos()))
                    .collect();
                cols.push((format!("eta_{x:.3}"), c));
            }
            for p in &case.output.probes_m {
                let c = t
                    .iter()
                    .map(|t| {
                        let amp = 0.5 * h * omega * (k * p[1]).cosh() / (k * d).sinh();
                        Some(amp * (kk * (p[0] - xp) - omega * t).cos())
                    })
                    .collect();
                cols.push((format!("u_{:.3}_{:.3}", p[0], p[1]), c));
            }
            record(&t, cols)
        };
        let good = progressive(&case, &make(k), 0.001, 182.0).unwrap();
        for c in &good.checks {
            assert!(c.passed, "{c:?}");
        }
        let long = progressive(&case, &make(k / 1.05), 0.001, 182.0).unwrap();
        let failed: Vec<&Check> = long.checks.iter().filter(|c| !c.passed).collect();
        assert_eq!(failed.len(), 1, "{failed:?}");
        assert!(failed[0].what.starts_with("wavelength"));
        assert!(
            (failed[0].error() - 0.05).abs() < 1e-3,
            "{}",
            failed[0].error()
        );
    }

    /// A standing wave with reflection coefficient 0.9 and the linear k: antinode 1.9 H,
    /// spacing L/4, first antinode at the wall.
    #[test]
    fn standing_checks_on_a_synthetic_wave() {
        let case = Case::load(std::path::Path::new("cases/wall_reflection.toml"), &[]).unwrap();
        let (h, period, _d, k, _) = linear_wave(&case).unwrap();
        let omega = TAU / period;
        let xw = case.flume.length_m;
        let t: Vec<f64> = (0..400).map(|i| i as f64 * 0.0475).collect();
        let cols = case
            .output
            .gauges_x_m
            .iter()
            .map(|&x| {
                let c = t
                    .iter()
                    .map(|t| {
                        let s = k * (xw - x);
                        Some(0.5 * h * ((-s - omega * t).cos() + 0.9 * (s - omega * t).cos()))
                    })
                    .collect();
                (format!("eta_{x:.3}"), c)
            })
            .collect();
        let r = standing(&case, &record(&t, cols)).unwrap();
        println!("{r:#?}");
        let antinode = &r.checks[0];
        assert!((antinode.measured - 1.9 * h).abs() < 1e-6, "{antinode:?}");
        let spacing = &r.checks[2];
        assert!(spacing.error().abs() < 1e-6, "{spacing:?}");
        let ratio = r
            .figures
            .iter()
            .find(|f| f.what.starts_with("reflection"))
            .unwrap();
        assert!((ratio.value - 0.9).abs() < 1e-6, "{ratio:?}");
        let at = r
            .figures
            .iter()
            .find(|f| f.what.starts_with("antinode nearest"))
            .unwrap();
        assert!(at.value.abs() < 1e-6, "{at:?}");
    }

    /// A cnoidal record from theory at the case's gauges: height, period and crest all agree.
    #[test]
    fn cnoidal_checks_on_a_theoretical_wave() {
        let case = Case::load(std::path::Path::new("cases/piston_cnoidal.toml"), &[]).unwrap();
        let w = case.wavemaker.as_ref().unwrap();
        let wave = CnoidalWave::new(w.height_m, w.period_s, 0.4, 9.81).unwrap();
        let t: Vec<f64> = (0..1200).map(|i| i as f64 * 0.02).collect();
        let cols = case
            .output
            .gauges_x_m
            .iter()
            .map(|&x| {
                let c = t.iter().map(|&t| Some(wave.eta_m(x - w.x_m, t))).collect();
                (format!("eta_{x:.3}"), c)
            })
            .collect();
        let r = cnoidal(&case, &record(&t, cols)).unwrap();
        println!("{r:#?}");
        assert!(r.passed());
        assert!(r.checks[0].error().abs() < 0.005, "{:?}", r.checks[0]);
        let crest = r.figures.iter().find(|f| f.what == "crest / η_c").unwrap();
        assert!((crest.value - 1.0).abs() < 0.01, "{crest:?}");
    }
}
