//! `timeseries.csv`: one row per output time, flushed as it is written so that a run that
//! stops early leaves a readable file. The last three columns are the volume budget since
//! t = 0 (m², signed): area changed by remeshing, by the motion of the nodes, and put back by
//! the volume recovery; with the initial volume they add up to `volume_m2`.

use crate::diagnostics::Integrals;
use crate::validation::DamBreakSeries;
use std::io::Write;
use std::path::Path;

pub const HEADER: &str = "t_s,volume_m2,volume_ratio,kinetic_energy_j_per_m,max_speed_m_s,front_x_m,left_wall_height_m,fluid_particles,isolated_particles,steps,dt_s,remesh_area_change_m2,motion_area_change_m2,recovered_area_m2";

pub struct TimeseriesWriter {
    file: std::io::BufWriter<std::fs::File>,
}

impl TimeseriesWriter {
    pub fn create(path: &Path) -> std::io::Result<Self> {
        let mut file = std::io::BufWriter::new(std::fs::File::create(path)?);
        writeln!(file, "{HEADER}")?;
        file.flush()?;
        Ok(Self { file })
    }

    pub fn row(
        &mut self,
        m: &Integrals,
        initial_volume_m2: f64,
        steps: u64,
        dt_s: f64,
    ) -> std::io::Result<()> {
        writeln!(
            self.file,
            "{:.6},{:.8e},{:.8},{:.6e},{:.6e},{:.6},{:.6},{},{},{},{:.4e},{:.6e},{:.6e},{:.6e}",
            m.t_s,
            m.volume_m2,
            m.volume_m2 / initial_volume_m2,
            m.kinetic_energy_j_per_m,
            m.max_speed_m_s,
            m.front_x_m,
            m.left_wall_height_m,
            m.fluid_particles,
            m.isolated_particles,
            steps,
            dt_s,
            m.area_budget.remesh_m2,
            m.area_budget.motion_m2,
            m.area_budget.recovered_m2
        )?;
        self.file.flush()
    }
}

/// Reads a column of a CSV written by this module (or any simple numeric CSV with a header).
pub fn read_column(path: &Path, name: &str) -> std::io::Result<Vec<f64>> {
    let text = std::fs::read_to_string(path)?;
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap_or_default();
    let k = header.split(',').position(|h| h == name).ok_or_else(|| {
        std::io::Error::new(std::io::ErrorKind::InvalidData, format!("no column {name}"))
    })?;
    Ok(lines
        .filter_map(|l| l.split(',').nth(k).and_then(|v| v.parse().ok()))
        .collect())
}

/// Reads what the dam-break check compares from a `timeseries.csv` written by
/// [`TimeseriesWriter`]: the columns t_s, front_x_m, left_wall_height_m and volume_m2 of every
/// row (`particles` is left unknown; it is in the run's summary).
pub fn read_dam_break_series(path: &Path) -> std::io::Result<DamBreakSeries> {
    let bad = |m: String| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("{}: {m}", path.display()),
        )
    };
    let text = std::fs::read_to_string(path)?;
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let names = ["t_s", "front_x_m", "left_wall_height_m", "volume_m2"];
    let mut at = [0; 4];
    for (k, name) in names.iter().enumerate() {
        at[k] = header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| bad(format!("no column {name}")))?;
    }
    let mut columns: [Vec<f64>; 4] = Default::default();
    for (row, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        for (k, name) in names.iter().enumerate() {
            let value = cells
                .get(at[k])
                .and_then(|c| c.trim().parse().ok())
                .ok_or_else(|| bad(format!("row {}: {name} is not a number", row + 1)))?;
            columns[k].push(value);
        }
    }
    let [t_s, front_x_m, left_wall_height_m, volume_m2] = columns;
    Ok(DamBreakSeries {
        t_s,
        front_x_m,
        left_wall_height_m,
        volume_m2,
        particles: None,
    })
}

/// `gauges.csv`: `t_s`, then one column per surface-elevation gauge, `eta_<x in m, 3 decimals>`
/// (m above the still-water level), then two per velocity probe, `u_<x>_<y>` and `w_<x>_<y>`
/// (m/s, horizontal and vertical); a cell is empty when its gauge or probe is dry.
pub struct GaugeWriter {
    file: std::io::BufWriter<std::fs::File>,
}

/// Column names of `gauges.csv` after `t_s`.
pub fn gauge_columns(gauges_x_m: &[f64], probes_m: &[[f64; 2]]) -> Vec<String> {
    let mut columns: Vec<String> = gauges_x_m.iter().map(|x| format!("eta_{x:.3}")).collect();
    for [x, y] in probes_m {
        columns.push(format!("u_{x:.3}_{y:.3}"));
        columns.push(format!("w_{x:.3}_{y:.3}"));
    }
    columns
}

impl GaugeWriter {
    pub fn create(path: &Path, columns: &[String]) -> std::io::Result<Self> {
        let mut file = std::io::BufWriter::new(std::fs::File::create(path)?);
        writeln!(file, "t_s,{}", columns.join(","))?;
        file.flush()?;
        Ok(Self { file })
    }

    pub fn row(&mut self, t_s: f64, values: &[Option<f64>]) -> std::io::Result<()> {
        let cells: Vec<String> = values
            .iter()
            .map(|e| e.map_or(String::new(), |v| format!("{v:.6}")))
            .collect();
        writeln!(self.file, "{t_s:.6},{}", cells.join(","))?;
        self.file.flush()
    }
}

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

/// Reads a `gauges.csv` written by [`GaugeWriter`]: every column after `t_s`, empty cells as
/// dry (`None`).
pub fn read_gauges(path: &Path) -> std::io::Result<GaugeRecord> {
    let bad = |m: String| std::io::Error::new(std::io::ErrorKind::InvalidData, m);
    let text = std::fs::read_to_string(path)?;
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    if header.first() != Some(&"t_s") {
        return Err(bad(format!(
            "{}: the first column is not t_s",
            path.display()
        )));
    }
    let mut record = GaugeRecord {
        names: header[1..].iter().map(|s| s.to_string()).collect(),
        columns: vec![Vec::new(); header.len() - 1],
        ..Default::default()
    };
    for (row, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        if cells.len() != header.len() {
            return Err(bad(format!(
                "{}: row {} has {} cells, the header {}",
                path.display(),
                row + 1,
                cells.len(),
                header.len()
            )));
        }
        let t: f64 = cells[0].parse().map_err(|_| {
            bad(format!(
                "{}: row {}: t_s is not a number",
                path.display(),
                row + 1
            ))
        })?;
        record.t_s.push(t);
        for (j, cell) in cells[1..].iter().enumerate() {
            record.columns[j].push(cell.parse().ok().filter(|v: &f64| v.is_finite()));
        }
    }
    Ok(record)
}
