//! The statistics of the sampled difference `d_k`: moments, the raw cross second moments and
//! their Gershgorin bound, the averaged periodogram's largest eigenvalue, and the correlation
//! time of `|d|` (the study's module docs give the definitions).
//!
//! Correlations are computed through zero-padded FFTs (rustfft): the padding to at least
//! twice the record makes the circular correlation the linear one, exactly the direct sums
//! `Σ_k x(k) y(k+m)` up to rounding, at `O(K log K)` rather than `O(K L)`.

use nalgebra::{Matrix6, Vector3};
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

use super::OmissionOptions;

/// The statistics of `d` over one flight.
#[derive(Debug, Clone, PartialEq)]
pub struct Statistics {
    /// Mean of `d` per axis (m/s²).
    pub mean_mps2: [f64; 3],
    /// RMS of `d` per axis, mean included (m/s²).
    pub rms_axis_mps2: [f64; 3],
    /// RMS of `|d|` (m/s²).
    pub rms_mps2: f64,
    /// Largest `|d|` (m/s²).
    pub max_mps2: f64,
    /// First lag at which the autocorrelation of `|d|` (mean removed) falls below `1/e` (s);
    /// `None` if it never does within the record, or `|d|` does not vary.
    pub correlation_time_s: Option<f64>,
    /// The largest lag `L` used (s): the option, at most the record's length.
    pub max_lag_s: f64,
    /// `q_bound` at `L` (m²/s³).
    pub q_bound_m2_s3: f64,
    /// `max_f λ_max(S(f))` of the averaged periodogram (m²/s³).
    pub q_periodogram_m2_s3: f64,
    /// The frequency of that maximum (Hz).
    pub periodogram_peak_hz: f64,
    /// `tr S(0) / 3` of the averaged periodogram (m²/s³): the density a constant state sees,
    /// over the horizon of one segment (its mean included), per axis on average: the
    /// isotropic density with the same total zero-frequency power (module docs).
    pub q_zero_frequency_m2_s3: f64,
    /// Length of the periodogram's segments (s) and how many were averaged.
    pub segment_s: f64,
    /// Number of segments averaged.
    pub segments: usize,
    /// `q_bound` at each of the options' report lags.
    pub bounds_by_lag: Vec<LagBound>,
}

/// The Gershgorin bound with the lags truncated at one `L`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LagBound {
    /// The lag asked for (s).
    pub max_lag_s: f64,
    /// The lag used, at most the record's length (s).
    pub used_lag_s: f64,
    /// `q_bound` (m²/s³).
    pub q_bound_m2_s3: f64,
}

/// The statistics of `d` sampled every `options.sample_s` (at least two samples).
pub fn statistics(difference: &[Vector3<f64>], options: &OmissionOptions) -> Statistics {
    let sample_s = options.sample_s;
    let count = difference.len();
    let axes: [Vec<f64>; 3] =
        std::array::from_fn(|axis| difference.iter().map(|d| d[axis]).collect());
    let mut planner = FftPlanner::new();
    let moments = CrossMoments::new(&mut planner, &axes);
    let lag_samples = |lag_s: f64| lag_count(lag_s, sample_s, count);
    let max_lag = lag_samples(options.max_lag_s);
    let bounds_by_lag = options
        .report_lags_s
        .iter()
        .map(|&lag_s| LagBound {
            max_lag_s: lag_s,
            used_lag_s: lag_samples(lag_s) as f64 * sample_s,
            q_bound_m2_s3: moments.gershgorin_bound(lag_samples(lag_s), sample_s),
        })
        .collect();
    let segment = (2 * max_lag).clamp(2, count.max(2));
    let periodogram = welch_peak(&mut planner, &axes, segment, sample_s);
    let magnitudes: Vec<f64> = difference.iter().map(|d| d.norm()).collect();
    let total = count.max(1) as f64;
    let sum_squares = |axis: &Vec<f64>| axis.iter().map(|x| x * x).sum::<f64>();
    Statistics {
        mean_mps2: std::array::from_fn(|axis| axes[axis].iter().sum::<f64>() / total),
        rms_axis_mps2: std::array::from_fn(|axis| (sum_squares(&axes[axis]) / total).sqrt()),
        rms_mps2: (axes.iter().map(sum_squares).sum::<f64>() / total).sqrt(),
        max_mps2: magnitudes.iter().copied().fold(0.0, f64::max),
        correlation_time_s: correlation_time_s(&mut planner, &magnitudes, sample_s),
        max_lag_s: max_lag as f64 * sample_s,
        q_bound_m2_s3: moments.gershgorin_bound(max_lag, sample_s),
        q_periodogram_m2_s3: periodogram.q_m2_s3,
        periodogram_peak_hz: periodogram.frequency_hz,
        q_zero_frequency_m2_s3: periodogram.zero_frequency_m2_s3,
        segment_s: segment as f64 * sample_s,
        segments: periodogram.segments,
        bounds_by_lag,
    }
}

/// The number of whole samples in `lag_s`, at most `count − 1` (the longest lag a record of
/// `count` samples has); a millionth of a sample is forgiven so 1000 s at 0.1 s is 10000.
fn lag_count(lag_s: f64, sample_s: f64, count: usize) -> usize {
    // Finite and at least one sample (the study checks both); the cast saturates.
    let lags = (lag_s / sample_s * (1.0 + 1.0e-6)).floor() as usize;
    lags.min(count.saturating_sub(1))
}

/// The zero-padded FFT size for linear correlations of `count` samples.
fn padded_size(count: usize) -> usize {
    (2 * count).next_power_of_two()
}

/// The FFT of `series` zero-padded to `size`.
fn transform(planner: &mut FftPlanner<f64>, series: &[f64], size: usize) -> Vec<Complex<f64>> {
    let mut buffer: Vec<Complex<f64>> = series
        .iter()
        .map(|&x| Complex::new(x, 0.0))
        .chain(std::iter::repeat(Complex::new(0.0, 0.0)))
        .take(size)
        .collect();
    planner.plan_fft_forward(size).process(&mut buffer);
    buffer
}

/// `c(m) = (1/K) Σ_k x(k) y(k+m)` from the padded transforms `X`, `Y` (length `size`),
/// circularly indexed: lag `m ≥ 0` at `m`, lag `−m` at `size − m`. `IFFT(conj(X)·Y)` is that
/// sum (rustfft's inverse is unnormalised: the `1/size` is applied here).
fn correlation(
    planner: &mut FftPlanner<f64>,
    x: &[Complex<f64>],
    y: &[Complex<f64>],
    count: usize,
) -> Vec<f64> {
    let size = x.len();
    let mut buffer: Vec<Complex<f64>> = x.iter().zip(y).map(|(a, b)| a.conj() * b).collect();
    planner.plan_fft_inverse(size).process(&mut buffer);
    let scale = 1.0 / (size as f64 * count.max(1) as f64);
    buffer.iter().map(|value| value.re * scale).collect()
}

/// The raw (mean not removed, biased `1/K`) cross second moments `R_ij(m)` of the three axes,
/// every lag.
struct CrossMoments {
    /// `R_ij` for `i, j` in 0..3, row-major, circularly indexed as [`correlation`].
    pairs: Vec<Vec<f64>>,
    /// The FFT size.
    size: usize,
}

impl CrossMoments {
    fn new(planner: &mut FftPlanner<f64>, axes: &[Vec<f64>; 3]) -> Self {
        let count = axes[0].len();
        let size = padded_size(count);
        let transforms: Vec<Vec<Complex<f64>>> = axes
            .iter()
            .map(|axis| transform(planner, axis, size))
            .collect();
        let mut pairs = Vec::with_capacity(9);
        for x in &transforms {
            for y in &transforms {
                pairs.push(correlation(planner, x, y, count));
            }
        }
        Self { pairs, size }
    }

    /// `q_bound = max_i Σ_j Σ_{|m| ≤ max_lag} |R_ij(m)| Δ` (study docs, Gershgorin bound).
    fn gershgorin_bound(&self, max_lag: usize, sample_s: f64) -> f64 {
        let lag_sum = |pair: &Vec<f64>| {
            let positive: f64 = pair[..=max_lag].iter().map(|r| r.abs()).sum();
            // Lags −max_lag..=−1; empty for `max_lag = 0`.
            let negative: f64 = pair[self.size - max_lag..].iter().map(|r| r.abs()).sum();
            positive + negative
        };
        (0..3)
            .map(|row| {
                (0..3)
                    .map(|column| lag_sum(&self.pairs[3 * row + column]))
                    .sum::<f64>()
                    * sample_s
            })
            .fold(0.0, f64::max)
    }
}

/// The largest eigenvalue of the averaged periodogram over frequency.
struct PeriodogramPeak {
    q_m2_s3: f64,
    frequency_hz: f64,
    zero_frequency_m2_s3: f64,
    segments: usize,
}

/// Welch's averaged periodogram of the three axes: Hann-windowed (periodic, `w_k =
/// sin²(πk/S)`) segments of `segment` samples overlapping by half, the two-sided spectral
/// matrix `S(f) = Δ/(Σ w²) · mean X Xᴴ` at `f = k/(SΔ)`, `k = 0..=S/2` (a real signal's
/// `S(−f)` is the conjugate, with the same eigenvalues); returns `max_f λ_max(S(f))` and
/// `tr S(0) / 3`, the mean of `S(0)`'s eigenvalues (module docs: the allowance at zero
/// frequency).
fn welch_peak(
    planner: &mut FftPlanner<f64>,
    axes: &[Vec<f64>; 3],
    segment: usize,
    sample_s: f64,
) -> PeriodogramPeak {
    let count = axes[0].len();
    let window: Vec<f64> = (0..segment)
        .map(|k| {
            (std::f64::consts::PI * k as f64 / segment as f64)
                .sin()
                .powi(2)
        })
        .collect();
    let window_power: f64 = window.iter().map(|w| w * w).sum();
    let bins = segment / 2 + 1;
    let mut sums = vec![[[Complex::new(0.0, 0.0); 3]; 3]; bins];
    let hop = (segment / 2).max(1);
    let mut segments = 0;
    let mut start = 0;
    while start + segment <= count {
        let transforms = windowed_transforms(planner, axes, start, &window);
        for (bin, sum) in sums.iter_mut().enumerate() {
            for (row, x) in transforms.iter().enumerate() {
                for (column, y) in transforms.iter().enumerate() {
                    sum[row][column] += x[bin] * y[bin].conj();
                }
            }
        }
        segments += 1;
        start += hop;
    }
    let scale = sample_s / (window_power * segments.max(1) as f64);
    let spectrum: Vec<f64> = sums
        .iter()
        .map(|sum| largest_eigenvalue(sum) * scale)
        .collect();
    let (bin, largest) =
        spectrum
            .iter()
            .copied()
            .enumerate()
            .fold(
                (0, 0.0),
                |best, (bin, value)| {
                    if value > best.1 {
                        (bin, value)
                    } else {
                        best
                    }
                },
            );
    PeriodogramPeak {
        q_m2_s3: largest,
        frequency_hz: bin as f64 / (segment as f64 * sample_s),
        zero_frequency_m2_s3: sums.first().map_or(0.0, |zero| {
            (0..3).map(|axis| zero[axis][axis].re).sum::<f64>() / 3.0
        }) * scale,
        segments,
    }
}

/// The FFTs of the three axes' samples `start..start + window.len()`, windowed.
fn windowed_transforms(
    planner: &mut FftPlanner<f64>,
    axes: &[Vec<f64>; 3],
    start: usize,
    window: &[f64],
) -> Vec<Vec<Complex<f64>>> {
    axes.iter()
        .map(|axis| {
            let windowed: Vec<f64> = axis[start..start + window.len()]
                .iter()
                .zip(window)
                .map(|(x, w)| x * w)
                .collect();
            transform(planner, &windowed, window.len())
        })
        .collect()
}

/// `λ_max` of a Hermitian 3×3 matrix `H = A + iB` through its real 6×6 form
/// `[[A, −B], [B, A]]`, symmetric, whose eigenvalues are those of `H`, each twice.
fn largest_eigenvalue(hermitian: &[[Complex<f64>; 3]; 3]) -> f64 {
    let real = Matrix6::from_fn(|row, column| {
        let value = hermitian[row % 3][column % 3];
        match (row < 3, column < 3) {
            (true, true) | (false, false) => value.re,
            (true, false) => -value.im,
            (false, true) => value.im,
        }
    });
    real.symmetric_eigenvalues().max()
}

/// The first lag (s) at which the autocovariance of `magnitudes` (mean removed) falls below
/// `1/e` of its value at lag 0; `None` if it never does, or the magnitudes do not vary (a
/// standard deviation below 1e-12 of their mean).
fn correlation_time_s(
    planner: &mut FftPlanner<f64>,
    magnitudes: &[f64],
    sample_s: f64,
) -> Option<f64> {
    let count = magnitudes.len();
    let mean = magnitudes.iter().sum::<f64>() / count.max(1) as f64;
    let centred: Vec<f64> = magnitudes.iter().map(|x| x - mean).collect();
    let spectrum = transform(planner, &centred, padded_size(count));
    let autocovariance = correlation(planner, &spectrum, &spectrum, count);
    let variance = autocovariance[0];
    // A standard deviation below 1e-12 of the mean is rounding, not variation.
    if variance <= (1.0e-12 * mean).powi(2) {
        return None;
    }
    autocovariance[..count]
        .iter()
        .position(|c| *c < variance / std::f64::consts::E)
        .map(|lag| lag as f64 * sample_s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(sample_s: f64, max_lag_s: f64) -> OmissionOptions {
        OmissionOptions {
            sample_s,
            max_lag_s,
            report_lags_s: vec![max_lag_s],
        }
    }

    /// The FFT correlations equal the direct sums.
    #[test]
    fn fft_correlation_matches_the_direct_sum() {
        let x: Vec<f64> = (0..37).map(|k| (0.3 * k as f64).sin() + 0.1).collect();
        let y: Vec<f64> = (0..37).map(|k| (0.17 * k as f64).cos()).collect();
        let mut planner = FftPlanner::new();
        let size = padded_size(x.len());
        let (fx, fy) = (
            transform(&mut planner, &x, size),
            transform(&mut planner, &y, size),
        );
        let fast = correlation(&mut planner, &fx, &fy, x.len());
        for lag in 0..x.len() {
            let direct: f64 = (0..x.len() - lag).map(|k| x[k] * y[k + lag]).sum::<f64>() / 37.0;
            assert!((fast[lag] - direct).abs() < 1e-14, "lag {lag}");
            let behind: f64 = (0..x.len() - lag).map(|k| x[k + lag] * y[k]).sum::<f64>() / 37.0;
            let index = if lag == 0 { 0 } else { size - lag };
            assert!((fast[index] - behind).abs() < 1e-14, "lag -{lag}");
        }
    }

    /// A constant `c` along x: `R(m) = c² (1 − m/K)`, so the bound is `Σ_{|m|≤M} c²(1 −
    /// |m|/K) Δ`; the periodogram's peak is at 0 Hz, `c² Δ (Σw)²/Σw² = c² S Δ · 2/3` for the
    /// Hann window, below the bound.
    #[test]
    fn a_constant_gives_the_closed_form_bound_and_periodogram() {
        let (c, sample_s, count, max_lag) = (2.0e-5, 0.5, 4000_usize, 500_usize);
        let difference = vec![Vector3::new(c, 0.0, 0.0); count];
        let statistics = statistics(&difference, &options(sample_s, max_lag as f64 * sample_s));
        let expected: f64 = (-(max_lag as i64)..=max_lag as i64)
            .map(|m| c * c * (1.0 - m.unsigned_abs() as f64 / count as f64) * sample_s)
            .sum();
        let relative = (statistics.q_bound_m2_s3 - expected).abs() / expected;
        assert!(
            relative < 1e-9,
            "{} vs {expected}",
            statistics.q_bound_m2_s3
        );
        let periodogram = c * c * sample_s * (2 * max_lag) as f64 * 2.0 / 3.0;
        let relative = (statistics.q_periodogram_m2_s3 - periodogram).abs() / periodogram;
        assert!(relative < 1e-3, "{}", statistics.q_periodogram_m2_s3);
        assert!(statistics.periodogram_peak_hz.abs() < 1e-12);
        // A constant along x: S(0) has rank one, its mean eigenvalue a third of its largest.
        let relative = (3.0 * statistics.q_zero_frequency_m2_s3 - statistics.q_periodogram_m2_s3)
            .abs()
            / statistics.q_periodogram_m2_s3;
        assert!(relative < 1e-12, "{}", statistics.q_zero_frequency_m2_s3);
        assert_eq!(statistics.correlation_time_s, None);
        assert!((statistics.rms_mps2 - c).abs() < 1e-18);
    }

    /// White noise of variance σ² sampled every Δ has the density `σ² Δ`: the periodogram
    /// finds it (its largest bin a few times it, from the estimate's own scatter), and the
    /// bound exceeds it.
    #[test]
    fn white_noise_density_is_found() {
        use rand::SeedableRng as _;
        use rand_distr::Distribution as _;
        let (sigma, sample_s) = (1.0e-4, 0.1);
        let mut random = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let normal = rand_distr::Normal::new(0.0, sigma).unwrap();
        let difference: Vec<Vector3<f64>> = (0..20_000)
            .map(|_| Vector3::from_fn(|_, _| normal.sample(&mut random)))
            .collect();
        let statistics = statistics(&difference, &options(sample_s, 10.0));
        let density = sigma * sigma * sample_s;
        assert!(statistics.q_periodogram_m2_s3 > density);
        assert!(
            statistics.q_periodogram_m2_s3 < 4.0 * density,
            "{statistics:?}"
        );
        assert!(statistics.q_bound_m2_s3 > statistics.q_periodogram_m2_s3);
        // White: the zero-frequency bin is the density too, within the same scatter.
        assert!(statistics.q_zero_frequency_m2_s3 > density / 4.0);
        assert!(statistics.q_zero_frequency_m2_s3 <= statistics.q_periodogram_m2_s3);
        assert_eq!(statistics.correlation_time_s, Some(sample_s));
    }

    #[test]
    fn largest_eigenvalue_of_a_hermitian_matrix() {
        // [[2, i], [−i, 2]] ⊕ [1]: eigenvalues 1, 1, 3.
        let zero = Complex::new(0.0, 0.0);
        let matrix = [
            [Complex::new(2.0, 0.0), Complex::new(0.0, 1.0), zero],
            [Complex::new(0.0, -1.0), Complex::new(2.0, 0.0), zero],
            [zero, zero, Complex::new(1.0, 0.0)],
        ];
        assert!((largest_eigenvalue(&matrix) - 3.0).abs() < 1e-12);
    }
}
