//! `[uncertainty]`: block parameters drawn per analysis, each replacing the
//! grid list of the same name, and a stack's (`[uncertainty.stack.NAME.BODY]`,
//! [`super::stack_draws`]).

use super::draw_checks::{check_value, friction_pair};
use super::locate::Origin;
use super::raw::{GridFile, UncertaintyFile};
use super::study::Uncertainty;
use crate::error::Result;
use crate::uncertainty::Property;

/// Validates `[uncertainty]` against the `[grid]` as written: a parameter
/// is on the grid or drawn, never both; `mu_s` and `mu_k_over_mu_s` come
/// together and replace `grid.friction`; width, aspect and restitution take
/// distributions only (a fixed value is a one-value grid list). `seed` is
/// the default seed of the draws.
pub(super) fn uncertainty(
    spec: &Origin,
    table: Option<UncertaintyFile>,
    grid: &GridFile,
    seed: u64,
    stacks: &[super::stack::StudyStack],
) -> Result<Option<Uncertainty>> {
    let Some(table) = table else {
        return Ok(None);
    };
    let values = [
        table.width,
        table.aspect,
        table.restitution,
        table.mu_s,
        table.mu_k_over_mu_s,
    ];
    if values.iter().all(Option::is_none) && table.stack.is_empty() {
        return Err(spec.bad(
            "uncertainty",
            &"[uncertainty]",
            "at least one of width, aspect, restitution, mu_s (with mu_k_over_mu_s), or a \
             stack's [uncertainty.stack.NAME.BODY]",
        ));
    }
    let stack_draws = super::stack_draws::stack_draws(spec, &table.stack, stacks)?;
    let on_grid = [
        grid.width.is_some(),
        grid.aspect.is_some(),
        grid.restitution.is_some(),
        grid.friction.is_some(),
        grid.friction.is_some(),
    ];
    for ((param, value), on_grid) in Property::ALL.into_iter().zip(&values).zip(on_grid) {
        let Some(value) = value else { continue };
        let field = format!("uncertainty.{}", param.name());
        let grid_name = match param {
            Property::MuS | Property::MuKOverMuS => "friction",
            p => p.name(),
        };
        if on_grid {
            return Err(spec.bad(
                &field,
                &"(given)",
                &format!(
                    "to be left out when grid.{grid_name} is given (a parameter is on the \
                     grid or drawn, not both)"
                ),
            ));
        }
        let fixed_allowed = matches!(param, Property::MuS | Property::MuKOverMuS);
        check_value(spec, &field, value, param.range(), fixed_allowed, |x| {
            format!("on the grid: grid.{} = [{x}]", param.name())
        })?;
    }
    let [width, aspect, restitution, mu_s, mu_k_over_mu_s] = values;
    friction_pair(
        spec,
        "uncertainty",
        "uncertainty.",
        mu_s.is_some(),
        mu_k_over_mu_s.is_some(),
    )?;
    Ok(Some(Uncertainty {
        seed: table.seed.unwrap_or(seed),
        width,
        aspect,
        restitution,
        mu_s,
        mu_k_over_mu_s,
        stacks: stack_draws,
    }))
}

/// In a study of stacks alone (no block case), `[uncertainty]` keys of a
/// block would draw nothing: refused, saying where a stack's draws go.
pub(super) fn no_block_draws(spec: &Origin, table: Option<&UncertaintyFile>) -> Result<()> {
    let Some(u) = table else { return Ok(()) };
    let given = [
        ("restitution", u.restitution.is_some()),
        ("mu_s", u.mu_s.is_some()),
        ("mu_k_over_mu_s", u.mu_k_over_mu_s.is_some()),
    ];
    if let Some((key, _)) = given.iter().find(|(_, g)| *g) {
        return Err(spec.bad(
            &format!("uncertainty.{key}"),
            &"(given)",
            "a draw of a block case, and this study has stacks only: draw a \
             stack's under [uncertainty.stack.NAME.BODY] (BODY base, middle or top), \
             or give grid.width or grid.aspect for block cases (rockfrag infer \
             takes no stacks yet)",
        ));
    }
    Ok(())
}
