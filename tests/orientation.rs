//! Two horizontal components and the block's orientation (issue 32): the
//! rotated component a(φ) = cos φ·H1 + sin φ·H2 and the RotD intensities
//! (Boore 2010). Each test opens with the fact it checks and why its
//! tolerance is what it is.

use std::f64::consts::{FRAC_1_SQRT_2, TAU};

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use rockfrag::motion::{
    Floor, Pair, ROTD_ANGLES, Record, SynthesisSettings, Synthesizer, floor_record, rotated_peaks,
    rotd, rotd_series,
};

const EPS: f64 = f64::EPSILON;

fn noise(seed: u64, n: usize, dt: f64) -> Record {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut acc: Vec<f64> = (0..n).map(|_| rng.random::<f64>() - 0.5).collect();
    acc[0] = -0.0;
    acc[3] = 0.0;
    Record::from_acc(format!("noise{seed}"), dt, acc).unwrap()
}

fn noise_pair() -> Pair {
    Pair::new(noise(1, 400, 0.01), noise(2, 400, 0.01)).unwrap()
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// Same Δt, vertical and series, bit for bit (the name says the angle).
fn assert_same_motion(a: &Record, b: &Record, what: &str) {
    assert_eq!(a.dt.to_bits(), b.dt.to_bits(), "{what}: dt");
    assert_eq!(a.acc_v, b.acc_v, "{what}: vertical");
    for (x, y) in [(&a.acc, &b.acc), (&a.vel, &b.vel), (&a.disp, &b.disp)] {
        assert_eq!(bits(x), bits(y), "{what}");
    }
}

fn negated(r: &Record) -> Record {
    let mut n = r.clone();
    for s in [&mut n.acc, &mut n.vel, &mut n.disp] {
        s.iter_mut().for_each(|v| *v = -*v);
    }
    n
}

#[test]
fn the_axes_give_the_components_bit_for_bit() {
    // φ = 0° is H1 and φ = 90° is H2, exactly (also their negative zeros);
    // a half turn negates, whole turns change nothing: angles on the axes
    // are special-cased, not computed with cos(π/2) ≈ 6e-17.
    let pair = noise_pair();
    let (h1, h2) = (&pair.h1, &pair.h2);
    for (angle, want) in [
        (0.0, h1.clone()),
        (90.0, h2.clone()),
        (180.0, negated(h1)),
        (270.0, negated(h2)),
        (360.0, h1.clone()),
        (-90.0, negated(h2)),
        (450.0, h2.clone()),
        (-0.0, h1.clone()),
    ] {
        let got = pair.rotated(angle).unwrap();
        assert_same_motion(&got, &want, &format!("{angle}°"));
        assert_eq!(got.name, format!("noise1+noise2@{angle}deg"));
    }
}

#[test]
fn a_general_angle_is_the_projection_on_the_rocking_plane() {
    // a(φ) = cos φ·H1 + sin φ·H2: against the formula in radians to 4 ulps of
    // |H1| + |H2| (one rounding each in the angle, the sine or cosine, the
    // products and the sum); a(φ + 180°) = −a(φ) and a(φ + 360°) = a(φ)
    // exactly when φ + 180° and φ + 360° are exact in floating point (the
    // angle is reduced exactly; 17.3 + 180 is not exact, 200.5 + 180 is),
    // as numbers: the sign of a zero sample is not kept by a sum
    // (c·(−0) + s·(−0) is +0 for c, s of opposite signs); and the rotation is
    // orthogonal, a(φ)² + a(φ + 90°)² = H1² + H2², to 8 ulps of the sum.
    let pair = noise_pair();
    for angle in [1.0, 17.3, 45.0, 60.0, 123.0, 200.5, 359.0, -33.0] {
        let a = pair.rotated(angle).unwrap();
        let (s, c) = angle.to_radians().sin_cos();
        for k in 0..a.len() {
            let (x1, x2) = (pair.h1.acc[k], pair.h2.acc[k]);
            let want = c * x1 + s * x2;
            assert!(
                (a.acc[k] - want).abs() <= 4.0 * EPS * (x1.abs() + x2.abs()),
                "{angle}° sample {k}"
            );
        }
        if angle + 360.0 - 360.0 == angle {
            let (half, whole) = (
                pair.rotated(angle + 180.0).unwrap(),
                pair.rotated(angle + 360.0).unwrap(),
            );
            let minus = negated(&a);
            for (x, y) in [(&half.acc, &minus.acc), (&half.vel, &minus.vel)] {
                assert_eq!(x, y, "{angle}° + 180°");
            }
            assert_eq!(half.disp, minus.disp, "{angle}° + 180°");
            assert_same_motion(&whole, &a, &format!("{angle}° + 360°"));
        } else {
            assert_eq!(angle, 17.3);
        }
        let b = pair.rotated(angle + 90.0).unwrap();
        for k in 0..a.len() {
            let (x1, x2) = (pair.h1.vel[k], pair.h2.vel[k]);
            let sum = x1 * x1 + x2 * x2;
            let rot = a.vel[k] * a.vel[k] + b.vel[k] * b.vel[k];
            assert!((rot - sum).abs() <= 8.0 * EPS * sum, "{angle}° sample {k}");
        }
    }
    assert!(pair.rotated(f64::NAN).is_err());
    assert!(pair.rotated(f64::INFINITY).is_err());
}

#[test]
fn pairs_that_are_not_sampled_together_are_refused() {
    // A different Δt or length means the files are not one instrument's
    // pair: refused with both values named, not truncated or padded.
    let h1 = noise(1, 400, 0.01);
    let err = Pair::new(h1.clone(), noise(2, 400, 0.02))
        .unwrap_err()
        .to_string();
    assert!(err.contains("dt = 0.01 s and 0.02 s"), "{err}");
    let err = Pair::new(h1.clone(), noise(2, 399, 0.01))
        .unwrap_err()
        .to_string();
    assert!(err.contains("400 and 399 samples"), "{err}");
    assert!(err.contains("noise1+noise2"), "{err}");
    // a Δt within the reading tolerance (1e-6 relative) is the same step
    assert!(Pair::new(h1.clone(), noise(2, 400, 0.01 * (1.0 + 1e-9))).is_ok());
    // a public field edited after construction is caught on use
    let mut pair = noise_pair();
    pair.h2.acc.pop();
    assert!(pair.rotated(30.0).is_err());
    assert!(rotd(&pair, 50.0).is_err());
    // verticals: one is carried, two must agree
    let mut pair = noise_pair();
    pair.h2.acc_v = Some(vec![0.5; 400]);
    assert_eq!(pair.rotated(30.0).unwrap().acc_v, Some(vec![0.5; 400]));
    pair.h1.acc_v = Some(vec![0.25; 400]);
    assert!(pair.rotated(30.0).is_err());
    assert!(rotd_series(&[1.0, 2.0], &[1.0], 50.0).is_err());
    for p in [-1.0, 100.5, f64::NAN] {
        assert!(rotd(&noise_pair(), p).is_err());
    }
}

#[test]
fn rotd_of_a_single_component_is_its_pga_times_cos_45() {
    // H2 = 0: peak |a(φ)| = |cos φ|·PGA(H1) exactly (rounding is monotone, so
    // the peak of the rounded products is the rounded product with the
    // peak). Over φ = 0…179° the sorted values are 0 (90°), then cos 89°,
    // cos 89°, cos 88°, cos 88°, … (φ and 180° − φ), …, cos 1° twice, 1 (0°):
    // the 90th and 91st (0-based 89, 90) are both cos 45°·PGA, so RotD50 =
    // PGA/√2 (the 1/√2 used at 45° is correctly rounded: within 1 ulp of
    // the product). RotD100 = PGA, RotD00 = 0, and RotD25 at position
    // 0.25·179 = 44.75 lies between cos 68° (index 44) and cos 67° (45).
    let h1 = noise(3, 600, 0.005);
    let mut h2 = h1.clone();
    h2.acc.iter_mut().for_each(|v| *v = 0.0);
    h2.name = "zero".into();
    let pga = h1.pga();
    let pair = Pair::new(h1, h2).unwrap();
    let rotd50 = rotd(&pair, 50.0).unwrap();
    assert!(
        (rotd50 - pga * FRAC_1_SQRT_2).abs() <= EPS * rotd50,
        "{rotd50}"
    );
    assert_eq!(rotd(&pair, 100.0).unwrap(), pga);
    assert_eq!(rotd(&pair, 0.0).unwrap(), 0.0);
    let (c67, c68) = (67f64.to_radians().cos(), 68f64.to_radians().cos());
    let rotd25 = rotd(&pair, 25.0).unwrap();
    let want = pga * (c68 + 0.75 * (c67 - c68));
    assert!(
        (rotd25 - want).abs() <= 4.0 * EPS * want,
        "{rotd25} vs {want}"
    );
    let peaks = rotated_peaks(&pair.h1.acc, &pair.h2.acc).unwrap();
    for (i, p) in peaks.iter().enumerate() {
        let c = (i as f64).to_radians().cos().abs();
        assert!((p - c * pga).abs() <= 2.0 * EPS * pga, "{i}°");
    }
}

#[test]
fn a_circularly_polarised_pair_has_the_same_peak_in_every_direction() {
    // H1 = A cos ωt, H2 = A sin ωt: a(φ) = A cos(ωt − φ), so every direction
    // has the peak A and RotD00 = RotD50 = RotD100 = A. With 360 samples a
    // period there is a sample at phase φ for every whole degree, so the
    // sampled peak is A to rounding (4 ulps: the samples' cosines, the
    // rotation's products and sum). With 137 samples a period the sampled
    // peak can miss the crest by half a step in phase, so it lies in
    // [A cos(ωΔt/2), A]: 1 − cos(π/137) = 2.6e-4 below A at most.
    let a = 0.35 * 9.81;
    for (n_per, low) in [(360, 1.0 - 4.0 * EPS), (137, (TAU / 137.0 / 2.0).cos())] {
        let dt = 1.0 / n_per as f64;
        let n = 5 * n_per + 1;
        let phase = |k: usize| TAU * ((k % n_per) as f64 / n_per as f64);
        let h1 = Record::from_acc("cos", dt, (0..n).map(|k| a * phase(k).cos()).collect());
        let h2 = Record::from_acc("sin", dt, (0..n).map(|k| a * phase(k).sin()).collect());
        let pair = Pair::new(h1.unwrap(), h2.unwrap()).unwrap();
        let peaks = rotated_peaks(&pair.h1.acc, &pair.h2.acc).unwrap();
        for (i, p) in peaks.iter().enumerate() {
            assert!(
                *p >= a * low && *p <= a * (1.0 + 4.0 * EPS),
                "{n_per} samples/period, {i}°: {p} vs {a}"
            );
            // and each peak is the peak of the rotated record, to the bit
            assert_eq!(*p, pair.rotated(i as f64).unwrap().pga());
        }
        let (r0, r50, r100) = (
            rotd(&pair, 0.0).unwrap(),
            rotd(&pair, 50.0).unwrap(),
            rotd(&pair, 100.0).unwrap(),
        );
        eprintln!(
            "{n_per} samples/period: RotD00 {:.2e}, RotD50 {:.2e}, RotD100 {:.2e} (relative to A)",
            r0 / a - 1.0,
            r50 / a - 1.0,
            r100 / a - 1.0
        );
        assert!(r0 >= a * low && r100 <= a * (1.0 + 4.0 * EPS) && r0 <= r50 && r50 <= r100);
    }
}

/// RotD by the definition, written directly: a(φ) in radians for each whole
/// degree, its peak, the sorted peaks' percentile by numpy's linear rule.
fn rotd_direct(x1: &[f64], x2: &[f64], p: f64) -> f64 {
    let mut peaks: Vec<f64> = (0..180)
        .map(|i| {
            let (s, c) = (i as f64).to_radians().sin_cos();
            x1.iter()
                .zip(x2)
                .map(|(a, b)| (c * a + s * b).abs())
                .fold(0.0, f64::max)
        })
        .collect();
    peaks.sort_by(f64::total_cmp);
    let pos = p / 100.0 * 179.0;
    let lo = pos.floor() as usize;
    let hi = (lo + 1).min(179);
    peaks[lo] + (pos - lo as f64) * (peaks[hi] - peaks[lo])
}

#[test]
fn rotd_of_recorded_like_pairs_is_orientation_independent() {
    // Two independent synthetic components (the generator's records 0 and 1,
    // a stand-in for a recorded pair) and their floor motions. RotD50 and
    // RotD100 against the definition computed directly (radians, no octant
    // reduction): 1e-15 relative (the directions' sines differ by an ulp).
    // Orientation independence (Boore 2010): swapping H1 and H2 gives the
    // same RotD to the bit (the angle set maps onto itself and the octant
    // reduction makes sin φ = cos(90° − φ) exactly); turning the instrument
    // by a whole number of degrees changes it only by rounding (1e-15).
    let mut synth = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let h1 = synth.generate(3, 0, 0.4 * 9.81).unwrap();
    let h2 = synth.generate(3, 1, 0.3 * 9.81).unwrap();
    let ground = Pair::new(h1, h2).unwrap();
    let roof = Floor::one_mode(0.8, 0.05, 1.3);
    let floor = Pair::new(
        floor_record(&ground.h1, &roof).unwrap(),
        floor_record(&ground.h2, &roof).unwrap(),
    )
    .unwrap();
    for pair in [&ground, &floor] {
        let swapped = Pair::new(pair.h2.clone(), pair.h1.clone()).unwrap();
        let turned = Pair::new(pair.rotated(37.0).unwrap(), pair.rotated(127.0).unwrap()).unwrap();
        for p in [50.0, 100.0, 0.0, 90.0] {
            let r = rotd(pair, p).unwrap();
            let direct = rotd_direct(&pair.h1.acc, &pair.h2.acc, p);
            assert!((r - direct).abs() <= 1e-15 * r, "RotD{p}: {r} vs {direct}");
            assert_eq!(r, rotd(&swapped, p).unwrap(), "RotD{p} swapped");
            let t = rotd(&turned, p).unwrap();
            assert!((r - t).abs() <= 1e-15 * r, "RotD{p}: {r} turned {t}");
        }
        let (r50, r100) = (rotd(pair, 50.0).unwrap(), rotd(pair, 100.0).unwrap());
        let (p1, p2) = (pair.h1.pga(), pair.h2.pga());
        eprintln!(
            "PGA H1 {:.3} g, H2 {:.3} g: RotD50 {:.3} g, RotD100 {:.3} g",
            p1 / 9.81,
            p2 / 9.81,
            r50 / 9.81,
            r100 / 9.81
        );
        // RotD100 is the largest peak over directions: at least either PGA
        assert!(r100 >= p1.max(p2) && r50 <= r100);
    }
    assert_eq!(ROTD_ANGLES, 180);
}

#[test]
fn the_floor_filter_commutes_with_rotation() {
    // The building is linear, so filtering the rotated ground motion equals
    // rotating the two filtered components: floor(a(φ)) = cos φ·floor(H1) +
    // sin φ·floor(H2). A study that draws φ per analysis can filter each
    // component once and rotate per analysis. Not bit for bit (the roundings
    // differ): to 1e-14 of each series' peak, a few roundings of the
    // largest terms, which are O(peak).
    let mut synth = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let ground = Pair::new(
        synth.generate(5, 0, 0.5 * 9.81).unwrap(),
        synth.generate(5, 1, 0.5 * 9.81).unwrap(),
    )
    .unwrap();
    let roof = Floor::one_mode(0.7, 0.05, 1.3);
    let filtered = Pair::new(
        floor_record(&ground.h1, &roof).unwrap(),
        floor_record(&ground.h2, &roof).unwrap(),
    )
    .unwrap();
    let mut worst = 0.0_f64;
    for angle in [0.0, 25.0, 90.0, 133.0, 290.5] {
        let a = floor_record(&ground.rotated(angle).unwrap(), &roof).unwrap();
        let b = filtered.rotated(angle).unwrap();
        for (x, y) in [(&a.acc, &b.acc), (&a.vel, &b.vel), (&a.disp, &b.disp)] {
            let peak = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let d = x
                .iter()
                .zip(y)
                .fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()));
            assert!(d <= 1e-14 * peak, "{angle}°: {d:e} of {peak:e}");
            worst = worst.max(d / peak);
        }
    }
    eprintln!("worst difference {worst:.1e} of the peak");
}
