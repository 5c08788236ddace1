//! What a sweep runs: the `--vary` axes (lists and `START:STOP:STEP` ranges), their product
//! (the points, in product order: the first `--vary` changes slowest), each point's run
//! directory name, and `--shard I/N`.

use super::SweepError;
use serde::{Deserialize, Serialize};

/// At most this many points in one range and in one sweep.
pub const MAX_POINTS: usize = 1000;

/// One `--vary KEY=...` argument: the dotted case field and its values, each a TOML value as
/// `--set` takes it (ranges expanded).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VaryAxis {
    pub key: String,
    /// The argument's text after `=`, as given.
    pub given: String,
    pub values: Vec<String>,
}

/// One point of the sweep: its index in product order, the value of each axis, and the
/// directory its run writes to (relative to the sweep's directory).
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub index: usize,
    /// `key=value` for each axis, in the axes' order: the point's `--set` overrides.
    pub overrides: Vec<String>,
    /// The values alone, in the axes' order.
    pub values: Vec<String>,
    pub dir_name: String,
}

/// `--shard I/N`: this process runs the points whose index % N == I.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// The whole sweep in one process.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `I/N` (0 ≤ I < N).
    pub fn parse(text: &str) -> Result<Shard, SweepError> {
        let bad = |message: &str| SweepError::BadShard {
            given: text.to_owned(),
            message: message.to_owned(),
        };
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| bad("expected I/N, e.g. 0/4"))?;
        let index: usize = i
            .trim()
            .parse()
            .map_err(|_| bad("I is not a whole number"))?;
        let count: usize = n
            .trim()
            .parse()
            .map_err(|_| bad("N is not a whole number"))?;
        if count == 0 {
            return Err(bad("N must be at least 1"));
        }
        if index >= count {
            return Err(bad("I must be below N (I counts from 0)"));
        }
        Ok(Shard { index, count })
    }

    /// Whether this shard runs the point with `index`.
    pub fn owns(&self, index: usize) -> bool {
        index % self.count == self.index
    }
}

/// Parses one `--vary KEY=V1,V2,...` argument. Items are separated by commas outside brackets
/// and quotes; an unquoted item with colons is a range `START:STOP:STEP`.
pub fn parse_vary(arg: &str) -> Result<VaryAxis, SweepError> {
    let (key, given) = arg.split_once('=').ok_or_else(|| SweepError::BadVary {
        given: arg.to_owned(),
        message: "expected KEY=V1,V2,... or KEY=START:STOP:STEP".into(),
    })?;
    let key = key.trim();
    if key.is_empty()
        || key.split('.').any(|s| {
            s.is_empty()
                || !s
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        })
    {
        return Err(SweepError::BadVary {
            given: arg.to_owned(),
            message: format!("`{key}` is not a dotted field path such as solver.alpha"),
        });
    }
    let given = given.trim();
    let mut values = Vec::new();
    for item in split_top_level(given) {
        let item = item.trim();
        if item.is_empty() {
            return Err(SweepError::BadVary {
                given: arg.to_owned(),
                message: "an empty value (two commas in a row, or nothing after `=`)".into(),
            });
        }
        if is_range(item) {
            values.extend(expand_range(key, item)?);
        } else {
            values.push(item.to_owned());
        }
        if values.len() > MAX_POINTS {
            return Err(SweepError::TooManyPoints {
                what: format!("--vary {key}"),
                points: values.len(),
            });
        }
    }
    Ok(VaryAxis {
        key: key.to_owned(),
        given: given.to_owned(),
        values,
    })
}

/// Splits at commas that are not inside `[...]`, `{...}` or quotes.
fn split_top_level(text: &str) -> Vec<&str> {
    let mut items = Vec::new();
    let (mut depth, mut quote, mut start) = (0i32, None::<char>, 0);
    for (i, c) in text.char_indices() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '"' | '\'') => quote = Some(c),
            (None, '[' | '{') => depth += 1,
            (None, ']' | '}') => depth -= 1,
            (None, ',') if depth == 0 => {
                items.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    items.push(&text[start..]);
    items
}

fn is_range(item: &str) -> bool {
    !item.starts_with(['"', '\'', '[', '{']) && item.contains(':')
}

/// Expands `START:STOP:STEP` into START, START + STEP, ... up to STOP (included within
/// round-off). Integers when all three are written as integers; otherwise each value is rounded
/// to the most decimals written in the three and printed with at least one decimal.
pub fn expand_range(key: &str, item: &str) -> Result<Vec<String>, SweepError> {
    let bad = |message: String| SweepError::BadRange {
        key: key.to_owned(),
        range: item.to_owned(),
        message,
    };
    let parts: Vec<&str> = item.split(':').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(bad("a range is START:STOP:STEP, e.g. 1.0:4.0:0.25".into()));
    }
    let mut numbers = [0.0f64; 3];
    for (n, p) in numbers.iter_mut().zip(&parts) {
        *n = p
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(format!("`{p}` is not a number")))?;
    }
    let [start, stop, step] = numbers;
    if step <= 0.0 {
        return Err(bad(format!("the step must be positive, got {step}")));
    }
    if stop < start {
        return Err(bad(format!("STOP ({stop}) is below START ({start})")));
    }
    let steps = (stop - start) / step;
    if steps >= MAX_POINTS as f64 {
        return Err(SweepError::TooManyPoints {
            what: format!("--vary {key}={item}"),
            points: steps as usize + 1,
        });
    }
    // STOP counts when it is within a billionth of a step of the last value.
    let count = (steps + 1e-9 * steps.max(1.0)).floor() as usize + 1;
    let integers = parts
        .iter()
        .all(|p| !p.contains(['.', 'e', 'E']) && p.parse::<i64>().is_ok());
    let decimals = parts
        .iter()
        .map(|p| match p.split_once('.') {
            Some((_, frac)) if !p.contains(['e', 'E']) => frac.len(),
            _ => 0,
        })
        .max()
        .unwrap_or(0);
    let scientific = parts.iter().any(|p| p.contains(['e', 'E']));
    Ok((0..count)
        .map(|i| {
            let v = start + i as f64 * step;
            if integers {
                format!("{}", v.round() as i64)
            } else if scientific {
                // Twelve significant digits hide the round-off of start + i·step.
                let text = format!("{v:.11e}");
                let v: f64 = text.parse().unwrap_or(v);
                with_decimal_point(format!("{v}"))
            } else {
                with_decimal_point(trim_zeros(format!("{v:.decimals$}")))
            }
        })
        .collect())
}

fn trim_zeros(text: String) -> String {
    if text.contains('.') {
        text.trim_end_matches('0').to_owned()
    } else {
        text
    }
}

/// `1` → `1.0`, `1.` → `1.0`: a float stays a float when read back as TOML.
fn with_decimal_point(text: String) -> String {
    if text.ends_with('.') {
        text + "0"
    } else if text.contains(['.', 'e', 'E', 'n', 'N']) {
        text
    } else {
        text + ".0"
    }
}

/// The product of the axes' values, first axis slowest; refused over [`MAX_POINTS`] points or
/// when two points would share a directory name.
pub fn points(axes: &[VaryAxis]) -> Result<Vec<Point>, SweepError> {
    let total = axes
        .iter()
        .try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
        .unwrap_or(usize::MAX);
    if axes.is_empty() {
        return Err(SweepError::BadVary {
            given: String::new(),
            message: "a sweep needs at least one --vary KEY=V1,V2,...".into(),
        });
    }
    if total > MAX_POINTS {
        return Err(SweepError::TooManyPoints {
            what: "the sweep (the product of the --vary lists)".into(),
            points: total,
        });
    }
    for (k, a) in axes.iter().enumerate() {
        if axes[..k].iter().any(|b| b.key == a.key) {
            return Err(SweepError::BadVary {
                given: format!("{}={}", a.key, a.given),
                message: format!("`{}` is varied twice", a.key),
            });
        }
    }
    let mut out: Vec<Point> = Vec::with_capacity(total);
    for index in 0..total {
        // Mixed radix, the last axis fastest.
        let mut rest = index;
        let mut values = vec![String::new(); axes.len()];
        for (k, a) in axes.iter().enumerate().rev() {
            values[k] = a.values[rest % a.values.len()].clone();
            rest /= a.values.len();
        }
        let overrides: Vec<String> = axes
            .iter()
            .zip(&values)
            .map(|(a, v)| format!("{}={v}", a.key))
            .collect();
        let dir_name = axes
            .iter()
            .zip(&values)
            .map(|(a, v)| format!("{}={}", safe_name(&a.key), safe_name(&display_value(v))))
            .collect::<Vec<_>>()
            .join(",");
        if dir_name.len() > 240 {
            return Err(SweepError::BadVary {
                given: overrides.join(" "),
                message: "the run directory's name would be over 240 bytes long".into(),
            });
        }
        if let Some(other) = out.iter().find(|p| p.dir_name == dir_name) {
            return Err(SweepError::BadVary {
                given: overrides.join(" "),
                message: format!(
                    "this point and {} would share the directory `{dir_name}` (a value given twice?)",
                    other.overrides.join(" ")
                ),
            });
        }
        out.push(Point {
            index,
            overrides,
            values,
            dir_name,
        });
    }
    Ok(out)
}

/// A value as it reads in a name: a TOML string without its quotes, anything else as given.
fn display_value(value: &str) -> String {
    match toml::from_str::<toml::Table>(&format!("v = {value}")) {
        Ok(t) => match t.get("v") {
            Some(toml::Value::String(s)) => s.clone(),
            _ => value.to_owned(),
        },
        Err(_) => value.to_owned(),
    }
}

/// Keeps ASCII letters, digits and `. _ + -`; every other character becomes `_`, so that the
/// name is a single path component on any file system.
pub fn safe_name(text: &str) -> String {
    let name: String = text
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '+' | '-') {
                c
            } else {
                '_'
            }
        })
        .collect();
    // `.` and `..` are not names of a directory of their own.
    if name.chars().all(|c| c == '.') {
        name.replace('.', "_")
    } else {
        name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values(arg: &str) -> Vec<String> {
        parse_vary(arg).unwrap().values
    }

    #[test]
    fn lists_split_at_top_level_commas() {
        assert_eq!(values("solver.alpha=1.2,1.3"), ["1.2", "1.3"]);
        assert_eq!(
            values("solver.tau = kratos, \"a,b\""),
            ["kratos", "\"a,b\""]
        );
        assert_eq!(
            values("output.gauges_x_m=[1.0, 2.0],[3.0]"),
            ["[1.0, 2.0]", "[3.0]"]
        );
        assert_eq!(parse_vary("a.b=1").unwrap().key, "a.b");
    }

    #[test]
    fn ranges_include_stop_within_round_off() {
        let v = values("wavemaker.period_s=1.0:4.0:0.25");
        assert_eq!(v.len(), 13);
        assert_eq!(v[0], "1.0");
        assert_eq!(v[1], "1.25");
        assert_eq!(v[12], "4.0");
        assert_eq!(values("x.y=0.1:0.3:0.1"), ["0.1", "0.2", "0.3"]);
        assert_eq!(values("x.y=0:1:0.1").len(), 11);
        assert_eq!(values("x.y=1:3:1"), ["1", "2", "3"]);
        assert_eq!(values("x.y=1:2:0.3"), ["1.0", "1.3", "1.6", "1.9"]);
        assert_eq!(values("x.y=2:2:1"), ["2"]);
        assert_eq!(values("x.y=1e-3:3e-3:1e-3"), ["0.001", "0.002", "0.003"]);
        // Lists and ranges mix.
        assert_eq!(values("x.y=0.5,1.0:1.5:0.5"), ["0.5", "1.0", "1.5"]);
    }

    #[test]
    fn bad_ranges_and_lists_are_refused() {
        let err = |arg: &str| parse_vary(arg).unwrap_err().to_string();
        assert!(err("x.y=1:2:0").contains("step must be positive"));
        assert!(err("x.y=1:2:-0.5").contains("step must be positive"));
        assert!(err("x.y=3:2:0.5").contains("below START"));
        assert!(err("x.y=a:2:0.5").contains("`a` is not a number"));
        assert!(err("x.y=1:2").contains("START:STOP:STEP"));
        assert!(err("x.y=0:2000:1").contains("more than 1000"));
        assert!(err("x.y=1,,2").contains("empty value"));
        assert!(err("x.y=").contains("empty value"));
        assert!(err("novalue").contains("KEY="));
        assert!(err("a..b=1").contains("dotted field path"));
        // The key is named.
        assert!(err("wavemaker.period_s=4:1:1").contains("wavemaker.period_s"));
    }

    #[test]
    fn points_are_the_product_first_axis_slowest() {
        let axes = [
            parse_vary("solver.alpha=1.2,1.3").unwrap(),
            parse_vary("particles.spacing_m=0.05,0.04,0.03").unwrap(),
        ];
        let p = points(&axes).unwrap();
        assert_eq!(p.len(), 6);
        assert_eq!(
            p[0].overrides,
            ["solver.alpha=1.2", "particles.spacing_m=0.05"]
        );
        assert_eq!(p[1].values, ["1.2", "0.04"]);
        assert_eq!(p[3].values, ["1.3", "0.05"]);
        assert_eq!(p[5].dir_name, "solver.alpha=1.3,particles.spacing_m=0.03");
        assert!(p.iter().enumerate().all(|(i, q)| q.index == i));
    }

    #[test]
    fn directory_names_are_safe_and_distinct() {
        let axes = [parse_vary("solver.tau=\"kratos\",\"a/b c\",[1, 2]").unwrap()];
        let names: Vec<String> = points(&axes)
            .unwrap()
            .into_iter()
            .map(|p| p.dir_name)
            .collect();
        assert_eq!(
            names,
            ["solver.tau=kratos", "solver.tau=a_b_c", "solver.tau=_1__2_"]
        );
        assert_eq!(safe_name(".."), "__");
        // Two values that would share a directory.
        let axes = [parse_vary("solver.tau=\"a b\",\"a_b\"").unwrap()];
        assert!(points(&axes).unwrap_err().to_string().contains("share"));
        let axes = [parse_vary("a.b=1,2").unwrap(), parse_vary("a.b=3").unwrap()];
        assert!(
            points(&axes)
                .unwrap_err()
                .to_string()
                .contains("varied twice")
        );
        let big = [
            parse_vary("a.b=0:99:1").unwrap(),
            parse_vary("a.c=0:10:1").unwrap(),
        ];
        assert!(points(&big).unwrap_err().to_string().contains("1100"));
    }

    #[test]
    fn shards_cover_every_point_exactly_once() {
        for total in [1usize, 4, 7, 13] {
            for count in 1..=4 {
                let mut seen = vec![0; total];
                for index in 0..count {
                    let shard = Shard::parse(&format!("{index}/{count}")).unwrap();
                    for (i, s) in seen.iter_mut().enumerate() {
                        if shard.owns(i) {
                            *s += 1;
                        }
                    }
                }
                assert!(
                    seen.iter().all(|&s| s == 1),
                    "{total} points, {count} shards"
                );
            }
        }
        assert!(Shard::parse("4/4").is_err());
        assert!(Shard::parse("0/0").is_err());
        assert!(Shard::parse("1").is_err());
        assert!(Shard::parse("a/2").is_err());
        assert_eq!(
            Shard::parse(" 1 / 3 ").unwrap(),
            Shard { index: 1, count: 3 }
        );
    }
}
