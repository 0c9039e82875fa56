//! The status of a fitted curve, one typed value from the fit to every file
//! that carries it: [`FitStatus`] is `ok`, a [`Caveat`] (fitted, to be read
//! with it) or an [`UnfitKind`] (why there is no curve). `fragility.csv`,
//! `fragility_bootstrap.csv`, `risk.csv` and the summaries write it with
//! [`Display`](std::fmt::Display) and read it back with
//! [`FromStr`](std::str::FromStr); the keywords are defined here and
//! nowhere else.

use std::cmp::Ordering;
use std::fmt;
use std::str::FromStr;

use super::fit::Unfit;

/// What a fitted curve is to be read with: the `status` of a fitted row of
/// `fragility.csv` other than `ok` (the numbers are written all the same).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Caveat {
    /// The median lies above the strongest stripe: the data hold only the
    /// curve's lower part, the rest is extrapolated.
    ExtrapolatedAbove,
    /// The median lies below the weakest stripe: the data hold only the
    /// curve's upper part.
    ExtrapolatedBelow,
    /// More likely than a milder limit state of its case (listed before
    /// it) somewhere within the stripes, by more than [`ORDER_TOLERANCE`](crate::fragility::ORDER_TOLERANCE):
    /// the limit states are not in order of severity for this case, and
    /// OpenQuake and pelicun would give the milder one's damage state a
    /// negative probability. Left out of `fragility.xml` and the exports.
    OutOfOrder,
}

impl Caveat {
    /// Every caveat, in order of precedence (a curve out of order and
    /// extrapolated is written `out-of-order`).
    pub const ALL: [Caveat; 3] = [
        Caveat::OutOfOrder,
        Caveat::ExtrapolatedAbove,
        Caveat::ExtrapolatedBelow,
    ];

    /// Its keyword in `fragility.csv`'s `status` column.
    pub fn status(self) -> &'static str {
        match self {
            Caveat::ExtrapolatedAbove => "extrapolated-above",
            Caveat::ExtrapolatedBelow => "extrapolated-below",
            Caveat::OutOfOrder => "out-of-order",
        }
    }

    /// The caveat of a fit with median `median` over stripes spanning
    /// `im_range`, when its median lies outside them.
    pub fn of_median(median: f64, im_range: Option<(f64, f64)>) -> Option<Caveat> {
        let (lo, hi) = im_range?;
        if median > hi {
            Some(Caveat::ExtrapolatedAbove)
        } else if median < lo {
            Some(Caveat::ExtrapolatedBelow)
        } else {
            None
        }
    }
}

/// Why a curve could not be fitted, without the numbers an [`Unfit`]
/// carries: what a file keeps of it (its keyword, [`UnfitKind::keyword`]).
/// Ordered by keyword, the order in which `boot_unfit_reasons` lists them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnfitKind {
    /// [`Unfit::NoData`].
    NoData,
    /// [`Unfit::NoneOverturned`].
    NoneOverturned,
    /// [`Unfit::AllOverturned`].
    AllOverturned,
    /// [`Unfit::SingleLevel`].
    SingleLevel,
    /// [`Unfit::Separated`].
    Separated,
    /// [`Unfit::Decreasing`].
    Decreasing,
    /// [`Unfit::NoConvergence`].
    NoConvergence,
}

impl UnfitKind {
    /// Every kind.
    pub const ALL: [UnfitKind; 7] = [
        UnfitKind::NoData,
        UnfitKind::NoneOverturned,
        UnfitKind::AllOverturned,
        UnfitKind::SingleLevel,
        UnfitKind::Separated,
        UnfitKind::Decreasing,
        UnfitKind::NoConvergence,
    ];

    /// Its keyword in the `status` columns.
    pub fn keyword(self) -> &'static str {
        match self {
            UnfitKind::NoData => "no-data",
            UnfitKind::NoneOverturned => "none-overturned",
            UnfitKind::AllOverturned => "all-overturned",
            UnfitKind::SingleLevel => "single-im-level",
            UnfitKind::Separated => "separated",
            UnfitKind::Decreasing => "decreasing",
            UnfitKind::NoConvergence => "no-convergence",
        }
    }
}

impl Unfit {
    /// The kind of reason, as a file keeps it.
    pub fn kind(&self) -> UnfitKind {
        match self {
            Unfit::NoData => UnfitKind::NoData,
            Unfit::NoneOverturned => UnfitKind::NoneOverturned,
            Unfit::AllOverturned => UnfitKind::AllOverturned,
            Unfit::SingleLevel { .. } => UnfitKind::SingleLevel,
            Unfit::Separated { .. } => UnfitKind::Separated,
            Unfit::Decreasing => UnfitKind::Decreasing,
            Unfit::NoConvergence { .. } => UnfitKind::NoConvergence,
        }
    }

    /// Short keyword used in the `status` column of `fragility.csv`.
    pub fn status(&self) -> &'static str {
        self.kind().keyword()
    }
}

impl PartialOrd for UnfitKind {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for UnfitKind {
    fn cmp(&self, other: &Self) -> Ordering {
        self.keyword().cmp(other.keyword())
    }
}

impl fmt::Display for UnfitKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.keyword())
    }
}

impl FromStr for UnfitKind {
    type Err = String;

    /// A keyword of [`UnfitKind::keyword`]; the error says what was expected.
    fn from_str(s: &str) -> Result<UnfitKind, String> {
        UnfitKind::ALL
            .into_iter()
            .find(|k| k.keyword() == s)
            .ok_or_else(|| {
                format!(
                    "why a curve could not be fitted ({})",
                    UnfitKind::ALL.map(UnfitKind::keyword).join(", ")
                )
            })
    }
}

/// A fitted curve's status: fitted (`ok`), fitted with a caveat, or not
/// fitted and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitStatus {
    /// Fitted, nothing to add.
    Ok,
    /// Fitted, to be read with the caveat.
    Caveat(Caveat),
    /// Not fitted.
    Unfit(UnfitKind),
}

impl FitStatus {
    /// The status of a fit (or why there is none) with its caveat, if any.
    pub fn of<T>(fit: &Result<T, Unfit>, caveat: Option<Caveat>) -> FitStatus {
        match (fit, caveat) {
            (Ok(_), None) => FitStatus::Ok,
            (Ok(_), Some(c)) => FitStatus::Caveat(c),
            (Err(reason), _) => FitStatus::Unfit(reason.kind()),
        }
    }

    /// Whether the curve was fitted (`ok` or a caveat).
    pub fn is_fitted(self) -> bool {
        !matches!(self, FitStatus::Unfit(_))
    }

    /// The caveat, if any.
    pub fn caveat(self) -> Option<Caveat> {
        match self {
            FitStatus::Caveat(c) => Some(c),
            _ => None,
        }
    }

    /// Why the curve was not fitted, if it was not.
    pub fn unfit(self) -> Option<UnfitKind> {
        match self {
            FitStatus::Unfit(k) => Some(k),
            _ => None,
        }
    }

    /// Its keyword in the `status` columns.
    pub fn keyword(self) -> &'static str {
        match self {
            FitStatus::Ok => "ok",
            FitStatus::Caveat(c) => c.status(),
            FitStatus::Unfit(k) => k.keyword(),
        }
    }
}

impl fmt::Display for FitStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.keyword())
    }
}

impl serde::Serialize for FitStatus {
    /// As its keyword (`inference.json`'s `fit`).
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.keyword())
    }
}

impl FromStr for FitStatus {
    type Err = String;

    /// `ok`, a [`Caveat`]'s keyword or an [`UnfitKind`]'s; the error says
    /// what was expected (for [`crate::table::Row::error`]).
    fn from_str(s: &str) -> Result<FitStatus, String> {
        if s == "ok" {
            return Ok(FitStatus::Ok);
        }
        if let Some(c) = Caveat::ALL.into_iter().find(|c| c.status() == s) {
            return Ok(FitStatus::Caveat(c));
        }
        s.parse().map(FitStatus::Unfit).map_err(|_| {
            format!(
                "a fit's status: ok, a caveat ({}) or why it could not be fitted ({})",
                Caveat::ALL.map(Caveat::status).join(", "),
                UnfitKind::ALL.map(UnfitKind::keyword).join(", ")
            )
        })
    }
}

/// Why a curve could not be fitted, in words a user reads.
pub fn unfit_words(kind: UnfitKind) -> String {
    match kind {
        UnfitKind::NoData => "no successful analysis".to_string(),
        UnfitKind::NoneOverturned => "no analysis exceeded it, so its median lies beyond the \
                                      strongest stripe"
            .to_string(),
        UnfitKind::AllOverturned => "every analysis exceeded it, so its median lies below the \
                                     weakest stripe"
            .to_string(),
        UnfitKind::SingleLevel => "every analysis is at one intensity".to_string(),
        UnfitKind::Separated => "no analysis exceeded it below some stripe and every one did \
                                 above, so the data say it is a step (β = 0) somewhere between \
                                 them"
            .to_string(),
        UnfitKind::Decreasing => "it becomes less likely as the intensity grows".to_string(),
        UnfitKind::NoConvergence => "the fit did not converge".to_string(),
    }
}

/// What to try for a curve that could not be fitted: why in words
/// ([`unfit_words`]) and the remedy, naming the intensities the analyses
/// spanned (`im_range`) where that helps.
pub fn unfit_advice(kind: UnfitKind, im_range: Option<(f64, f64)>) -> String {
    let range = im_range.map_or(String::new(), |(lo, hi)| {
        format!(
            " ({}–{} here)",
            crate::io_util::sig3(lo),
            crate::io_util::sig3(hi)
        )
    });
    let words = unfit_words(kind);
    match kind {
        UnfitKind::NoData => {
            "every analysis failed: see the `error` column of outcomes.csv".to_string()
        }
        UnfitKind::NoneOverturned => {
            format!("{words}; run stripes above the strongest{range}, where it is exceeded")
        }
        UnfitKind::AllOverturned => {
            format!("{words}; run stripes below the weakest{range}, where it is not")
        }
        UnfitKind::SingleLevel => "run at least two intensity levels".to_string(),
        UnfitKind::Separated => format!(
            "{words}; run stripes between those two levels, or more records, so that some \
             stripe has runs on both sides"
        ),
        UnfitKind::Decreasing => format!("{words}; check the limit state's measure and threshold"),
        UnfitKind::NoConvergence => format!("{words}; refit with more records or stripes"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every status a file can hold reads back as itself, and its text is
    /// the keyword files have always carried.
    #[test]
    fn keywords_round_trip() {
        let all = std::iter::once(FitStatus::Ok)
            .chain(Caveat::ALL.map(FitStatus::Caveat))
            .chain(UnfitKind::ALL.map(FitStatus::Unfit));
        let mut seen = Vec::new();
        for s in all {
            let text = s.to_string();
            assert_eq!(text.parse::<FitStatus>(), Ok(s), "{text}");
            assert!(!seen.contains(&text), "{text} twice");
            seen.push(text);
        }
        assert_eq!(
            seen,
            [
                "ok",
                "out-of-order",
                "extrapolated-above",
                "extrapolated-below",
                "no-data",
                "none-overturned",
                "all-overturned",
                "single-im-level",
                "separated",
                "decreasing",
                "no-convergence"
            ]
        );
    }

    /// An unknown keyword (a typo, another case) is refused with the list
    /// of the ones that exist, not read as a reason for having no curve.
    #[test]
    fn unknown_status_refused() {
        for bad in ["", "OK", "fitted", "no_data"] {
            let e = bad.parse::<FitStatus>().unwrap_err();
            assert!(
                e.contains("extrapolated-above") && e.contains("no-data"),
                "{e}"
            );
        }
    }

    /// Kinds sort by keyword, the order `boot_unfit_reasons` has always
    /// listed them in.
    #[test]
    fn kinds_sort_by_keyword() {
        let mut kinds = UnfitKind::ALL;
        kinds.sort();
        let mut words = UnfitKind::ALL.map(UnfitKind::keyword);
        words.sort();
        assert_eq!(kinds.map(UnfitKind::keyword), words);
    }
}
