//! The numbers of a `.scene` line: read as finite f64 (then straight in the scene's precision
//! where no transform applies), and colours and powers in f32.

use crate::math::Real;

/// Parses `expect` numbers (finite, as f64; see [`exact`] for reading them in `T`).
pub(super) fn numbers(words: &[&str], expect: &[usize], what: &str) -> Result<Vec<f64>, String> {
    if !expect.contains(&words.len()) {
        let want = match expect {
            [n] => format!("{n} numbers"),
            [a, b] => format!("{a} or {b} numbers"),
            _ => unreachable!("one or two counts"),
        };
        return Err(format!("{what} needs {want}, found {}", words.len()));
    }
    words.iter().map(|w| number(w)).collect()
}

pub(super) fn number(w: &str) -> Result<f64, String> {
    let shown = crate::words::shown(w);
    match w.parse::<f64>() {
        Ok(x) if x.is_nan() => Err(format!("'{shown}' is NaN")),
        Ok(x) if !x.is_finite() => Err(format!("'{shown}' is not finite")),
        Ok(x) => Ok(x),
        Err(_) => Err(format!("'{shown}' is not a number")),
    }
}

/// `w` read straight in precision `T` (it parsed as a finite f64 already).
pub(super) fn exact<T: Real>(w: &str) -> T {
    w.parse::<T>().unwrap_or_else(|_| T::of(f64::NAN))
}

/// `values` in f32, or the first that f32 cannot hold, named by `what`.
pub(super) fn f32_channels<const N: usize>(
    what: &str,
    values: [f64; N],
) -> Result<[f32; N], String> {
    match values.iter().find(|v| !(**v as f32).is_finite()) {
        Some(v) => Err(format!(
            "{what} {v:e} is beyond what f32 holds ({:e})",
            f32::MAX
        )),
        None => Ok(values.map(|v| v as f32)),
    }
}
