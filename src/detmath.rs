//! Deterministic floating-point functions: the same bits on every platform.
//!
//! `f64::sin`, `exp`, `ln`, `powf`, … call the platform's math library
//! (glibc, musl, macOS, Windows, and glibc's FMA or non-FMA variant chosen
//! at run time), whose results differ in the last bits; compile-time constant
//! folding uses the compiler host's library too. Near an overturning
//! threshold a last-bit difference becomes an O(1) difference in a study's
//! outcomes. So every transcendental function whose result can reach an
//! output goes through this module, implemented with the `libm` crate (a
//! pure-Rust port of musl's libm, the same code on every target) or with
//! plain IEEE-754 arithmetic of our own, never with the platform's library.
//! `tests/determinism.rs` fails on any `f64` transcendental method called
//! elsewhere in `src/`.
//!
//! Only `+ − × ÷`, `sqrt` (all correctly rounded by IEEE 754), comparisons,
//! `abs`, `floor`, `round` and friends (exact) may be used directly; no
//! `mul_add` (a fused multiply-add rounds once where `a * b + c` rounds
//! twice, and whether it is a hardware instruction differs by target).
//!
//! Also here, for the same reason, the standard normal distribution (Φ, its
//! complement and Φ⁻¹) and ln n! / ln C(n, k): `statrs` computes them with
//! the platform's `exp` and `ln`.

use std::f64::consts::SQRT_2;

/// sin x.
#[inline]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}

/// cos x.
#[inline]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}

/// (sin x, cos x), with one argument reduction.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// tan x.
#[inline]
pub fn tan(x: f64) -> f64 {
    libm::tan(x)
}

/// arcsin x in [−π/2, π/2].
#[inline]
pub fn asin(x: f64) -> f64 {
    libm::asin(x)
}

/// arccos x in [0, π].
#[inline]
pub fn acos(x: f64) -> f64 {
    libm::acos(x)
}

/// arctan x in (−π/2, π/2).
#[inline]
pub fn atan(x: f64) -> f64 {
    libm::atan(x)
}

/// The angle of (x, y) from the x axis, in (−π, π] (argument order as
/// `f64::atan2`: `y.atan2(x)` is `atan2(y, x)`).
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// eˣ.
#[inline]
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}

/// eˣ − 1, accurate for small x.
#[inline]
pub fn exp_m1(x: f64) -> f64 {
    libm::expm1(x)
}

/// Natural logarithm ln x.
#[inline]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}

/// ln(1 + x), accurate for small x.
#[inline]
pub fn ln_1p(x: f64) -> f64 {
    libm::log1p(x)
}

/// log₁₀ x.
#[inline]
pub fn log10(x: f64) -> f64 {
    libm::log10(x)
}

/// log₂ x.
#[inline]
pub fn log2(x: f64) -> f64 {
    libm::log2(x)
}

/// xʸ for real y.
#[inline]
pub fn powf(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// xⁿ for integer n by binary powering: the multiplications of LLVM's and
/// compiler-rt's `powi` (r = r·x^(2ʲ) for each set bit j, 1/r for n < 0),
/// written out so that no target's `__powidf2` is involved. With a constant
/// n it unrolls to the same few multiplications.
#[inline]
pub fn powi(x: f64, n: i32) -> f64 {
    let mut k = n.unsigned_abs();
    let mut base = x;
    let mut r = 1.0;
    loop {
        if k & 1 == 1 {
            r *= base;
        }
        k >>= 1;
        if k == 0 {
            break;
        }
        base *= base;
    }
    if n < 0 { 1.0 / r } else { r }
}

/// x^(1/n) for x ≥ 0, n ≥ 1, faster than [`powf`] (about half its time, a
/// fifth for n = 8): repeated square roots for n = 1, 2, 4, 8 (each correctly
/// rounded), else e^(ln x / n), within about (1 + |ln x|/n) ulp (ln x to half
/// an ulp of |ln x|, which exp turns into a relative error), so 1e-15 for
/// x^(1/7) of x in [1e-30, 1e30]. For step-size rules, where a root's last
/// bits do not matter but its speed does.
#[inline]
pub fn root(x: f64, n: u32) -> f64 {
    match n {
        1 => x,
        2 => x.sqrt(),
        4 => x.sqrt().sqrt(),
        8 => x.sqrt().sqrt().sqrt(),
        _ => exp(ln(x) / n as f64),
    }
}

/// √(x² + y²) without undue overflow or underflow.
#[inline]
pub fn hypot(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

/// ∛x.
#[inline]
pub fn cbrt(x: f64) -> f64 {
    libm::cbrt(x)
}

/// sinh x.
#[inline]
pub fn sinh(x: f64) -> f64 {
    libm::sinh(x)
}

/// cosh x.
#[inline]
pub fn cosh(x: f64) -> f64 {
    libm::cosh(x)
}

/// tanh x.
#[inline]
pub fn tanh(x: f64) -> f64 {
    libm::tanh(x)
}

/// The error function erf x.
#[inline]
pub fn erf(x: f64) -> f64 {
    libm::erf(x)
}

/// The complementary error function erfc x = 1 − erf x, accurate for large x.
#[inline]
pub fn erfc(x: f64) -> f64 {
    libm::erfc(x)
}

/// Φ(x), the standard normal cumulative distribution function:
/// Φ(x) = ½ erfc(−x/√2), accurate in the lower tail (to Φ ≈ 1e-308).
pub fn norm_cdf(x: f64) -> f64 {
    0.5 * erfc(-x / SQRT_2)
}

/// 1 − Φ(x), the standard normal survival function: ½ erfc(x/√2), accurate
/// in the upper tail.
pub fn norm_sf(x: f64) -> f64 {
    0.5 * erfc(x / SQRT_2)
}

/// Φ⁻¹(p), the standard normal quantile, by Wichura's algorithm AS 241
/// (PPND16, *Appl. Statist.* 37(3), 1988): rational approximations in
/// q = p − ½ for |q| ≤ 0.425, else in r = √(−ln min(p, 1 − p)), relative
/// error about 1e-16. Φ⁻¹(0) = −∞, Φ⁻¹(1) = +∞.
///
/// # Panics
/// If p is not in [0, 1] (as `statrs`'s `inverse_cdf`).
// the coefficients as published, digit for digit (beyond f64's 17)
#[allow(clippy::excessive_precision)]
pub fn norm_inv_cdf(p: f64) -> f64 {
    assert!((0.0..=1.0).contains(&p), "p = {p} must be in [0, 1]");
    const A: [f64; 8] = [
        3.387_132_872_796_366_608,
        1.331_416_678_917_843_774_5e2,
        1.971_590_950_306_551_442_7e3,
        1.373_169_376_550_946_112_5e4,
        4.592_195_393_154_987_145_7e4,
        6.726_577_092_700_870_085_3e4,
        3.343_057_558_358_812_810_5e4,
        2.509_080_928_730_122_672_7e3,
    ];
    const B: [f64; 8] = [
        1.0,
        4.231_333_070_160_091_125_2e1,
        6.871_870_074_920_579_083e2,
        5.394_196_021_424_751_107_7e3,
        2.121_379_430_158_659_586_7e4,
        3.930_789_580_009_271_061e4,
        2.872_908_573_572_194_267_4e4,
        5.226_495_278_852_854_561e3,
    ];
    const C: [f64; 8] = [
        1.423_437_110_749_683_577_34,
        4.630_337_846_156_545_295_9,
        5.769_497_221_460_691_405_5,
        3.647_848_324_763_204_605_04,
        1.270_458_252_452_368_382_58,
        2.417_807_251_774_506_117_7e-1,
        2.272_384_498_926_918_458_33e-2,
        7.745_450_142_783_414_076_4e-4,
    ];
    const D: [f64; 8] = [
        1.0,
        2.053_191_626_637_758_821_87,
        1.676_384_830_183_803_849_4,
        6.897_673_349_851_000_045_5e-1,
        1.481_039_764_274_800_745_9e-1,
        1.519_866_656_361_645_719_66e-2,
        5.475_938_084_995_344_946e-4,
        1.050_750_071_644_416_843_24e-9,
    ];
    const E: [f64; 8] = [
        6.657_904_643_501_103_777_2,
        5.463_784_911_164_114_369_9,
        1.784_826_539_917_291_335_8,
        2.965_605_718_285_048_912_3e-1,
        2.653_218_952_657_612_309_3e-2,
        1.242_660_947_388_078_438_6e-3,
        2.711_555_568_743_487_578_15e-5,
        2.010_334_399_292_288_132_65e-7,
    ];
    const F: [f64; 8] = [
        1.0,
        5.998_322_065_558_879_376_9e-1,
        1.369_298_809_227_358_053_1e-1,
        1.487_536_129_085_061_485_25e-2,
        7.868_691_311_456_132_591e-4,
        1.846_318_317_510_054_681_8e-5,
        1.421_511_758_316_445_888_7e-7,
        2.044_263_103_389_939_785_64e-15,
    ];
    // Σ c_k r^k by Horner, highest degree first
    let poly = |c: &[f64; 8], r: f64| c.iter().rev().fold(0.0, |acc, &ck| acc * r + ck);
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180_625 - q * q;
        return q * poly(&A, r) / poly(&B, r);
    }
    if p == 0.0 {
        return f64::NEG_INFINITY;
    }
    if p == 1.0 {
        return f64::INFINITY;
    }
    let tail = if q < 0.0 { p } else { 1.0 - p };
    let r = (-ln(tail)).sqrt();
    let z = if r <= 5.0 {
        let r = r - 1.6;
        poly(&C, r) / poly(&D, r)
    } else {
        let r = r - 5.0;
        poly(&E, r) / poly(&F, r)
    };
    if q < 0.0 { -z } else { z }
}

/// The largest n whose n! is a finite `f64`.
const MAX_FACTORIAL: usize = 170;

/// n! for n ≤ 170 as `f64`, by the recurrence n! = n·(n − 1)! (as `statrs`).
const FACTORIALS: [f64; MAX_FACTORIAL + 1] = {
    let mut f = [1.0; MAX_FACTORIAL + 1];
    let mut i = 1;
    while i <= MAX_FACTORIAL {
        f[i] = f[i - 1] * i as f64;
        i += 1;
    }
    f
};

/// ln n!: ln of the tabulated n! up to 170, else ln Γ(n + 1).
pub fn ln_factorial(n: u64) -> f64 {
    match FACTORIALS.get(n as usize) {
        Some(&f) => ln(f),
        None => libm::lgamma(n as f64 + 1.0),
    }
}

/// ln Γ(x) for x > 0 (the beta-binomial's normalisers).
#[inline]
pub fn ln_gamma(x: f64) -> f64 {
    libm::lgamma(x)
}

/// ln C(n, k) = ln n! − ln k! − ln (n − k)!; −∞ for k > n.
pub fn ln_binomial(n: u64, k: u64) -> f64 {
    if k > n {
        f64::NEG_INFINITY
    } else {
        ln_factorial(n) - ln_factorial(k) - ln_factorial(n - k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use statrs::distribution::{ContinuousCDF, Normal};

    /// Relative difference, with `floor` as the smallest magnitude divided by.
    fn rel(a: f64, b: f64, floor: f64) -> f64 {
        (a - b).abs() / a.abs().max(b.abs()).max(floor)
    }

    /// Arguments spread over many decades, both signs.
    fn args() -> Vec<f64> {
        let mut v = vec![0.0, 1.0, -1.0, 0.5, 2.0];
        for k in -300..=300 {
            let x = powf(10.0, k as f64 / 20.0) * 1.234_567;
            v.extend([x, -x]);
        }
        v
    }

    #[test]
    fn root_is_the_power() {
        for x in args().into_iter().filter(|&x| x > 0.0) {
            for n in 1..=12 {
                let (r, p) = (root(x, n), powf(x, 1.0 / n as f64));
                let tol = 2.3e-16 * (2.0 + ln(x).abs() / n as f64);
                assert!(rel(r, p, 0.0) < tol, "{x}^(1/{n}): {r} vs {p}");
            }
        }
        for n in [1, 2, 7, 8] {
            assert_eq!(root(0.0, n), 0.0);
            assert_eq!(root(f64::INFINITY, n), f64::INFINITY);
        }
    }

    #[test]
    fn powi_is_the_same_multiplications_as_the_builtin() {
        for x in args() {
            for n in -12..=12 {
                assert_eq!(powi(x, n).to_bits(), x.powi(n).to_bits(), "{x}^{n}");
            }
        }
        assert_eq!(powi(0.0, -1), f64::INFINITY);
        assert_eq!(powi(2.0, 0), 1.0);
    }

    /// The wrappers are libm's functions, within an ulp or two of the
    /// platform's (which is all that differs).
    #[test]
    fn wrappers_agree_with_the_platform_to_rounding() {
        for x in args() {
            let check = |name: &str, ours: f64, std: f64| {
                if ours == std {
                    return;
                }
                if ours.is_nan() || std.is_nan() {
                    assert!(
                        ours.is_nan() && std.is_nan(),
                        "{name}({x}): {ours} vs {std}"
                    );
                } else {
                    assert!(
                        rel(ours, std, 1e-300) <= 4.5e-16,
                        "{name}({x}): {ours} vs {std}"
                    );
                }
            };
            if x.abs() < 1e6 {
                check("sin", sin(x), x.sin());
                check("cos", cos(x), x.cos());
                check("sin_cos.0", sin_cos(x).0, x.sin());
                check("sin_cos.1", sin_cos(x).1, x.cos());
            }
            if x.abs() < 700.0 {
                check("exp", exp(x), x.exp());
                check("exp_m1", exp_m1(x), x.exp_m1());
                check("sinh", sinh(x), x.sinh());
                check("cosh", cosh(x), x.cosh());
            }
            check("tanh", tanh(x), x.tanh());
            check("atan", atan(x), x.atan());
            check("atan2", atan2(x, 0.7), x.atan2(0.7));
            check("ln", ln(x), x.ln());
            check("ln_1p", ln_1p(x), x.ln_1p());
            check("log10", log10(x), x.log10());
            check("log2", log2(x), x.log2());
            check("hypot", hypot(x, 0.3), x.hypot(0.3));
            check("cbrt", cbrt(x), x.cbrt());
            if x.abs() <= 1.0 {
                check("asin", asin(x), x.asin());
                check("acos", acos(x), x.acos());
            }
            if x.abs() < 1e3 {
                check("tan", tan(x), x.tan());
                check("powf", powf(x.abs(), 1.7), x.abs().powf(1.7));
            }
        }
    }

    /// Φ(x) to 20 digits (mpmath's `ncdf` at 50).
    #[allow(clippy::excessive_precision)]
    const PHI: &[(f64, f64)] = &[
        (-37.5, 4.6053530095819548438e-308),
        (-30.0, 4.9067139271481870595e-198),
        (-25.3, 1.5971151302421997966e-141),
        (-20.0, 2.7536241186062336951e-89),
        (-12.5, 3.7325642988777133772e-36),
        (-8.0, 6.2209605742717841235e-16),
        (-5.5, 1.8989562465887719384e-8),
        (-3.0, 1.3498980316300945267e-3),
        (-2.2, 1.3903447513498604313e-2),
        (-1.3, 9.6800484585610325542e-2),
        (-0.71, 2.3885206808998673293e-1),
        (-0.5, 3.0853753872598689636e-1),
        (-0.1, 4.6017216272297101633e-1),
        (-1e-05, 4.9999601057719605216e-1),
        (0.0, 5.0e-1),
        (0.3, 6.1791142218895263307e-1),
        (0.71, 7.6114793191001326707e-1),
        (1.0, 8.4134474606854294859e-1),
        (1.9, 9.7128344018399819477e-1),
        (2.5, 9.9379033467422386483e-1),
        (4.0, 9.9996832875816688008e-1),
        (6.5, 9.9999999995983999416e-1),
        (8.2, 9.9999999999999987981e-1),
    ];

    /// Φ⁻¹(p) to 20 digits (mpmath at 50, the root of `ln ncdf(z) = ln p`).
    #[allow(clippy::excessive_precision)]
    const PHI_INV: &[(f64, f64)] = &[
        (1e-300, -3.7047096299361199237e+1),
        (1e-100, -2.1273453560965324294e+1),
        (3.7e-40, -1.3212819273108164195e+1),
        (1e-20, -9.2623400897984075796),
        (1e-10, -6.3613409024040561991),
        (2e-06, -4.6113823623026683581),
        (0.001, -3.0902323061678135354),
        (0.0123, -2.2476267557951377576),
        (0.02425, -1.9729610513118848376),
        (0.1, -1.2815515655446004353),
        (0.3, -5.2440051270804081597e-1),
        (0.4, -2.5334710313579974132e-1),
        (0.5, 0.0),
        (0.6, 2.5334710313579974132e-1),
        (0.75, 6.744897501960817432e-1),
        (0.9, 1.2815515655446005935),
        (0.97575, 1.9729610513118849594),
        (0.99, 2.3263478740408407676),
        (0.999999, 4.7534243088170877657),
    ];

    /// Φ to about an ulp: within 2.5e-16 relative, times the conditioning
    /// max(1, x²) of evaluating erfc at x/√2 rounded (2e-13 at x = −37.5).
    #[test]
    fn normal_cdf_is_accurate() {
        for &(x, phi) in PHI {
            let tol = 2.5e-16 * (x * x).max(1.0);
            assert!(
                rel(norm_cdf(x), phi, 0.0) <= tol,
                "Φ({x}) = {:e}, not {phi:e}",
                norm_cdf(x)
            );
            assert!(
                rel(norm_sf(-x), phi, 0.0) <= tol,
                "1 − Φ({}) = {:e}",
                -x,
                norm_sf(-x)
            );
        }
        assert_eq!(norm_cdf(0.0), 0.5);
        assert_eq!(norm_cdf(f64::NEG_INFINITY), 0.0);
        assert_eq!(norm_cdf(f64::INFINITY), 1.0);
    }

    /// statrs's Φ (Boost's erfc with its single-precision split constants
    /// written as doubles) is within 2e-10 of ours: the difference is its
    /// error, which the reference values above show.
    #[test]
    fn normal_cdf_agrees_with_statrs_to_its_accuracy() {
        let n = Normal::standard();
        let mut worst: f64 = 0.0;
        for i in -3700..=3700 {
            let x = i as f64 / 100.0;
            worst = worst.max(rel(norm_cdf(x), n.cdf(x), 0.0));
            worst = worst.max(rel(norm_sf(x), n.sf(x), 0.0));
        }
        assert!(worst < 2e-10, "worst relative difference {worst:e}");
    }

    #[test]
    fn normal_quantile_is_accurate_and_matches_statrs() {
        for &(p, z) in PHI_INV {
            assert!(
                rel(norm_inv_cdf(p), z, 1e-300) <= 1e-15,
                "Φ⁻¹({p}) = {}, not {z}",
                norm_inv_cdf(p)
            );
        }
        let n = Normal::standard();
        let mut worst: f64 = 0.0;
        let mut ps: Vec<f64> = (1..10_000).map(|i| i as f64 / 10_000.0).collect();
        for k in 4..=300 {
            let p = powf(10.0, -k as f64);
            ps.extend([p, 1.0 - p, 3.7 * p]);
        }
        for p in ps {
            let z = norm_inv_cdf(p);
            worst = worst.max(rel(z, n.inverse_cdf(p), 1e-300));
            // and back through Φ, where p keeps its digits: dp/p = z² dz/z
            if p < 0.5 && z.is_finite() {
                let tol = 2e-15 * (z * z).max(1.0);
                assert!(
                    rel(norm_cdf(z), p, 0.0) < tol,
                    "Φ(Φ⁻¹({p})) = {:e}",
                    norm_cdf(z)
                );
            }
        }
        assert!(
            worst < 1e-15,
            "worst relative difference from statrs {worst:e}"
        );
        assert_eq!(norm_inv_cdf(0.5), 0.0);
        assert_eq!(norm_inv_cdf(0.0), f64::NEG_INFINITY);
        assert_eq!(norm_inv_cdf(1.0), f64::INFINITY);
    }

    #[test]
    fn ln_binomial_matches_statrs() {
        use statrs::function::factorial::{ln_binomial as s_binom, ln_factorial as s_fact};
        for n in 0..400u64 {
            assert!(rel(ln_factorial(n), s_fact(n), 1.0) < 1e-15, "ln {n}!");
            for k in [0, 1, n / 3, n / 2, n.saturating_sub(1), n, n + 1] {
                let (a, b) = (ln_binomial(n, k), s_binom(n, k));
                if b.is_infinite() {
                    assert_eq!(a, b);
                } else {
                    // ln C is a difference of up to ln 400! ≈ 2000: relative
                    // to the terms
                    assert!(
                        (a - b).abs() < 1e-15 * ln_factorial(n).max(1.0),
                        "ln C({n},{k})"
                    );
                }
            }
        }
    }
}
