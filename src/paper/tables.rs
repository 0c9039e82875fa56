//! The published results of the seed paper (Shenton and Jones, Tables 1–3):
//! 2B = 0.5 m, 25 firm-soil records per cell, infinite friction.
//!
//! The paper counted as overturned both the runs that reached θ = π/2 and
//! the runs its program stopped at a lift-off (N = 0 during rock, 27 % of its
//! runs); averages are over the runs that did not overturn in that sense.
//! Table 1 has no row for A_g = 0.3 (too weak to start rocking at H/B = 2),
//! and the cells where every run overturned have no averages.

use crate::motion::{SynthesisSettings, preset};

/// One row of Tables 1–3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperRow {
    /// Aspect ratio H/B.
    pub aspect: f64,
    /// Coefficient of restitution e.
    pub restitution: f64,
    /// Peak ground acceleration A_g, g.
    pub pga: f64,
    /// Number of the 25 runs that overturned (paper's convention).
    pub overturned: u32,
    /// Mean θmax/θc over the runs that did not overturn.
    pub theta_max_over_theta_c: Option<f64>,
    /// Mean friction demand during rocking, μ_mot.
    pub mu_motion: Option<f64>,
    /// Mean friction demand at impact, μ_imp.
    pub mu_impact: Option<f64>,
}

/// Base width 2B of the paper's blocks, m.
pub const WIDTH: f64 = 0.5;
/// Records per cell in the paper.
pub const RECORDS: usize = 25;

const fn row(
    aspect: f64,
    restitution: f64,
    pga: f64,
    overturned: u32,
    stats: Option<(f64, f64, f64)>,
) -> PaperRow {
    let (t, m, i) = match stats {
        Some((t, m, i)) => (Some(t), Some(m), Some(i)),
        None => (None, None, None),
    };
    PaperRow {
        aspect,
        restitution,
        pga,
        overturned,
        theta_max_over_theta_c: t,
        mu_motion: m,
        mu_impact: i,
    }
}

/// Tables 1, 2 and 3, in the paper's order.
pub const TABLES: &[PaperRow] = &[
    // Table 1: H/B = 2
    row(2.0, 0.0, 0.6, 0, Some((0.0155, 0.524, 0.353))),
    row(2.0, 0.0, 0.9, 8, Some((0.434, 0.575, 0.353))),
    row(2.0, 0.0, 1.2, 14, Some((0.753, 0.613, 0.353))),
    row(2.0, 0.3, 0.6, 0, Some((0.0149, 0.524, 3.01))),
    row(2.0, 0.3, 0.9, 6, Some((0.305, 0.569, 14.9))),
    row(2.0, 0.3, 1.2, 17, Some((0.404, 0.631, 11.4))),
    row(2.0, 0.6, 0.6, 0, Some((0.0242, 0.523, 111.0))),
    row(2.0, 0.6, 0.9, 1, Some((0.214, 0.572, 87.4))),
    row(2.0, 0.6, 1.2, 7, Some((0.503, 0.595, 91.8))),
    row(2.0, 0.9, 0.6, 0, Some((0.0128, 0.521, 71.3))),
    row(2.0, 0.9, 0.9, 0, Some((0.166, 0.547, 55.4))),
    row(2.0, 0.9, 1.2, 2, Some((0.273, 0.557, 80.6))),
    // Table 2: H/B = 4
    row(4.0, 0.0, 0.3, 0, Some((0.102, 0.262, 0.185))),
    row(4.0, 0.0, 0.6, 18, Some((0.595, 0.309, 0.185))),
    row(4.0, 0.0, 0.9, 21, Some((0.697, 0.354, 0.185))),
    row(4.0, 0.0, 1.2, 25, None),
    row(4.0, 0.3, 0.3, 0, Some((0.0858, 0.262, 3.54))),
    row(4.0, 0.3, 0.6, 16, Some((0.554, 0.303, 5.76))),
    row(4.0, 0.3, 0.9, 22, Some((0.575, 0.315, 1.85))),
    row(4.0, 0.3, 1.2, 24, Some((0.656, 0.424, 3.19))),
    row(4.0, 0.6, 0.3, 1, Some((0.124, 0.262, 20.5))),
    row(4.0, 0.6, 0.6, 15, Some((0.543, 0.297, 17.8))),
    row(4.0, 0.6, 0.9, 19, Some((0.638, 0.312, 74.9))),
    row(4.0, 0.6, 1.2, 24, Some((0.820, 0.311, 2.46))),
    row(4.0, 0.9, 0.3, 0, Some((0.0657, 0.261, 5480.0))),
    row(4.0, 0.9, 0.6, 9, Some((0.475, 0.230, 237.0))),
    row(4.0, 0.9, 0.9, 19, Some((0.523, 0.333, 9550.0))),
    row(4.0, 0.9, 1.2, 23, Some((0.600, 0.324, 42.0))),
    // Table 3: H/B = 6
    row(6.0, 0.0, 0.3, 5, Some((0.306, 0.194, 0.124))),
    row(6.0, 0.0, 0.6, 21, Some((0.478, 0.218, 0.124))),
    row(6.0, 0.0, 0.9, 24, Some((0.941, 0.338, 0.124))),
    row(6.0, 0.0, 1.2, 23, Some((0.848, 0.287, 0.124))),
    row(6.0, 0.3, 0.3, 6, Some((0.322, 0.195, 69.9))),
    row(6.0, 0.3, 0.6, 21, Some((0.535, 0.222, 3.36))),
    row(6.0, 0.3, 0.9, 24, Some((1.07, 0.232, 2.56))),
    row(6.0, 0.3, 1.2, 24, Some((0.628, 0.325, 1.57))),
    row(6.0, 0.6, 0.3, 6, Some((0.372, 0.192, 6.37))),
    row(6.0, 0.6, 0.6, 19, Some((0.504, 0.221, 64.6))),
    row(6.0, 0.6, 0.9, 22, Some((0.665, 0.245, 3.92))),
    row(6.0, 0.6, 1.2, 24, Some((0.774, 0.265, 46.7))),
    row(6.0, 0.9, 0.3, 3, Some((0.344, 0.191, 160.0))),
    row(6.0, 0.9, 0.6, 22, Some((0.468, 0.198, 6.78))),
    row(6.0, 0.9, 0.9, 24, Some((0.814, 0.219, 26.1))),
    row(6.0, 0.9, 1.2, 25, None),
];

/// One candidate reading of the paper's section 4.
#[derive(Clone, Debug, PartialEq)]
pub struct Reading {
    /// Short name, e.g. `rad/s band`.
    pub name: &'static str,
    /// What the reading takes the sentence to mean.
    pub meaning: &'static str,
    /// The synthesis settings of the reading.
    pub settings: SynthesisSettings,
}

/// The readings of section 4 that `rockfrag paper` compares: as written,
/// the rad/s band and the whole rad/s grid (see `paper::check`). The
/// built-in study uses the rad/s grid.
pub fn readings() -> Vec<Reading> {
    let written = preset("shenton-jones-as-written").expect("a preset");
    let band = SynthesisSettings {
        f_max: written.f_max / (2.0 * std::f64::consts::PI),
        ..written.clone()
    };
    vec![
        Reading {
            name: "as written",
            meaning: "Δf = 0.05 Hz over 0.05–25 Hz",
            settings: written,
        },
        Reading {
            name: "rad/s band",
            meaning: "0.05–25 rad/s (0.05–3.98 Hz), Δf = 0.05 Hz",
            settings: band,
        },
        Reading {
            name: "rad/s grid",
            meaning: "Δω = 0.05 rad/s over 0.05–25 rad/s (Δf ≈ 0.00796 Hz, up to 3.98 Hz)",
            settings: preset("shenton-jones").expect("a preset"),
        },
    ]
}

/// The paper's row for (H/B, e, A_g), if it published one.
pub fn lookup(aspect: f64, restitution: f64, pga: f64) -> Option<&'static PaperRow> {
    TABLES
        .iter()
        .find(|r| r.aspect == aspect && r.restitution == restitution && r.pga == pga)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_have_the_papers_shape() {
        assert_eq!(TABLES.len(), 12 + 16 + 16);
        // Section 6: "Of the 1200 time history analyses conducted, 584 […]
        // resulted in overturning" (H/B = 2 at 0.3 g: no rocking, no row).
        assert_eq!(TABLES.iter().map(|r| r.overturned).sum::<u32>(), 584);
        assert!(lookup(2.0, 0.0, 0.3).is_none());
        assert_eq!(lookup(4.0, 0.9, 0.9).unwrap().mu_impact, Some(9550.0));
        // e = 0 impact demand is eq. (8), independent of A_g.
        assert!(
            TABLES
                .iter()
                .filter(|r| r.restitution == 0.0 && r.mu_impact.is_some())
                .all(|r| r.mu_impact == Some([0.353, 0.185, 0.124][(r.aspect / 2.0) as usize - 1]))
        );
    }
}
