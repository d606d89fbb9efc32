//! The `--vary` axes of a sweep: a Hill parameter and the values it takes, given as a list
//! (`sigma0=5e5,7e5,9e5`) or as N evenly spaced values from LO to HI (`sigma0=5e5:9e5:3`).

use anyhow::{Result, bail};

/// One varied parameter and its values (in the order given).
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Hill parameter name, as in `musclefem materials`.
    pub name: String,
    pub values: Vec<f64>,
}

impl Axis {
    /// Smallest and largest value.
    pub fn range(&self) -> (f64, f64) {
        let lo = self.values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = self
            .values
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    }
}

/// Parse every `--vary` token; a parameter may be varied once.
pub fn parse_axes(tokens: &[String]) -> Result<Vec<Axis>> {
    let mut axes: Vec<Axis> = Vec::new();
    for token in tokens {
        let axis = parse_axis(token)?;
        if axes.iter().any(|a| a.name == axis.name) {
            bail!(
                "--vary '{token}': parameter '{}' is varied more than once",
                axis.name
            );
        }
        axes.push(axis);
    }
    Ok(axes)
}

/// Parse `NAME=V1,V2,...` or `NAME=LO:HI:N`.
pub fn parse_axis(token: &str) -> Result<Axis> {
    let Some((name, spec)) = token.split_once('=') else {
        bail!("--vary '{token}': expected NAME=V1,V2,... or NAME=LO:HI:N, e.g. sigma0=5e5:9e5:3");
    };
    let name = name.trim();
    if name.is_empty() {
        bail!("--vary '{token}': the parameter name before '=' is empty");
    }
    let number = |text: &str| -> Result<f64> {
        match text.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => bail!("--vary '{token}': '{}' is not a finite number", text.trim()),
        }
    };
    let values = if spec.contains(':') {
        let parts: Vec<&str> = spec.split(':').collect();
        let [lo, hi, count] = parts[..] else {
            bail!("--vary '{token}': a range is LO:HI:N, e.g. sigma0=5e5:9e5:3");
        };
        let (lo, hi) = (number(lo)?, number(hi)?);
        let count: usize = match count.trim().parse() {
            Ok(n) if n >= 2 => n,
            _ => bail!(
                "--vary '{token}': N = '{}' must be a whole number of values, at least 2",
                count.trim()
            ),
        };
        if lo >= hi {
            bail!("--vary '{token}': LO must be below HI");
        }
        // The ends exactly as given, the values between rounded.
        (0..count)
            .map(|i| match i {
                0 => lo,
                i if i == count - 1 => hi,
                i => lo + (hi - lo) * i as f64 / (count - 1) as f64,
            })
            .collect()
    } else {
        spec.split(',').map(number).collect::<Result<Vec<f64>>>()?
    };
    Ok(Axis {
        name: name.to_string(),
        values,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_list_and_a_range_give_their_values() {
        let list = parse_axis("sigma0=5e5, 7e5,9e5").unwrap();
        assert_eq!(list.name, "sigma0");
        assert_eq!(list.values, vec![5e5, 7e5, 9e5]);
        let range = parse_axis("D=1e-9:5e-9:3").unwrap();
        assert_eq!(range.values.len(), 3);
        assert_eq!(range.range(), (1e-9, 5e-9));
        approx::assert_relative_eq!(range.values[1], 3e-9, max_relative = 1e-15);
    }

    #[test]
    fn bad_tokens_are_named_in_the_error() {
        for (token, expected) in [
            ("sigma0", "expected NAME="),
            ("=1,2", "name before '=' is empty"),
            ("b=1,x", "'x' is not a finite number"),
            ("b=1:2", "a range is LO:HI:N"),
            ("b=1:2:1", "at least 2"),
            ("b=2:1:3", "LO must be below HI"),
        ] {
            let error = parse_axis(token).unwrap_err().to_string();
            assert!(error.contains(token), "{error}");
            assert!(error.contains(expected), "{error}");
        }
        let twice = parse_axes(&["b=1,2".into(), "b=3".into()]).unwrap_err();
        assert!(twice.to_string().contains("more than once"));
    }
}
