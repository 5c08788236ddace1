//! `--set dotted.path=value`: change one field of a parsed case before it is checked.
//!
//! The value is read as a TOML value (`1.3`, `true`, `"cg"`, `[0, 1]`); a bare word that is not
//! valid TOML is taken as a string, so `--set solver.tau=kratos` works without quotes. A numeric
//! path segment indexes an array of tables, e.g. `water.0.depth_m`.

/// Applies one `key=value` assignment to `table`. Missing tables along the path are created, so
/// `--set output.mesh=true` works on a case without an `[output]` table; unknown names are left
/// for the schema to refuse, with the field named.
pub fn apply_override(table: &mut toml::Table, assignment: &str) -> Result<(), String> {
    let (path, raw) = assignment
        .split_once('=')
        .ok_or_else(|| "expected KEY=VALUE, e.g. solver.alpha=1.3".to_owned())?;
    let path = path.trim();
    if path.is_empty() || path.split('.').any(str::is_empty) {
        return Err(format!("`{path}` is not a dotted field path"));
    }
    let value = parse_value(raw.trim());
    let segments: Vec<&str> = path.split('.').collect();
    let mut root = toml::Value::Table(std::mem::take(table));
    let result = set_path(&mut root, &segments, value, path);
    if let toml::Value::Table(t) = root {
        *table = t;
    }
    result
}

fn set_path(
    root: &mut toml::Value,
    segments: &[&str],
    value: toml::Value,
    path: &str,
) -> Result<(), String> {
    let (last, parents) = segments.split_last().expect("non-empty path");
    let mut node = root;
    for seg in parents {
        node = child(node, seg)?;
    }
    match node {
        toml::Value::Table(t) => {
            t.insert((*last).to_owned(), value);
            Ok(())
        }
        toml::Value::Array(a) => {
            let i = index(seg_index(last)?, a.len(), last)?;
            a[i] = value;
            Ok(())
        }
        _ => Err(format!("`{path}`: the parent of `{last}` is not a table")),
    }
}

fn child<'a>(node: &'a mut toml::Value, seg: &str) -> Result<&'a mut toml::Value, String> {
    match node {
        toml::Value::Table(t) => Ok(t
            .entry(seg.to_owned())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()))),
        toml::Value::Array(a) => {
            let len = a.len();
            let i = index(seg_index(seg)?, len, seg)?;
            Ok(&mut a[i])
        }
        _ => Err(format!(
            "`{seg}` is inside a value that is neither a table nor an array"
        )),
    }
}

fn seg_index(seg: &str) -> Result<usize, String> {
    seg.parse::<usize>()
        .map_err(|_| format!("`{seg}` must be an array index (0, 1, …) here"))
}

fn index(i: usize, len: usize, seg: &str) -> Result<usize, String> {
    if i < len {
        Ok(i)
    } else {
        Err(format!(
            "index {seg} is out of range: the array has {len} entries"
        ))
    }
}

fn parse_value(raw: &str) -> toml::Value {
    match toml::from_str::<toml::Table>(&format!("v = {raw}")) {
        Ok(mut t) => t.remove("v").expect("key v was parsed"),
        Err(_) => toml::Value::String(raw.to_owned()),
    }
}
