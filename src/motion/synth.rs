//! Stochastic ground motions by the spectral representation method
//! (paper section 4).
//!
//! The stationary process is a sum of cosines at the frequencies f_k = k·Δf
//! in [f_min, f_max], with amplitudes A_k = sqrt(2·S(f_k)·Δf) (S one-sided,
//! in Hz, [`CloughPenzien`]) and independent phases φ_k uniform on [0, 2π):
//!
//! ```text
//! a(t) = Σ_k A_k cos(2π f_k t + φ_k),   E[a²] = Σ_k A_k²/2 ≈ ∫ S(f) df
//! ```
//!
//! It is periodic with period 1/Δf. One period is synthesised exactly on the
//! DFT grid, N = 1/(Δf·Δt) samples, by one inverse real FFT, and repeated
//! for longer records. Components at or above the Nyquist frequency 1/(2Δt)
//! cannot be represented (a cosine at Nyquist keeps only A·cos φ·(−1)ⁿ, its
//! phase is lost) and are left out.
//!
//! **The default model** (a study without `[motion]`, `rockfrag motion`,
//! `simulate --seed`): the Clough–Penzien spectrum with Kung and Pecknold's
//! firm-soil parameters ([`CloughPenzien::default`]), components from
//! 0.05 Hz up to 25 Hz (the band of the seed paper's section 4: below
//! 0.05 Hz the spectrum's second filter and the 0.07 Hz high-pass leave
//! nothing; above 25 Hz, the Nyquist frequency of the 0.02 s step, firm soil
//! carries under 0.1 % of the variance and a rigid block, whose rocking
//! frequencies are a few Hz, does not respond), on the frequency grid of one
//! FFT over the whole record: Δf = 1/(N·Δt) with N the smallest power of two
//! of at least as many samples as the record (40.96 s for the 30-s record
//! at 0.02 s). So the process does not repeat within the record, whatever
//! its duration and step. A sum of cosines on a coarser grid repeats every
//! 1/Δf: the seed paper's grid read as written (Δf = 0.05 Hz) repeats every
//! 20 s inside a 30-s record.
//!
//! **Presets** ([`preset`]): named models a spec asks for with `[motion]
//! preset = "…"`: `shenton-jones`, the seed paper's section 4 with its
//! frequency grid read in rad/s (Δω = 0.05 rad/s over 0.05–25 rad/s; the
//! reading that reproduces its Tables 1–3), and `shenton-jones-as-written`
//! (Δf = 0.05 Hz over 0.05–25 Hz).
//!
//! The record is then modulated by the [`Envelope`] c(t), baseline-processed
//! ([`Baseline`]: zero-phase high-pass, drift-free consistent integration)
//! and scaled to the target PGA.
//!
//! Record i of an ensemble is a pure function of (seed, i): its phases come
//! from a Xoshiro256++ stream seeded with [`record_seed`]`(seed, i)`:
//! φ_k = 2π·u_k with u_k the stream's f64 draws on [0, 1), one per component
//! in increasing frequency order. Nothing depends on thread count or on
//! which records were generated before.

use crate::detmath as dm;
use std::sync::Arc;

use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner};

use super::baseline::{Baseline, Processor};
use super::envelope::Envelope;
use super::psd::CloughPenzien;
use super::record::{G_STANDARD, Record};
use crate::error::{Error, Result};
use crate::io_util::{number, sig3};

/// Settings of the stochastic ground-motion generator (defaults: see the
/// docs of `src/motion/synth.rs`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SynthesisSettings {
    /// Target power spectral density, eq. (6) (default: "firm soil").
    pub psd: CloughPenzien,
    /// Frequency step Δf of the components, Hz (default: none, one FFT over
    /// the whole record, 1/(N·Δt) with N the smallest power of two ≥ the
    /// record's samples). The process repeats every 1/Δf seconds; a step
    /// given must make 1/(Δf·Δt) an integer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub df: Option<f64>,
    /// Lowest component frequency, Hz (default: 0.05).
    pub f_min: f64,
    /// Highest component frequency, Hz (default: 25.0); components at or
    /// above the Nyquist frequency 1/(2Δt) are left out.
    pub f_max: f64,
    /// Sample interval Δt, s (default: 0.02).
    pub dt: f64,
    /// Record duration, s (default: 30.0): samples at t = 0, Δt, …, duration.
    pub duration: f64,
    /// Time envelope c(t) (default: the paper's eq. (7)).
    pub envelope: Envelope,
    /// High-pass filter and integration (default: 0.07 Hz, order 4).
    pub baseline: Baseline,
    /// Gravity used to convert intensities given in g, m/s² (default: 9.81).
    pub g: f64,
}

impl Default for SynthesisSettings {
    fn default() -> Self {
        SynthesisSettings {
            psd: CloughPenzien::default(),
            df: None,
            f_min: 0.05,
            f_max: 25.0,
            dt: 0.02,
            duration: 30.0,
            envelope: Envelope::default(),
            baseline: Baseline::default(),
            g: G_STANDARD,
        }
    }
}

/// Relative tolerance for "is an integer" tests on ratios of user inputs.
const INTEGER_TOL: f64 = 1e-9;

impl SynthesisSettings {
    /// Checks every field; errors name the field.
    pub fn validate(&self) -> Result<()> {
        self.psd.validate()?;
        for (name, v) in [
            ("df", self.df.unwrap_or(1.0)),
            ("f_min", self.f_min),
            ("f_max", self.f_max),
            ("dt", self.dt),
            ("duration", self.duration),
            ("g", self.g),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::invalid(name, v, "a positive finite number"));
            }
        }
        if self.f_max < self.f_min {
            return Err(Error::invalid("f_max", self.f_max, "≥ f_min"));
        }
        if self.duration < self.dt {
            return Err(Error::invalid("duration", self.duration, "≥ dt"));
        }
        // before anything is sized by it (`duration = 1e9` aborted on an
        // allocation, leaving a run's lock behind)
        if self.samples() > super::record::MAX_SAMPLES {
            return Err(Error::invalid(
                "duration",
                format!(
                    "{} s with dt = {} s ({} samples)",
                    number(self.duration),
                    number(self.dt),
                    sig3(self.duration / self.dt + 1.0)
                ),
                &format!(
                    "at most {} samples, duration/dt + 1 (2^22: a duration of {} s at this dt, \
                     or a dt of {} s for this duration; a record takes about 110 bytes of \
                     memory a sample per thread, so the limit keeps one under 450 MB)",
                    super::record::MAX_SAMPLES,
                    sig3((super::record::MAX_SAMPLES - 1) as f64 * self.dt),
                    sig3(self.duration / (super::record::MAX_SAMPLES - 1) as f64)
                ),
            ));
        }
        self.period_len()?;
        self.components()?;
        self.envelope.validate()?;
        self.baseline.validate(self.dt)?;
        Ok(())
    }

    /// Number of samples per record: duration/Δt + 1.
    pub fn samples(&self) -> usize {
        (self.duration / self.dt * (1.0 + INTEGER_TOL)).floor() as usize + 1
    }

    /// Converts an intensity in g to m/s² with this setting's `g`.
    pub fn pga_from_g(&self, pga_g: f64) -> f64 {
        pga_g * self.g
    }

    /// The frequency step Δf (Hz): the one given, or one FFT over the whole
    /// record (see [`SynthesisSettings::df`]).
    pub fn frequency_step(&self) -> f64 {
        match self.df {
            Some(df) => df,
            None => 1.0 / (self.samples().next_power_of_two() as f64 * self.dt),
        }
    }

    /// N = 1/(Δf·Δt), the number of samples in one period of the process;
    /// an error if it is not an integer.
    pub fn period_len(&self) -> Result<usize> {
        let Some(df) = self.df else {
            return Ok(self.samples().next_power_of_two());
        };
        let x = 1.0 / (df * self.dt);
        let n = x.round();
        if !(x.is_finite() && n >= 2.0 && (x - n).abs() <= INTEGER_TOL * x) {
            return Err(Error::invalid(
                "df",
                df,
                &format!(
                    "a frequency step such that 1/(df·dt) is an integer ≥ 2 \
                     (one period of the process on the time grid); with dt = {} it is {x}",
                    self.dt
                ),
            ));
        }
        Ok(n as usize)
    }

    /// When Δt does not fit the fixed frequency step (see
    /// [`SynthesisSettings::period_len`]), the message that says so and which
    /// round steps near it do fit, naming the setting `name` as its user
    /// gives it (`--dt` on the command line); `None` when it fits.
    pub fn dt_misfit(&self, name: &str) -> Option<String> {
        if self.period_len().is_ok() {
            return None;
        }
        let (dt, df) = (self.dt, self.frequency_step());
        let n = 1.0 / (df * dt);
        // Round steps that fit, nearest below and above the one given.
        let fits = |d: f64| {
            let m = SynthesisSettings {
                dt: d,
                ..self.clone()
            };
            m.period_len().is_ok()
        };
        let round: Vec<f64> = [1.0, 2.0, 2.5, 4.0, 5.0, 8.0]
            .iter()
            .flat_map(|m| (-4..=0).map(move |e| m * dm::powi(10.0, e)))
            .filter(|&d| fits(d))
            .collect();
        let below = round
            .iter()
            .copied()
            .filter(|&d| d < dt)
            .fold(f64::NAN, f64::max);
        let above = round
            .iter()
            .copied()
            .filter(|&d| d > dt)
            .fold(f64::NAN, f64::min);
        let near: Vec<String> = [below, above]
            .iter()
            .filter(|d| d.is_finite())
            .map(|d| format!("{name} {d}"))
            .collect();
        Some(format!(
            "{name} {dt} does not fit the generator's frequency step df = {df} Hz (fixed): \
             1/(df·dt) = {n:.6} must be a whole number ≥ 2, i.e. dt = {} s / n; {} would work",
            1.0 / df,
            near.join(" or ")
        ))
    }

    /// The component indices k (f_k = k·Δf), an inclusive range: f_min ≤ f_k
    /// ≤ f_max and f_k below Nyquist.
    fn components(&self) -> Result<(usize, usize)> {
        let n = self.period_len()?;
        let df = self.frequency_step();
        let k_min = ((self.f_min / df) * (1.0 - INTEGER_TOL)).ceil().max(1.0) as usize;
        let k_top = ((self.f_max / df) * (1.0 + INTEGER_TOL)).floor() as usize;
        let k_max = k_top.min((n - 1) / 2);
        if k_min > k_max {
            return Err(Error::invalid(
                "f_min",
                self.f_min,
                &format!(
                    "a band [f_min, f_max] holding at least one multiple of df = {} below \
                     the Nyquist frequency {} Hz",
                    crate::error::number(df),
                    crate::error::number(0.5 / self.dt)
                ),
            ));
        }
        Ok((k_min, k_max))
    }
}

/// The named ground-motion models a spec can ask for (`[motion] preset`):
/// name and what it is.
pub const PRESETS: [(&str, &str); 2] = [
    (
        "shenton-jones",
        "the seed paper's section 4 with its frequency grid read in rad/s: components every \
         0.05 rad/s over 0.05-25 rad/s (0.008-3.98 Hz), firm soil; reproduces its Tables 1-3",
    ),
    (
        "shenton-jones-as-written",
        "the seed paper's section 4 as written: components every 0.05 Hz over 0.05-25 Hz, firm \
         soil (repeats every 20 s)",
    ),
];

/// The settings of the preset `name` ([`PRESETS`]), `None` for an unknown
/// name.
///
/// ```
/// use rockfrag::motion::preset;
/// let p = preset("shenton-jones").unwrap();
/// assert!((1.0 / (p.df.unwrap() * p.dt) - 6283.0).abs() < 1e-9);
/// assert!(preset("kanai").is_none());
/// ```
pub fn preset(name: &str) -> Option<SynthesisSettings> {
    let base = SynthesisSettings::default();
    match name {
        "shenton-jones-as-written" => Some(SynthesisSettings {
            df: Some(0.05),
            f_min: 0.05,
            f_max: 25.0,
            ..base
        }),
        "shenton-jones" => {
            let two_pi = 2.0 * std::f64::consts::PI;
            // Δω = 0.05 rad/s is Δf = 0.05/2π Hz; 1/(Δf·Δt) = 6283.2 at
            // Δt = 0.02 s, rounded to the integer 6283 the FFT synthesis needs.
            let n = (two_pi / (0.05 * base.dt)).round();
            let df = 1.0 / (n * base.dt);
            Some(SynthesisSettings {
                df: Some(df),
                f_min: df,
                f_max: 25.0 / two_pi,
                ..base
            })
        }
        _ => None,
    }
}

/// The 64-bit seed of record `index` of the ensemble `seed`: the splitmix64
/// finaliser of `seed ^ index·φ64 + φ64` (φ64 = 0x9E3779B97F4A7C15). A
/// bijection in `seed` for fixed `index` and in `index` for fixed `seed`.
///
/// ```
/// use rockfrag::motion::record_seed;
/// assert_ne!(record_seed(1, 0), record_seed(1, 1));
/// assert_ne!(record_seed(1, 0), record_seed(2, 0));
/// ```
pub fn record_seed(seed: u64, index: u64) -> u64 {
    const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut z = (seed ^ index.wrapping_mul(GOLDEN)).wrapping_add(GOLDEN);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The ensemble seed whose record i is the second horizontal component of
/// record i of ensemble `seed`, in a study of synthetic pairs
/// (`components = 2`): a stream of its own, independent of the first
/// component's.
///
/// ```
/// use rockfrag::motion::{record_seed, second_component_seed};
/// let s2 = second_component_seed(1);
/// assert_ne!(s2, 1);
/// assert_ne!(record_seed(s2, 0), record_seed(1, 0));
/// ```
pub fn second_component_seed(seed: u64) -> u64 {
    // "rockfrag:H2" domain tag (an arbitrary odd constant), mixed
    record_seed(seed ^ 0x4832_C0B1_7E5E_ED2B, u64::MAX)
}

/// A ground-motion generator built once from [`SynthesisSettings`]: holds the
/// FFT plans, component amplitudes, envelope samples, filter gains and
/// scratch buffers. `Clone` is cheap (plans are shared); give each thread its
/// own clone.
///
/// ```
/// use rockfrag::motion::{SynthesisSettings, Synthesizer};
/// let mut s = Synthesizer::new(&SynthesisSettings::default()).unwrap();
/// let r = s.generate(7, 0, 0.3 * 9.81).unwrap();
/// assert_eq!(r.len(), 1501);
/// assert_eq!(r.pga(), 0.3 * 9.81);
/// ```
#[derive(Clone)]
pub struct Synthesizer {
    settings: SynthesisSettings,
    /// First component index (f = k_min·Δf).
    k_min: usize,
    /// A_k/2 for k = k_min..=k_max.
    half_amp: Vec<f64>,
    /// c(t_n), n = 0..samples.
    envelope: Vec<f64>,
    inverse: Arc<dyn ComplexToReal<f64>>,
    spectrum: Vec<Complex<f64>>,
    period: Vec<f64>,
    scratch: Vec<Complex<f64>>,
    processor: Processor,
}

impl std::fmt::Debug for Synthesizer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Synthesizer")
            .field("settings", &self.settings)
            .field("period_len", &self.period.len())
            .field("components", &self.half_amp.len())
            .finish_non_exhaustive()
    }
}

impl Synthesizer {
    /// Validates the settings and precomputes everything that does not depend
    /// on the seed.
    pub fn new(settings: &SynthesisSettings) -> Result<Self> {
        settings.validate()?;
        let n = settings.period_len()?;
        let (k_min, k_max) = settings.components()?;
        let half_amp = (k_min..=k_max)
            .map(|k| {
                let df = settings.frequency_step();
                let f = k as f64 * df;
                0.5 * (2.0 * settings.psd.density(f) * df).sqrt()
            })
            .collect();
        let len = settings.samples();
        let envelope = settings.envelope.sample(settings.dt, len);
        let inverse = RealFftPlanner::<f64>::new().plan_fft_inverse(n);
        Ok(Synthesizer {
            settings: settings.clone(),
            k_min,
            half_amp,
            envelope,
            spectrum: inverse.make_input_vec(),
            period: inverse.make_output_vec(),
            scratch: inverse.make_scratch_vec(),
            inverse,
            processor: Processor::new(&settings.baseline, settings.dt, len)?,
        })
    }

    /// The settings this generator was built from.
    pub fn settings(&self) -> &SynthesisSettings {
        &self.settings
    }

    /// Number of samples per record.
    pub fn samples(&self) -> usize {
        self.envelope.len()
    }

    /// Number of samples N in one period of the stationary process.
    pub fn period_len(&self) -> usize {
        self.period.len()
    }

    /// Component frequencies f_k (Hz), in the order their phases are drawn.
    pub fn frequencies(&self) -> Vec<f64> {
        (0..self.half_amp.len())
            .map(|i| (self.k_min + i) as f64 * self.settings.frequency_step())
            .collect()
    }

    /// Component amplitudes A_k = sqrt(2·S(f_k)·Δf) (m/s², before PGA
    /// scaling), matching [`Synthesizer::frequencies`].
    pub fn amplitudes(&self) -> Vec<f64> {
        self.half_amp.iter().map(|h| 2.0 * h).collect()
    }

    /// One period (N samples at t = n·Δt) of the stationary process of record
    /// (`seed`, `index`): no envelope, no filter, no scaling.
    pub fn stationary(&mut self, seed: u64, index: u64) -> &[f64] {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(record_seed(seed, index));
        self.spectrum.fill(Complex::default());
        let bins = &mut self.spectrum[self.k_min..self.k_min + self.half_amp.len()];
        // Two passes: the generator's state is a serial chain, the
        // trigonometry is not, and kept apart the latter pipelines well.
        for x in bins.iter_mut() {
            x.re = rng.random::<f64>();
        }
        for (x, &h) in bins.iter_mut().zip(&self.half_amp) {
            let (s, c) = sin_cos_turns(x.re);
            *x = Complex::new(h * c, h * s);
        }
        // With X_k = (A_k/2)·e^{iφ_k} the unnormalised inverse real FFT gives
        // x_n = Σ_k A_k cos(2π k n/N + φ_k) = a(n·Δt), since f_k·t_n = k n/N.
        self.inverse
            .process_with_scratch(&mut self.spectrum, &mut self.period, &mut self.scratch)
            .expect("buffers sized by the plan");
        &self.period
    }

    /// Generates record (`seed`, `index`) scaled to peak |acc| = `pga_m_s2`.
    pub fn generate(&mut self, seed: u64, index: u64, pga_m_s2: f64) -> Result<Record> {
        let mut r = Record::empty(self.settings.dt);
        self.generate_into(seed, index, pga_m_s2, &mut r)?;
        Ok(r)
    }

    /// As [`Synthesizer::generate`], reusing `out`'s buffers (no allocation
    /// once they have grown to the record length).
    ///
    /// The peak |acc| equals `pga_m_s2` exactly (bitwise): the record is
    /// scaled by pga/max|acc| and the peak sample is then set to ±pga, a
    /// change of at most one ulp. Velocity and displacement are integrated
    /// from the scaled acceleration by the linear rule (the same arithmetic
    /// as [`super::integrate_linear`]), from the scaled initial velocity and
    /// `disp[0] = 0`.
    pub fn generate_into(
        &mut self,
        seed: u64,
        index: u64,
        pga_m_s2: f64,
        out: &mut Record,
    ) -> Result<()> {
        if !(pga_m_s2.is_finite() && pga_m_s2 > 0.0) {
            return Err(Error::invalid(
                "pga",
                pga_m_s2,
                "a positive finite peak ground acceleration",
            ));
        }
        self.generate_scaled(seed, index, Some(pga_m_s2), out)
    }

    /// Record (`seed`, `index`) at the model's own amplitude (its spectral
    /// density's, not scaled to a PGA): for the two components of a
    /// synthetic pair, whose amplitudes keep their natural ratio and which
    /// are then scaled together by their RotD50.
    pub fn generate_natural(&mut self, seed: u64, index: u64) -> Result<Record> {
        let mut r = Record::empty(self.settings.dt);
        self.generate_scaled(seed, index, None, &mut r)?;
        Ok(r)
    }

    /// [`Synthesizer::generate_into`] to the peak `pga_m_s2`, or unscaled
    /// (`None`).
    fn generate_scaled(
        &mut self,
        seed: u64,
        index: u64,
        pga_m_s2: Option<f64>,
        out: &mut Record,
    ) -> Result<()> {
        let (v0, i_peak, peak) = self.natural_into(seed, index, &mut out.acc)?;
        self.finish(seed, index, v0, i_peak, peak, pga_m_s2, out);
        Ok(())
    }

    /// The part of record (`seed`, `index`) that no scaling changes: its
    /// filtered acceleration at the model's own amplitude (into `acc`),
    /// with its initial velocity and peak ([`Natural`]). Kept once per
    /// ensemble member, it serves every intensity level
    /// ([`Synthesizer::scaled_into`]) without a second FFT or filter.
    pub fn natural(&mut self, seed: u64, index: u64, acc: &mut Vec<f64>) -> Result<Natural> {
        let (v0, i_peak, peak) = self.natural_into(seed, index, acc)?;
        Ok(Natural {
            seed,
            index,
            v0,
            i_peak,
            peak,
        })
    }

    /// [`Synthesizer::generate_into`] from the member's natural
    /// acceleration `acc` and its [`Natural`] values: the same bits as
    /// generating it afresh (the scaling, clamp and integration are the same
    /// arithmetic on the same samples).
    pub fn scaled_into(
        &self,
        acc: &[f64],
        natural: &Natural,
        pga_m_s2: f64,
        out: &mut Record,
    ) -> Result<()> {
        if !(pga_m_s2.is_finite() && pga_m_s2 > 0.0) {
            return Err(Error::invalid(
                "pga",
                pga_m_s2,
                "a positive finite peak ground acceleration",
            ));
        }
        out.acc.clear();
        out.acc.extend_from_slice(acc);
        let Natural {
            seed,
            index,
            v0,
            i_peak,
            peak,
        } = *natural;
        self.finish(seed, index, v0, i_peak, peak, Some(pga_m_s2), out);
        Ok(())
    }

    /// Fills `acc` with the filtered, unscaled acceleration of record
    /// (`seed`, `index`); returns its initial velocity and the index and
    /// value of its peak |acc|.
    fn natural_into(
        &mut self,
        seed: u64,
        index: u64,
        acc: &mut Vec<f64>,
    ) -> Result<(f64, usize, f64)> {
        self.stationary(seed, index);
        let n = self.period.len();
        acc.clear();
        // The process repeats every N samples: sample i uses period[i mod N].
        for env in self.envelope.chunks(n) {
            acc.extend(env.iter().zip(&self.period).map(|(c, a)| c * a));
        }
        let v0 = self.processor.process(acc);
        let (i_peak, peak) = acc
            .iter()
            .enumerate()
            .fold((0, 0.0_f64), |(im, m), (i, a)| {
                if a.abs() > m { (i, a.abs()) } else { (im, m) }
            });
        if !(peak > 0.0 && peak.is_finite()) {
            return Err(Error::InvalidRecord {
                name: format!("synthetic seed={seed} index={index}"),
                message: format!(
                    "peak acceleration before scaling is {}",
                    crate::error::number(peak)
                ),
            });
        }
        Ok((v0, i_peak, peak))
    }

    /// Scales `out.acc` (the natural acceleration, peak `peak` at `i_peak`)
    /// to the peak `pga_m_s2` (or leaves it, `None`) and integrates it.
    #[allow(clippy::too_many_arguments)]
    fn finish(
        &self,
        seed: u64,
        index: u64,
        v0: f64,
        i_peak: usize,
        peak: f64,
        pga_m_s2: Option<f64>,
        out: &mut Record,
    ) {
        let scale = match pga_m_s2 {
            Some(pga) => {
                let scale = pga / peak;
                for a in out.acc.iter_mut() {
                    *a = (*a * scale).clamp(-pga, pga);
                }
                out.acc[i_peak] = pga.copysign(out.acc[i_peak]);
                scale
            }
            None => 1.0,
        };
        integrate_into(
            self.settings.dt,
            &out.acc,
            v0 * scale,
            0.0,
            &mut out.vel,
            &mut out.disp,
        );
        out.name.clear();
        use std::fmt::Write;
        write!(out.name, "synthetic seed={seed} index={index}").expect("writing to a String");
        out.dt = self.settings.dt;
        out.acc_v = None;
        debug_assert_eq!(out.acc.len(), self.samples());
    }
}

/// What every scaling of one synthetic record shares besides its natural
/// acceleration ([`Synthesizer::natural`]): its initial velocity and peak.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Natural {
    seed: u64,
    index: u64,
    v0: f64,
    i_peak: usize,
    peak: f64,
}

/// (sin 2πu, cos 2πu) for u in [0, 1], to about one ulp.
///
/// Our own polynomial rather than the platform's `sin`/`cos`: it is faster
/// here (the phase loop is a large share of a record's cost) and, being plain
/// IEEE arithmetic, gives the same bits on every platform, which keeps
/// ensembles reproducible across machines. The angle is reduced exactly to a
/// quarter turn q plus θ = 2π·x, |x| ≤ 1/8, and sin θ, cos θ are their Taylor
/// series to θ¹⁷ and θ¹⁸ (truncation below 1e-19 for |θ| ≤ π/4).
fn sin_cos_turns(u: f64) -> (f64, f64) {
    const S: [f64; 8] = [
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362_880.0,
        -1.0 / 39_916_800.0,
        1.0 / 6_227_020_800.0,
        -1.0 / 1_307_674_368_000.0,
        1.0 / 355_687_428_096_000.0,
    ];
    const C: [f64; 9] = [
        -1.0 / 2.0,
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40_320.0,
        -1.0 / 3_628_800.0,
        1.0 / 479_001_600.0,
        -1.0 / 87_178_291_200.0,
        1.0 / 20_922_789_888_000.0,
        -1.0 / 6_402_373_705_728_000.0,
    ];
    // Nearest quarter turn q: adding 2^52 rounds 4u to an integer held in the
    // low mantissa bits (no libm `round`, no int→float conversion).
    const SHIFT: f64 = 4_503_599_627_370_496.0;
    let shifted = 4.0 * u + SHIFT;
    let q = shifted.to_bits() & 3;
    // Exact: u and q/4 are within a factor 2 of each other, or q = 0.
    let x = u - 0.25 * (shifted - SHIFT);
    let t = std::f64::consts::TAU * x;
    let z = t * t;
    let mut ps = S[7];
    for c in S[..7].iter().rev() {
        ps = ps * z + c;
    }
    let sin = t + t * z * ps;
    let mut pc = C[8];
    for c in C[..8].iter().rev() {
        pc = pc * z + c;
    }
    let cos = 1.0 + z * pc;
    // Rotate by q quarter turns: (s, c), (c, −s), (−s, −c), (−c, s);
    // branch-free so that successive components overlap in the pipeline.
    let (a, b) = if q & 1 == 0 { (sin, cos) } else { (cos, sin) };
    let sign_a = if q & 2 == 0 { 1.0 } else { -1.0 };
    let sign_b = if (q + 1) & 2 == 0 { 1.0 } else { -1.0 };
    (sign_a * a, sign_b * b)
}

/// [`super::integrate_linear`] into reused buffers (identical arithmetic).
fn integrate_into(dt: f64, acc: &[f64], v0: f64, d0: f64, vel: &mut Vec<f64>, disp: &mut Vec<f64>) {
    vel.resize(acc.len(), 0.0);
    disp.resize(acc.len(), 0.0);
    let (mut v, mut d) = (v0, d0);
    for (k, (vk, dk)) in vel.iter_mut().zip(disp.iter_mut()).enumerate() {
        *vk = v;
        *dk = d;
        if k + 1 < acc.len() {
            let (a0, a1) = (acc[k], acc[k + 1]);
            d += dt * v + dt * dt * (2.0 * a0 + a1) / 6.0;
            v += dt * (a0 + a1) / 2.0;
        }
    }
}

/// Generates record (`seed`, `index`) with peak |acc| = `pga_m_s2` (m/s²).
/// Builds a [`Synthesizer`] each call: for ensembles, build one and reuse it.
///
/// ```
/// use rockfrag::motion::{SynthesisSettings, synthesize};
/// let s = SynthesisSettings::default();
/// let r = synthesize(&s, 42, 3, s.pga_from_g(0.5)).unwrap();
/// assert_eq!(r.name, "synthetic seed=42 index=3");
/// assert_eq!(r.pga(), 0.5 * 9.81);
/// ```
pub fn synthesize(
    settings: &SynthesisSettings,
    seed: u64,
    index: u64,
    pga_m_s2: f64,
) -> Result<Record> {
    Synthesizer::new(settings)?.generate(seed, index, pga_m_s2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fft_synthesis_equals_the_sum_of_cosines() {
        // Direct evaluation of a(t_n) = Σ A_k cos(2π f_k t_n + φ_k) with the
        // same phases; differences are rounding only.
        let settings = SynthesisSettings::default();
        let mut s = Synthesizer::new(&settings).unwrap();
        let x = s.stationary(3, 4).to_vec();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(record_seed(3, 4));
        let phases: Vec<f64> = s
            .frequencies()
            .iter()
            .map(|_| std::f64::consts::TAU * rng.random::<f64>())
            .collect();
        // (The synthesis evaluates these phases with `sin_cos_turns`.)
        let amps = s.amplitudes();
        let freqs = s.frequencies();
        let scale = amps.iter().map(|a| a * a).sum::<f64>().sqrt();
        for n in [0, 1, 17, 500, 999] {
            let t = n as f64 * settings.dt;
            let direct: f64 = (0..amps.len())
                .map(|i| amps[i] * dm::cos(std::f64::consts::TAU * freqs[i] * t + phases[i]))
                .sum();
            assert!(
                (x[n] - direct).abs() < 1e-12 * scale,
                "n={n}: {} vs {direct}",
                x[n]
            );
        }
    }

    #[test]
    fn sin_cos_turns_matches_std() {
        // Both are within about one ulp of the exact values.
        let mut worst: f64 = 0.0;
        for i in 0..=100_000 {
            let u = i as f64 / 100_000.0 + if i % 2 == 0 { 0.0 } else { 1.3e-7 };
            let u = u.min(1.0);
            let (s, c) = sin_cos_turns(u);
            let (s0, c0) = dm::sin_cos(std::f64::consts::TAU * u);
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        // std's reference rounds 2πu first, an argument error of up to
        // ulp(2π)/2 = 4.4e-16: hence 1e-15 here, and 3e-16 on the reduced
        // angle, where that rounding is absent.
        assert!(worst < 1e-15, "{worst}");
        for i in 0..=10_000 {
            // u and x = u − 1 (exact) for u in [7/8, 1]; u itself in [0, 1/8].
            let lo = 0.125 * i as f64 / 10_000.0;
            for (u, x) in [(lo, lo), (0.875 + lo, 0.875 + lo - 1.0)] {
                let (s, c) = sin_cos_turns(u);
                let (s0, c0) = dm::sin_cos(std::f64::consts::TAU * x);
                assert!((s - s0).abs() < 3e-16 && (c - c0).abs() < 3e-16, "u={u}");
            }
        }
        assert_eq!(sin_cos_turns(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_turns(0.25), (1.0, 0.0));
    }

    /// The default model does not repeat within the record: one period of
    /// 2048 samples (40.96 s) covers the 1501 of a 30-s record at 0.02 s,
    /// and any step or duration gets a period at least as long as the
    /// record. The paper's grid read as written repeats every 20 s.
    #[test]
    fn default_grid_covers_the_record() {
        let s = SynthesisSettings::default();
        assert_eq!(s.samples(), 1501);
        assert_eq!(s.period_len().unwrap(), 2048);
        // 0.0732 Hz (the first multiple of Δf from 0.05 Hz) … below Nyquist.
        assert_eq!(s.components().unwrap(), (3, 1023));
        for (dt, duration) in [(0.01, 30.0), (0.005, 61.3), (0.03, 20.0)] {
            let s = SynthesisSettings {
                dt,
                duration,
                ..SynthesisSettings::default()
            };
            let period = s.period_len().unwrap() as f64 * dt;
            assert!(period >= duration, "{dt} {duration}: {period}");
            assert!(Synthesizer::new(&s).is_ok());
        }
        let written = preset("shenton-jones-as-written").unwrap();
        assert_eq!(written.period_len().unwrap(), 1000);
        // 0.05 … 24.95 Hz: the 25 Hz component sits on Nyquist and is dropped.
        assert_eq!(written.components().unwrap(), (1, 499));
    }

    /// A record scaled from its member's kept natural part is the record
    /// made afresh, bit for bit (acc, vel, disp, name), at every level: the
    /// promise that lets a run filter each member once.
    #[test]
    fn scaling_the_natural_part_is_generating_afresh() {
        let settings = SynthesisSettings::default();
        let mut s = Synthesizer::new(&settings).unwrap();
        let mut acc = Vec::new();
        for index in [0, 7, 31] {
            let natural = s.natural(5, index, &mut acc).unwrap();
            for pga_g in [0.1, 0.37, 1.2, 2.0] {
                let pga = pga_g * 9.81;
                let fresh = s.generate(5, index, pga).unwrap();
                let mut kept = Record::empty(0.5);
                s.scaled_into(&acc, &natural, pga, &mut kept).unwrap();
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&kept.acc), bits(&fresh.acc), "acc {index} {pga_g}");
                assert_eq!(bits(&kept.vel), bits(&fresh.vel), "vel {index} {pga_g}");
                assert_eq!(bits(&kept.disp), bits(&fresh.disp), "disp {index} {pga_g}");
                assert_eq!((kept.name, kept.dt), (fresh.name, fresh.dt));
            }
        }
        // a peak of 0 is refused, as `generate` refuses it
        let natural = s.natural(5, 0, &mut acc).unwrap();
        assert!(
            s.scaled_into(&acc, &natural, 0.0, &mut Record::empty(0.02))
                .is_err()
        );
    }

    #[test]
    fn non_integer_period_is_an_error() {
        let s = SynthesisSettings {
            dt: 0.03,
            ..preset("shenton-jones-as-written").unwrap()
        };
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("df") && e.contains("integer"), "{e}");
    }
}
