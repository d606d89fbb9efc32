//! A Python dict as the text of a scene file (`Scene.from_dict`), with the key of every
//! line, so that an error the scene reader reports at a line can name the dict's key
//! (`parts[0].material`) instead.
//!
//! Layout: in each table its plain values first (one `key = value` line each), then its
//! sub-tables (`[a.b]`) and arrays of tables (`[[a.c]]`, a list whose items are all
//! dicts); dicts inside other lists are inline tables. Values: `str` and `os.PathLike`
//! (strings), `bool`, `int`, `float` (also NumPy scalars), lists and tuples, and NumPy
//! arrays (through `tolist()`). `None` has no TOML value: leave the key out.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyList, PyString, PyTuple};

use crate::MusclefemError;

/// A scene's TOML text and the key each of its lines holds (`""` for none).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TomlText {
    pub text: String,
    /// `keys[k]`: the dotted key of line k + 1, e.g. `parts[0].mesh.size`.
    pub keys: Vec<String>,
}

impl TomlText {
    /// The key of 1-based `line`, if the line holds one.
    pub fn key_at(&self, line: usize) -> Option<&str> {
        let key = self.keys.get(line.checked_sub(1)?)?;
        (!key.is_empty()).then_some(key.as_str())
    }

    fn line(&mut self, text: String, key: String) {
        self.text.push_str(&text);
        self.text.push('\n');
        self.keys.push(key);
    }
}

/// The TOML text of `dict` (the root table of a scene).
pub(crate) fn toml_from_dict(dict: &Bound<'_, PyDict>) -> PyResult<TomlText> {
    let mut out = TomlText {
        text: String::new(),
        keys: Vec::new(),
    };
    write_table(&mut out, dict, &[], "")?;
    Ok(out)
}

/// What a value of a table becomes.
enum Entry<'py> {
    Inline(String),
    Table(Bound<'py, PyDict>),
    Tables(Vec<Bound<'py, PyDict>>),
}

/// The entries of `dict` (at dotted key `at`) under the header path `header`.
fn write_table(
    out: &mut TomlText,
    dict: &Bound<'_, PyDict>,
    header: &[String],
    at: &str,
) -> PyResult<()> {
    let mut tables = Vec::new();
    for (key, value) in dict.iter() {
        let name = table_key(&key, at)?;
        let path = join(at, &name);
        match classify(&value, &path)? {
            Entry::Inline(text) => out.line(format!("{} = {text}", bare_or_quoted(&name)), path),
            entry => tables.push((name, path, entry)),
        }
    }
    for (name, path, entry) in tables {
        let mut inner = header.to_vec();
        inner.push(bare_or_quoted(&name));
        match entry {
            Entry::Table(table) => {
                out.line(format!("[{}]", inner.join(".")), path.clone());
                write_table(out, &table, &inner, &path)?;
            }
            Entry::Tables(items) => {
                for (k, table) in items.iter().enumerate() {
                    let item = format!("{path}[{k}]");
                    out.line(format!("[[{}]]", inner.join(".")), item.clone());
                    write_table(out, table, &inner, &item)?;
                }
            }
            Entry::Inline(_) => unreachable!("inline entries are written above"),
        }
    }
    Ok(())
}

/// A table entry: a sub-table, an array of tables, or an inline value.
fn classify<'py>(value: &Bound<'py, PyAny>, path: &str) -> PyResult<Entry<'py>> {
    if let Ok(table) = value.cast::<PyDict>() {
        return Ok(Entry::Table(table.clone()));
    }
    if let Some(items) = sequence(value)?
        && !items.is_empty()
        && items.iter().all(|item| item.cast::<PyDict>().is_ok())
    {
        let tables = items
            .into_iter()
            .map(|item| Ok(item.cast_into::<PyDict>()?))
            .collect::<PyResult<_>>()?;
        return Ok(Entry::Tables(tables));
    }
    Ok(Entry::Inline(inline(value, path)?))
}

/// The items of a list, tuple or NumPy array (`tolist()`), or `None` for other values.
fn sequence<'py>(value: &Bound<'py, PyAny>) -> PyResult<Option<Vec<Bound<'py, PyAny>>>> {
    if let Ok(list) = value.cast::<PyList>() {
        return Ok(Some(list.iter().collect()));
    }
    if let Ok(tuple) = value.cast::<PyTuple>() {
        return Ok(Some(tuple.iter().collect()));
    }
    if value.hasattr("tolist")? && value.hasattr("shape")? {
        let listed = value.call_method0("tolist")?;
        if let Ok(list) = listed.cast::<PyList>() {
            return Ok(Some(list.iter().collect()));
        }
    }
    Ok(None)
}

/// A value written on one line: string, boolean, number, array or inline table.
fn inline(value: &Bound<'_, PyAny>, path: &str) -> PyResult<String> {
    if value.is_none() {
        return Err(at(
            path,
            "None has no TOML value (leave the key out for the default)",
        ));
    }
    if let Ok(flag) = value.cast::<PyBool>() {
        return Ok(flag.is_true().to_string());
    }
    if let Ok(text) = value.cast::<PyString>() {
        return Ok(quoted(&text.to_cow()?));
    }
    if value.hasattr("__fspath__")? {
        let os = value.py().import("os")?;
        let text: String = os.call_method1("fspath", (value,))?.extract()?;
        return Ok(quoted(&text));
    }
    if let Ok(table) = value.cast::<PyDict>() {
        let mut cells = Vec::new();
        for (key, item) in table.iter() {
            let name = table_key(&key, path)?;
            let text = inline(&item, &join(path, &name))?;
            cells.push(format!("{} = {text}", bare_or_quoted(&name)));
        }
        return Ok(if cells.is_empty() {
            "{}".to_string()
        } else {
            format!("{{ {} }}", cells.join(", "))
        });
    }
    if let Some(items) = sequence(value)? {
        let cells = items
            .iter()
            .enumerate()
            .map(|(k, item)| inline(item, &format!("{path}[{k}]")))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(format!("[{}]", cells.join(", ")));
    }
    if value.cast::<PyFloat>().is_err()
        && value.hasattr("__index__")?
        && let Ok(integer) = value.extract::<i64>()
    {
        return Ok(integer.to_string());
    }
    if let Ok(number) = value.extract::<f64>() {
        return Ok(float(number));
    }
    let kind = value.get_type().name()?;
    Err(at(
        path,
        &format!(
            "a {kind} has no TOML value (use str, bool, int, float, list, tuple, dict or a \
             NumPy array)"
        ),
    ))
}

/// A float as TOML writes it: always with a fraction or an exponent, `inf`, `nan`.
/// Rust's shortest round-trip form, so the scene reads back the same number.
fn float(x: f64) -> String {
    if x.is_nan() {
        return "nan".to_string();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.to_string();
    }
    let text = format!("{x:?}");
    if text.contains(['.', 'e', 'E']) {
        text
    } else {
        format!("{text}.0")
    }
}

/// A key of a table: a `str`, refused otherwise.
fn table_key(key: &Bound<'_, PyAny>, at: &str) -> PyResult<String> {
    key.extract::<String>().map_err(|_| {
        let shown = key.repr().map(|r| r.to_string()).unwrap_or_default();
        self::at(
            if at.is_empty() { "(the top level)" } else { at },
            &format!("key {shown} is not a string"),
        )
    })
}

fn join(at: &str, name: &str) -> String {
    if at.is_empty() {
        name.to_string()
    } else {
        format!("{at}.{name}")
    }
}

/// A key bare when TOML allows it (letters, digits, `_`, `-`), quoted otherwise.
fn bare_or_quoted(key: &str) -> String {
    let bare = !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare { key.to_string() } else { quoted(key) }
}

/// A TOML basic string.
fn quoted(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn at(path: &str, message: &str) -> PyErr {
    MusclefemError::new_err(format!("Scene.from_dict: {path}: {message}"))
}
