//! Checks shared by `[uncertainty]` and `[uncertainty.stack.NAME.BODY]`:
//! a value against its property's range, and μs beside μk/μs.

use super::locate::Origin;
use crate::error::Result;
use crate::uncertainty::Value;

/// Checks one value of `[uncertainty]` or `[uncertainty.stack.NAME.BODY]`
/// named `field` against its property's `range` (lo, hi, description): a
/// distribution within it; a fixed number only where `fixed_allowed` (μs
/// and μk/μs), within it; otherwise refused, saying where a fixed value
/// belongs (`belongs(x)`, e.g. `on the grid: grid.width = [0.3]`).
pub(super) fn check_value(
    spec: &Origin,
    field: &str,
    value: &Value,
    (lo, hi, what): (f64, f64, &str),
    fixed_allowed: bool,
    belongs: impl FnOnce(f64) -> String,
) -> Result<()> {
    match value {
        Value::Drawn(d) => d
            .validate(field, lo, hi, what)
            .map_err(|e| spec.nested("", e)),
        Value::Fixed(x) if fixed_allowed => {
            if !(x.is_finite() && (lo..=hi).contains(x)) {
                return Err(spec.bad(field, x, what));
            }
            Ok(())
        }
        Value::Fixed(x) => Err(spec.bad(
            field,
            x,
            &format!(
                "a distribution table such as {{ dist = \"uniform\", min = …, max = … }} \
                 (a fixed value belongs {})",
                belongs(*x)
            ),
        )),
    }
}

/// `mu_s` and `mu_k_over_mu_s` come together (μk = μs·ratio): refuses one
/// without the other, naming the missing field under `table` and the given
/// one as `beside` + its key.
pub(super) fn friction_pair(
    spec: &Origin,
    table: &str,
    beside: &str,
    mu_s: bool,
    ratio: bool,
) -> Result<()> {
    match (mu_s, ratio) {
        (true, false) => Err(spec.bad(
            &format!("{table}.mu_k_over_mu_s"),
            &"(missing)",
            &format!("a distribution or a number in [0, 1] beside {beside}mu_s (μk = μs·ratio)"),
        )),
        (false, true) => Err(spec.bad(
            &format!("{table}.mu_s"),
            &"(missing)",
            &format!("a distribution, or a number for a fixed μs, beside {beside}mu_k_over_mu_s"),
        )),
        _ => Ok(()),
    }
}
