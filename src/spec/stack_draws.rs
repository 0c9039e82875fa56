//! `[uncertainty.stack.NAME.BODY]`: the properties of a stack's bodies and
//! interfaces drawn per analysis ([`StackDraws`]), their validation, and the
//! stack an analysis simulates ([`StudyStack::drawn`]).
//!
//! ```toml
//! [uncertainty.stack.statue_on_pedestal.top]      # the statue
//! width = { dist = "normal", mean = 0.3, sd = 0.01, min = 0.27, max = 0.33 }
//! mu_s = { dist = "lognormal", median = 0.6, beta = 0.15 }   # statue on pedestal
//! mu_k_over_mu_s = 0.85
//!
//! [uncertainty.stack.statue_on_pedestal.base]     # the pedestal
//! density = { dist = "uniform", min = 0.8, max = 1.2 }
//! ```
//!
//! A body is named by its place (`base`, `middle`, `top`). Its table draws
//! its own `width`, `height` or `aspect`, `mass` (stacks that give masses)
//! or `density` (stacks that give none), `offset` (not the base's), and
//! the `restitution`, `mu_s` and `mu_k_over_mu_s` of the interface it
//! stands on (the base's: the ground's), as a single block's
//! `[uncertainty]` draws its own and its contact's. Each replaces the value
//! of `[[grid.stack]]`; the others keep it. A height given as an aspect
//! follows a drawn width, and a mass given as a density follows drawn
//! dimensions. Every analysis of the stack takes one uniform number per body
//! and property, drawn or not ([`crate::uncertainty::stack_uniforms`]).

use super::draw_checks::{check_value, friction_pair};
use super::locate::Origin;
use super::raw::StackDrawEntry;
use super::stack::StudyStack;
use crate::case::StackName;
use crate::error::{Error, Result};
use crate::outcome::Slot;
use crate::solver::Friction;
use crate::solver::stack::Stack;
use crate::uncertainty::{StackProperty, Value};
use std::collections::BTreeMap;

/// The properties one stack of a study draws per analysis.
#[derive(Clone, Debug, PartialEq)]
pub struct StackDraws {
    /// The stack's name (`[[grid.stack]] name`).
    pub stack: StackName,
    /// Per body, bottom first: the value of each property of
    /// [`StackProperty::ALL`] (`None`: the stack's own).
    pub bodies: Vec<[Option<Value>; 9]>,
}

impl StackDraws {
    /// Whether any property of the stack is drawn (not only fixed).
    pub fn any_drawn(&self) -> bool {
        self.bodies.iter().flatten().flatten().any(Value::is_drawn)
    }
}

impl StudyStack {
    /// The stack of one analysis: each property `draws` gives, at its
    /// uniform in `u` (bottom first, in the order of [`StackProperty::ALL`]),
    /// the others as the study gives them. Fails, naming the body and field,
    /// when the values make no valid stack.
    pub fn drawn(&self, draws: &StackDraws, u: &[[f64; 9]; 3]) -> Result<Stack> {
        use StackProperty as P;
        let mut stack = self.stack.clone();
        for (i, (body, under)) in stack
            .bodies
            .iter_mut()
            .zip(stack.interfaces.iter_mut())
            .enumerate()
        {
            let given = &draws.bodies[i];
            let at = |p: P| given[p.index()].map(|v| v.at(u[i][p.index()]));
            let form = self.forms[i];
            if let Some(w) = at(P::Width) {
                body.width = w;
            }
            body.height = match (at(P::Height), at(P::Aspect).or(form.aspect)) {
                (Some(h), _) => h,
                (None, Some(a)) => body.width * a,
                (None, None) => body.height,
            };
            body.mass = match form.density {
                // as `[[grid.stack]]` makes it: density × width × height
                Some(d) => at(P::Density).unwrap_or(d) * body.width * body.height,
                None => at(P::Mass).unwrap_or(body.mass),
            };
            if let Some(x) = at(P::Offset) {
                body.offset = x;
            }
            if let Some(e) = at(P::Restitution) {
                under.restitution = e;
            }
            if let (Some(mu_s), Some(ratio)) = (at(P::MuS), at(P::MuKOverMuS)) {
                // μk = μs · (μk/μs): μk ≤ μs by construction
                under.friction = Friction::Coulomb {
                    mu_s,
                    mu_k: mu_s * ratio,
                };
            }
        }
        let n = stack.bodies.len();
        stack.validate().map_err(|e| match e {
            // `body 2 width` → `top.width` of the drawn stack
            Error::InvalidParameter {
                field,
                value,
                expected,
            } => {
                let mut words = field.splitn(3, ' ');
                let field = match (words.next(), words.next().and_then(|k| k.parse().ok())) {
                    (Some("body"), Some(k @ 1..)) => format!(
                        "{}.{}",
                        Slot::of(k - 1, n).name(),
                        words.next().unwrap_or_default()
                    ),
                    _ => field,
                };
                Error::InvalidParameter {
                    field: format!("drawn stack {}: {field}", self.name),
                    value,
                    expected,
                }
            }
            other => other,
        })?;
        Ok(stack)
    }
}

/// The body of a stack of `n` bodies named `name` (`base`, `middle` of
/// three, `top`), as its index bottom first.
fn body_index(name: &str, n: usize) -> Option<usize> {
    (0..n).find(|&i| Slot::of(i, n).name() == name)
}

/// Checks `[uncertainty.stack]` against the study's `stacks`: every stack
/// and body named exists, every property is one the body can draw, every
/// distribution stays in the property's range, and the draws at their
/// medians make a valid stack. Errors name the field
/// (`uncertainty.stack.NAME.BODY.PROPERTY`) and the value.
pub(super) fn stack_draws(
    spec: &Origin,
    table: &BTreeMap<String, BTreeMap<String, StackDrawEntry>>,
    stacks: &[StudyStack],
) -> Result<Vec<StackDraws>> {
    use StackProperty as P;
    let mut out = Vec::new();
    for (name, bodies) in table {
        let field = format!("uncertainty.stack.{name}");
        let Some(stack) = stacks.iter().find(|s| s.name.as_str() == name) else {
            let names: Vec<&str> = stacks.iter().map(|s| s.name.as_str()).collect();
            let expected = if names.is_empty() {
                "the name of a [[grid.stack]] of the study (it has none)".to_string()
            } else {
                format!(
                    "the name of a [[grid.stack]] of the study: {}",
                    names.join(", ")
                )
            };
            return Err(spec.bad(&field, &format!("{name:?}"), &expected));
        };
        let n = stack.stack.bodies.len();
        let mut draws = StackDraws {
            stack: stack.name,
            bodies: vec![[None; 9]; n],
        };
        for (body, entry) in bodies {
            let field = format!("{field}.{body}");
            let Some(i) = body_index(body, n) else {
                let names: Vec<&str> = (0..n).map(|i| Slot::of(i, n).name()).collect();
                return Err(spec.bad(
                    &field,
                    &format!("{body:?}"),
                    &format!(
                        "a body of stack {name} ({n} bodies), by its place: {}",
                        names.join(", ")
                    ),
                ));
            };
            let values = entry.values();
            if values.iter().all(Option::is_none) {
                return Err(spec.bad(
                    &field,
                    &"(empty)",
                    "at least one of width, height, aspect, mass, density, offset, \
                     restitution, mu_s (with mu_k_over_mu_s)",
                ));
            }
            let form = stack.forms[i];
            for (p, value) in P::ALL.into_iter().zip(&values) {
                let Some(value) = value else { continue };
                let field = format!("{field}.{}", p.name());
                let block = format!("grid.stack's blocks[{i}]");
                let refused = match p {
                    P::Aspect if values[P::Height.index()].is_some() => {
                        Some("height or aspect, not both".to_string())
                    }
                    P::Mass if form.density.is_some() => Some(format!(
                        "density (stack {name} gives no masses: a body's mass is density × \
                         width × height)"
                    )),
                    P::Density if form.density.is_none() => Some(format!(
                        "mass (stack {name} gives masses; a density would not say how it \
                         weighs against the others')"
                    )),
                    P::Offset if i == 0 => Some(
                        "no offset for the base (its place on the ground is the origin)".into(),
                    ),
                    _ => None,
                };
                if let Some(expected) = refused {
                    return Err(spec.bad(&field, &"(given)", &expected));
                }
                let fixed_allowed = matches!(p, P::MuS | P::MuKOverMuS);
                check_value(spec, &field, value, p.range(), fixed_allowed, |_| {
                    let key = match p {
                        P::Restitution => "restitution of its interface",
                        _ => p.name(),
                    };
                    format!("in {block}.{key}")
                })?;
            }
            friction_pair(
                spec,
                &field,
                "",
                values[P::MuS.index()].is_some(),
                values[P::MuKOverMuS.index()].is_some(),
            )?;
            draws.bodies[i] = values;
        }
        // the draws at their medians must make a valid stack; a draw
        // elsewhere that does not is its analysis's failure, with its reason
        if let Err(e) = stack.drawn(&draws, &[[0.5; 9]; 3]) {
            let (value, why) = match e {
                Error::InvalidParameter {
                    field: f,
                    value,
                    expected,
                } => (value, format!("{f}: {expected}")),
                other => return Err(other),
            };
            return Err(spec.bad(
                &field,
                &value,
                &format!("draws whose medians make a valid stack ({why})"),
            ));
        }
        out.push(draws);
    }
    Ok(out)
}

/// The `[uncertainty.stack]` table of `draws`, as written.
pub(super) fn to_table(draws: &[StackDraws]) -> BTreeMap<String, BTreeMap<String, StackDrawEntry>> {
    draws
        .iter()
        .map(|d| {
            let n = d.bodies.len();
            let bodies = d
                .bodies
                .iter()
                .enumerate()
                .filter(|(_, v)| v.iter().any(Option::is_some))
                .map(|(i, v)| {
                    (
                        Slot::of(i, n).name().to_string(),
                        StackDrawEntry::from_values(*v),
                    )
                })
                .collect();
            (d.stack.to_string(), bodies)
        })
        .collect()
}
